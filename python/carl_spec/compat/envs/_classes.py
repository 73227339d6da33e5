"""carl-bench 1.1.1's environment classes over carl-spec's runtimes (defined here, exported from their
carl-bench module twins, e.g. `carl_spec.compat.envs.gymnasium.classic_control.carl_pendulum`).
Each class names its carl-spec runtime, carl-bench's names of the features carl-spec has (in
carl-bench's order; carl-spec's spec lists them as aliases where they differ), and the carl-bench
features carl-spec does not have, with the reason a user gets when passing one.
"""

from __future__ import annotations

from typing import Any

from .._pending import GOAL, PendingEnvironmentError
from ..carl_env import CARLEnv

_START = "carl-spec starts {env} exactly as Gymnasium does (same initial state for the same seed), so it has no {what} features"
_ROBOT = (
    "carl-spec's {env} (rapier3d runtime after Brax 2021) has no such feature; its physics features are "
    "gravity, friction, ang_damping (angular_damping), mass_torso (torso_mass), joint_stiffness, "
    "joint_angular_damping, actuator_strength and the body masses"
)


_GOAL = (
    "it is a goal feature of carl-bench's BraxWalkerGoalWrapper; carl-spec's {env} has no goal features yet: "
    "it needs {goal}"
)


def _robot_only(env: str) -> dict[str, str]:
    why = _ROBOT.format(env=env)
    goal = _GOAL.format(env=env, goal=GOAL)
    return {
        "elasticity": why,
        "viscosity": why,
        **{n: goal for n in ("target_distance", "target_direction", "target_radius")},
    }


class _Robot(CARLEnv):
    """carl-bench's Brax classes take `use_language_goals` (its goal option, pending here)."""

    def __init__(self, *args: Any, use_language_goals: bool = False, batch_size: int = 1, **kwargs: Any) -> None:
        if use_language_goals:
            raise PendingEnvironmentError(
                f"{type(self).__name__}(use_language_goals=True): carl-spec's {self.env_id} has no goal features yet: it needs {GOAL}"
            )
        if batch_size != 1:
            raise ValueError(f"{type(self).__name__}: batch_size={batch_size}: use carl_spec.make_vec({self.env_id!r}, num_envs)")
        super().__init__(*args, **kwargs)


class CARLCartPole(CARLEnv):
    env_id = "cartpole"
    bench_names = ("gravity", "masscart", "masspole", "length", "force_mag", "tau")
    bench_only = {
        n: _START.format(env="CartPole", what="initial-state range") + " (Gymnasium draws every component from U(-0.05, 0.05); carl-bench's default was U(-0.1, 0.1))"
        for n in ("initial_state_lower", "initial_state_upper")
    }


class CARLPendulum(CARLEnv):
    env_id = "pendulum"
    bench_names = ("dt", "g", "m", "l")
    bench_only = {
        "gravity": "it is dead in carl-bench 1.1.1 (Gymnasium's Pendulum reads g, so changing gravity never changed the dynamics); use g",
        "initial_angle_max": _START.format(env="Pendulum", what="initial-state range"),
        "initial_velocity_max": _START.format(env="Pendulum", what="initial-state range"),
    }


class CARLAcrobot(CARLEnv):
    env_id = "acrobot"
    bench_names = (
        "LINK_LENGTH_1", "LINK_LENGTH_2", "LINK_MASS_1", "LINK_MASS_2", "LINK_COM_POS_1",
        "LINK_COM_POS_2", "LINK_MOI", "MAX_VEL_1", "MAX_VEL_2",
    )
    bench_only = {
        "torque_noise_max": "carl-spec's Acrobot is Gymnasium's Acrobot-v1, whose torque noise is 0; it is not a context feature",
        **{
            n: _START.format(env="Acrobot", what="initial-state range")
            for n in ("INITIAL_ANGLE_LOWER", "INITIAL_ANGLE_UPPER", "INITIAL_VELOCITY_LOWER", "INITIAL_VELOCITY_UPPER")
        },
    }


class CARLMountainCar(CARLEnv):
    env_id = "mountain_car"
    bench_names = ("min_position", "max_position", "max_speed", "goal_position", "goal_velocity", "force", "gravity")
    bench_only = {
        n: "carl-spec's mountain_car draws the start from a normal distribution (CARL's paper): use start_position, "
        "start_position_std, start_velocity and start_velocity_std"
        for n in ("min_position_start", "max_position_start", "min_velocity_start", "max_velocity_start")
    }


class CARLMountainCarContinuous(CARLEnv):
    env_id = "mountain_car_continuous"
    bench_names = (
        "min_position", "max_position", "max_speed", "goal_position", "goal_velocity", "power",
        "min_position_start", "max_position_start", "min_velocity_start", "max_velocity_start",
    )


class CARLLunarLander(CARLEnv):
    env_id = "lunar_lander"
    bench_names = (
        "FPS", "SCALE", "MAIN_ENGINE_POWER", "SIDE_ENGINE_POWER", "INITIAL_RANDOM", "GRAVITY_X", "GRAVITY_Y",
        "LEG_AWAY", "LEG_DOWN", "LEG_W", "LEG_H", "LEG_SPRING_TORQUE", "SIDE_ENGINE_HEIGHT", "SIDE_ENGINE_AWAY",
        "VIEWPORT_W", "VIEWPORT_H",
    )


class CARLBipedalWalker(CARLEnv):
    env_id = "bipedal_walker"
    bench_names = (
        "FPS", "SCALE", "GRAVITY_X", "GRAVITY_Y", "FRICTION", "TERRAIN_STEP", "TERRAIN_LENGTH", "TERRAIN_HEIGHT",
        "TERRAIN_GRASS", "TERRAIN_STARTPAD", "MOTORS_TORQUE", "SPEED_HIP", "SPEED_KNEE", "LIDAR_RANGE", "LEG_DOWN",
        "LEG_W", "LEG_H", "INITIAL_RANDOM", "VIEWPORT_W", "VIEWPORT_H",
    )


class CARLVehicleRacing(CARLEnv):
    env_id = "vehicle_racing"
    bench_names = ("VEHICLE_ID",)


class CARLBraxAnt(_Robot):
    env_id = "ant"
    bench_names = ("gravity", "friction", "ang_damping", "mass_torso")
    bench_only = _robot_only("ant")


class CARLBraxHalfcheetah(_Robot):
    env_id = "half_cheetah"
    bench_names = (
        "gravity", "friction", "ang_damping", "mass_torso", "mass_bthigh", "mass_bshin", "mass_bfoot",
        "mass_fthigh", "mass_fshin", "mass_ffoot",
    )
    bench_only = _robot_only("half_cheetah")


class CARLBraxHumanoid(_Robot):
    env_id = "humanoid"
    bench_names = (
        "gravity", "friction", "ang_damping", "mass_torso", "mass_lwaist", "mass_pelvis", "mass_right_thigh",
        "mass_right_shin", "mass_left_thigh", "mass_left_shin", "mass_right_upper_arm", "mass_right_lower_arm",
        "mass_left_upper_arm", "mass_left_lower_arm",
    )
    bench_only = _robot_only("humanoid")


def _goal_only(env: str) -> dict[str, str]:
    goal = _GOAL.format(env=env, goal=GOAL)
    return {n: goal for n in ("target_distance", "target_direction", "target_radius")}


class CARLBraxHopper(_Robot):
    env_id = "hopper"
    bench_names = ("gravity", "friction", "elasticity", "ang_damping", "viscosity", "mass_torso", "mass_thigh",
                   "mass_leg", "mass_foot")
    bench_only = _goal_only("hopper")


class CARLBraxWalker2d(_Robot):
    env_id = "walker2d"
    bench_names = ("gravity", "friction", "elasticity", "ang_damping", "viscosity", "mass_torso", "mass_thigh",
                   "mass_leg", "mass_foot", "mass_thigh_left", "mass_leg_left", "mass_foot_left")
    bench_only = _goal_only("walker2d")


class CARLBraxInvertedPendulum(_Robot):
    env_id = "inverted_pendulum"
    bench_names = ("gravity", "friction", "elasticity", "mass_cart", "mass_pole", "ang_damping", "viscosity")


class CARLBraxInvertedDoublePendulum(_Robot):
    # carl-bench's key mass_pole2 (its hyperparameter is misnamed mass_pole, its default context lacks it)
    env_id = "inverted_double_pendulum"
    bench_names = (
        "gravity", "friction", "elasticity", "mass_cart", "mass_pole", "mass_pole2", "ang_damping", "viscosity",
    )


class CARLBraxReacher(_Robot):
    env_id = "reacher"
    bench_names = ("gravity", "friction", "elasticity", "ang_damping", "viscosity", "mass_body0", "mass_body1")


class CARLMarioEnv(CARLEnv):
    env_id = "mario"
    bench_names = ("level_width", "level_index", "noise_seed", "mario_state", "mario_inertia")


class CARLRnaDesignEnv(CARLEnv):
    env_id = "rna_design"
    bench_names = ("mutation_threshold", "reward_exponent", "state_radius", "dataset", "target_structure_ids")


CLASSES: dict[str, type[CARLEnv]] = {
    c.__name__: c
    for c in (
        CARLCartPole, CARLPendulum, CARLAcrobot, CARLMountainCar, CARLMountainCarContinuous, CARLLunarLander,
        CARLBipedalWalker, CARLVehicleRacing, CARLBraxAnt, CARLBraxHalfcheetah, CARLBraxHumanoid, CARLBraxHopper,
        CARLBraxWalker2d, CARLBraxInvertedPendulum, CARLBraxInvertedDoublePendulum, CARLBraxReacher, CARLMarioEnv,
        CARLRnaDesignEnv,
    )
}

__all__ = [*CLASSES, "CLASSES"]
