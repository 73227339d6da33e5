//! CARL's dm_control family: domains of the DeepMind Control Suite (dm_control 1.0.50) with
//! carl-bench 1.1.1's context features, on the articulated-body engine ([`carl_articulated`]).
//!
//! * [`mjcf`]: the models, converted from dm_control's own XML by `scripts/dmc_models.py`
//!   (MuJoCo compiles them; `models/<domain>.json` holds the compiled fields), loaded into a
//!   [`carl_articulated::Model`] with the family's context features applied;
//! * [`physics`]: [`physics::Physics`], the simulation an environment steps (dm_control's
//!   name), with the plumbing the five share: the control step's substeps, the divergence
//!   check and rollback, the state (`qpos`, `qvel`, `act`, then the environment's own entries)
//!   and resets from [`carl_articulated::Data::reset`]; and the observation's `Env` methods;
//! * [`rewards`]: dm_control's `rewards.tolerance` and its sigmoids;
//! * [`finger`]: `dmc_finger` (dm_control's `finger` domain, tasks `spin`, `turn_easy`,
//!   `turn_hard`);
//! * [`point_mass`]: `dmc_point_mass` (dm_control's `point_mass` domain, tasks `easy` and
//!   `hard`);
//! * [`quadruped`]: `dmc_quadruped` (dm_control's `quadruped` domain, tasks `walk` and `run`);
//! * [`walker`]: `dmc_walker` (dm_control's `walker` domain, tasks `walk`, `stand`, `run`);
//! * [`fish`]: `dmc_fish` (dm_control's `fish` domain, tasks `swim` and `upright`);
//! * [`registry`]: the family's registrations.
//!
//! Each environment steps dm_control's control step (the physics step times dm_control's
//! substeps) for dm_control's 1000-step episodes; its observation is dm_control's flat
//! observation (the task's dict in order), float64.

pub mod finger;
pub mod fish;
pub mod mjcf;
pub mod physics;
pub mod point_mass;
pub mod quadruped;
pub mod registry;
pub mod rewards;
pub mod walker;

pub use registry::REGISTRATIONS;
