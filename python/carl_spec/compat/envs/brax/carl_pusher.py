"""carl-bench's `carl.envs.brax.carl_pusher`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLBraxPusher = pending_class("CARLBraxPusher", __name__)

__all__ = ["CARLBraxPusher"]
