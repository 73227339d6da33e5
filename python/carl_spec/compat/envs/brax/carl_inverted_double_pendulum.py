"""carl-bench's `carl.envs.brax.carl_inverted_double_pendulum`."""

from .._classes import CARLBraxInvertedDoublePendulum

__all__ = ["CARLBraxInvertedDoublePendulum"]
