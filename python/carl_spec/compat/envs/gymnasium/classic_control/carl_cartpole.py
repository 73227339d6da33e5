"""carl-bench's `carl.envs.gymnasium.classic_control.carl_cartpole`."""

from ..._classes import CARLCartPole

__all__ = ["CARLCartPole"]
