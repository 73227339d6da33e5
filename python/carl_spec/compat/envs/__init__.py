"""carl-bench 1.1.1's `carl.envs`: its environment classes over carl-spec's runtimes.

As in carl-bench, `carl.envs` holds the environments that are available: here every one carl-spec
has (Box2D, Mario, RNA and the dm_control family need no extra package; only carl-bench's helpers
that return dm_control objects, in `carl_spec.compat.envs.dmc`, need dm_control). Submodules
mirror carl-bench's tree
(`carl_spec.compat.envs.gymnasium.classic_control.carl_pendulum`, ...).
"""

from __future__ import annotations

from ._classes import CLASSES as CLASSES  # carl-spec's table of the classes (not carl-bench's API)
from .brax import (
    CARLBraxAnt,
    CARLBraxHalfcheetah,
    CARLBraxHopper,
    CARLBraxHumanoid,
    CARLBraxHumanoidStandup,
    CARLBraxInvertedDoublePendulum,
    CARLBraxInvertedPendulum,
    CARLBraxPusher,
    CARLBraxReacher,
    CARLBraxWalker2d,
)
from .gymnasium import (
    CARLAcrobot,
    CARLBipedalWalker,
    CARLCartPole,
    CARLLunarLander,
    CARLMountainCar,
    CARLMountainCarContinuous,
    CARLPendulum,
    CARLVehicleRacing,
)
from .dmc import CARLDmcFingerEnv, CARLDmcFishEnv, CARLDmcPointMassEnv, CARLDmcQuadrupedEnv, CARLDmcWalkerEnv
from .mario import CARLMarioEnv
from .rna import CARLRnaDesignEnv

__all__ = [
    "CARLAcrobot",
    "CARLCartPole",
    "CARLMountainCar",
    "CARLMountainCarContinuous",
    "CARLPendulum",
    "CARLBipedalWalker",
    "CARLLunarLander",
    "CARLVehicleRacing",
    "CARLBraxAnt",
    "CARLBraxHalfcheetah",
    "CARLBraxHopper",
    "CARLBraxHumanoid",
    "CARLBraxWalker2d",
    "CARLBraxInvertedPendulum",
    "CARLBraxInvertedDoublePendulum",
    "CARLBraxReacher",
    "CARLBraxPusher",
    "CARLBraxHumanoidStandup",
    "CARLDmcFingerEnv",
    "CARLDmcFishEnv",
    "CARLDmcPointMassEnv",
    "CARLDmcWalkerEnv",
    "CARLDmcQuadrupedEnv",
    "CARLMarioEnv",
    "CARLRnaDesignEnv",
]
