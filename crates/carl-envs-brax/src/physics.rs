//! The physics behind a robot task: a rapier3d world or the articulated-body engine, chosen by
//! the side file's `engine` (and HalfCheetah's `rapier` option). The task calls the same
//! operations on each.

use std::sync::Arc;

use super::articulated::{ArticulatedSystem, ArticulatedWorld};
use super::model::{Engine, ModelError, RobotModel};
use super::params::RobotParams;
use super::world::{Configuration, RobotWorld};

/// One instance's physics.
#[derive(Debug)]
pub enum Physics {
    Rapier(Box<RobotWorld>),
    Articulated(Box<ArticulatedWorld>),
}

/// What a task builds its worlds from: the rapier world is rebuilt from model and context,
/// the articulated one from its prepared system (shared by all of the task's worlds).
#[derive(Debug, Clone)]
pub enum PhysicsBuilder {
    Rapier,
    Articulated(Arc<ArticulatedSystem>),
}

impl PhysicsBuilder {
    /// The builder for `model` under `params`, on the side file's engine (a model the
    /// articulated engine cannot take is refused with the reason).
    pub fn for_model(model: &RobotModel, params: &RobotParams) -> Result<Self, ModelError> {
        match model.side.engine {
            Engine::Rapier => Ok(PhysicsBuilder::Rapier),
            Engine::Articulated => {
                let sys = ArticulatedSystem::new(model, params).map_err(|e| ModelError::Side {
                    robot: model.name,
                    message: format!("\"engine\": \"articulated\": {e}"),
                })?;
                Ok(PhysicsBuilder::Articulated(Arc::new(sys)))
            }
        }
    }

    pub fn build(&self, model: &RobotModel, params: &RobotParams, q: &Configuration) -> Physics {
        match self {
            PhysicsBuilder::Rapier => Physics::Rapier(Box::new(RobotWorld::build(model, params, q))),
            PhysicsBuilder::Articulated(sys) => Physics::Articulated(Box::new(ArticulatedWorld::new(sys.clone(), q))),
        }
    }
}

impl Physics {
    pub fn configuration(&self) -> Configuration {
        match self {
            Physics::Rapier(w) => w.configuration(),
            Physics::Articulated(w) => w.configuration(),
        }
    }

    /// `n` physics steps under the same controls (an environment step's frame skip).
    pub fn steps(&mut self, ctrl: &[f32], n: usize) {
        match self {
            Physics::Rapier(w) => (0..n).for_each(|_| w.step(ctrl)),
            Physics::Articulated(w) => w.steps(ctrl, n),
        }
    }

    pub fn is_sane(&self, max_speed: f64) -> bool {
        match self {
            Physics::Rapier(w) => w.is_sane(max_speed),
            Physics::Articulated(w) => w.is_sane(max_speed),
        }
    }

    pub fn contact_wrenches(&self, out: &mut [f64]) {
        match self {
            Physics::Rapier(w) => w.contact_wrenches(out),
            Physics::Articulated(w) => w.contact_wrenches(out),
        }
    }

    pub fn actuator_forces(&self, ctrl: &[f32], out: &mut [f64]) {
        match self {
            Physics::Rapier(w) => w.actuator_forces(ctrl, out),
            Physics::Articulated(w) => w.actuator_forces(ctrl, out),
        }
    }

    pub fn center_of_mass(&self) -> [f64; 3] {
        match self {
            Physics::Rapier(w) => w.center_of_mass(),
            Physics::Articulated(w) => w.center_of_mass(),
        }
    }

    /// Generalized constraint forces of the last step (MuJoCo's `qfrc_constraint`), one per
    /// coordinate; the articulated engine's (zeros on rapier, whose impulses are not exposed).
    pub fn constraint_forces(&self, out: &mut [f64]) {
        match self {
            Physics::Rapier(_) => out.fill(0.0),
            Physics::Articulated(w) => w.constraint_forces(out),
        }
    }

    /// World position of the point `local` (link frame) of link `i`.
    pub fn link_point(&self, i: usize, local: [f64; 3]) -> [f64; 3] {
        match self {
            Physics::Rapier(w) => {
                let p = w.link_pose(i).transform_point(rapier3d::prelude::Vector::new(
                    local[0] as f32,
                    local[1] as f32,
                    local[2] as f32,
                ));
                [f64::from(p.x), f64::from(p.y), f64::from(p.z)]
            }
            Physics::Articulated(w) => w.link_point(i, local),
        }
    }

    /// The rapier world, if this is one (the com-based observation terms need it).
    pub fn rapier(&self) -> Option<&RobotWorld> {
        match self {
            Physics::Rapier(w) => Some(w),
            Physics::Articulated(_) => None,
        }
    }

    pub fn articulated(&self) -> Option<&ArticulatedWorld> {
        match self {
            Physics::Articulated(w) => Some(w),
            _ => None,
        }
    }

    pub fn render(&self) -> carl_pixels::Frame {
        match self {
            Physics::Rapier(w) => super::render::render_world(w),
            Physics::Articulated(w) => super::render::render_articulated(w),
        }
    }
}
