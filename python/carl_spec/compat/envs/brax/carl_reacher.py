"""carl-bench's `carl.envs.brax.carl_reacher`."""

from .._classes import CARLBraxReacher

__all__ = ["CARLBraxReacher"]
