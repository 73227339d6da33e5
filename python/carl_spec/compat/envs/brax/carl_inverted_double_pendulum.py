"""carl-bench's `carl.envs.brax.carl_inverted_double_pendulum`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLBraxInvertedDoublePendulum = pending_class("CARLBraxInvertedDoublePendulum", __name__)

__all__ = ["CARLBraxInvertedDoublePendulum"]
