"""carl-bench's `carl.envs.brax.carl_brax_env`: the base of its Brax classes, here carl-spec's
`CARLEnv` (carl-spec's robots run on its own engine, not Brax)."""

from ...carl_env import CARLEnv

CARLBraxEnv = CARLEnv

__all__ = ["CARLBraxEnv"]
