"""carl-bench's `carl.envs.carl_env`: the base class `CARLEnv`."""

from ..carl_env import CARLEnv

__all__ = ["CARLEnv"]
