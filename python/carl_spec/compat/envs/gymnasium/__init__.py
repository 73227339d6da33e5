"""carl-bench's `carl.envs.gymnasium`: classic control and (always present here) Box2D."""

from . import box2d, classic_control
from .box2d import CARLBipedalWalker, CARLLunarLander, CARLVehicleRacing
from .classic_control import CARLAcrobot, CARLCartPole, CARLMountainCar, CARLMountainCarContinuous, CARLPendulum

__all__ = [
    "CARLAcrobot",
    "CARLCartPole",
    "CARLMountainCar",
    "CARLMountainCarContinuous",
    "CARLPendulum",
    "CARLBipedalWalker",
    "CARLLunarLander",
    "CARLVehicleRacing",
]
