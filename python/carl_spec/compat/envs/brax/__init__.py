"""carl-bench's `carl.envs.brax`: Ant, HalfCheetah, Hopper, Humanoid, HumanoidStandup, Walker2d,
InvertedPendulum, InvertedDoublePendulum, Reacher and Pusher run on carl-spec's robots."""

from .carl_ant import CARLBraxAnt
from .carl_halfcheetah import CARLBraxHalfcheetah
from .carl_hopper import CARLBraxHopper
from .carl_humanoid import CARLBraxHumanoid
from .carl_humanoidstandup import CARLBraxHumanoidStandup
from .carl_inverted_double_pendulum import CARLBraxInvertedDoublePendulum
from .carl_inverted_pendulum import CARLBraxInvertedPendulum
from .carl_pusher import CARLBraxPusher
from .carl_reacher import CARLBraxReacher
from .carl_walker2d import CARLBraxWalker2d

__all__ = [
    "CARLBraxAnt",
    "CARLBraxHalfcheetah",
    "CARLBraxHopper",
    "CARLBraxHumanoid",
    "CARLBraxHumanoidStandup",
    "CARLBraxInvertedDoublePendulum",
    "CARLBraxInvertedPendulum",
    "CARLBraxPusher",
    "CARLBraxReacher",
    "CARLBraxWalker2d",
]
