"""carl-bench's `carl.envs.brax.carl_humanoidstandup`."""

from .._classes import CARLBraxHumanoidStandup

__all__ = ["CARLBraxHumanoidStandup"]
