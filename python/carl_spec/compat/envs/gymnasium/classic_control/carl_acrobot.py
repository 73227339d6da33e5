"""carl-bench's `carl.envs.gymnasium.classic_control.carl_acrobot`."""

from ..._classes import CARLAcrobot

__all__ = ["CARLAcrobot"]
