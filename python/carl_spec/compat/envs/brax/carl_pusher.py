"""carl-bench's `carl.envs.brax.carl_pusher`."""

from .._classes import CARLBraxPusher

__all__ = ["CARLBraxPusher"]
