"""carl-bench's `carl.envs.gymnasium.classic_control`."""

from .carl_acrobot import CARLAcrobot
from .carl_cartpole import CARLCartPole
from .carl_mountaincar import CARLMountainCar
from .carl_mountaincarcontinuous import CARLMountainCarContinuous
from .carl_pendulum import CARLPendulum

__all__ = ["CARLAcrobot", "CARLCartPole", "CARLMountainCar", "CARLMountainCarContinuous", "CARLPendulum"]
