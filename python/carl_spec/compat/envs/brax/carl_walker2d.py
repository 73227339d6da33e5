"""carl-bench's `carl.envs.brax.carl_walker2d`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLBraxWalker2d = pending_class("CARLBraxWalker2d", __name__)

__all__ = ["CARLBraxWalker2d"]
