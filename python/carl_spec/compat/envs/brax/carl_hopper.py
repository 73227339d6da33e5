"""carl-bench's `carl.envs.brax.carl_hopper`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLBraxHopper = pending_class("CARLBraxHopper", __name__)

__all__ = ["CARLBraxHopper"]
