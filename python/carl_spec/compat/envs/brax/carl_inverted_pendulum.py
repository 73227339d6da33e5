"""carl-bench's `carl.envs.brax.carl_inverted_pendulum`."""

from .._classes import CARLBraxInvertedPendulum

__all__ = ["CARLBraxInvertedPendulum"]
