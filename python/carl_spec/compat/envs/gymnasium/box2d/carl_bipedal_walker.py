"""carl-bench's `carl.envs.gymnasium.box2d.carl_bipedal_walker`."""

from ..._classes import CARLBipedalWalker

__all__ = ["CARLBipedalWalker"]
