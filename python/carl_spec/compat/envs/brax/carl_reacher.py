"""carl-bench's `carl.envs.brax.carl_reacher`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLBraxReacher = pending_class("CARLBraxReacher", __name__)

__all__ = ["CARLBraxReacher"]
