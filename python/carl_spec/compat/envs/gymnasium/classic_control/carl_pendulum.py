"""carl-bench's `carl.envs.gymnasium.classic_control.carl_pendulum`."""

from ..._classes import CARLPendulum

__all__ = ["CARLPendulum"]
