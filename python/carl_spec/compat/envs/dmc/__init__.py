"""carl-bench's `carl.envs.dmc`: CARLDmcPointMassEnv, CARLDmcWalkerEnv and CARLDmcQuadrupedEnv run
carl-spec's dmc_point_mass, dmc_walker and dmc_quadruped; the rest of
the family is pending (issue 27): building one of those classes raises `PendingEnvironmentError`
naming the missing environment."""

from .carl_dm_finger import CARLDmcFingerEnv
from .carl_dm_fish import CARLDmcFishEnv
from .carl_dm_pointmass import CARLDmcPointMassEnv
from .carl_dm_quadruped import CARLDmcQuadrupedEnv
from .carl_dm_walker import CARLDmcWalkerEnv

__all__ = ["CARLDmcFingerEnv", "CARLDmcFishEnv", "CARLDmcQuadrupedEnv", "CARLDmcWalkerEnv", "CARLDmcPointMassEnv"]
