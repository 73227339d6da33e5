//! Box2D 2.3's tuning constants (`b2Settings.h`), in SI units. Names follow Box2D's, without the
//! `b2_` prefix.

use std::f64::consts::PI;

/// Collision and constraint tolerance (m).
pub const LINEAR_SLOP: f64 = 0.005;
/// Collision and constraint tolerance (rad), 2°.
pub const ANGULAR_SLOP: f64 = 2.0 / 180.0 * PI;
/// Skin of polygons and edges (m): shapes touch when their cores are closer than two skins.
pub const POLYGON_RADIUS: f64 = 2.0 * LINEAR_SLOP;
/// Largest position correction per position iteration (m).
pub const MAX_LINEAR_CORRECTION: f64 = 0.2;
/// Largest angular correction per position iteration (rad), 8°.
pub const MAX_ANGULAR_CORRECTION: f64 = 8.0 / 180.0 * PI;
/// Fraction of the overlap the position solver removes per iteration.
pub const BAUMGARTE: f64 = 0.2;
/// The same inside a continuous-collision sub-step.
pub const TOI_BAUMGARTE: f64 = 0.75;
/// Closing speeds below this (m/s) are inelastic whatever the restitution.
pub const VELOCITY_THRESHOLD: f64 = 1.0;
/// Largest translation of a body in one step (m).
pub const MAX_TRANSLATION: f64 = 2.0;
/// Largest rotation of a body in one step (rad).
pub const MAX_ROTATION: f64 = 0.5 * PI;
/// Largest number of continuous-collision sub-steps per contact and step.
pub const MAX_SUB_STEPS: u32 = 8;
/// Contacts of one continuous-collision island at most.
pub const MAX_TOI_CONTACTS: usize = 32;
/// Fattening of the broad-phase boxes (m).
pub const AABB_EXTENSION: f64 = 0.1;
/// The broad-phase boxes also reach this many displacements ahead of a moving body.
pub const AABB_MULTIPLIER: f64 = 2.0;
/// Two-point manifolds whose normal mass is worse conditioned than this use one point.
pub const MAX_CONDITION_NUMBER: f64 = 1000.0;
/// Box2D's `b2_epsilon` (`FLT_EPSILON`).
pub const EPSILON: f64 = f32::EPSILON as f64;
