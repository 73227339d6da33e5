"""carl-bench's `carl.envs.dmc.carl_dm_finger`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLDmcFingerEnv = pending_class("CARLDmcFingerEnv", __name__)

__all__ = ["CARLDmcFingerEnv"]
