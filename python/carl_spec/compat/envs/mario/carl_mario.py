"""carl-bench's `carl.envs.mario.carl_mario`."""

from .._classes import CARLMarioEnv

__all__ = ["CARLMarioEnv"]
