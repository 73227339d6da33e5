"""carl-bench's `carl.envs.gymnasium.box2d` (carl-spec's Box2D-family runtimes need no Box2D)."""

from .carl_bipedal_walker import CARLBipedalWalker
from .carl_lunarlander import CARLLunarLander
from .carl_vehicle_racing import CARLVehicleRacing

__all__ = ["CARLBipedalWalker", "CARLLunarLander", "CARLVehicleRacing"]
