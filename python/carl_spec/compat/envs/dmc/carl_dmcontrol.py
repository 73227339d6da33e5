"""carl-bench's `carl.envs.dmc.carl_dmcontrol`: pending (issue 27)."""

from ..._pending import pending_class

CARLDmcEnv = pending_class("CARLDmcEnv", __name__)

__all__ = ["CARLDmcEnv"]
