"""carl-bench's `carl.envs.dmc.carl_dm_fish`."""

from .._classes import CARLDmcFishEnv

__all__ = ["CARLDmcFishEnv"]
