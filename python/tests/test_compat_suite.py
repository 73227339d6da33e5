"""What carl-bench 1.1.1's own suite (python/tests/carl_bench_suite) needs from `carl_spec.compat`,
checked beyond that suite: the vendored files are carl-bench's with only the import prefix
changed, the module twins, the API the suite uses, and the tests it cannot run yet."""

from __future__ import annotations

import hashlib
import importlib
import inspect
import re
import sys
from pathlib import Path

import gymnasium
import numpy as np
import pytest

import carl_spec as cs
from carl_spec.compat import CARLBraxAnt, CARLCartPole, CARLPendulum
from carl_spec.compat.context.context_space import (
    CategoricalContextFeature,
    ContextSpace,
    UniformFloatContextFeature,
    UniformIntegerContextFeature,
)
from carl_spec.compat.context.selection import RandomSelector, StaticSelector

SUITE = Path(__file__).parent / "carl_bench_suite"

# carl-bench 1.1.1's modules (v1.1.1, carl/**/*.py), each with a twin under carl_spec.compat.
TWINS = """
carl.context carl.context.context_space carl.context.sampler carl.context.search_space_encoding
carl.context.selection carl.context.utils carl.envs carl.envs.brax carl.envs.brax.brax_walker_goal_wrapper
carl.envs.brax.carl_ant carl.envs.brax.carl_brax_env carl.envs.brax.carl_halfcheetah carl.envs.brax.carl_hopper
carl.envs.brax.carl_humanoid carl.envs.brax.carl_humanoidstandup carl.envs.brax.carl_inverted_double_pendulum
carl.envs.brax.carl_inverted_pendulum carl.envs.brax.carl_pusher carl.envs.brax.carl_reacher carl.envs.brax.carl_walker2d
carl.envs.carl_env carl.envs.dmc carl.envs.dmc.carl_dm_finger carl.envs.dmc.carl_dm_fish carl.envs.dmc.carl_dm_pointmass
carl.envs.dmc.carl_dm_quadruped carl.envs.dmc.carl_dm_walker carl.envs.dmc.carl_dmcontrol carl.envs.dmc.dmc_tasks
carl.envs.dmc.dmc_tasks.finger carl.envs.dmc.dmc_tasks.fish carl.envs.dmc.dmc_tasks.pointmass
carl.envs.dmc.dmc_tasks.quadruped carl.envs.dmc.dmc_tasks.utils carl.envs.dmc.dmc_tasks.walker carl.envs.dmc.loader
carl.envs.dmc.wrappers carl.envs.gymnasium carl.envs.gymnasium.box2d carl.envs.gymnasium.box2d.carl_bipedal_walker
carl.envs.gymnasium.box2d.carl_lunarlander carl.envs.gymnasium.box2d.carl_vehicle_racing
carl.envs.gymnasium.carl_gymnasium_env carl.envs.gymnasium.classic_control
carl.envs.gymnasium.classic_control.carl_acrobot carl.envs.gymnasium.classic_control.carl_cartpole
carl.envs.gymnasium.classic_control.carl_mountaincar carl.envs.gymnasium.classic_control.carl_mountaincarcontinuous
carl.envs.gymnasium.classic_control.carl_pendulum carl.envs.mario carl.envs.mario.carl_mario carl.envs.rna
carl.envs.rna.carl_rna carl.utils carl.utils.types
""".split()
# carl-bench's implementation modules of runtimes carl-spec replaces (no twin: nothing of them is API):
# carl.envs.brax.wrappers (Brax -> Gym), carl.envs.gymnasium.box2d.parking_garage.* (the Box2D car
# bodies), carl.envs.mario.pcg_smb_env.* (Java game, TOAD-GAN in torch), carl.envs.rna.{carl_rna_definitions,
# parse_dot_brackets, rna_environment, data.*}, carl.utils.doc_building.* (its docs' plots).


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def test_vendored_files_are_carl_bench_with_only_the_import_prefix_changed() -> None:
    table = dict(
        (name, sha) for sha, name in re.findall(r"\| `([0-9a-f]{64})` \| `([^`]+)` \|", (SUITE / "PROVENANCE.md").read_text())
    )
    vendored = sorted(p.name for p in SUITE.glob("test_*.py"))
    assert len(vendored) == 13 and set(table) == {"LICENSE", *vendored}
    assert _sha((SUITE / "LICENSE").read_text()) == table["LICENSE"]
    for name in vendored:
        text = (SUITE / name).read_text()
        original = re.sub(r"^(\s*)import carl_spec\.compat$", r"\1import carl", text, flags=re.MULTILINE)
        original = original.replace("carl_spec.compat.", "carl.")
        assert _sha(original) == table[name], name
        assert not re.search(r"(?<![\w.])carl\.(?=\w)|^\s*import carl\s*$", text, re.MULTILINE), name
    # the rewrite is the script's
    sys.path.insert(0, str(Path(__file__).parents[2] / "scripts"))
    try:
        vendor = importlib.import_module("vendor_carl_bench_tests")
    finally:
        sys.path.pop(0)
    assert vendor.rewrite("import carl\nimport carl.envs\nfrom carl.x import y\nmy_carl.z\n") == (
        "import carl_spec.compat\nimport carl_spec.compat.envs\nfrom carl_spec.compat.x import y\nmy_carl.z\n"
    )


@pytest.mark.parametrize("module", TWINS)
def test_every_carl_bench_module_has_a_twin(module: str) -> None:
    importlib.import_module("carl_spec.compat" + module[len("carl"):])


def test_load_dmc_env_gives_every_domain() -> None:
    # carl-bench's five dm_control domains, each by dm_control's plain task name and carl-bench's.
    from carl_spec.compat.envs.dmc.loader import _DOMAINS, load_dmc_env

    assert set(_DOMAINS) == {"walker", "pointmass", "finger", "fish", "quadruped"}
    env = load_dmc_env(domain_name="finger", task_name="spin")
    assert type(env).__name__ == "CARLDmcFingerEnv"
    obs, _ = env.reset(seed=0)
    env.step(env.action_space.sample())
    fish = load_dmc_env(domain_name="fish", task_name="upright_context", context={"density": 4000.0})
    assert fish.contexts[0]["density"] == 4000.0
    with pytest.raises(ValueError, match="Task 'juggle' does not exist in domain 'finger'"):
        load_dmc_env(domain_name="finger", task_name="juggle")


def test_brax_classes_carl_spec_has_run_as_carl_bench_test_brax_env_does() -> None:
    # carl-bench's test_brax_env.py over every Brax class (the vendored file runs it too)
    import carl_spec.compat.envs.brax as brax

    ran = []
    for name, cls in inspect.getmembers(brax, inspect.isclass):
        if "CARL" in name:
            cls.get_context_features()
            env = cls()
            env._progress_instance()
            env._update_context()
            env.reset()
            ran.append(name)
    assert ran == [
        "CARLBraxAnt",
        "CARLBraxHalfcheetah",
        "CARLBraxHopper",
        "CARLBraxHumanoid",
        "CARLBraxHumanoidStandup",
        "CARLBraxInvertedDoublePendulum",
        "CARLBraxInvertedPendulum",
        "CARLBraxPusher",
        "CARLBraxReacher",
        "CARLBraxWalker2d",
    ]


def test_box2d_classes_run_as_carl_bench_test_box2d_envs_does() -> None:
    # carl-bench's test_box2d_envs.py does nothing (and passes) when the Box2D package is missing,
    # which carl-spec's Box2D-family runtimes never need: its body, run here whatever is installed.
    import carl_spec.compat.envs.gymnasium as gym_envs

    ran = []
    for name, cls in inspect.getmembers(gym_envs.box2d, inspect.isclass):
        if "CARL" in name:
            cls.get_context_features()
            env = cls()
            env._progress_instance()
            env._update_context()
            env.reset()
            ran.append(name)
    assert ran == ["CARLBipedalWalker", "CARLLunarLander", "CARLVehicleRacing"]


def test_goal_wrappers_run_the_goal_option() -> None:
    from carl_spec.compat.envs import CARLBraxHopper
    from carl_spec.compat.envs.brax.brax_walker_goal_wrapper import (
        DIRECTION_NAMES,
        BraxLanguageWrapper,
        BraxWalkerGoalWrapper,
        directions,
    )

    assert directions == [1, 3, 2, 4, 12, 32, 14, 34, 112, 332, 114, 334, 212, 232, 414, 434]
    assert set(DIRECTION_NAMES) == set(directions) and DIRECTION_NAMES[212] == "east north east"
    for wrapper in (BraxWalkerGoalWrapper, BraxLanguageWrapper):
        with pytest.raises(TypeError, match="Brax walkers"):
            wrapper(CARLCartPole())
    # Without goal features: carl-bench's task, no goal, no goal features in the context.
    plain = CARLBraxAnt()
    assert plain.env is None and plain.position is None
    assert "target_distance" not in CARLBraxAnt.get_default_context()
    assert CARLBraxAnt.get_default_goal_context()["target_direction"] == 1
    _, info = plain.reset(seed=0)
    assert "success" not in info and "target_distance" not in plain.context
    # A context naming a goal feature turns the goal on: reward = approach, success within the radius.
    env = CARLBraxHopper(contexts={0: {"target_distance": 0.5, "target_direction": 2, "target_radius": 0.1}})
    assert isinstance(env.env, BraxWalkerGoalWrapper) and env.position is None
    obs, info = env.reset(seed=1)
    assert info["success"] == 0 and info["goal_direction"] == "east" and env.position == (0.0, 0.0)
    assert np.allclose(env.env.goal_position, [0.5, 0.0])
    total = 0.0
    for t in range(200):
        obs, reward, terminated, truncated, info = env.step(np.array([0.0, 0.0, 0.0], dtype=np.float32))
        assert reward >= 0
        total += reward
        assert abs(info["goal_distance"] - np.hypot(*(env.env.goal_position - np.array(env.position)))) < 1e-9
        if terminated:
            break
    # Wrapping a walker turns the goal on; the language wrapper adds the goal in words.
    wrapped = BraxLanguageWrapper(BraxWalkerGoalWrapper(CARLBraxAnt(), "ant", "envs/assets/ant.xml"))
    obs, info = wrapped.reset(seed=0)
    assert obs["obs"]["goal"] == "The distance to the goal is 100.0m north. Move within 5.0m of the goal."
    assert wrapped.observation_space.contains(obs)
    assert wrapped.unwrapped.position == (0.0, 0.0) and info["success"] == 0
    with pytest.raises(ValueError, match="option goal"):
        cs.make("ant", context={"target_distance": 10.0})
    g = cs.make("ant", context={"target_distance": 10.0, "target_direction": "south east"}, options={"goal": True})
    _, info = g.reset(seed=0)
    assert info["goal_direction"] == "south east" and abs(info["goal_distance"] - 10.0) < 1e-9


def test_contexts_setter_replaces_the_set_from_the_next_reset() -> None:
    env = CARLCartPole(contexts={0: {"length": 0.6}, 1: {"length": 0.7}})
    ref = CARLCartPole(contexts={0: {"length": 0.6}, 1: {"length": 0.7}})
    env.reset(seed=0), ref.reset(seed=0)
    env.step(0), ref.step(0)
    env.contexts = {"x": {"length": 0.9}, "y": {"masscart": 2.0}, "z": {}}
    # the running episode keeps its context (and its runtime) until the next reset
    (obs, *_, info), (ref_obs, *_, ref_info) = env.step(1), ref.step(1)
    assert np.array_equal(obs["obs"], ref_obs["obs"]) and info == ref_info and env.context == ref.context
    assert env.contexts == {
        "x": {**CARLCartPole.get_default_context(), "length": 0.9},
        "y": {**CARLCartPole.get_default_context(), "masscart": 2.0},
        "z": CARLCartPole.get_default_context(),
    }
    assert env.context_selector.contexts_keys == ["x", "y", "z"]
    ids = [env.reset()[1]["context_id"] for _ in range(4)]
    assert ids == [0, 1, 2, 0]  # a new set starts at its first context
    assert env.context == env.contexts["x"]
    # a seeded run stays reproducible across the change of set (the new set's streams come from
    # the env's own seeded np_random); unseeded envs differ
    def curriculum(seed: int | None) -> list[bytes]:
        e = CARLCartPole(contexts={0: {"length": 0.6}, 1: {"length": 0.7}})
        e.reset(seed=seed)
        e.contexts = {0: {"length": 0.9}, 1: {}}
        return [e.reset()[0]["obs"].tobytes() for _ in range(3)]

    assert curriculum(5) == curriculum(5)
    assert curriculum(None) != curriculum(None)
    with pytest.raises(ValueError, match="length"):
        env.contexts = {0: {"length": 100.0}}
    assert len(env.contexts) == 3  # a refused set leaves the old one in place
    # pickling rebuilds with the set in force
    import pickle

    assert pickle.loads(pickle.dumps(env)).contexts == env.contexts


def test_unseeded_round_robin_starts_at_the_first_context() -> None:
    contexts = {k: {"length": 0.5 + 0.1 * i} for i, k in enumerate("abcde")}
    for _ in range(5):
        env = CARLCartPole(contexts=contexts)
        assert [env.reset()[1]["context_id"] for _ in range(6)] == [0, 1, 2, 3, 4, 0]
    # seeded selection stays: seed s starts at s mod n
    env = CARLCartPole(contexts=contexts)
    assert [env.reset(seed=7)[1]["context_id"], env.reset()[1]["context_id"]] == [2, 3]
    # unseeded envs still differ in their initial states (the runtime's stream is seeded by the OS)
    starts = {CARLCartPole(contexts=contexts).reset()[0]["obs"].tobytes() for _ in range(4)}
    assert len(starts) > 1
    # switching before the first reset: round robin continues after it, static stays on it
    env = CARLCartPole(contexts=contexts)
    env.context_id = 2
    assert env.reset()[1]["context_id"] == 3
    st = CARLCartPole(contexts=contexts, context_selector=StaticSelector)
    st.context_id = 4
    assert [st.reset()[1]["context_id"] for _ in range(2)] == [4, 4]


def test_progress_instance_and_update_context_have_carl_bench_meaning() -> None:
    contexts = {"a": {"length": 0.6}, "b": {"length": 0.7}, "c": {"length": 0.8}}
    env = CARLCartPole(contexts=contexts)
    assert env.context is None and env.context_id is None
    env._progress_instance()  # selects, as a reset does
    assert env.context_id == 0 and env.context == env.contexts["a"]
    env._update_context()  # nothing to push: every context has its own runtime
    assert env.reset()[1]["context_id"] == 1  # the reset selects again, as in carl-bench
    assert env.context_selector.n_calls == 2
    env.context = {**env.context, "length": 2.0}
    with pytest.raises(ValueError, match=r"changed in place \(length\).*env.contexts ="):
        env._update_context()
    rnd = CARLCartPole(contexts=contexts, context_selector=RandomSelector)
    rnd.reset(seed=3)
    rnd._progress_instance()
    assert rnd.context == rnd.contexts[list(contexts)[rnd.context_id]]


def test_unknown_selector_is_refused_before_the_contexts() -> None:
    with pytest.raises(ValueError, match="AbstractSelector class or instance, got str"):
        CARLPendulum(contexts={0: {"gravity": 10.0}}, context_selector="bork")


def test_get_context_bounds() -> None:
    from carl_spec.compat.context.utils import get_context_bounds

    lower, upper = get_context_bounds(["a", "b"], {"a": (0, np.inf, float), "b": (-1.0, 2.0, float), "c": (5, 6, int)})
    assert lower.tolist() == [0.0, -1.0] and upper.tolist() == [np.inf, 2.0] and lower.dtype == np.float64
    with pytest.raises(KeyError):
        get_context_bounds(["d"], {})


def test_context_space_sampling_and_gymnasium_space() -> None:
    space = ContextSpace(
        {
            "g": UniformFloatContextFeature("g", lower=1.0, upper=20.0, default_value=9.8),
            "n": UniformIntegerContextFeature("n", lower=1, upper=3, default_value=2),
            "c": CategoricalContextFeature("c", choices=["x", "y"], default_value="x"),
            "open": UniformFloatContextFeature("open", lower=0.1, upper=np.inf, default_value=1.0),
        }
    )
    one = space.sample_contexts(["g"], size=1, seed=0)
    assert isinstance(one, dict) and one["n"] == 2 and one["open"] == 1.0 and 1 <= one["g"] <= 20
    many = space.sample_contexts(["g", "n", "c"], size=20, seed=0)
    assert isinstance(many, list) and len(many) == 20 and all(space.verify_context(c) for c in many)
    assert many == space.sample_contexts(["g", "n", "c"], size=20, seed=0)
    assert {c["n"] for c in many} == {1, 2, 3} and {c["c"] for c in many} == {"x", "y"}
    with pytest.raises(ValueError, match="Invalid context feature name: nope"):
        space.sample_contexts(["nope"], size=0)
    with pytest.raises(ValueError, match=r"open: cannot draw uniformly from \[0.1, inf\]"):
        space.sample_contexts(["open"])
    box = space.to_gymnasium_space(["g", "n", "c"])
    assert isinstance(box, gymnasium.spaces.Box) and box.low.tolist() == [1, 1, 0] and box.high.tolist() == [20, 3, 1]
    d = space.to_gymnasium_space(as_dict=True)
    assert isinstance(d, gymnasium.spaces.Dict) and d["c"] == gymnasium.spaces.Discrete(2)
    assert d["g"].shape == (1,) and d["g"].dtype == np.float32
    # the env's observation space is this space's
    env_space = CARLCartPole.get_context_space().to_gymnasium_space(["length", "tau"], as_dict=True)
    assert env_space == CARLCartPole(obs_context_features=["length", "tau"]).observation_space["context"]


def test_search_space_encoding_names_the_optional_packages(monkeypatch: pytest.MonkeyPatch) -> None:
    from carl_spec.compat.context import search_space_encoding as sse

    monkeypatch.setitem(sys.modules, "ConfigSpace", None)
    with pytest.raises(ImportError, match=r'carl-spec\[compat\]'):
        sse.search_space_to_config_space({"hyperparameters": []})


def test_search_space_encoding_reads_hydra_and_json_spaces() -> None:
    pytest.importorskip("ConfigSpace", reason="ConfigSpace is optional (carl-spec[compat])")
    omegaconf = pytest.importorskip("omegaconf", reason="omegaconf is optional (carl-spec[compat])")
    from carl_spec.compat.context.search_space_encoding import search_space_to_config_space

    cfg = omegaconf.DictConfig(
        {"hyperparameters": {"x": {"type": "uniform_float", "lower": 0.0, "upper": 1.0}, "c": {"type": "categorical", "choices": ["a", "b"]}}}
    )
    space = search_space_to_config_space(cfg, seed=1)
    assert sorted(space) == ["c", "x"]
    assert list(cfg.hyperparameters) == ["x", "c"]  # read, not rewritten (carl-bench turns it into a list)
    old = {"hyperparameters": [{"name": "x0", "type": "uniform_float", "log": False, "lower": -512.0, "upper": 512.0, "default": -3.0, "q": None}]}
    assert search_space_to_config_space(old)["x0"].default_value == -3.0
    with pytest.raises(ValueError, match="search_space must be"):
        search_space_to_config_space(3)


def test_mario_without_its_data_says_how_to_get_it(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    # carl-bench ships Mario's levels and TOAD-GAN generators; carl-spec reads them from CARL_SPEC_DATA
    # (docs/guides/data.md), and the error of an env without them says how to get them.
    from carl_spec.compat import CARLMarioEnv

    monkeypatch.setenv("CARL_SPEC_DATA", str(tmp_path))
    with pytest.raises(ValueError, match=r"(?s)CARL_SPEC_DATA.*gen_toad_gan_weights\.py"):
        CARLMarioEnv().reset(seed=0)


def test_context_sampler_takes_configspace_hyperparameters_and_hydra_spaces(tmp_path: Path) -> None:
    configspace = pytest.importorskip("ConfigSpace", reason="ConfigSpace is optional (carl-spec[compat])")
    omegaconf = pytest.importorskip("omegaconf", reason="omegaconf is optional (carl-spec[compat])")
    from carl_spec.compat import ContextSampler

    space = CARLCartPole.get_context_space()
    hps = [configspace.UniformFloatHyperparameter("length", 0.2, 2.0), configspace.CategoricalHyperparameter("masscart", [1.0, 2.0])]
    contexts = ContextSampler(hps, context_space=space, seed=0).sample_contexts(8)
    assert all(0.2 <= c["length"] <= 2.0 and c["masscart"] in (1.0, 2.0) and c["tau"] == 0.02 for c in contexts.values())
    CARLCartPole(contexts=contexts).reset(seed=0)
    hydra = omegaconf.DictConfig({"hyperparameters": {"length": {"type": "uniform_float", "lower": 0.2, "upper": 2.0}}})
    a = ContextSampler(hydra, context_space=space, seed=1).sample_contexts(3)
    path = tmp_path / "space.json"
    path.write_text('{"hyperparameters": [{"name": "length", "type": "uniform_float", "lower": 0.2, "upper": 2.0, "log": false}]}')
    b = ContextSampler(str(path), context_space=space, seed=1).sample_contexts(3)
    assert a == b and len({c["length"] for c in a.values()}) == 3
    with pytest.raises(ValueError, match="NormalIntegerHyperparameter is not a distribution"):
        ContextSampler([configspace.NormalIntegerHyperparameter("length", mu=1, sigma=1, lower=0, upper=3)], context_space=space, seed=0)
    with pytest.raises(ValueError, match="unknown context feature"):
        ContextSampler([configspace.UniformFloatHyperparameter("lenght", 0.2, 2.0)], context_space=space, seed=0)
