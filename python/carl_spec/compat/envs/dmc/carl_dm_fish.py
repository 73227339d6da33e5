"""carl-bench's `carl.envs.dmc.carl_dm_fish`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLDmcFishEnv = pending_class("CARLDmcFishEnv", __name__)

__all__ = ["CARLDmcFishEnv"]
