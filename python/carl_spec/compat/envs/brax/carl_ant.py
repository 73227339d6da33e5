"""carl-bench's `carl.envs.brax.carl_ant`."""

from .._classes import CARLBraxAnt

__all__ = ["CARLBraxAnt"]
