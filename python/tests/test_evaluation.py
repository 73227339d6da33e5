"""carl_spec.evaluate and carl_spec.report: determinism, provenance, the estimators (by hand and
against rliable where it is installed), and the errors for bad input."""

from __future__ import annotations

import dataclasses
import json
import sys
from typing import Any

import numpy as np
import pytest

import carl_spec as cs
from carl_spec import _core
from carl_spec.evaluation import (
    Episode,
    Episodes,
    EvaluationResult,
    aggregate_iqm,
    aggregate_mean,
    aggregate_median,
    episode_seed,
    score_distribution,
    stratified_resamples,
)
from carl_spec.evaluation._stats import bootstrap, percentile_interval

PLANETS = "lunar_lander/landing_in_space_test_planets"
TRAIN = "lunar_lander/landing_in_space_train"


def constant(action: int) -> Any:
    return lambda obs: np.full(len(obs), action, dtype=np.int64)


def heuristic(obs: np.ndarray) -> np.ndarray:
    """A crude deterministic lander: fire the main engine when falling fast, else steer upright."""
    a = np.zeros(len(obs), dtype=np.int64)
    a[obs[:, 4] > 0.1] = 3
    a[obs[:, 4] < -0.1] = 1
    a[obs[:, 3] < -0.3] = 2
    return a


def zeros_box(obs: np.ndarray) -> np.ndarray:
    return np.zeros((len(obs), 1), dtype=np.float32)


@pytest.fixture(scope="module")
def planets() -> EvaluationResult:
    return cs.evaluate(heuristic, instances=PLANETS, episodes=3, seed=7, num_envs=4)


# ---------------------------------------------------------------------------------------------
# evaluate


def test_every_instance_gets_its_episodes(planets: EvaluationResult) -> None:
    iset = cs.instances.load(PLANETS)
    assert [i.name for i in planets.instances] == iset.names
    assert [i.split for i in planets.instances] == iset.splits
    assert [i.context for i in planets.instances] == iset.contexts
    assert [(e.instance, e.episode) for e in planets.episodes] == [(k, e) for k in range(6) for e in range(3)]
    for e in planets.episodes:
        assert e.seed == episode_seed(7, e.instance, e.episode, 6)
        assert e.seed % 6 == e.instance
        assert e.terminated != e.truncated and e.length > 0
    assert len(planets.summary()) == 6
    s = planets.summary()[3]
    assert s.instance.name == "Mars" and s.episodes == 3
    assert s.mean == pytest.approx(planets.returns("Mars").mean())
    assert planets.returns(3).tolist() == planets.returns("Mars").tolist()
    assert planets.scores.shape == (6,)
    rows = planets.records()
    assert len(rows) == 18
    assert rows[9] == {**planets.episodes[9].to_dict(), "name": "Mars", "split": "in_distribution",
                       "context": iset.contexts[3]}


def test_provenance(planets: EvaluationResult) -> None:
    p = planets.provenance
    iset = cs.instances.load(PLANETS)
    assert p["source"] == {"kind": "instances", "name": PLANETS, "content_hash": iset.content_hash}
    assert p["env"] == "lunar_lander"
    assert p["env_version"] == _core.VERSIONS["lunar_lander"]
    assert p["gym_id"] == cs.gym_id("lunar_lander")
    assert p["carl_spec_version"] == cs.__version__
    assert p["seed"] == 7 and p["episodes"] == 3 and p["num_envs"] == 4
    assert "SplitMix64" in p["seed_rule"]
    assert p["policy"] == "function test_evaluation.heuristic"


def test_episode_seeds() -> None:
    from carl_spec.evaluation._run import _mix

    # SplitMix64's first output from state 0 (its reference implementation's known answer).
    assert int(_mix(np.array([0], dtype=np.uint64))[0]) == 0xE220A8397B1DCDAF
    assert episode_seed(2**64 + 5, 1, 2, None) == episode_seed(5, 1, 2, None) < 2**63
    assert {episode_seed(0, 4, e, 6) % 6 for e in range(50)} == {4}
    assert len({episode_seed(0, k, e, None) for k in range(30) for e in range(30)}) == 900


def test_the_binding_derives_the_same_seeds() -> None:
    from carl_spec.evaluation._run import episode_seeds

    rng = np.random.default_rng(0)
    inst, eps = rng.integers(0, 50, 500), rng.integers(0, 10**6, 500)
    for seed in (0, 7, 2**63 + 5, 2**64 - 1):
        for n in (None, 50):
            assert np.array_equal(_core.episode_seeds(seed, inst, eps, n), episode_seeds(seed, inst, eps, n))
    with pytest.raises(ValueError, match="negative"):
        _core.episode_seeds(0, np.array([-1]), np.array([0]), None)
    with pytest.raises(ValueError, match="2 instances for 1 episodes"):
        _core.episode_seeds(0, np.array([1, 2]), np.array([0]), None)


def test_play_returns_the_jobs_in_the_order_asked_and_refuses_a_bad_order() -> None:
    venv = cs.make_vec("cartpole", 2, autoreset_mode="disabled")
    seeds = np.arange(5, dtype=np.uint64)
    act = constant(1)
    plain = venv._core.play(act, lambda a: a, seeds)
    back = venv._core.play(act, lambda a: a, seeds, None, False, np.arange(5)[::-1].copy())
    for a, b in zip(plain[:4], back[:4]):
        assert b.tolist() == a.tolist()[::-1]
    assert back[4] == plain[4][::-1] == ["failed"] * 5
    for order in ([0, 1, 2, 3], [0, 1, 2, 3, 3], [0, 1, 2, 3, 5], [-1, 0, 1, 2, 3]):
        with pytest.raises(ValueError, match="order"):
            venv._core.play(act, lambda a: a, seeds, None, False, np.array(order, dtype=np.int64))
    venv.close()


def test_same_seed_same_results_any_batch(planets: EvaluationResult) -> None:
    again = cs.evaluate(heuristic, instances=PLANETS, episodes=3, seed=7, num_envs=4)
    assert again.to_dict() == planets.to_dict()
    for n in (1, 5, 18):
        other = cs.evaluate(heuristic, instances=PLANETS, episodes=3, seed=7, num_envs=n, threads=2 if n > 1 else 1)
        assert other.episodes == planets.episodes, f"num_envs={n}"
    different = cs.evaluate(heuristic, instances=PLANETS, episodes=3, seed=8, num_envs=4)
    assert [e.return_ for e in different.episodes] != [e.return_ for e in planets.episodes]


def test_an_episode_is_the_single_env_episode_of_its_seed(planets: EvaluationResult) -> None:
    for rec in planets.episodes[::5]:
        env = cs.make("lunar_lander", instances=PLANETS)
        obs, info = env.reset(seed=rec.seed)
        assert info["instance_id"] == rec.instance
        total, steps, done = 0.0, 0, False
        while not done:
            obs, r, term, trunc, _ = env.step(int(heuristic(obs[None])[0]))
            total += float(r)
            steps += 1
            done = term or trunc
        assert (total, steps, term, trunc) == (rec.return_, rec.length, rec.terminated, rec.truncated)


def test_json_round_trip(planets: EvaluationResult, tmp_path: Any) -> None:
    text = planets.to_json()
    back = EvaluationResult.from_json(text)
    assert back == planets
    assert back.to_json() == text
    doc = json.loads(text)
    assert doc["format"] == "carl-spec-evaluation/1"
    assert doc["episodes"][0]["return"] == planets.episodes[0].return_
    assert doc["summary"][3]["name"] == "Mars"
    planets.to_json(tmp_path / "r.json")
    assert EvaluationResult.load(tmp_path / "r.json") == planets
    with pytest.raises(ValueError, match="not a carl-spec evaluation"):
        EvaluationResult.from_json('{"format": "other"}')
    assert "| 3 | Mars | in_distribution |" in planets.table()
    assert "Mars" not in repr(planets) and "6 instances, 18 episodes" in repr(planets)


def test_episodes_are_columns(planets: EvaluationResult) -> None:
    eps = planets.episodes
    assert isinstance(eps, Episodes) and len(eps) == 18
    assert eps.return_.dtype == np.float64 and eps.seed.dtype == np.uint64 and eps.terminated.dtype == np.bool_
    rows = list(eps)
    assert all(isinstance(e, Episode) for e in rows) and eps[0] == rows[0] and eps[-2:] == rows[-2:]
    # Columns and rows agree field by field, and a result made from rows equals the columnar one.
    assert [e.return_ for e in rows] == eps.return_.tolist() and [e.seed for e in rows] == eps.seed.tolist()
    assert eps == rows and rows == list(eps)
    again = EvaluationResult(provenance=planets.provenance, instances=planets.instances, episodes=rows)
    assert again == planets and again.summary() == planets.summary()
    # Aggregates follow the episodes whatever order they are listed in.
    shuffled = EvaluationResult(provenance=planets.provenance, instances=planets.instances, episodes=rows[::-1])
    assert np.array_equal(shuffled.scores, planets.scores)
    assert np.array_equal(shuffled.returns("Mars"), planets.returns("Mars")[::-1])
    with pytest.raises(ValueError, match="differ in length"):
        Episodes([0, 1], [0], [1, 2], [0.0, 1.0], [1, 1], [True, True], [False, False])
    with pytest.raises(ValueError, match="refers to instance 99"):
        EvaluationResult(planets.provenance, planets.instances, [rows[0]._replace(instance=99), *rows[1:]])
    with pytest.raises(ValueError, match="instance 0 has no episode"):
        EvaluationResult(planets.provenance, planets.instances, [e for e in rows if e.instance != 0])


def test_distribution_draws() -> None:
    a = cs.evaluate(zeros_box, "pendulum", distribution="q1_g_sigma_0_5", draws=5, seed=3, num_envs=2)
    b = cs.evaluate(zeros_box, "pendulum", distribution="q1_g_sigma_0_5", draws=5, seed=3, num_envs=5)
    assert a.episodes == b.episodes and a.instances == b.instances
    assert a.provenance["source"] == {"kind": "distribution", "name": "q1_g_sigma_0_5", "draws": 5}
    assert a.provenance["episodes"] is None
    assert [set(i.context) for i in a.instances] == [{"g"}] * 5
    assert len({i.context["g"] for i in a.instances}) == 5
    for rec, inst in zip(a.episodes, a.instances):
        env = cs.make("pendulum", distribution="q1_g_sigma_0_5")
        _, info = env.reset(seed=rec.seed)
        assert info["context"]["g"] == inst.context["g"]
        assert int(info["context_seed"]) == rec.context_seed
    assert EvaluationResult.from_json(a.to_json()) == a


def test_fixed_and_default_context() -> None:
    r = cs.evaluate(zeros_box, "pendulum", context={"g": 5.0}, episodes=3, seed=0)
    assert r.provenance["source"] == {"kind": "context", "context": {"g": 5.0}}
    assert len(r.instances) == 1 and r.instances[0].context == {"g": 5.0}
    assert [e.length for e in r.episodes] == [200, 200, 200]
    d = cs.evaluate(zeros_box, "pendulum", episodes=2)
    assert d.provenance["source"] == {"kind": "context", "context": {}}
    env = cs.make("pendulum", context={"g": 5.0})
    obs, _ = env.reset(seed=r.episodes[1].seed)
    total = 0.0
    for _ in range(200):
        obs, rew, *_ = env.step(np.zeros(1, dtype=np.float32))
        total += float(rew)
    assert total == r.episodes[1].return_


def test_visible_context_and_options() -> None:
    seen = []

    def policy(obs: np.ndarray) -> np.ndarray:
        seen.append(obs.shape)
        return np.zeros(len(obs), dtype=np.int64)

    r = cs.evaluate(policy, instances=PLANETS, episodes=1, obs_context=["GRAVITY_Y"], num_envs=3)
    assert seen[0] == (3, 9)
    assert r.provenance["obs_context"] == ["GRAVITY_Y"]
    c = cs.evaluate(lambda o: np.zeros((len(o), 2), np.float32), instances=PLANETS, episodes=1, options={"continuous": True})
    assert c.provenance["options"] == {"continuous": True}


def test_outcomes_from_the_environment() -> None:
    """Each episode records the environment's own outcome (`infos["outcome"]` at its last step:
    LunarLander's landed / crashed / out_of_view, timed_out at the limit), the same as a scalar
    env's `info["outcome"]` for that episode; the summary and the report count them."""
    r = cs.evaluate(heuristic, instances=PLANETS, episodes=3, seed=7, num_envs=4)
    for e in r.episodes:
        assert e.outcome in ("landed", "crashed", "out_of_view", "timed_out")
        assert (e.outcome == "timed_out") == e.truncated
    assert {e.outcome for e in r.episodes} >= {"landed", "crashed"}
    env = cs.make("lunar_lander", instances=PLANETS)
    for e in r.episodes[:4]:
        obs, _ = env.reset(seed=e.seed)
        done = False
        while not done:
            obs, _, term, trunc, info = env.step(int(heuristic(obs[None])[0]))
            done = term or trunc
        assert info["outcome"] == e.outcome
    for s in r.summary():
        eps = [e for e in r.episodes if e.instance == s.instance.id]
        assert s.outcomes == {o: sum(e.outcome == o for e in eps) for o in sorted({e.outcome for e in eps} - {None})}
    assert EvaluationResult.from_json(r.to_json()) == r
    rep = cs.report(test=[r], reps=10)
    assert rep.groups["test"]["per_instance"][0]["outcomes"] == r.summary()[0].outcomes
    assert "outcomes" in rep.to_markdown()


class FakeModel:
    """What evaluate needs of a Stable-Baselines3 model."""

    def __init__(self, shape: tuple[int, ...] = (8,)) -> None:
        import gymnasium

        self.observation_space = gymnasium.spaces.Box(-np.inf, np.inf, shape)
        self.calls: list[bool] = []

    def predict(self, obs: np.ndarray, deterministic: bool = False) -> tuple[np.ndarray, None]:
        self.calls.append(deterministic)
        return heuristic(obs), None


def test_model_with_predict(planets: EvaluationResult) -> None:
    m = FakeModel()
    r = cs.evaluate(m, instances=PLANETS, episodes=3, seed=7, num_envs=4)
    assert r.episodes == planets.episodes
    assert set(m.calls) == {True}
    assert r.provenance["policy"].startswith("model ") and r.provenance["deterministic"] is True
    cs.evaluate(m, instances=PLANETS, episodes=1, deterministic=False)
    assert m.calls[-1] is False
    with pytest.raises(ValueError, match=r"observes shape \(9,\).*shape \(8,\).*obs_context"):
        cs.evaluate(FakeModel((9,)), instances=PLANETS, episodes=1)


# ---------------------------------------------------------------------------------------------
# evaluate: bad input


@pytest.mark.parametrize(
    ("policy", "message"),
    [
        (lambda o: np.zeros(len(o) + 1, np.int64), r"has shape \(5,\); Discrete\(4\) takes one integer per environment, shape \(4,\)"),
        (lambda o: np.zeros((len(o), 1), np.int64), r"has shape \(4, 1\).*reshape\(-1\)"),
        (lambda o: np.zeros(len(o), np.float32), r"are float32; Discrete\(4\) takes integers \(for scores"),
        (lambda o: np.zeros(len(o), bool), r"are bool; Discrete\(4\) takes integers"),
        (lambda o: np.full(len(o), 4), r"environment 0 got action 4, outside Discrete\(4\) \(valid: 0..3\)"),
        (lambda o: ["a"] * len(o), r"are <U1; Discrete\(4\) takes integers"),
    ],
)
def test_discrete_actions_that_do_not_fit(policy: Any, message: str) -> None:
    with pytest.raises(ValueError, match=r"evaluate\(lunar_lander\): the policy's first batch of actions:? " + message):
        cs.evaluate(policy, instances=PLANETS, episodes=1, num_envs=4)


@pytest.mark.parametrize(
    ("policy", "message"),
    [
        (lambda o: np.zeros(len(o), np.float32), r"has shape \(3,\); Box\(-2.0, 2.0, \(1,\), float32\) takes shape \(3, 1\)"),
        (lambda o: np.full((len(o), 1), 2.5), r"environment 0 got 2.5 for component 0, outside the action space's bounds \[-2, 2\]"),
        (lambda o: np.full((len(o), 1), np.nan), r"environment 0 got a NaN or infinite action"),
        (lambda o: np.zeros((len(o), 1), bool), r"are bool; Box.* takes real numbers"),
    ],
)
def test_box_actions_that_do_not_fit(policy: Any, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        cs.evaluate(policy, "pendulum", episodes=3, num_envs=3)


def test_bad_arguments_name_the_problem() -> None:
    with pytest.raises(ValueError, match="belongs to lunar_lander, not to cartpole"):
        cs.evaluate(constant(0), "cartpole", instances=PLANETS)
    with pytest.raises(ValueError, match="one of instances=, distribution= or context="):
        cs.evaluate(constant(0), "pendulum", instances="pendulum/q1_g_sigma_0_5", distribution="q1_g_sigma_0_5")
    with pytest.raises(ValueError, match="has no distribution 'nope'; its distributions: .*q1_g_sigma_0_5"):
        cs.evaluate(zeros_box, "pendulum", distribution="nope")
    with pytest.raises(ValueError, match="pass draws="):
        cs.evaluate(zeros_box, "pendulum", distribution="q1_g_sigma_0_5", episodes=3)
    with pytest.raises(ValueError, match="episodes must be a positive integer, got 0"):
        cs.evaluate(constant(0), instances=PLANETS, episodes=0)
    with pytest.raises(ValueError, match="seed must be a non-negative integer"):
        cs.evaluate(constant(0), instances=PLANETS, seed=-1)
    with pytest.raises(ValueError, match="num_envs must be a positive integer"):
        cs.evaluate(constant(0), instances=PLANETS, num_envs=0)
    with pytest.raises(ValueError, match="needs its environment"):
        cs.evaluate(constant(0), instances="landing_in_space_test_planets")
    with pytest.raises(ValueError, match="say what to evaluate"):
        cs.evaluate(constant(0))
    with pytest.raises(TypeError, match="the policy must be a function of a batch of observations"):
        cs.evaluate(42, instances=PLANETS, episodes=1)
    with pytest.raises(KeyError):
        cs.evaluate(constant(0), instances="lunar_lander/no_such_set")
    r = cs.evaluate(heuristic, "lunar_lander", instances="landing_in_space_test_planets", episodes=1)
    assert r.provenance["source"]["name"] == PLANETS


def test_instance_set_object_is_accepted() -> None:
    iset = cs.instances.load(PLANETS)
    r = cs.evaluate(heuristic, instances=iset, episodes=1, seed=1)
    assert r.provenance["source"]["content_hash"] == iset.content_hash
    tampered = dataclasses.replace(iset, content_hash="sha256:0")
    with pytest.raises(ValueError, match="is not the one make_vec loads"):
        cs.evaluate(heuristic, instances=tampered, episodes=1)


# ---------------------------------------------------------------------------------------------
# The estimators, by hand

HAND = np.array([[1.0, 2.0, 3.0, 10.0], [4.0, 5.0, 6.0, 20.0]])


def test_estimators_by_hand() -> None:
    # Per-task means over the two runs: 2.5, 3.5, 4.5, 15.
    assert aggregate_mean(HAND) == 6.375
    assert aggregate_median(HAND) == 4.0
    # IQM: 8 scores, int(0.25 * 8) = 2 cut at each end of 1 2 | 3 4 5 6 | 10 20.
    assert aggregate_iqm(HAND) == 4.5
    # 10 scores: int(2.5) = 2 cut at each end (scipy.stats.trim_mean's rule): 3..8.
    assert aggregate_iqm(np.arange(1.0, 11.0).reshape(2, 5)) == 5.5
    # 3 scores: nothing cut.
    assert aggregate_iqm(np.array([[1.0, 2.0, 9.0]])) == 4.0
    assert score_distribution(HAND, np.array([0.0, 4.0, 4.5, 20.0])).tolist() == [1.0, 0.5, 0.5, 0.0]
    lo, hi = percentile_interval(np.arange(101.0), 0.95)
    assert (lo, hi) == pytest.approx((2.5, 97.5))
    with pytest.raises(ValueError, match="NaN"):
        aggregate_mean(np.array([[1.0, np.nan]]))


def test_stratified_resamples_stay_within_each_task() -> None:
    x = np.array([[1.0, 10.0, 100.0], [2.0, 20.0, 200.0], [3.0, 30.0, 300.0]])
    for b in stratified_resamples(x, 500, np.random.default_rng(0)):
        for t in range(3):
            assert set(np.unique(b[:, :, t])) <= set(x[:, t])
        # Tasks are resampled independently: some resample mixes rows across tasks.
        assert any(not any((r == row).all() for row in x) for s in b for r in s)


def test_bootstrap_distribution_by_hand() -> None:
    # One task, two runs scoring 0 and 1: a resample's mean is 0, 0.5 or 1 with probability 1/4,
    # 1/2, 1/4; the 95 % percentile interval is [0, 1].
    b = bootstrap(np.array([[0.0], [1.0]]), reps=40000, rng=np.random.default_rng(1))
    values, counts = np.unique(b["mean"], return_counts=True)
    assert values.tolist() == [0.0, 0.5, 1.0]
    assert counts / counts.sum() == pytest.approx([0.25, 0.5, 0.25], abs=0.01)
    assert percentile_interval(b["mean"], 0.95) == (0.0, 1.0)
    # One run: every resample is the data itself, the interval has zero width.
    one = bootstrap(HAND[:1], reps=50, rng=np.random.default_rng(2), tau=np.array([2.5]))
    assert set(one["iqm"]) == {aggregate_iqm(HAND[:1])}
    assert set(one["profile"][:, 0]) == {0.5}


def test_against_rliable() -> None:
    """Where `rliable` is installed (not a dependency: it pulls SciPy and arch): the same point
    estimates, and percentile intervals within bootstrap noise of its own."""
    rly = pytest.importorskip("rliable")
    from rliable import library as rl
    from rliable import metrics

    rng = np.random.default_rng(5)
    scores = rng.normal(size=(5, 7)) * np.arange(1, 8) + np.arange(7)
    assert aggregate_mean(scores) == pytest.approx(metrics.aggregate_mean(scores))
    assert aggregate_median(scores) == pytest.approx(metrics.aggregate_median(scores))
    assert aggregate_iqm(scores) == pytest.approx(metrics.aggregate_iqm(scores))
    tau = np.linspace(-3, 12, 7)
    assert score_distribution(scores, tau) == pytest.approx(rl.score_distributions(scores, tau))
    reps = 20000
    np.random.seed(0)
    fn = {"mean": metrics.aggregate_mean, "median": metrics.aggregate_median, "iqm": metrics.aggregate_iqm}
    ours = bootstrap(scores, reps=reps, rng=np.random.default_rng(0))
    for name, f in fn.items():
        _, theirs = rl.get_interval_estimates({"x": scores}, lambda s, f=f: np.array([f(s)]), reps=reps)
        lo, hi = percentile_interval(ours[name], 0.95)
        width = hi - lo
        assert lo == pytest.approx(theirs["x"][0, 0], abs=0.05 * width), name
        assert hi == pytest.approx(theirs["x"][1, 0], abs=0.05 * width), name
    assert rly is not None


# ---------------------------------------------------------------------------------------------
# report


@pytest.fixture(scope="module")
def runs() -> tuple[list[EvaluationResult], list[EvaluationResult]]:
    policies = [heuristic, constant(0), constant(2)]
    train = [cs.evaluate(p, instances=TRAIN, episodes=1, seed=0, run=k, num_envs=16) for k, p in enumerate(policies)]
    test = [cs.evaluate(p, instances=PLANETS, episodes=2, seed=0, run=k) for k, p in enumerate(policies)]
    return train, test


def test_report_numbers(runs: tuple[list[EvaluationResult], list[EvaluationResult]]) -> None:
    train, test = runs
    rep = cs.report(train=train, test=test, reps=500, seed=3)
    g = rep.groups
    assert list(g) == ["train", "test", "test/in_distribution", "test/out_of_distribution"]
    xtr = np.stack([r.scores for r in train])
    xte = np.stack([r.scores for r in test])
    assert xtr.shape == (3, 100) and xte.shape == (3, 6)
    assert rep.aggregate("train", "iqm")[0] == aggregate_iqm(xtr)
    assert rep.aggregate("test", "mean")[0] == aggregate_mean(xte)
    assert rep.aggregate("test", "median")[0] == aggregate_median(xte)
    ind = [k for k, i in enumerate(test[0].instances) if i.split == "in_distribution"]
    assert ind == [3, 4]
    assert g["test/in_distribution"]["instances"] == 2 and g["test/out_of_distribution"]["instances"] == 4
    assert rep.aggregate("test/in_distribution", "mean")[0] == aggregate_mean(xte[:, ind])
    for key in g:
        for m in ("mean", "median", "iqm"):
            est, lo, hi = rep.aggregate(key, m)
            assert lo <= hi
    gap = rep.gap["test"]["iqm"]
    assert gap["estimate"] == pytest.approx(aggregate_iqm(xtr) - aggregate_iqm(xte))
    assert gap["ci"][0] <= gap["ci"][1]
    assert set(rep.gap) == {"test", "test/in_distribution", "test/out_of_distribution"}
    mars = g["test"]["per_instance"][3]
    assert mars["name"] == "Mars" and mars["run_scores"] == xte[:, 3].tolist() and mars["episodes"] == 6
    prof = g["test"]["profile"]
    tau = np.array(rep.data["tau"])
    assert prof["fraction"] == score_distribution(xte, tau).tolist()
    assert tau[0] == min(xtr.min(), xte.min()) and tau[-1] == max(xtr.max(), xte.max())
    assert rep.data["train"]["runs"] == [0, 1, 2]
    assert rep.data["test"]["source"]["content_hash"] == cs.instances.load(PLANETS).content_hash
    assert rep.data["env_version"] == _core.VERSIONS["lunar_lander"]


def test_report_is_deterministic_and_round_trips(
    runs: tuple[list[EvaluationResult], list[EvaluationResult]], tmp_path: Any
) -> None:
    train, test = runs
    a = cs.report(train=train, test=test, reps=300, seed=1)
    b = cs.report(train=train, test=test, reps=300, seed=1)
    assert a.to_json() == b.to_json()
    c = cs.report(train=train, test=test, reps=300, seed=2)
    assert c.aggregate("train", "iqm")[0] == a.aggregate("train", "iqm")[0]
    assert c.aggregate("train", "iqm")[1:] != a.aggregate("train", "iqm")[1:]
    assert cs.Report.from_json(a.to_json()).data == a.data
    md = a.to_markdown()
    for heading in ("# Generalization report: lunar_lander", "## Aggregate returns (95 % intervals)",
                    "## Generalization gap: train minus test", "## Per instance: test", "## Performance profile"):
        assert heading in md
    assert "| test, out of distribution | 3 | 4 |" in md
    paths = a.save(tmp_path / "out")
    assert [p.rsplit("/", 1)[1] for p in paths] == ["report.json", "report.md"]
    with open(paths[0]) as f:
        assert json.load(f)["format"] == "carl-spec-report/1"
    one = cs.report(test=test[:1], reps=50)
    assert one.aggregate("test", "iqm")[1] == one.aggregate("test", "iqm")[2]
    assert "zero width" in one.to_markdown()
    assert list(cs.report(train=train, reps=50).groups) == ["train"]


def test_report_refuses_mixed_results(runs: tuple[list[EvaluationResult], list[EvaluationResult]]) -> None:
    train, test = runs
    with pytest.raises(ValueError, match=r"train mixes sets .*run 0 has .*landing_in_space_train.*run 1 has .*test_planets"):
        cs.report(train=[train[0], test[1]])
    pend = cs.evaluate(zeros_box, "pendulum", episodes=1)
    with pytest.raises(ValueError, match="train and test differ in environments: 'lunar_lander' vs 'pendulum'"):
        cs.report(train=train, test=[pend])
    newer = dataclasses.replace(test[1], provenance={**test[1].provenance, "env_version": 99})
    v = _core.VERSIONS["lunar_lander"]
    with pytest.raises(ValueError, match=f"test mixes environment versions: run 0 has {v}, run 1 has 99"):
        cs.report(test=[test[0], newer])
    other = dataclasses.replace(test[1], provenance={**test[1].provenance, "carl_spec_version": "9.9.9"})
    with pytest.raises(ValueError, match="test mixes carl-spec versions"):
        cs.report(test=[test[0], other])
    visible = dataclasses.replace(test[1], provenance={**test[1].provenance, "obs_context": ["GRAVITY_Y"]})
    with pytest.raises(ValueError, match="test mixes visible context features"):
        cs.report(test=[test[0], visible])
    d0 = cs.evaluate(zeros_box, "pendulum", distribution="q1_g_sigma_0_5", draws=3, seed=0, run=0)
    d1 = cs.evaluate(zeros_box, "pendulum", distribution="q1_g_sigma_0_5", draws=3, seed=1, run=1)
    with pytest.raises(ValueError, match="run 1 drew other contexts than run 0 .*with the same seed"):
        cs.report(test=[d0, d1])
    same = cs.evaluate(zeros_box, "pendulum", distribution="q1_g_sigma_0_5", draws=3, seed=0, run=1)
    assert cs.report(test=[d0, same], reps=10).groups["test"]["instances"] == 3
    with pytest.raises(ValueError, match="holds run 0 twice"):
        cs.report(test=[test[0], test[0]])
    with pytest.raises(TypeError, match=r"test\[1\] is a dict, not an EvaluationResult"):
        cs.report(test=[test[0], {}])  # type: ignore[list-item]
    with pytest.raises(ValueError, match="give train= and/or test="):
        cs.report()
    with pytest.raises(ValueError, match="confidence must be in"):
        cs.report(test=test, confidence=95)


def test_plot(runs: tuple[list[EvaluationResult], list[EvaluationResult]], tmp_path: Any) -> None:
    pytest.importorskip("matplotlib")
    train, test = runs
    rep = cs.report(train=train, test=test, reps=100)
    fig = rep.plot(tmp_path / "r.png")
    assert len(fig.axes) == 3  # aggregates, profile, return against the one varied feature
    assert (tmp_path / "r.png").stat().st_size > 10_000
    paths = rep.save(tmp_path / "o", figure=True)
    assert paths[-1].endswith("report.png")
    import matplotlib.pyplot as plt

    plt.close("all")


def test_plot_without_matplotlib(runs: tuple[list[EvaluationResult], list[EvaluationResult]], monkeypatch: Any) -> None:
    rep = cs.report(test=runs[1], reps=20)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"needs matplotlib.*pip install 'carl-spec\[plot\]'"):
        rep.plot()
