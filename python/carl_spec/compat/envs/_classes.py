"""carl-bench 1.1.1's environment classes over carl-spec's runtimes (defined here, exported from their
carl-bench module twins, e.g. `carl_spec.compat.envs.gymnasium.classic_control.carl_pendulum`).
Each class names its carl-spec runtime, carl-bench's names of the features carl-spec has (in
carl-bench's order; carl-spec's spec lists them as aliases where they differ), and the carl-bench
features carl-spec does not have, with the reason a user gets when passing one.
"""

from __future__ import annotations

from typing import Any

from ..carl_env import CARLEnv

_START = "carl-spec starts {env} exactly as Gymnasium does (same initial state for the same seed), so it has no {what} features"
_ROBOT = (
    "carl-spec's {env} (rapier3d runtime after Brax 2021) has no such feature; its physics features are "
    "gravity, friction, ang_damping (angular_damping), mass_torso (torso_mass), joint_stiffness, "
    "joint_angular_damping, actuator_strength and the body masses"
)


#: carl-bench's goal features of its walkers, in its order (they act with the `goal` option).
_GOAL_NAMES = ("target_distance", "target_direction", "target_radius")


def _robot_only(env: str) -> dict[str, str]:
    why = _ROBOT.format(env=env)
    return {"elasticity": why, "viscosity": why}


class _Robot(CARLEnv):
    """carl-bench's Brax walkers: `use_language_goals`, and its goal-directed variant (carl-spec's
    `goal` option) whenever a context names a goal feature (target_distance, target_direction,
    target_radius) or a goal wrapper of `brax_walker_goal_wrapper` wraps the env."""

    def __init__(self, *args: Any, use_language_goals: bool = False, batch_size: int = 1, **kwargs: Any) -> None:
        if batch_size != 1:
            raise ValueError(f"{type(self).__name__}: batch_size={batch_size}: use carl_spec.make_vec({self.env_id!r}, num_envs)")
        from .brax.brax_walker_goal_wrapper import GOAL_FEATURES, BraxLanguageWrapper, BraxWalkerGoalWrapper

        contexts = kwargs.get("contexts") if "contexts" in kwargs else (args[1] if len(args) > 1 else None)
        self._goal = bool(use_language_goals) or (
            isinstance(contexts, dict) and any(isinstance(c, dict) and GOAL_FEATURES & set(c) for c in contexts.values())
        )
        self.use_language_goals = bool(use_language_goals)
        self.env: Any = None
        self._tracker: Any = None
        super().__init__(*args, **kwargs)
        if use_language_goals:
            self._ctor["use_language_goals"] = True
        if self._goal:
            self.env = BraxWalkerGoalWrapper(self, self.env_id, "")
            if use_language_goals:
                self.env = BraxLanguageWrapper(self.env)

    @classmethod
    def get_default_context(cls) -> dict[str, Any]:
        """carl-bench's: the default context without the goal features."""
        from .brax.brax_walker_goal_wrapper import GOAL_FEATURES

        return {k: v for k, v in super().get_default_context().items() if k not in GOAL_FEATURES}

    @classmethod
    def get_default_goal_context(cls) -> dict[str, Any]:
        """carl-bench's: the default context with the goal features."""
        return super().get_default_context()

    def _env_options(self, canonical_contexts: list[dict[str, Any]]) -> dict[str, Any] | None:
        return {"goal": True} if getattr(self, "_goal", False) else None

    def _compat(self, canonical: dict[str, float]) -> dict[str, Any]:
        from .brax.brax_walker_goal_wrapper import GOAL_FEATURES

        out = super()._compat(canonical)
        return out if self._goal else {k: v for k, v in out.items() if k not in GOAL_FEATURES}

    def _enable_goal(self) -> None:
        """Rebuild the context set with the goal option (a goal wrapper wrapped this env)."""
        if self._goal:
            return
        self._goal = True
        self._set_contexts(self._ctor.get("contexts"))
        first = next(iter(self._contexts.values()))
        self.obs_context_features = [*self.obs_context_features, *(n for n in first if n not in self.obs_context_features)]
        self.observation_space = self.get_observation_space(self.obs_context_features)

    def _enable_language(self) -> None:
        self._enable_goal()
        self.use_language_goals = True
        self.observation_space = self.get_observation_space(self.obs_context_features)

    @property
    def position(self) -> Any:
        """carl-bench's goal wrapper's `position` (None without the goal or before a reset)."""
        tracker = getattr(self, "_tracker", None)
        return None if tracker is None else tracker.position

    def get_observation_space(self, obs_context_feature_names: list[str] | None = None) -> Any:
        from gymnasium import spaces

        space = super().get_observation_space(obs_context_feature_names)
        if getattr(self, "use_language_goals", False):
            from .brax.brax_walker_goal_wrapper import GOAL_TEXT

            space = spaces.Dict({"obs": spaces.Dict({"obs": space["obs"], "goal": GOAL_TEXT}), "context": space["context"]})
        return space

    def _goal_step(self, obs: dict[str, Any], info: dict[str, Any]) -> dict[str, Any]:
        goal = self._runtime().goal_info() if self._goal else None
        if goal is None:
            return obs
        info.update(goal)
        tracker = getattr(self, "_tracker", None)
        if tracker is not None:
            tracker._track(goal, self.context or {})
        if self.use_language_goals:
            from .brax.brax_walker_goal_wrapper import goal_description

            obs["obs"] = {"obs": obs["obs"], "goal": goal_description(self.context or {})}
        return obs

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> tuple[dict[str, Any], dict[str, Any]]:
        obs, info = super().reset(seed=seed, options=options)
        return self._goal_step(obs, info), info

    def step(self, action: Any) -> tuple[dict[str, Any], Any, bool, bool, dict[str, Any]]:
        obs, reward, terminated, truncated, info = super().step(action)
        return self._goal_step(obs, info), reward, terminated, truncated, info


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
    bench_names = ("gravity", "friction", "ang_damping", "mass_torso", *_GOAL_NAMES)
    bench_only = _robot_only("ant")


class CARLBraxHalfcheetah(_Robot):
    env_id = "half_cheetah"
    bench_names = (
        "gravity", "friction", "ang_damping", "mass_torso", "mass_bthigh", "mass_bshin", "mass_bfoot",
        "mass_fthigh", "mass_fshin", "mass_ffoot", *_GOAL_NAMES,
    )
    bench_only = _robot_only("half_cheetah")


class CARLBraxHumanoid(_Robot):
    env_id = "humanoid"
    bench_names = (
        "gravity", "friction", "ang_damping", "mass_torso", "mass_lwaist", "mass_pelvis", "mass_right_thigh",
        "mass_right_shin", "mass_left_thigh", "mass_left_shin", "mass_right_upper_arm", "mass_right_lower_arm",
        "mass_left_upper_arm", "mass_left_lower_arm", *_GOAL_NAMES,
    )
    bench_only = _robot_only("humanoid")


class CARLBraxHopper(_Robot):
    env_id = "hopper"
    bench_names = ("gravity", "friction", "elasticity", "ang_damping", "viscosity", "mass_torso", "mass_thigh",
                   "mass_leg", "mass_foot", *_GOAL_NAMES)


class CARLBraxWalker2d(_Robot):
    env_id = "walker2d"
    bench_names = ("gravity", "friction", "elasticity", "ang_damping", "viscosity", "mass_torso", "mass_thigh",
                   "mass_leg", "mass_foot", "mass_thigh_left", "mass_leg_left", "mass_foot_left", *_GOAL_NAMES)


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


class CARLBraxPusher(_Robot):
    env_id = "pusher"
    bench_names = (
        "gravity", "friction", "elasticity", "ang_damping", "viscosity", "mass_r_shoulder_pan_link",
        "mass_r_shoulder_lift_link", "mass_r_upper_arm_roll_link", "mass_r_elbow_flex_link",
        "mass_r_forearm_roll_link", "mass_r_wrist_flex_link", "mass_r_wrist_roll_link", "mass_object",
        "goal_position_x", "goal_position_y", "goal_position_z",
    )


class CARLBraxHumanoidStandup(_Robot):
    env_id = "humanoid_standup"
    bench_names = (
        "gravity", "friction", "elasticity", "ang_damping", "viscosity", "mass_torso", "mass_lwaist", "mass_pelvis",
        "mass_right_thigh", "mass_right_shin", "mass_left_thigh", "mass_left_shin", "mass_right_upper_arm",
        "mass_right_lower_arm", "mass_left_upper_arm", "mass_left_lower_arm",
    )


_DMC_PHYSICS = (
    "gravity", "friction_torsional", "friction_rolling", "friction_tangential", "timestep", "joint_damping",
    "joint_stiffness", "actuator_strength", "density", "viscosity", "geom_density", "wind_x", "wind_y", "wind_z",
)


class _Dmc(CARLEnv):
    """carl-bench's dm_control classes (`CARLDmcEnv`): its `task` argument names the dm_control task
    (`tasks`: carl-bench's task name -> carl-spec's runtime options)."""

    tasks: dict[str, dict[str, Any]] = {}
    task: str = ""

    def __init__(self, *args: Any, task: str | None = None, **kwargs: Any) -> None:
        task = type(self).task if task is None else task
        if task not in self.tasks:
            raise ValueError(f"{type(self).__name__}: task {task!r} is not one of {', '.join(self.tasks)}")
        self.task = task
        super().__init__(*args, **kwargs)
        self._ctor["task"] = task

    def _env_options(self, canonical_contexts: list[dict[str, Any]]) -> dict[str, Any] | None:
        return self.tasks[self.task] or None


class CARLDmcPointMassEnv(_Dmc):
    env_id = "dmc_point_mass"
    domain = "pointmass"
    task = "easy_pointmass"
    tasks = {"easy_pointmass": {}, "hard_pointmass": {"hard": True}}
    bench_names = (*_DMC_PHYSICS, "mass", "starting_x", "starting_y", "target_x", "target_y", "area_size")


class CARLDmcWalkerEnv(_Dmc):
    env_id = "dmc_walker"
    domain = "walker"
    task = "walk_context"
    tasks = {"walk_context": {}, "stand_context": {"move_speed": 0.0}, "run_context": {"move_speed": 8.0}}
    bench_names = _DMC_PHYSICS


class CARLDmcFingerEnv(_Dmc):
    env_id = "dmc_finger"
    domain = "finger"
    task = "spin_context"
    tasks = {
        "spin_context": {},
        "turn_easy_context": {"target_radius": 0.07},
        "turn_hard_context": {"target_radius": 0.03},
    }
    bench_names = (*_DMC_PHYSICS, "limb_length_0", "limb_length_1", "spinner_radius", "spinner_length")


class CARLDmcFishEnv(_Dmc):
    env_id = "dmc_fish"
    domain = "fish"
    task = "swim_context"
    tasks = {"swim_context": {}, "upright_context": {"upright": True}}
    bench_names = _DMC_PHYSICS


class CARLDmcQuadrupedEnv(_Dmc):
    env_id = "dmc_quadruped"
    domain = "quadruped"
    task = "walk_context"
    tasks = {"walk_context": {}, "run_context": {"move_speed": 5.0}}
    bench_names = _DMC_PHYSICS


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
        CARLBraxWalker2d, CARLBraxInvertedPendulum, CARLBraxInvertedDoublePendulum, CARLBraxReacher, CARLBraxPusher,
        CARLBraxHumanoidStandup, CARLDmcFingerEnv, CARLDmcFishEnv, CARLDmcPointMassEnv, CARLDmcQuadrupedEnv,
        CARLDmcWalkerEnv, CARLMarioEnv, CARLRnaDesignEnv,
    )
}

__all__ = [*CLASSES, "CLASSES"]
