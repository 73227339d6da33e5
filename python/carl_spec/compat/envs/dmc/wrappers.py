"""carl-bench's `carl.envs.dmc.wrappers`: pending (issue 27; see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

MujocoToGymWrapper = pending_class("MujocoToGymWrapper", __name__)

__all__ = ["MujocoToGymWrapper"]
