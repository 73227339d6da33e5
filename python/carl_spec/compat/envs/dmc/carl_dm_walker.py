"""carl-bench's `carl.envs.dmc.carl_dm_walker`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLDmcWalkerEnv = pending_class("CARLDmcWalkerEnv", __name__)

__all__ = ["CARLDmcWalkerEnv"]
