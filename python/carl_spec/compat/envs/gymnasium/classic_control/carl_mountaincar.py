"""carl-bench's `carl.envs.gymnasium.classic_control.carl_mountaincar`."""

from ..._classes import CARLMountainCar

__all__ = ["CARLMountainCar"]
