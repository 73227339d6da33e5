"""`carl_spec.sb3.CarlSB3VecEnv`: SB3's VecEnv contract, checked against SB3's own DummyVecEnv
over `cs.make` environments (same seeds, same actions, bit for bit)."""

from __future__ import annotations

import pickle
import warnings

import gymnasium
import numpy as np
import pytest
from stable_baselines3.common.env_checker import check_env
from gymnasium.error import ClosedEnvironmentError
from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv, VecMonitor

import carl_spec as cs
from carl_spec.sb3 import CarlSB3VecEnv

SET = "pendulum/q1_l_sigma_0_5"


def dummy(env: str, n: int, **kw: object) -> DummyVecEnv:
    return DummyVecEnv([lambda: cs.make(env, **kw) for _ in range(n)])


def rollout(venv: object, actions: list[np.ndarray]) -> list[tuple]:
    out = []
    for a in actions:
        obs, rew, done, infos = venv.step(a)  # type: ignore[attr-defined]
        out.append((obs.copy(), rew.copy(), done.copy(), infos))
    return out


@pytest.mark.parametrize("env", ["cartpole", "pendulum"])
def test_steps_match_dummy_vec_env(env: str) -> None:
    n, steps = 4, 600
    ours, ref = CarlSB3VecEnv(env, n), dummy(env, n)
    ours.seed(7), ref.seed(7)
    o1, o2 = ours.reset(), ref.reset()
    np.testing.assert_array_equal(o1, o2)
    space = ours.action_space
    space.seed(0)
    actions = [np.stack([space.sample() for _ in range(n)]) for _ in range(steps)]
    a, b = rollout(ours, actions), rollout(ref, actions)
    ended = truncated = 0
    for (oa, ra, da, ia), (ob, rb, db, ib) in zip(a, b):
        np.testing.assert_array_equal(oa, ob)
        assert ra.dtype == rb.dtype == np.float32
        np.testing.assert_array_equal(ra, rb)
        np.testing.assert_array_equal(da, db)
        for x, y in zip(ia, ib):
            assert x["TimeLimit.truncated"] == y["TimeLimit.truncated"]
            assert ("terminal_observation" in x) == ("terminal_observation" in y)
            if "terminal_observation" in x:
                ended += 1
                truncated += x["TimeLimit.truncated"]
                np.testing.assert_array_equal(x["terminal_observation"], y["terminal_observation"])
    assert ended > 0, "the rollout must cover episode ends"
    if env == "pendulum":
        assert truncated == ended, "pendulum only ends by its time limit"


def test_contextual_batch_matches_dummy_and_reports_instances() -> None:
    n = 3
    kw = {"instances": SET, "selection": "random"}
    ours, ref = CarlSB3VecEnv("pendulum", n, **kw), dummy("pendulum", n, **kw)
    ours.seed(3), ref.seed(3)
    np.testing.assert_array_equal(ours.reset(), ref.reset())
    assert [i["instance_id"] for i in ours.reset_infos] == [i["instance_id"] for i in ref.reset_infos]
    rng = np.random.default_rng(1)
    seen = set()
    for _ in range(700):
        a = rng.uniform(-2, 2, size=(n, 1)).astype(np.float32)
        oa, _, da, ia = ours.step(a)
        ob, _, db, ib = ref.step(a)
        np.testing.assert_array_equal(oa, ob)
        np.testing.assert_array_equal(da, db)
        for i in np.flatnonzero(da):
            # After an autoreset the info names the new episode's instance, as the reset info of
            # the single env does.
            assert ia[i]["instance_id"] == ref.reset_infos[i]["instance_id"]
        seen.update(x["instance_id"] for x in ia)
    assert len(seen) > 1
    assert ours.get_attr("instance_id") == [x["instance_id"] for x in ia]
    ctx = ours.get_attr("context", indices=[1])[0]
    assert ctx == ours.env_method("context_info", indices=1)[0]["context"]


def test_seeding_follows_sb3() -> None:
    v = CarlSB3VecEnv("cartpole", 4)
    assert v.seed(11) == [11, 12, 13, 14]
    first = v.reset()
    v.seed(11)
    np.testing.assert_array_equal(v.reset(), first)
    # Seeds are used once: a plain reset continues the streams instead of repeating them.
    assert not np.array_equal(v.reset(), first)
    # Per-env seeds in any order, and an unseeded batch draws OS entropy.
    v._seeds = [14, 13, 12, 11]
    np.testing.assert_array_equal(v.reset(), first[::-1])
    a, b = CarlSB3VecEnv("cartpole", 4).reset(), CarlSB3VecEnv("cartpole", 4).reset()
    assert not np.array_equal(a, b)


def test_attributes_methods_and_errors() -> None:
    v = CarlSB3VecEnv("cartpole", 3)
    v.reset()
    assert v.get_attr("render_mode") == [None] * 3
    assert v.get_attr("observation_space", indices=[0, 2]) == [v.observation_space] * 2
    assert v.env_is_wrapped(gymnasium.Wrapper) == [False] * 3
    assert v.get_attr("num_envs") == [3, 3, 3]
    v.set_attr("note", 1)
    assert v.get_attr("note") == [1, 1, 1]
    with pytest.raises(ValueError, match="share attributes"):
        v.set_attr("note", 2, indices=[0])
    with pytest.raises(AttributeError, match="not settable"):
        v.set_attr("num_envs", 4)
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        v.get_attr("nope")
    with pytest.raises(AttributeError, match="no method 'nope'"):
        v.env_method("nope")
    with pytest.raises(IndexError):
        v.get_attr("context", indices=[3])
    with pytest.raises(ValueError, match="same_step"):
        CarlSB3VecEnv("cartpole", 2, autoreset_mode="next_step")
    with pytest.raises(ValueError, match="same_step"):
        CarlSB3VecEnv(cs.make_vec("cartpole", 2))


def test_render_tiles_each_env_from_its_state() -> None:
    v = CarlSB3VecEnv("lunar_lander", 2, render_mode="rgb_array")
    v.seed(0)
    v.reset()
    actions = [np.array([a, 3 - a]) for a in (0, 1, 2, 3) * 5]
    for a in actions:
        v.step(a)
    imgs = v.get_images()
    single = cs.make("lunar_lander", render_mode="rgb_array")
    single.reset(seed=1)
    for a in actions:
        single.step(int(a[1]))
    np.testing.assert_array_equal(imgs[1], single.render())
    assert not np.array_equal(imgs[0], imgs[1])
    big = v.render()
    assert big is not None and big.shape[2] == 3
    with pytest.raises(ValueError, match="no renderer"):
        CarlSB3VecEnv("cartpole", 2, render_mode="rgb_array")


def test_pickles_through_its_batch() -> None:
    v = CarlSB3VecEnv("cartpole", 2)
    w = pickle.loads(pickle.dumps(v.venv))
    assert isinstance(CarlSB3VecEnv(w), CarlSB3VecEnv)


@pytest.mark.parametrize("start_method", ["spawn", "forkserver"])
def test_subproc_vec_env_ships_make_lambdas(start_method: str) -> None:
    # Issue 31 item 4: SB3 cloudpickles the env functions; their global `cs` must pickle by
    # reference (it failed with "cannot pickle '_Package' object").
    ours = SubprocVecEnv([lambda: cs.make("cartpole") for _ in range(2)], start_method=start_method)
    try:
        ref = dummy("cartpole", 2)
        ours.seed(5), ref.seed(5)
        np.testing.assert_array_equal(ours.reset(), ref.reset())
        actions = [np.array([t % 2, (t // 3) % 2]) for t in range(80)]
        ended = 0
        for (oa, ra, da, _), (ob, rb, db, _) in zip(rollout(ours, actions), rollout(ref, actions)):
            np.testing.assert_array_equal(oa, ob)
            np.testing.assert_array_equal(ra, rb)
            np.testing.assert_array_equal(da, db)
            ended += int(da.sum())
        assert ended > 0
    finally:
        ours.close()


def test_a_closed_batch_stops() -> None:
    v = CarlSB3VecEnv("cartpole", 2)
    v.reset()
    v.close()
    with pytest.raises(ClosedEnvironmentError, match="is closed"):
        v.step(np.zeros(2, dtype=np.int64))


def test_vec_monitor_counts_episodes() -> None:
    v = VecMonitor(CarlSB3VecEnv("cartpole", 4))
    v.seed(0)
    v.reset()
    episodes = []
    for _ in range(300):
        _, _, done, infos = v.step(np.zeros(4, dtype=np.int64))
        episodes += [i["episode"]["l"] for d, i in zip(done, infos) if d]
    assert episodes and all(8 <= n <= 20 for n in episodes), episodes


@pytest.mark.parametrize("env", cs.RUNTIMES)
def test_sb3_check_env(env: str) -> None:
    made = cs.make(env)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        check_env(made, warn=True)
    # SB3 advises a [-1, 1] action space; environments whose Box keeps Gymnasium's other bounds
    # (Pendulum's [-2, 2], CarRacing's gas/brake in [0, 1], Humanoid's [-0.4, 0.4],
    # InvertedPendulum's [-3, 3]) get that advice. Any other warning fails.
    advice = "We recommend you to use a symmetric and normalized Box action space"
    space = made.action_space
    allowed = isinstance(space, gymnasium.spaces.Box) and not (np.all(space.low == -1) and np.all(space.high == 1))
    bad = [str(w.message) for w in caught if not (allowed and str(w.message).startswith(advice))]
    assert not bad, bad


def test_sb3_training_leaves_no_log_folder_in_tmp(tmp_path: object) -> None:
    """SB3 makes `$TMPDIR/SB3-<date>` for every model unless SB3_LOGDIR is set; the tier's
    conftest points it into the test's tmp_path, so repeated runs leave nothing behind."""
    import tempfile
    from pathlib import Path

    from stable_baselines3 import PPO

    tmp = Path(tempfile.gettempdir())
    before = set(tmp.glob("SB3-*"))
    model = PPO("MlpPolicy", CarlSB3VecEnv("cartpole", 2), n_steps=16, batch_size=16, n_epochs=1, device="cpu", seed=0)
    model.learn(32)
    assert set(tmp.glob("SB3-*")) == before, "SB3 wrote a log folder into the system temp dir"
    assert (Path(str(tmp_path)) / "sb3-logs").is_dir()


def test_render_a_set_that_allows_out_of_bounds_contexts() -> None:
    # Issue 31, item 8: the renderer took the set's contexts as a fixed context= and refused the
    # ones outside the bounds that the set itself allows.
    venv = CarlSB3VecEnv("lunar_lander", 2, instances="lunar_lander/landing_in_space_test_planets", render_mode="rgb_array")
    venv.seed(0)
    venv.reset()
    frames = venv.get_images()
    assert len(frames) == 2 and all(f is not None and f.ndim == 3 for f in frames)
    venv.close()


def test_non_finite_actions_refused_through_the_adapter() -> None:
    # Issue 31, item 3: the adapter goes through make_vec's checks.
    venv = CarlSB3VecEnv("pendulum", 2)
    venv.seed(0)
    venv.reset()
    with pytest.raises(ValueError, match="finite"):
        venv.step(np.array([[np.nan], [0.0]], dtype=np.float32))
    venv.close()
