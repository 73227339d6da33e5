"""Curriculum hooks: a selector chooses each episode's context from outside and hears every
finished episode's context and return, in `make` and per environment in `make_vec`; the two
built-ins (ADR, self-paced) move within the spec's bounds, reproducibly for a seed; misuse is a
clear error."""

from __future__ import annotations

from typing import Any, Mapping

import numpy as np
import pytest

import carl_spec as cs
from carl_spec.curriculum import AutomaticDomainRandomization, SelfPacedCurriculum


class Recorder:
    """Plays pole lengths 0.3, 0.4, ... in turn and records what it hears."""

    def __init__(self) -> None:
        self.n = 0
        self.chosen: dict[int, list[float]] = {}
        self.heard: list[tuple[int, float, float]] = []

    def select(self, env_index: int) -> dict[str, float]:
        self.n += 1
        x = round(0.2 + 0.1 * self.n, 6)
        self.chosen.setdefault(env_index, []).append(x)
        return {"pole_length": x}

    def update(self, env_index: int, context: Mapping[str, float], episode_return: float) -> None:
        self.heard.append((env_index, context["pole_length"], episode_return))

    def describe(self) -> dict[str, Any]:
        return {"chosen": self.n}


def test_each_environment_plays_the_chosen_context_and_reports_its_return() -> None:
    rec = Recorder()
    venv = cs.make_vec("cartpole", 3, curriculum=rec)
    _, infos = venv.reset(seed=0)
    assert list(infos["context"]["pole_length"]) == [0.3, 0.4, 0.5]
    assert infos["curriculum"] == {"chosen": 3}
    returns = np.zeros(3)
    for t in range(300):
        _, rewards, term, trunc, infos = venv.step(np.full(3, t % 2))
        returns += rewards
        for i in np.flatnonzero(term | trunc):
            env_index, length, ret = rec.heard[-len(np.flatnonzero(term | trunc)) + list(np.flatnonzero(term | trunc)).index(i)]
            assert (env_index, ret) == (i, returns[i])
            assert length == rec.chosen[i][-2], "the finished episode played the context chosen for it"
            returns[i] = 0.0
    assert len(rec.heard) > 10
    # The context the curriculum chose last for env 0 is the one it plays now.
    assert venv.context_info(0)["context"]["pole_length"] in rec.chosen[0][-2:]


def test_single_environment_curriculum() -> None:
    rec = Recorder()
    env = cs.make("cartpole", curriculum=rec)
    for ep in range(3):
        _, info = env.reset(seed=ep)
        assert info["context"]["pole_length"] == rec.chosen[0][-1]
        total, done = 0.0, False
        while not done:
            _, r, term, trunc, info = env.step(1)
            total += r
            done = term or trunc
        assert rec.heard[-1] == (0, rec.chosen[0][-1], total)
        assert info["curriculum"] == {"chosen": ep + 1}


def test_disabled_autoreset_chooses_at_the_masked_reset() -> None:
    rec = Recorder()
    venv = cs.make_vec("cartpole", 2, curriculum=rec, autoreset_mode="disabled")
    venv.reset(seed=1)
    _, infos = venv.reset(options={"reset_mask": np.array([False, True])})
    assert rec.chosen == {0: [0.3], 1: [0.4, 0.5]}
    assert list(infos["context"]["pole_length"])[1] == 0.5


def run_adr(seed: int) -> tuple[dict[str, Any], list[float]]:
    adr = AutomaticDomainRandomization(
        "cartpole", ["pole_length", "gravity"], delta={"pole_length": 0.05, "gravity": 0.5}, threshold=5, buffer_size=3, seed=seed
    )
    venv = cs.make_vec("cartpole", 4, curriculum=adr)
    venv.reset(seed=0)
    played = []
    for t in range(1500):
        _, _, term, trunc, infos = venv.step(np.full(4, t % 2))
        if (term | trunc).any():
            played.extend(infos["context"]["pole_length"])
    return adr.describe(), played


def test_adr_widens_within_the_bounds_reproducibly() -> None:
    a, played = run_adr(0)
    b, _ = run_adr(0)
    c, _ = run_adr(1)
    assert a == b and a != c
    lo, hi = a["ranges"]["pole_length"]
    assert 0.05 <= lo < 0.5 < hi <= 5.0, a
    assert all(0.05 <= x <= 5.0 for x in played)
    never = AutomaticDomainRandomization("cartpole", ["pole_length"], delta=0.1, threshold=1e9, buffer_size=1)
    venv = cs.make_vec("cartpole", 2, curriculum=never)
    venv.reset(seed=0)
    for t in range(300):
        venv.step(np.full(2, t % 2))
    assert never.describe()["ranges"]["pole_length"] == (0.5, 0.5), "no widening below the threshold"


def test_self_paced_moves_towards_the_target() -> None:
    sp = SelfPacedCurriculum("pendulum", target={"g": (15.0, 2.0)}, initial={"g": (10.0, 0.1)}, threshold=-1e9, episodes_per_update=2, step=0.5)
    venv = cs.make_vec("pendulum", 2, curriculum=sp)
    venv.reset(seed=0)
    for _ in range(201 * 3):  # next-step autoreset: a step per reset
        venv.step(np.zeros((2, 1), dtype=np.float32))
    d = sp.describe()["distribution"]["g"]
    assert sp.updates == 3 and d["mean"] == pytest.approx(15.0 - 5.0 / 8) and d["std"] == pytest.approx(2.0 - 1.9 / 8)


@pytest.mark.parametrize(
    ("make", "error", "message"),
    [
        (lambda: cs.make_vec("cartpole", 2, curriculum=Recorder(), autoreset_mode="same_step"), ValueError, "next_step"),
        (lambda: cs.make("cartpole", instances="cartpole/gravity_pole_length_train", curriculum=Recorder()).reset(seed=0), ValueError, "instance set"),
        (lambda: cs.make_vec("cartpole", 2, curriculum=object()), TypeError, "lacks select, update, describe"),
        (lambda: AutomaticDomainRandomization("cartpole", ["pole_lenght"], delta=0.1, threshold=1), cs.UnknownNameError, "pole_lenght"),
        (lambda: AutomaticDomainRandomization("cartpole", {"pole_length": (0.01, 1.0)}, delta=0.1, threshold=1), ValueError, "inside its bounds"),
        (lambda: AutomaticDomainRandomization("cartpole", ["pole_length"], delta=-1, threshold=1), ValueError, "delta"),
        (lambda: SelfPacedCurriculum("pendulum", target={"g": (15, 1)}, initial={"l": (1, 0.1)}, threshold=0), ValueError, "same features"),
        (lambda: SelfPacedCurriculum("pendulum", target={"g": (-3, 1)}, initial={"g": (10, 0.1)}, threshold=0), ValueError, "bounds"),
    ],
)
def test_misuse_is_a_clear_error(make: Any, error: type[BaseException], message: str) -> None:
    with pytest.raises(error, match=message):
        make()


def test_a_selected_context_outside_the_bounds_is_refused() -> None:
    class Out(Recorder):
        def select(self, env_index: int) -> dict[str, float]:
            return {"pole_length": -5.0}

    with pytest.raises(ValueError, match="pole_length = -5 is outside its bounds") as vec_error:
        cs.make_vec("cartpole", 2, curriculum=Out()).reset(seed=0)
    with pytest.raises(ValueError, match="pole_length") as env_error:
        cs.make("cartpole", curriculum=Out()).reset(seed=0)
    # The error names the curriculum that chose the context.
    for e in (vec_error, env_error):
        assert "the curriculum Out chose this context" in str(e.value)


def test_allow_out_of_bounds_lets_a_curriculum_leave_the_bounds() -> None:
    class Out(Recorder):
        def select(self, env_index: int) -> dict[str, float]:
            return {"pole_length": 7.5}

    _, info = cs.make("cartpole", curriculum=Out(), allow_out_of_bounds=True).reset(seed=0)
    assert info["context"]["pole_length"] == 7.5
    _, infos = cs.make_vec("cartpole", 2, curriculum=Out(), allow_out_of_bounds=True).reset(seed=0)
    assert list(infos["context"]["pole_length"]) == [7.5, 7.5]
