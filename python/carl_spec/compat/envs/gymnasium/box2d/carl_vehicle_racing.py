"""carl-bench's `carl.envs.gymnasium.box2d.carl_vehicle_racing`."""

from ..._classes import CARLVehicleRacing

__all__ = ["CARLVehicleRacing"]
