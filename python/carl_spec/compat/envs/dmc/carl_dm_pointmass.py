"""carl-bench's `carl.envs.dmc.carl_dm_pointmass`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLDmcPointMassEnv = pending_class("CARLDmcPointMassEnv", __name__)

__all__ = ["CARLDmcPointMassEnv"]
