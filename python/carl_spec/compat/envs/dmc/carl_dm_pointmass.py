"""carl-bench's `carl.envs.dmc.carl_dm_pointmass`."""

from .._classes import CARLDmcPointMassEnv

__all__ = ["CARLDmcPointMassEnv"]
