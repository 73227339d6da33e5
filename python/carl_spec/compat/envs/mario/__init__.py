"""carl-bench's `carl.envs.mario` (carl-spec's Mario runtime: no Java, no torch)."""

from .carl_mario import CARLMarioEnv

__all__ = ["CARLMarioEnv"]
