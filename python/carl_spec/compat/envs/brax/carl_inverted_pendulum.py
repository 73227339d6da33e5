"""carl-bench's `carl.envs.brax.carl_inverted_pendulum`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLBraxInvertedPendulum = pending_class("CARLBraxInvertedPendulum", __name__)

__all__ = ["CARLBraxInvertedPendulum"]
