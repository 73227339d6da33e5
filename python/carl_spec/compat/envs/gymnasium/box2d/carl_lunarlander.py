"""carl-bench's `carl.envs.gymnasium.box2d.carl_lunarlander`."""

from ..._classes import CARLLunarLander

__all__ = ["CARLLunarLander"]
