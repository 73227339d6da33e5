"""`cs.wrap` (a user's Gymnasium env made contextual from the user's spec file) and `cs.audit`
(every `affects` claim checked against that env)."""

from __future__ import annotations

import json
import pickle
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
import pytest
from gymnasium import spaces
from gymnasium.envs.classic_control.cartpole import CartPoleEnv
from gymnasium.envs.classic_control.pendulum import PendulumEnv

import carl_spec as cs

from conftest import ROOT, cli


class ToyEnv(gymnasium.Env[np.ndarray, np.ndarray]):
    """x' = x + gain * a; reward = -|x'| + bonus. `dead` is read by nothing."""

    def __init__(self) -> None:
        self.gain = 1.0
        self.dead = 1.0
        self.bonus = 0.0
        self.observation_space = spaces.Box(-np.inf, np.inf, (1,), np.float64)
        self.action_space = spaces.Box(-1.0, 1.0, (1,), np.float32)
        self.state = np.zeros(1)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        super().reset(seed=seed)
        self.state = self.np_random.uniform(-1, 1, size=1)
        return self.state.copy(), {}

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        self.state = self.state + self.gain * float(np.asarray(action).reshape(-1)[0])
        return self.state.copy(), float(-abs(self.state[0]) + self.bonus), False, False, {}


class HiddenStateToy(ToyEnv):
    """The same dynamics without a `state` attribute (the audit's trajectory mode)."""

    def __init__(self) -> None:
        super().__init__()
        self._x = self.__dict__.pop("state")

    def __getattr__(self, name: str) -> Any:
        if name == "state":
            raise AttributeError(name)
        return super().__getattribute__(name)

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[np.ndarray, dict[str, Any]]:
        gymnasium.Env.reset(self, seed=seed)
        self._x = self.np_random.uniform(-1, 1, size=1)
        return self._x.copy(), {}

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        self._x = self._x + self.gain * float(np.asarray(action).reshape(-1)[0])
        return self._x.copy(), float(-abs(self._x[0]) + self.bonus), False, False, {}


def feature(name: str, default: float, bounds: list[float | None], affects: list[str]) -> dict[str, Any]:
    return {
        "name": name,
        "type": "float",
        "default": default,
        "bounds": bounds,
        "unit": "1",
        "description": f"The toy's {name}.",
        "affects": affects,
    }


def write_spec(tmp: Path, doc: dict[str, Any], name: str = "spec.json") -> Path:
    p = tmp / name
    p.write_text(json.dumps(doc, indent=1))
    return p


def toy_spec(tmp: Path, *, bonus_claims: list[str] | None = None) -> Path:
    return write_spec(
        tmp,
        {
            "id": "toy",
            "family": "custom",
            "upstream": {"library": "tests", "id": "ToyEnv"},
            "description": "A one-dimensional toy with one live and one dead feature.",
            "observation_space": {"type": "box", "shape": [1], "low": None, "high": None, "dtype": "float64"},
            "action_space": {"type": "box", "shape": [1], "low": -1, "high": 1, "dtype": "float32"},
            "max_episode_steps": 50,
            "features": [
                feature("gain", 1.0, [0.1, 10], ["dynamics"]),
                feature("dead", 1.0, [0.1, 10], ["dynamics"]),
                feature("bonus", 0.0, [-1, 1], bonus_claims or []),
            ],
        },
    )


def test_audit_flags_the_dead_feature(tmp_path: Path) -> None:
    report = cs.audit(ToyEnv, toy_spec(tmp_path, bonus_claims=["reward"]))
    assert report.mode == "state" and report.base_states > 5
    gain, dead, bonus = (report.feature(n) for n in ("gain", "dead", "bonus"))
    assert gain.effects["dynamics"].verdict == "ok" and gain.effects["dynamics"].held
    assert gain.effects["dynamics"].differing > 0
    assert dead.effects["dynamics"].verdict == "missing_effect" and dead.effects["dynamics"].held is False
    assert dead.effects["dynamics"].differing == 0 and dead.effects["dynamics"].compared > 0
    assert bonus.effects["reward"].verdict == "ok"
    assert not report.passed
    assert len(report.contradictions) == 1 and report.contradictions[0].startswith("dead claims dynamics")
    assert "FAILED" in str(report)


def test_audit_flags_an_undeclared_effect(tmp_path: Path) -> None:
    # bonus changes the reward but claims nothing
    report = cs.audit(ToyEnv, toy_spec(tmp_path))
    bonus = report.feature("bonus")
    assert bonus.effects["reward"].verdict == "undeclared_effect"
    assert any(c.startswith("bonus changes the reward") for c in report.contradictions)


def test_audit_without_state_access_uses_trajectories(tmp_path: Path) -> None:
    report = cs.audit(HiddenStateToy, toy_spec(tmp_path, bonus_claims=["reward"]))
    assert report.mode == "trajectory"
    assert report.feature("gain").effects["dynamics"].verdict == "ok"
    assert report.feature("dead").effects["dynamics"].verdict == "missing_effect"
    assert report.feature("gain").effects["observation"].verdict == "not_applicable"


def test_audit_passes_when_every_claim_holds(tmp_path: Path) -> None:
    doc = json.loads(toy_spec(tmp_path, bonus_claims=["reward"]).read_text())
    doc["features"] = [f for f in doc["features"] if f["name"] != "dead"]
    report = cs.audit(ToyEnv, write_spec(tmp_path, doc))
    assert report.passed, str(report)


class NanRewardToy(ToyEnv):
    """The toy whose reward is NaN whenever `bonus` leaves its default."""

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = super().step(action)
        return obs, (float("nan") if self.bonus != 0.0 else reward), terminated, truncated, info


class InfObservationToy(HiddenStateToy):
    """Trajectory mode; the observation is infinite whenever `gain` leaves its default."""

    def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = super().step(action)
        return (obs * np.inf if self.gain != 1.0 else obs), reward, terminated, truncated, info


def test_audit_flags_non_finite_rewards_instead_of_reading_a_change(tmp_path: Path) -> None:
    # Issue 31 item 10: NaN != NaN made a NaN reward read as "bonus changes the reward".
    doc = json.loads(toy_spec(tmp_path).read_text())
    doc["features"] = [f for f in doc["features"] if f["name"] != "dead"]
    spec = write_spec(tmp_path, doc)
    # The finite toy: bonus's (undeclared) effect on the reward is measured.
    assert cs.audit(ToyEnv, spec).feature("bonus").effects["reward"].verdict == "undeclared_effect"
    report = cs.audit(NanRewardToy, spec)
    bonus = report.feature("bonus")
    assert bonus.effects["reward"].measured == "unchanged" and bonus.effects["reward"].differing == 0
    assert report.contradictions == []
    assert report.non_finite and all(n.startswith("bonus = ") and "reward nan" in n for n in report.non_finite)
    assert not report.passed
    assert "non-finite output: bonus = " in str(report) and "FAILED: non-finite output under" in str(report)


def test_audit_flags_non_finite_observations_in_trajectory_mode(tmp_path: Path) -> None:
    report = cs.audit(InfObservationToy, toy_spec(tmp_path, bonus_claims=["reward"]))
    assert report.mode == "trajectory"
    assert report.non_finite and all(n.startswith("gain = ") and "observation inf" in n for n in report.non_finite)
    assert report.feature("gain").effects["dynamics"].differing == 0  # never compared
    assert not report.passed


def test_audit_flags_non_finite_output_at_the_default_context(tmp_path: Path) -> None:
    class AlwaysNan(ToyEnv):
        def step(self, action: np.ndarray) -> tuple[np.ndarray, float, bool, bool, dict[str, Any]]:
            obs, _, terminated, truncated, info = super().step(action)
            return obs, float("nan"), terminated, truncated, info

    report = cs.audit(AlwaysNan, toy_spec(tmp_path, bonus_claims=["reward"]))
    assert report.non_finite[0].startswith("default context: reward nan")
    assert not report.passed



# -- wrap ------------------------------------------------------------------------------------


def test_wrap_applies_contexts_and_refuses_bad_ones(tmp_path: Path) -> None:
    spec = toy_spec(tmp_path)
    env = cs.wrap(ToyEnv, spec, context={"gain": 3.0})
    obs, info = env.reset(seed=1)
    assert env.unwrapped.gain == 3.0 and info["context"] == {"gain": 3.0, "dead": 1.0, "bonus": 0.0}
    nxt, *_ = env.step(np.array([0.5], dtype=np.float32))
    assert nxt[0] == pytest.approx(obs[0] + 1.5)
    with pytest.raises(ValueError, match="gain") as oob:
        cs.wrap(ToyEnv, spec, context={"gain": 50.0})  # outside [0.1, 10]
    # wrap has no allow_out_of_bounds=: the message suggests what works (issue 31 item 13)
    assert "allow_out_of_bounds" not in str(oob.value) and f"widen its bounds in {spec}" in str(oob.value)
    with pytest.raises(cs.UnknownNameError, match=r"did you mean .gain.\?\); valid names: gain, dead, bonus"):
        cs.wrap(ToyEnv, spec, context={"gian": 2.0})
    with pytest.raises(ValueError, match="no attribute for feature"):
        cs.wrap(ToyEnv, spec, attributes={"gain": "nope"})
    with pytest.raises(ValueError, match="not both"):
        cs.wrap(ToyEnv, spec, attributes={"gain": "gain"}, apply=lambda env, ctx: None)
    with pytest.raises(ValueError, match="needs instance="):
        cs.wrap(ToyEnv, spec, selection="static")


def test_wrap_refuses_a_feature_given_twice_by_alias_and_name(tmp_path: Path) -> None:
    doc = json.loads(toy_spec(tmp_path).read_text())
    doc["features"][0]["aliases"] = ["g", "k"]
    spec = write_spec(tmp_path, doc)
    assert cs.wrap(ToyEnv, spec, context={"g": 2.0}).reset(seed=0)[1]["context"]["gain"] == 2.0
    for ctx in ({"g": 2.0, "gain": 3.0}, {"gain": 3.0, "g": 3.0}, {"g": 2.0, "k": 2.0}):
        first, second = list(ctx)
        with pytest.raises(ValueError, match=f'gives feature gain twice, as "{first}" and "{second}"'):
            cs.wrap(ToyEnv, spec, context=ctx)


def test_wrap_validates_the_spec_with_located_errors(tmp_path: Path) -> None:
    doc = json.loads(toy_spec(tmp_path).read_text())
    doc["features"][0]["default"] = 100.0  # outside its own bounds
    bad = write_spec(tmp_path, doc, "bad.json")
    with pytest.raises(ValueError, match=r"bad\.json:\d+:\d+"):
        cs.wrap(ToyEnv, bad)
    assert not cs.validate(bad).valid


def test_wrap_obs_context_and_pickling(tmp_path: Path) -> None:
    env = cs.wrap(ToyEnv, toy_spec(tmp_path), context={"gain": 2.0}, obs_context=["gain"])
    assert env.observation_space.shape == (2,)
    obs, _ = env.reset(seed=0)
    assert obs[1] == 2.0 and obs in env.observation_space
    clone = pickle.loads(pickle.dumps(env))
    assert np.array_equal(clone.reset(seed=0)[0], obs)
    with pytest.raises(TypeError, match="factory"):
        pickle.dumps(cs.wrap(ToyEnv(), toy_spec(tmp_path)))


# -- wrap over Gymnasium's own environments equals cs.make ----------------------------------------


def user_copy(tmp: Path, env: str, new_id: str, *, freeze: bool = True) -> Path:
    """The bundled spec of `env` as a user's spec under another id (and its sets frozen there)."""
    doc = json.loads((ROOT / "specs" / f"{env}.json").read_text())
    doc["id"] = new_id
    doc.pop("aliases", None)
    doc.pop("$schema", None)
    for f in doc["features"]:
        f.pop("aliases", None)
    path = write_spec(tmp, doc, f"{new_id}.json")
    for name in doc.get("instance_sets", {}) if freeze else []:
        cli("--specs", str(tmp), "freeze", f"{new_id}/{name}")
    return path


def cartpole_apply(env: gymnasium.Env[Any, Any], ctx: dict[str, Any]) -> None:
    """Gymnasium's CartPole caches total_mass and polemass_length at construction."""
    u = env.unwrapped
    u.gravity, u.masscart, u.masspole = ctx["gravity"], ctx["masscart"], ctx["masspole"]
    u.length, u.force_mag, u.tau = ctx["pole_length"], ctx["force_magnifier"], ctx["update_interval"]
    u.total_mass = u.masspole + u.masscart
    u.polemass_length = u.masspole * u.length


def rollout(env: gymnasium.Env[Any, Any], seeds: list[int | None], steps: int = 30) -> list[Any]:
    out = []
    for s in seeds:
        obs, info = env.reset(seed=s)
        out.append((np.asarray(obs, dtype=np.float64).round(5).tolist(), info.get("instance_id"), info["context"]))
        for t in range(steps):
            discrete = isinstance(env.action_space, spaces.Discrete)
            obs, r, term, trunc, _ = env.step(t % 2 if discrete else np.array([t % 3 - 1.0], dtype=np.float32))
            out.append(np.asarray(obs, dtype=np.float64).round(5).tolist())
            if term or trunc:
                break
    return out


def test_wrapped_gymnasium_cartpole_equals_cs_make(tmp_path: Path) -> None:
    spec = user_copy(tmp_path, "cartpole", "my_cartpole")
    ctx = {"pole_length": 0.9, "masscart": 2.0}
    mine = cs.wrap(lambda: CartPoleEnv(), spec, context=ctx, apply=cartpole_apply)
    ref = cs.make("cartpole", context=ctx)
    seeds = [3, None, None, 7, None]
    assert rollout(mine, seeds) == rollout(ref, seeds)


def test_audit_finds_cartpoles_cached_masses(tmp_path: Path) -> None:
    """Setting masscart on Gymnasium's CartPoleEnv by attribute does nothing (total_mass is
    computed in __init__): exactly the dead-feature bug the audit exists for."""
    spec = user_copy(tmp_path, "cartpole", "my_cartpole")
    names = {"pole_length": "length", "force_magnifier": "force_mag", "update_interval": "tau"}
    naive = cs.audit(CartPoleEnv, spec, attributes=names, seeds=2, steps=20)
    assert naive.feature("masscart").effects["dynamics"].verdict == "missing_effect"
    assert naive.feature("gravity").effects["dynamics"].verdict == "ok"
    fixed = cs.audit(CartPoleEnv, spec, apply=cartpole_apply, seeds=2, steps=20)
    assert fixed.passed, str(fixed)


def pendulum_apply(env: gymnasium.Env[Any, Any], ctx: dict[str, Any]) -> None:
    for k, v in ctx.items():
        setattr(env.unwrapped, k, v)


@pytest.mark.parametrize("selection", ["round_robin", "random"])
def test_wrapped_pendulum_set_selection_and_seeding_equal_cs_make(tmp_path: Path, selection: str) -> None:
    spec = user_copy(tmp_path, "pendulum", "my_pendulum")
    mine = cs.wrap(PendulumEnv, spec, instances="q1_g_sigma_0_5", selection=selection)
    ref = cs.make("pendulum", instances="pendulum/q1_g_sigma_0_5", selection=selection)
    seeds = [11, None, None, 4, None, 99, None]
    a, b = rollout(mine, seeds, 20), rollout(ref, seeds, 20)
    ids = [x[1] for x in a if isinstance(x, tuple)]
    assert ids == [x[1] for x in b if isinstance(x, tuple)] and len(set(ids)) > 2
    for x, y in zip(a, b):
        if isinstance(x, tuple):
            assert x[2] == pytest.approx(y[2])
            x = x[0]
            y = y[0]
        np.testing.assert_allclose(x, y, atol=2e-5)


def test_wrapped_pendulum_distribution_draws_equal_cs_make(tmp_path: Path) -> None:
    spec = user_copy(tmp_path, "pendulum", "my_pendulum")
    mine = cs.wrap(PendulumEnv, spec, distribution="q1_l_sigma_0_5")
    ref = cs.make("pendulum", distribution="q1_l_sigma_0_5")
    for s in [5, None, None, 6]:
        _, i1 = mine.reset(seed=s)
        _, i2 = ref.reset(seed=s)
        assert i1["context_seed"] == i2["context_seed"]
        assert i1["context"] == pytest.approx(i2["context"])
        assert mine.unwrapped.l == i1["context"]["l"]


def test_wrap_obs_context_names_are_checked(tmp_path: Path) -> None:
    with pytest.raises(cs.UnknownNameError, match="features: gain, dead, bonus"):
        cs.wrap(ToyEnv, toy_spec(tmp_path), obs_context=["gian"])
    env = cs.wrap(ToyEnv, toy_spec(tmp_path), obs_context=True)
    assert env.observation_space.shape == (4,)


def test_wrap_names_the_freeze_command_for_an_unfrozen_set(tmp_path: Path) -> None:
    spec = user_copy(tmp_path, "pendulum", "my_pendulum", freeze=False)
    with pytest.raises(ValueError, match=f"carl-spec --specs {tmp_path} freeze my_pendulum/q1_g_sigma_0_5"):
        cs.wrap(PendulumEnv, spec, instances="q1_g_sigma_0_5")
    with pytest.raises(cs.UnknownNameError, match="sets of my_pendulum: g_l_extrapolation, .*q1_dt_sigma_0_1"):
        cs.wrap(PendulumEnv, spec, instances="nope")


@pytest.mark.parametrize("redraw", ["episode", "step"])
def test_wrap_context_noise_equals_cs_make(tmp_path: Path, redraw: str) -> None:
    """The same noise option as cs.make, drawn by the library's noise code from the same seed:
    the wrapped env observes exactly what cs.make's observes, and pickles with it."""
    spec = user_copy(tmp_path, "pendulum", "my_pendulum")
    kw: dict[str, Any] = dict(obs_context=["g", "m"], context_noise={"g": "10%", "m": 0.2}, context_noise_redraw=redraw)
    mine = cs.wrap(PendulumEnv, spec, instances="q1_g_sigma_0_5", selection="random", **kw)
    ref = cs.make("pendulum", instances="pendulum/q1_g_sigma_0_5", selection="random", **kw)
    assert mine.observation_space.low[-2] == -np.inf and mine.observation_space.high[-2] == np.inf
    # The context part is the spec's declared bounds in both; cs.make also unbounds the runtime's
    # velocity (max_speed moves it, whatever the source), the user's env keeps its own ±8.
    keep = [0, 1, 3, 4]
    np.testing.assert_array_equal(mine.observation_space.low[keep], ref.observation_space.low[keep])
    np.testing.assert_array_equal(mine.observation_space.high[keep], ref.observation_space.high[keep])
    assert mine.observation_space.high[2] == 8 and ref.observation_space.high[2] == np.inf
    seen = []
    for seed in [3, None, 8, None]:
        (o1, i1), (o2, i2) = mine.reset(seed=seed), ref.reset(seed=seed)
        for t in range(6):
            assert i1["observed_context"] == i2["observed_context"], (seed, t)
            assert i1["context"] == pytest.approx(i2["context"]), "the env keeps the true context"
            np.testing.assert_array_equal(o1[-2:], o2[-2:])
            assert o1[-2] == np.float32(i1["observed_context"]["g"]) != np.float32(i1["context"]["g"])
            seen.append(float(o1[-2]))
            a = np.array([t % 3 - 1.0], dtype=np.float32)
            o1, *_, i1 = mine.step(a)
            o2, *_, i2 = ref.step(a)
    # Per episode: one measurement per episode (4 distinct); per step: a fresh one every step.
    assert len(set(seen)) == (4 if redraw == "episode" else len(seen))
    clone = pickle.loads(pickle.dumps(mine))
    np.testing.assert_array_equal(clone.reset(seed=5)[0], mine.reset(seed=5)[0])


def test_wrap_context_noise_is_checked(tmp_path: Path) -> None:
    with pytest.raises(ValueError, match="context_noise applies to observed context features"):
        cs.wrap(ToyEnv, toy_spec(tmp_path), context_noise={"gain": 0.1})
    with pytest.raises(ValueError, match="the feature is not observed"):
        cs.wrap(ToyEnv, toy_spec(tmp_path), obs_context=["gain"], context_noise={"bonus": 0.1})
    with pytest.raises(ValueError, match="relative noise on a feature whose default is 0"):
        cs.wrap(ToyEnv, toy_spec(tmp_path), obs_context=["bonus"], context_noise={"bonus": "10%"})
    with pytest.raises(ValueError, match="context_noise_redraw must be"):
        cs.wrap(ToyEnv, toy_spec(tmp_path), obs_context=["gain"], context_noise={"gain": 0.1}, context_noise_redraw="often")
