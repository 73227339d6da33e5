"""carl-bench's `carl.envs.brax.carl_humanoidstandup`: pending (see `carl_spec.compat._pending`)."""

from ..._pending import pending_class

CARLBraxHumanoidStandup = pending_class("CARLBraxHumanoidStandup", __name__)

__all__ = ["CARLBraxHumanoidStandup"]
