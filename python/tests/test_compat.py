"""`carl_spec.compat` against carl-bench 1.1.1's observed behaviour.

carl-bench pins gymnasium < 1.0, so it cannot be imported here: its behaviour was recorded by
scripts/record_carl_bench.py into fixtures/carl_bench_1_1_1.json, and these tests check the
compat layer against those facts. `test_fixture_is_current` re-records with a carl-bench
interpreter when CARL_BENCH_PYTHON names one.
"""

from __future__ import annotations

import json
import os
import pickle
import subprocess
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
import pytest
from gymnasium.utils.env_checker import check_env

import carl_spec as cs
from carl_spec import compat
from carl_spec.compat import CLASSES, CARLCartPole, CARLLunarLander, CARLPendulum
from carl_spec.compat.context import selection

from conftest import ROOT

FIXTURE = Path(__file__).parent / "fixtures" / "carl_bench_1_1_1.json"
FACTS: dict[str, Any] = json.loads(FIXTURE.read_text())
BEHAVIOUR = FACTS["behaviour"]

# carl-spec's defaults that differ from carl-bench's, each for a documented reason.
DEFAULT_DIFFERENCES = {
    # Gymnasium's values (carl-bench swapped the two MountainCar goals)
    ("CARLMountainCar", "goal_position"): 0.5,
    ("CARLMountainCarContinuous", "goal_position"): 0.45,
    # Brax 2021's system configs (carl-spec's robots), not Brax 0.12's
    ("CARLBraxAnt", "friction"): 0.6,
    ("CARLBraxHalfcheetah", "friction"): 0.6,
    ("CARLBraxHalfcheetah", "mass_torso"): 9.457333,
    ("CARLBraxHumanoid", "friction"): 0.6,
    ("CARLBraxHumanoid", "mass_torso"): 8.907463,
    ("CARLBraxHumanoid", "mass_right_shin"): 2.75569617,
    ("CARLBraxHumanoid", "mass_left_shin"): 2.75569617,
    # carl-bench's feature has no default (target_structure_ids=False); carl-spec: all targets
    ("CARLRnaDesignEnv", "target_structure_ids"): None,
}


def close(a: Any, b: Any) -> bool:
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return bool(np.isclose(a, b, rtol=1e-6))
    return bool(a == b)


@pytest.mark.parametrize("name", sorted(FACTS["classes"]))
def test_feature_names_cover_carl_bench(name: str) -> None:
    cls = CLASSES[name]
    bench = [f["name"] for f in FACTS["classes"][name]["features"]]
    # every carl-bench feature is either offered under its name or refused with a reason
    assert set(cls.bench_names) | set(cls.bench_only) == set(bench)
    assert not set(cls.bench_names) & set(cls.bench_only)
    feats = cls.get_context_features()
    assert [n for n in feats if n in bench] == [n for n in bench if n in cls.bench_names]  # carl-bench's order
    for row in FACTS["classes"][name]["features"]:
        n = row["name"]
        if n in cls.bench_only:
            with pytest.raises(cs.UnknownNameError, match=f'"{n}".*Valid features: '):
                cls._canonical(n)
            continue
        expected = DEFAULT_DIFFERENCES.get((name, n), row["default"])
        if (name, n) not in DEFAULT_DIFFERENCES or expected is not None:
            assert close(feats[n].default_value, expected), (n, feats[n].default_value, expected)


def test_gym_ids_are_registered() -> None:
    for gym_id in FACTS["gym_ids"]:
        assert gym_id in gymnasium.registry
    for name in CLASSES:
        assert compat.gym_id(name) in gymnasium.registry
    env = gymnasium.make("carl/CARLCartPole-v0", contexts={0: {"length": 0.7}})
    obs, info = env.reset(seed=0)
    assert info == {"context_id": 0} and obs["context"]["length"][0] == np.float32(0.7)


def test_observation_and_info_layout() -> None:
    contexts = {"a": {"length": 0.6}, "b": {"length": 0.7}, "c": {"masscart": 2.0}}
    env = CARLCartPole(contexts=contexts)
    bench_space = BEHAVIOUR["cartpole_observation_space"]
    obs, info = env.reset(seed=0)
    assert sorted(info) == BEHAVIOUR["cartpole_info_keys_reset"]
    assert sorted(env.step(0)[4]) == BEHAVIOUR["cartpole_info_keys_step"]
    assert set(obs) == set(bench_space) == {"obs", "context"}
    kept = [n for n in BEHAVIOUR["cartpole_default_obs_context_features"] if n in CARLCartPole.bench_names]
    assert env.obs_context_features == kept
    for n in kept:
        box = env.observation_space["context"][n]
        assert [list(box.shape), str(box.dtype)] == [bench_space["context"][n]["shape"], bench_space["context"][n]["dtype"]]
    # carl-bench's observation is not in its own space; carl-spec's is
    assert BEHAVIOUR["cartpole_obs_in_space"] is False
    assert obs in env.observation_space
    # the filled context set: carl-bench's values, without the features carl-spec does not have
    filled = {k: {n: v for n, v in c.items() if n in kept} for k, c in BEHAVIOUR["cartpole_contexts_filled"].items()}
    assert env.contexts.keys() == filled.keys()
    for k, c in env.contexts.items():
        assert c == pytest.approx(filled[k])


def test_vector_context_observation() -> None:
    env = CARLCartPole(contexts={0: {"length": 0.6}}, obs_context_features=["gravity", "length"], obs_context_as_dict=False)
    obs, _ = env.reset(seed=0)
    space = BEHAVIOUR["vector_context_space"]["context"]
    assert list(env.observation_space["context"].shape) == space["shape"] and obs["context"].dtype == np.float32
    np.testing.assert_allclose(obs["context"], BEHAVIOUR["vector_context_value"], rtol=1e-6)
    # carl-bench crashes here with partial contexts (its env.context lacks the defaults)
    assert BEHAVIOUR["vector_context_partial_contexts"].startswith("KeyError")


def test_selectors_follow_carl_bench_where_it_is_sound() -> None:
    contexts = {"a": {"length": 0.6}, "b": {"length": 0.7}, "c": {"masscart": 2.0}}
    env = CARLCartPole(contexts=contexts)
    ids = [env.reset(seed=0)[1]["context_id"]] + [env.reset()[1]["context_id"] for _ in range(5)]
    assert ids == BEHAVIOUR["round_robin_context_ids"]
    # env.context: the full context (carl-bench's lacks the defaults)
    for got, bench in zip([env.context], BEHAVIOUR["env_context_after_resets"][-1:]):
        assert got is not None and all(close(got[k], v) for k, v in bench.items()) and len(got) == 6
    st = CARLCartPole(contexts=contexts, context_selector=selection.StaticSelector)
    assert [st.reset(seed=s)[1]["context_id"] for s in range(3)] == BEHAVIOUR["static_ids"]
    # carl-bench's round robin ignores the seed; carl-spec's starts at seed mod n
    assert BEHAVIOUR["round_robin_same_seed_ids"] == [0, 1, 2, 0]
    again = CARLCartPole(contexts=contexts)
    assert [again.reset(seed=123)[1]["context_id"] for _ in range(4)] == [0, 0, 0, 0]


def test_random_selection_is_seeded() -> None:
    seqs = BEHAVIOUR["random_selector_same_env_seed_sequences"]
    assert seqs[0] != seqs[1]  # carl-bench: same env seed, different instances (global RNG)
    contexts = {i: {"length": 0.5 + 0.1 * i} for i in range(10)}

    def run() -> list[int]:
        env = CARLCartPole(contexts=contexts, context_selector=selection.RandomSelector)
        out = [env.reset(seed=0)[1]["context_id"]]
        return out + [env.reset()[1]["context_id"] for _ in range(7)]

    a, b = run(), run()
    assert a == b and len(set(a)) > 3
    # the same stream as cs.make's random selection over a set
    ref = cs.make("lunar_lander", instances="lunar_lander/landing_in_space_train", selection="random")
    lander = CARLLunarLander(
        contexts={i: {"GRAVITY_Y": c["GRAVITY_Y"]} for i, c in enumerate(cs.instances.load("lunar_lander/landing_in_space_train").contexts)},
        context_selector=selection.RandomSelector,
    )
    for s in [4, None, None, 9, None]:
        assert lander.reset(seed=s)[1]["context_id"] == ref.reset(seed=s)[1]["instance_id"]


def test_carl_bench_selector_classes_are_accepted_by_name() -> None:
    class RandomSelector:  # stands in for carl.context.selection.RandomSelector
        pass

    env = CARLCartPole(contexts={0: {}, 1: {"length": 0.9}}, context_selector=RandomSelector)
    assert env.context_selector.mode == "random"

    def pick_last(sel: selection.AbstractSelector) -> tuple[dict[str, Any], int]:
        return sel.contexts[sel.contexts_keys[-1]], len(sel.contexts) - 1

    custom = CARLCartPole(contexts={0: {}, 1: {"length": 0.9}}, context_selector=selection.CustomSelector,
                          context_selector_kwargs={"selector_function": pick_last})
    assert custom.reset(seed=0)[1]["context_id"] == 1 and custom.context["length"] == 0.9


def test_flaws_are_refused_with_reasons() -> None:
    # Pendulum's gravity is dead in carl-bench: refused, pointing at g
    assert BEHAVIOUR["pendulum_gravity_changes_step"] is False
    with pytest.raises(cs.UnknownNameError, match=r'"gravity".*dead.*use g'):
        CARLPendulum(contexts={0: {"gravity": 20.0}})
    a, b = CARLPendulum(contexts={0: {"g": 8.0}}), CARLPendulum(contexts={0: {"g": 20.0}})
    a.reset(seed=0), b.reset(seed=0)
    act = np.array([0.5], dtype=np.float32)
    assert not np.array_equal(a.step(act)[0]["obs"], b.step(act)[0]["obs"])
    # carl-bench accepts values outside the bounds silently; carl-spec refuses them
    assert BEHAVIOUR["out_of_bounds_accepted"] is True
    with pytest.raises(ValueError, match="length|pole_length") as oob:
        CARLCartPole(contexts={0: {"length": 100.0}})
    # The compat API has no allow_out_of_bounds=: the message names what does (issue 31 item 13)
    assert "allow_out_of_bounds=True) runs it" in str(oob.value) and "carl_spec.make('cartpole'" in str(oob.value)
    assert "pass allow_out_of_bounds" not in str(oob.value)
    with pytest.raises(cs.UnknownNameError, match="valid features: gravity, masscart"):
        CARLCartPole(contexts={0: {"lenght": 0.6}})
    with pytest.raises(cs.UnknownNameError, match="initial_state_lower.*U\\(-0.05, 0.05\\)"):
        CARLCartPole(contexts={0: {"initial_state_lower": -0.2}})
    with pytest.raises(ValueError, match="env= is not supported"):
        CARLCartPole(env=gymnasium.make("CartPole-v1"))


def test_no_global_state_between_envs() -> None:
    # carl-bench's LunarLander writes MAIN_ENGINE_POWER into Gymnasium's module for every env
    leak = BEHAVIOUR["lunar_lander_module_global_after_other_env"]
    assert leak["before"] != leak["after"]

    def episode(env: CARLLunarLander, steps: int = 60) -> list[list[float]]:
        env.reset(seed=1)
        return [env.step(2)[0]["obs"].tolist() for _ in range(steps)]

    alone = episode(CARLLunarLander(contexts={0: {"MAIN_ENGINE_POWER": 13.0}}))
    strong = CARLLunarLander(contexts={0: {"MAIN_ENGINE_POWER": 20.0}})
    weak = CARLLunarLander(contexts={0: {"MAIN_ENGINE_POWER": 13.0}})
    strong.reset(seed=1), weak.reset(seed=1)
    interleaved = []
    for _ in range(60):
        strong.step(2)
        interleaved.append(weak.step(2)[0]["obs"].tolist())
    assert interleaved == alone


def test_compat_equals_cs_make_step_for_step() -> None:
    env = CARLCartPole(contexts={0: {"length": 0.7, "force_mag": 12.0}})
    ref = cs.make("cartpole", context={"pole_length": 0.7, "force_magnifier": 12})
    gym = gymnasium.make("CartPole-v1")
    plain = CARLCartPole()
    for seed in [3, None, 8, None]:
        a, b = env.reset(seed=seed)[0]["obs"], ref.reset(seed=seed)[0]
        # the default context is Gymnasium's CartPole-v1, unseeded resets included
        assert np.array_equal(plain.reset(seed=seed)[0]["obs"], gym.reset(seed=seed)[0])
        assert np.array_equal(a, b)
        for t in range(50):
            (oa, ra, ta, ua, _), (ob, rb, tb, ub, _) = env.step(t % 2), ref.step(t % 2)
            assert np.array_equal(oa["obs"], ob) and (ra, ta, ua) == (rb, tb, ub)
            if ta or ua:
                break


def test_check_env_pickling_and_defaults() -> None:
    env = CARLLunarLander(contexts={0: {"GRAVITY_Y": -3.7}, 1: {"GRAVITY_Y": -9.8}}, obs_context_features=["GRAVITY_Y"])
    check_env(env, skip_render_check=True)
    clone = pickle.loads(pickle.dumps(env))
    assert np.array_equal(clone.reset(seed=2)[0]["obs"], env.reset(seed=2)[0]["obs"])
    assert CARLCartPole.get_default_context() == {
        "gravity": 9.8, "masscart": 1.0, "masspole": 0.1, "length": 0.5, "force_mag": 10, "tau": 0.02,
    }
    f = CARLCartPole.get_context_features()["length"]
    assert (f.lower, f.upper, f.canonical_name) == (0.05, 5.0, "pole_length")
    # carl-spec starts CartPole as Gymnasium does (±0.05), carl-bench from ±0.1
    assert BEHAVIOUR["cartpole_initial_state_abs_max"] > 0.09
    starts = np.array([CARLCartPole().reset(seed=s)[0]["obs"] for s in range(200)])
    assert np.abs(starts).max() <= 0.05


def test_fixture_is_current(tmp_path: Path) -> None:
    """Re-record carl-bench's behaviour and compare (needs a carl-bench 1.1.1 interpreter)."""
    python = os.environ.get("CARL_BENCH_PYTHON")
    if not python:
        pytest.skip("set CARL_BENCH_PYTHON to a python with carl-bench==1.1.1 to re-record (see scripts/record_carl_bench.py)")
    out = tmp_path / "facts.json"
    subprocess.run([python, str(ROOT / "scripts" / "record_carl_bench.py"), str(out)], check=True,
                   env={**os.environ, "SDL_VIDEODRIVER": "dummy"}, capture_output=True)
    fresh = json.loads(out.read_text())
    for c in fresh["classes"].values():
        c.pop("import_error", None)
    recorded = json.loads(FIXTURE.read_text())
    for c in recorded["classes"].values():
        c.pop("import_error", None)
    random_key = "random_selector_same_env_seed_sequences"  # global-RNG draws: only their inequality is a fact
    assert fresh["behaviour"].pop(random_key) and recorded["behaviour"].pop(random_key)
    assert fresh == recorded


@pytest.mark.parametrize("name", sorted(CLASSES))
def test_every_class_runs_with_its_default_context(name: str) -> None:
    cls = CLASSES[name]
    env = cls()
    assert env.contexts == {0: cls.get_default_context()}
    obs, info = env.reset(seed=0)
    assert info == {"context_id": 0} and obs in env.observation_space
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert obs in env.observation_space and info == {"context_id": 0}
    assert isinstance(reward, float) and isinstance(terminated, bool) and isinstance(truncated, bool)


def test_context_id_setter_switches_from_the_next_reset() -> None:
    contexts = {"a": {"length": 0.6}, "b": {"length": 0.7}, "c": {"length": 0.8}}
    rr = CARLCartPole(contexts=contexts)
    rr.reset(seed=0)
    rr.context_id = 2
    assert rr.context_id == 2
    assert rr.reset()[1]["context_id"] == 0  # round robin continues after 2, as carl-bench's
    st = CARLCartPole(contexts=contexts, context_selector=selection.StaticSelector)
    st.reset(seed=0)
    st.context_id = 1
    assert [st.reset()[1]["context_id"] for _ in range(3)] == [1, 1, 1]
    assert st.context is not None and st.context["length"] == 0.7
    with pytest.raises(ValueError, match="not in the context set"):
        st.context_id = 5
