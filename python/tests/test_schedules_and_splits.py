"""Contexts that change within an episode (`schedules=`) and the split kinds' instance sets, as a
Python user meets them: the same values in `make` and `make_vec`, the current value in `info`,
clear errors for schedules that cannot work, and the protocol's sets loadable and evaluable."""

from __future__ import annotations

import numpy as np
import pytest

import carl_spec as cs

SINE = {"g": {"kind": "sine", "amplitude": 2.0, "period": 8}}


def test_make_reports_the_current_value_and_observes_it() -> None:
    env = cs.make("pendulum", schedules={"g": {"kind": "linear", "to": 15, "over": 4}}, obs_context=["g"])
    obs, info = env.reset(seed=0)
    assert info["context"]["g"] == 10.0 and obs[-1] == 10.0
    seen = []
    for _ in range(5):
        obs, _, _, _, info = env.step(np.array([0.0]))
        assert obs[-1] == np.float32(info["context"]["g"])
        seen.append(info["context"]["g"])
    assert seen == [11.25, 12.5, 13.75, 15.0, 15.0]
    _, info = env.reset(seed=1)
    assert info["context"]["g"] == 10.0, "every episode starts from the context's own value"


def test_make_vec_equals_make_under_a_schedule() -> None:
    walk = {"g": {"kind": "random_walk", "std": 0.3, "low": 8.0, "high": 12.0}}
    venv = cs.make_vec("pendulum", 3, schedules=walk, instances="pendulum/g_l_train", obs_context=["g", "l"])
    envs = [cs.make("pendulum", schedules=walk, instances="pendulum/g_l_train", obs_context=["g", "l"]) for _ in range(3)]
    obs, infos = venv.reset(seed=4)
    for i, e in enumerate(envs):
        o, info = e.reset(seed=4 + i)
        np.testing.assert_array_equal(obs[i], o)
    for t in range(60):
        actions = np.full((3, 1), np.sin(t), dtype=np.float32)
        obs, _, _, _, infos = venv.step(actions)
        for i, e in enumerate(envs):
            o, _, _, _, info = e.step(actions[i])
            np.testing.assert_array_equal(obs[i], o)
            assert infos["context"]["g"][i] == info["context"]["g"]
    assert len(set(infos["context"]["g"])) == 3, "each environment walks on its own stream"


def test_random_walks_repeat_with_the_seed() -> None:
    def run(seed: int) -> list[float]:
        env = cs.make("cartpole", schedules={"gravity": {"kind": "random_walk", "std": 0.5, "low": 5.0, "high": 15.0}})
        env.reset(seed=seed)
        return [env.step(0)[4]["context"]["gravity"] for _ in range(8)]

    assert run(3) == run(3)
    assert run(3) != run(4)


@pytest.mark.parametrize(
    ("schedules", "message"),
    [
        ({"g": {"kind": "linear", "to": -1, "over": 3}}, "outside the bounds"),
        ({"g": {"kind": "wobble"}}, "unknown variant"),
        ({"g": {"kind": "step", "at": 1.5, "to": 2}}, "expected u64"),
        ({"g": 5}, "must be a dict"),
        ({"g": {"kind": "sine", "amplitude": float("nan"), "period": 3}}, "finite"),
        ({"gg": {"kind": "step", "at": 1, "to": 2}}, "did you mean"),
        ([1, 2], "must be a dict"),
    ],
)
def test_bad_schedules_raise_value_errors_naming_the_problem(schedules: object, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        cs.make("pendulum", schedules=schedules)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=message):
        cs.make_vec("pendulum", 2, schedules=schedules)  # type: ignore[arg-type]


def test_a_runtime_that_fixes_its_context_refuses_schedules() -> None:
    with pytest.raises(ValueError, match="fixes the context when it is built"):
        cs.make("lunar_lander", schedules={"GRAVITY_Y": {"kind": "step", "at": 3, "to": -2.0}})


@pytest.mark.parametrize(
    "region",
    [
        "cartpole/gravity_pole_length",
        "pendulum/g_l",
        "acrobot/link_length_1_link_mass_1",
        "mountain_car/force_gravity",
        "mountain_car_continuous/max_speed_power",
        "lunar_lander/gravity_y_main_engine_power",
    ],
)
def test_every_shipped_protocol_has_its_five_sets(region: str) -> None:
    sizes = {"_train": 25, "_train_single": 10, "_interpolation": 16, "_extrapolation_single": 12, "_extrapolation": 12}
    for suffix, n in sizes.items():
        s = cs.instances.load(region + suffix)
        assert len(s.contexts) == n, suffix
    test = cs.instances.load(region + "_extrapolation")
    assert set(test.splits) == {"out_of_distribution"}
    assert set(cs.instances.load(region + "_interpolation").splits) == {"in_distribution"}


def test_train_and_extrapolation_sets_evaluate_side_by_side() -> None:
    def policy(obs: np.ndarray) -> np.ndarray:
        return np.zeros(len(obs), dtype=np.int64)

    train = cs.evaluate(policy, instances="cartpole/gravity_pole_length_train", episodes=1, seed=0)
    test = cs.evaluate(policy, instances="cartpole/gravity_pole_length_extrapolation", episodes=1, seed=0)
    assert len(train.instances) == 25 and len(test.instances) == 12
    assert {i.name for i in test.instances} >= {"gravity+1,pole_length+1", "gravity-0.25,pole_length-0.25"}
