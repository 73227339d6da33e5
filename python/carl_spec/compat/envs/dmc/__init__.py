"""carl-bench's `carl.envs.dmc`: its five environments (Finger, Fish, PointMass, Quadruped,
Walker) run carl-spec's dmc_finger, dmc_fish, dmc_point_mass, dmc_quadruped and dmc_walker."""

from .carl_dm_finger import CARLDmcFingerEnv
from .carl_dm_fish import CARLDmcFishEnv
from .carl_dm_pointmass import CARLDmcPointMassEnv
from .carl_dm_quadruped import CARLDmcQuadrupedEnv
from .carl_dm_walker import CARLDmcWalkerEnv

__all__ = ["CARLDmcFingerEnv", "CARLDmcFishEnv", "CARLDmcQuadrupedEnv", "CARLDmcWalkerEnv", "CARLDmcPointMassEnv"]
