"""carl-bench's `carl.envs.brax.carl_halfcheetah`."""

from .._classes import CARLBraxHalfcheetah

__all__ = ["CARLBraxHalfcheetah"]
