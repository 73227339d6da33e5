"""carl-bench 1.1.1's API over carl-spec: switching is a one-line import change.

    # before:  from carl.envs import CARLLunarLander
    from carl_spec.compat import CARLLunarLander

    env = CARLLunarLander(contexts={0: {"GRAVITY_Y": -3.7}, 1: {"GRAVITY_Y": -9.8}})

Every `carl.` import has a `carl_spec.compat.` twin (`carl_spec.compat.envs`,
`carl_spec.compat.context.selection`, `carl_spec.compat.envs.gymnasium.classic_control.carl_pendulum`,
...); importing this package registers the `carl/CARL<Name>-v0` Gymnasium ids. carl-bench 1.1.1's
own test suite runs against it (python/tests/carl_bench_suite). The differences from carl-bench
(its flaws are not reproduced) are listed in docs/guides/migration.md.
"""

from __future__ import annotations

import gymnasium

from .carl_env import CARLEnv
from .context.context_space import ContextFeature, ContextSpace, NormalFloatContextFeature, UniformFloatContextFeature
from .context.sampler import ContextSampler
from .context.selection import AbstractSelector, CustomSelector, RandomSelector, RoundRobinSelector, StaticSelector
from .envs import (
    CLASSES,
    CARLAcrobot,
    CARLBipedalWalker,
    CARLBraxAnt,
    CARLBraxHalfcheetah,
    CARLBraxHumanoid,
    CARLCartPole,
    CARLLunarLander,
    CARLMarioEnv,
    CARLMountainCar,
    CARLMountainCarContinuous,
    CARLPendulum,
    CARLRnaDesignEnv,
    CARLVehicleRacing,
)


def gym_id(cls_name: str) -> str:
    """carl-bench's Gymnasium id of a class, e.g. `carl/CARLCartPole-v0`."""
    return f"carl/{cls_name}-v0"


def _register() -> None:
    for name in CLASSES:
        if gym_id(name) not in gymnasium.registry:
            gymnasium.register(id=gym_id(name), entry_point=f"carl_spec.compat.envs:{name}")


_register()

__all__ = [
    "AbstractSelector",
    "CARLAcrobot",
    "CARLBipedalWalker",
    "CARLBraxAnt",
    "CARLBraxHalfcheetah",
    "CARLBraxHumanoid",
    "CARLCartPole",
    "CARLEnv",
    "CARLLunarLander",
    "CARLMarioEnv",
    "CARLMountainCar",
    "CARLMountainCarContinuous",
    "CARLPendulum",
    "CARLRnaDesignEnv",
    "CARLVehicleRacing",
    "CLASSES",
    "ContextFeature",
    "ContextSampler",
    "ContextSpace",
    "NormalFloatContextFeature",
    "UniformFloatContextFeature",
    "CustomSelector",
    "RandomSelector",
    "RoundRobinSelector",
    "StaticSelector",
    "gym_id",
]
