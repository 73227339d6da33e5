"""carl-bench's `carl.envs.gymnasium.carl_gymnasium_env`: the base of its Gymnasium-family
classes, here carl-spec's `CARLEnv`."""

from ...carl_env import CARLEnv

CARLGymnasiumEnv = CARLEnv

__all__ = ["CARLGymnasiumEnv"]
