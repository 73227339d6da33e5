"""carl-bench's `carl.envs.brax.carl_hopper`."""

from .._classes import CARLBraxHopper

__all__ = ["CARLBraxHopper"]
