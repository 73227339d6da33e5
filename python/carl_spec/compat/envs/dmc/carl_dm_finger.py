"""carl-bench's `carl.envs.dmc.carl_dm_finger`."""

from .._classes import CARLDmcFingerEnv

__all__ = ["CARLDmcFingerEnv"]
