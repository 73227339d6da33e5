"""RLlib over carl-spec: each EnvRunner steps its `num_envs_per_env_runner` environments as one
batched `CarlVectorEnv` (RLlib's `gym_env_vectorize_mode="vector_entry_point"`).

    from ray.rllib.algorithms.ppo import PPOConfig
    import carl_spec.rllib
    config = (PPOConfig()
        .environment(carl_spec.rllib.register(), env_config={"env": "lunar_lander",
                                              "instances": "lunar_lander/landing_in_space_train",
                                              "selection": "random"})
        .env_runners(num_env_runners=2, num_envs_per_env_runner=8,
                     gym_env_vectorize_mode="vector_entry_point"))

`env_config` is `{"env": NAME, **make_vec keyword arguments}`. Seeding: RLlib resets the env of
runner `w` with `config.seed + w` (`.debugging(seed=...)`); that seed selects a block of
`num_envs` environment seeds of its own, so runners never share an instance stream (RLlib's
`seed + w` with Gymnasium's per-env `seed + i` would). Without a seed every runner draws OS
entropy. Needs the `rllib` extra (ray[rllib]).
"""

from __future__ import annotations

from typing import Any

import gymnasium
import numpy as np

from .env import CarlEnv
from .vector import CarlVectorEnv

__all__ = ["RllibVectorEnv", "env_creator", "register"]

# Keys RLlib's EnvContext adds to env_config that are not make_vec arguments.
_RLLIB_KEYS = ("worker_index", "vector_index", "num_workers", "remote", "recreated_worker")


class RllibVectorEnv(CarlVectorEnv):
    """A next-step `CarlVectorEnv` whose `reset(seed=s)` seeds environment `i` with
    `s * num_envs + i`: consecutive runner seeds give disjoint environment seeds."""

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict[str, Any] | None = None
    ) -> tuple[np.ndarray, dict[str, Any]]:
        if isinstance(seed, (int, np.integer)):
            seed = (int(seed) * self.num_envs) % 2**64
        return super().reset(seed=seed, options=options)

    def __reduce__(self) -> tuple[Any, ...]:
        return (_rebuild, (self._ctor,))


def _rebuild(ctor: dict[str, Any]) -> RllibVectorEnv:
    ctor = dict(ctor)
    return RllibVectorEnv(ctor.pop("env"), ctor.pop("num_envs"), **ctor)


def env_creator(env_config: dict[str, Any]) -> CarlVectorEnv | CarlEnv:
    """RLlib env creator: a batch when RLlib passes `num_envs` (vector entry point), else one env."""
    cfg = {k: v for k, v in dict(env_config).items() if k not in _RLLIB_KEYS}
    if "env" not in cfg:
        raise ValueError('env_config needs "env" (a carl-spec environment name, e.g. "lunar_lander")')
    name = cfg.pop("env")
    num_envs = cfg.pop("num_envs", None)
    mode = cfg.pop("autoreset_mode", "next_step")
    if num_envs is None:
        cfg.pop("threads", None)
        return CarlEnv(name, **cfg)
    if mode not in ("next_step", gymnasium.vector.AutoresetMode.NEXT_STEP):
        raise ValueError(f"RLlib's env runners need autoreset_mode='next_step', got {mode!r}")
    return RllibVectorEnv(name, int(num_envs), autoreset_mode="next_step", **cfg)


def register(name: str = "carl_spec") -> str:
    """Registers `env_creator` with Ray Tune's env registry under `name` (after `ray.init()`,
    in the driver: Ray ships the registry to every runner) and returns the name for
    `config.environment(name, env_config=...)`."""
    from ray.tune.registry import register_env

    register_env(name, env_creator)
    return name
