"""carl-bench's `carl.envs.brax.carl_walker2d`."""

from .._classes import CARLBraxWalker2d

__all__ = ["CARLBraxWalker2d"]
