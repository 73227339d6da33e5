"""carl-bench's `carl.envs.dmc.carl_dm_quadruped`."""

from .._classes import CARLDmcQuadrupedEnv

__all__ = ["CARLDmcQuadrupedEnv"]
