"""carl-bench's `carl.envs.brax.carl_humanoid`."""

from .._classes import CARLBraxHumanoid

__all__ = ["CARLBraxHumanoid"]
