"""RLlib (new API stack) over carl-spec on a local loopback Ray: PPO on LunarLander drawn from
`landing_in_space_train`, 2 env runners x 4 batched envs each (vector entry point)."""

from __future__ import annotations

import math
import time
from typing import Any

import numpy as np
import pytest

import carl_spec as cs
from carl_spec.rllib import RllibVectorEnv, env_creator, register

LOOPBACK = "127.0.0.1"
SET = "lunar_lander/landing_in_space_train"
ENV_CONFIG = {"env": "lunar_lander", "instances": SET, "selection": "random"}


def test_env_creator_builds_a_batch_or_one_env() -> None:
    batch = env_creator({**ENV_CONFIG, "num_envs": 4, "worker_index": 1})
    assert isinstance(batch, RllibVectorEnv) and batch.num_envs == 4
    assert batch.metadata["autoreset_mode"].name == "NEXT_STEP"
    single = env_creator(ENV_CONFIG)
    assert isinstance(single, cs.CarlEnv)


def test_runner_seeds_give_disjoint_env_seeds() -> None:
    # RLlib seeds runner w with seed + w; plain Gymnasium seeding (env i <- seed + i) would give
    # runner 1's env 1 the stream of runner 2's env 0.
    n = 4
    a = env_creator({**ENV_CONFIG, "num_envs": n})
    b = env_creator({**ENV_CONFIG, "num_envs": n})
    oa, _ = a.reset(seed=1)
    ob, _ = b.reset(seed=2)
    plain = cs.make_vec("lunar_lander", n, instances=SET, selection="random")
    op, _ = plain.reset(seed=1 * n)
    np.testing.assert_array_equal(oa, op)  # runner 1's envs are seeds 4..7
    op, _ = plain.reset(seed=2 * n)
    np.testing.assert_array_equal(ob, op)  # runner 2's envs are seeds 8..11
    assert not any(np.array_equal(x, y) for x in oa for y in ob)


@pytest.mark.xdist_group("ray")  # one loopback Ray per worker: keep its tests together
def test_rllib_ppo_iteration_on_loopback_ray(loopback_ray: Any) -> None:
    from ray.rllib.algorithms.ppo import PPOConfig

    def runner_report(runner: Any) -> dict[str, Any]:
        # Defined here so that cloudpickle ships it by value (runners cannot import this module).
        import ray

        env = runner.env.unwrapped
        return {
            "worker_index": runner.worker_index,
            "node_ip": ray.util.get_node_ip_address(),
            "type": type(env).__name__,
            "num_envs": env.num_envs,
            "contexts": [env.context_info(i)["context"] for i in range(env.num_envs)],
            "instance_ids": env._core.instance_ids().tolist(),
        }

    config = (
        PPOConfig()
        .environment(register(), env_config=ENV_CONFIG)
        .env_runners(num_env_runners=2, num_envs_per_env_runner=4, gym_env_vectorize_mode="vector_entry_point")
        .training(train_batch_size_per_learner=1024, minibatch_size=256, num_epochs=2)
        .debugging(seed=0)
    )
    t0 = time.perf_counter()
    algo = config.build_algo()
    try:
        result = algo.train()
        reports = algo.env_runner_group.foreach_env_runner(runner_report, local_env_runner=False)
    finally:
        algo.stop()
    print(f"RLlib PPO iteration: {time.perf_counter() - t0:.0f}s")
    steps = result["env_runners"]["num_env_steps_sampled_lifetime"]
    assert steps >= 1024, result["env_runners"]
    learner = result["learners"]["default_policy"]
    assert math.isfinite(learner["total_loss"]) and math.isfinite(learner["vf_loss"]), learner
    assert sorted(r["worker_index"] for r in reports) == [1, 2]
    for r in reports:
        assert r["node_ip"] == LOOPBACK
        assert r["type"] == "RllibVectorEnv" and r["num_envs"] == 4
        assert all(i >= 0 for i in r["instance_ids"]), r
    # Each runner draws its own instances: different contexts across runners.
    assert reports[0]["contexts"] != reports[1]["contexts"]
    iset = cs.instances.load(SET)
    for r in reports:
        for iid, ctx in zip(r["instance_ids"], r["contexts"]):
            assert all(ctx[k] == v for k, v in iset.contexts[iid].items()), (iid, ctx)
