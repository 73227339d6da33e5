"""carl-bench's `carl.envs.dmc.carl_dm_quadruped`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLDmcQuadrupedEnv = pending_class("CARLDmcQuadrupedEnv", __name__)

__all__ = ["CARLDmcQuadrupedEnv"]
