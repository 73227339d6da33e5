"""carl-bench's `carl.envs.dmc.carl_dm_walker`."""

from .._classes import CARLDmcWalkerEnv

__all__ = ["CARLDmcWalkerEnv"]
