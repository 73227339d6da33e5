"""carl-bench's `carl.envs.gymnasium.classic_control.carl_mountaincarcontinuous`."""

from ..._classes import CARLMountainCarContinuous

__all__ = ["CARLMountainCarContinuous"]
