//! carl-spec's integration tests, one harness (one binary to link): the registry of every
//! family, the CLI, the contextual wrapper, VecEnv, the audit, renders and experiments.

mod audit;
mod bench_cli;
mod bipedal_walker;
mod cli;
mod common;
mod context_noise;
mod contextual;
mod control_tasks_vs_mujoco;
mod curriculum;
mod evaluate;
mod fetch;
mod fold_cli;
mod goal_option;
mod golden;
mod grasp;
mod hostile_input;
mod hostile_limits;
mod humanoid;
mod instances;
mod isolation;
mod landing_in_space;
mod lunar_lander;
mod planar_walkers_vs_mujoco;
mod plot;
mod render;
mod rna_design_options;
mod robots;
mod robots_vs_mujoco;
mod rollout;
mod runtime_registry;
mod schedules;
mod ur5e;
mod vec_env;
mod vec_env_modes;
mod vehicle_racing;
