"""Train here, test there: one observation space whatever the context source, `reset(options=
{"instance": i})`, the episode's outcome in `info` from the environment itself, and the CLI's
`carl-spec evaluate` playing the same episodes as `cs.evaluate`."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import gymnasium
import numpy as np
import pytest

import carl_spec as cs

TRAIN = "lunar_lander/landing_in_space_train"
PLANETS = "lunar_lander/landing_in_space_test_planets"


def test_one_observation_space_for_train_and_test_sets() -> None:
    """What SB3's `set_env` / `DQN.load(path, env=test_env)` compare: train on the train set (or
    the distribution), test on the planets, GRAVITY_Y visible."""
    kw: dict[str, Any] = dict(obs_context=["GRAVITY_Y"])
    train = cs.make("lunar_lander", instances=TRAIN, **kw)
    test = cs.make("lunar_lander", instances=PLANETS, **kw)
    dist = cs.make("lunar_lander", distribution="landing_in_space", **kw)
    default = cs.make("lunar_lander", **kw)
    assert train.observation_space == test.observation_space == dist.observation_space == default.observation_space
    box = test.observation_space
    assert isinstance(box, gymnasium.spaces.Box)
    assert (box.low[-1], box.high[-1]) == (np.float32(-20), np.float32(-0.01))  # the spec's bounds
    # The vector envs agree with each other and with the scalar ones.
    vtrain = cs.make_vec("lunar_lander", 2, instances=TRAIN, **kw)
    vtest = cs.make_vec("lunar_lander", 3, instances=PLANETS, **kw)
    assert vtrain.single_observation_space == vtest.single_observation_space == box
    # Jupiter shows its true gravity, below the declared bound (a deliberately out-of-bounds set).
    obs, info = test.reset(seed=0, options={"instance": 0})
    assert info["instance_name"] == "Jupiter" and obs[-1] < -20


@pytest.mark.parametrize(
    "sources",
    [
        ("pendulum/q1_max_speed_sigma_0_5", "pendulum/q1_g_sigma_0_5", "q1_max_speed_sigma_0_5", {"max_speed": 20.0}),
    ],
)
def test_one_space_whatever_the_source_even_when_bounds_follow_the_context(sources: tuple[Any, ...]) -> None:
    a, b, dist, ctx = sources
    spaces = [
        cs.make("pendulum", instances=a, obs_context=True).observation_space,
        cs.make("pendulum", instances=b, obs_context=True).observation_space,
        cs.make("pendulum", distribution=dist, obs_context=True).observation_space,
        cs.make("pendulum", context=ctx, obs_context=True).observation_space,
        cs.make("pendulum", obs_context=True).observation_space,
    ]
    assert all(s == spaces[0] for s in spaces)
    # max_speed moves the velocity's bound: no context source narrows it to the default's 8.
    box = spaces[0]
    assert isinstance(box, gymnasium.spaces.Box) and box.high[2] == np.inf
    # Observations of any source stay in it (here max_speed 20, beyond the default's 8).
    env = cs.make("pendulum", context=ctx, obs_context=True)
    env.reset(seed=0)
    for _ in range(200):
        obs, *_ = env.step(np.array([2.0], dtype=np.float32))
        assert obs in box


def test_reset_options_select_an_instance() -> None:
    env = cs.make("pendulum", instances="pendulum/q1_g_sigma_0_5")
    n = len(cs.instances.load("pendulum/q1_g_sigma_0_5"))
    obs_a, info = env.reset(seed=7, options={"instance": 2})
    assert info["instance_id"] == 2
    _, info = env.reset()
    assert info["instance_id"] == 3, "round robin goes on from the chosen instance"
    plain = cs.make("pendulum", instances="pendulum/q1_g_sigma_0_5")
    obs_b, info_b = plain.reset(seed=7)
    assert info_b["instance_id"] == 7 % n
    np.testing.assert_array_equal(obs_a, obs_b)  # the same initial state: same seed
    _, info = env.reset(options={"instance": np.int64(4)})
    assert info["instance_id"] == 4
    _, info = env.reset(seed=1, options={})
    assert info["instance_id"] == 1 % n
    with pytest.raises(ValueError, match=rf"instance {n} is outside the set: it has {n} instance"):
        env.reset(options={"instance": n})
    with pytest.raises(ValueError, match="not an instance index"):
        env.reset(options={"instance": -1})
    for bad in (1.0, "2", True, [1]):
        with pytest.raises(TypeError, match="instance index"):
            env.reset(options={"instance": bad})
    with pytest.raises(ValueError, match=r"reset options 'instanc' are not known; valid keys: instance"):
        env.reset(options={"instanc": 1})
    with pytest.raises(TypeError, match="must be a dict"):
        env.reset(options=[("instance", 1)])  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="not an instance set"):
        cs.make("pendulum").reset(options={"instance": 0})
    with pytest.raises(ValueError, match="distribution"):
        cs.make("pendulum", distribution="q1_g_sigma_0_5").reset(options={"instance": 0})


def test_vector_reset_options_select_instances_per_env() -> None:
    venv = cs.make_vec("lunar_lander", 3, instances=PLANETS)
    _, infos = venv.reset(seed=0, options={"instance": [4, None, -1]})
    ids = infos["instance_id"]
    assert ids[0] == 4 and ids[1] == 1 and ids[2] == 2  # seeds 0, 1, 2: their own round robin
    _, infos = venv.reset(seed=[5, 5, 5], options={"instance": [0, 0, 5]})
    assert infos["instance_id"].tolist() == [0, 0, 5]
    with pytest.raises(ValueError, match="environment 2 of the batch: instance 6 is outside the set"):
        venv.reset(seed=0, options={"instance": [0, 0, 6]})
    with pytest.raises(ValueError, match="num_envs=3 entries"):
        venv.reset(options={"instance": [0, 1]})
    with pytest.raises(TypeError, match="one instance per environment"):
        venv.reset(options={"instance": 1})
    with pytest.raises(ValueError, match="'nope' are not known"):
        venv.reset(options={"nope": 1})
    plain = cs.make_vec("cartpole", 2)
    with pytest.raises(ValueError, match="not an instance set"):
        plain.reset(seed=0, options={"instance": [0, 0]})


def _episode(env: gymnasium.Env[Any, Any], action: Any, seed: int, **reset: Any) -> tuple[list[dict[str, Any]], int]:
    env.reset(seed=seed, **reset)
    infos = []
    while True:
        _, _, term, trunc, info = env.step(action)
        infos.append(info)
        if term or trunc:
            return infos, len(infos)


def test_outcome_in_info_at_the_last_step() -> None:
    # LunarLander with the engines off falls: Jupiter crashes it.
    env = cs.make("lunar_lander", instances=PLANETS)
    infos, _ = _episode(env, 0, 0, options={"instance": 0})
    assert infos[-1]["outcome"] == "crashed"
    assert all("outcome" not in i for i in infos[:-1])
    # CartPole pushed one way fails; MountainCar doing nothing times out.
    infos, _ = _episode(cs.make("cartpole"), 1, 0)
    assert infos[-1]["outcome"] == "failed"
    infos, n = _episode(cs.make("mountain_car"), 1, 0)
    assert infos[-1]["outcome"] == "timed_out" and n == 200
    infos, _ = _episode(cs.make("pendulum"), np.array([0.0], dtype=np.float32), 0)
    assert infos[-1]["outcome"] == "timed_out"


@pytest.mark.parametrize("mode", ["same_step", "next_step", "disabled"])
def test_vector_outcomes_match_the_scalar_env(mode: str) -> None:
    n = 6  # one environment per planet
    venv = cs.make_vec("lunar_lander", n, instances=PLANETS, autoreset_mode=mode)
    venv.reset(seed=0, options={"instance": list(range(n))})
    words: list[str | None] = [None] * n
    for _ in range(1000):
        _, _, term, trunc, infos = venv.step(np.zeros(n, dtype=np.int64))
        ended = np.flatnonzero(term | trunc)
        where = infos["final_info"] if mode == "same_step" and len(ended) else infos
        for i in ended:
            if words[i] is None:
                assert where["_outcome"][i]
                words[i] = str(where["outcome"][i])
        if all(w is not None for w in words):
            break
        if mode == "disabled" and len(ended):
            venv.reset(seed=[0] * n, options={"reset_mask": (term | trunc)})
    scalar = cs.make("lunar_lander", instances=PLANETS)
    for i in range(n):
        infos, _ = _episode(scalar, 0, i, options={"instance": i})
        assert words[i] == infos[-1]["outcome"], i


# --- the CLI and Python play the same episodes -------------------------------------------------


def _script() -> str:
    name = "carl-spec.exe" if os.name == "nt" else "carl-spec"
    path = Path(sys.executable).parent / name
    if not path.exists():
        pytest.fail(f"the package installs no {name} script beside {Path(sys.executable).name}")
    return str(path)


def _cli_stdin(args: list[str], act: Any, out: Path) -> dict[str, Any]:
    """`carl-spec evaluate ... --policy stdin --out FILE`, each action computed by `act(obs)`
    (the results go to a file: on stderr a large result would fill the pipe while this reads
    stdout)."""
    with subprocess.Popen(
        [_script(), "evaluate", *args, "--policy", "stdin", "--out", str(out)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    ) as p:
        assert p.stdin is not None and p.stdout is not None and p.stderr is not None
        for line in p.stdout:
            v = json.loads(line)
            if "episode" in v:
                continue
            if "reset" in v:
                obs = v["reset"]["obs"]
            elif v["terminated"] or v["truncated"]:
                continue
            else:
                obs = v["obs"]
            p.stdin.write(json.dumps(act(np.array(obs, dtype=np.float32))) + "\n")
            p.stdin.flush()
        p.stdin.close()
        err = p.stderr.read()
        assert p.wait(timeout=300) == 0, err
    doc: dict[str, Any] = json.loads(out.read_text())
    return doc


def _cartpole(obs: np.ndarray) -> int:
    return int(obs[2] + 0.3 * obs[3] > 0)


def _lander(obs: np.ndarray) -> int:
    # Fire the main engine when falling fast, else steer towards the centre.
    if obs[3] < -0.25:
        return 2
    return 1 if obs[0] > 0.05 else 3 if obs[0] < -0.05 else 0


def _pendulum(obs: np.ndarray) -> list[float]:
    return [float(np.float32(np.clip(-2.0 * obs[2] - 1.0 * obs[1], -2.0, 2.0)))]


@pytest.mark.parametrize(
    "target, kw, act",
    [
        ("cartpole", dict(env="cartpole", episodes=3), _cartpole),
        (PLANETS, dict(instances=PLANETS, episodes=2), _lander),
        ("pendulum/q1_g_sigma_0_5", dict(instances="pendulum/q1_g_sigma_0_5", episodes=1), _pendulum),
    ],
    ids=["cartpole-context", "lunar-planets", "pendulum-set"],
)
def test_cli_and_python_evaluations_agree(target: str, kw: dict[str, Any], act: Any, tmp_path: Path) -> None:
    seed = 3
    cli_args = [target, "--seed", str(seed), "--episodes", str(kw["episodes"])]
    doc = _cli_stdin(cli_args, act, tmp_path / "cli.json")

    def batch(obs: np.ndarray) -> np.ndarray:
        return np.array([act(o) for o in obs])

    py = cs.evaluate(batch, seed=seed, **kw)
    cli = cs.EvaluationResult.from_json(json.dumps(doc))
    assert [e._replace(context_seed=None) for e in cli.episodes] == list(py.episodes)
    assert cli.provenance["seed_rule"] == py.provenance["seed_rule"]
    assert cli.provenance["source"] == py.provenance["source"]
    assert cli.provenance["env_version"] == py.provenance["env_version"]
    assert any(e.outcome is not None for e in py.episodes)


def test_cli_evaluate_bad_input_exits_2() -> None:
    for args, want in [
        (["lunar_lander/no_such_set"], "no_such_set"),
        (["pendulum/q1_g_sigma_0_5", "--env", "lunar_lander"], "belongs to pendulum"),
    ]:
        r = subprocess.run([_script(), "evaluate", *args], capture_output=True, text=True, timeout=120)
        assert r.returncode == 2 and want in r.stderr, r.stderr
        assert "panicked" not in r.stderr
    r = subprocess.run(
        [_script(), "evaluate", "cartpole", "--policy", "stdin", "--episodes", "1"],
        input="5\n",
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert r.returncode == 2 and "5" in r.stderr and "panicked" not in r.stderr, r.stderr
