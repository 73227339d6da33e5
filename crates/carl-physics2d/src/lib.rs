//! A small 2-D rigid-body engine with Box2D 2.3's semantics, for the Box2D environments
//! (Gymnasium 1.4 runs box2d-py 2.3.x): sequential impulses with warm starting, a two-point
//! block solver for contacts, non-linear (NGS) position correction, revolute joints with
//! velocity motors and Box2D 2.3's limit states, Box2D's collision manifolds with feature ids,
//! fat-box broad phase, contact begin/end events in Box2D's order, and continuous collision
//! (Box2D's `SolveTOI`: dynamic-versus-static sub-steps, built on `distance` (GJK) and `toi`
//! (conservative advancement)).
//!
//! Written from Erin Catto's papers and GDC talks ("Iterative Dynamics with Temporal
//! Coherence", "Modeling and Solving Constraints", "Computing Distance", "Continuous
//! Collision") and Box2D's documented behaviour; constants and the order of operations follow
//! Box2D 2.3 (© Erin Catto, zlib licence), whose source was read to learn them. No Box2D code is
//! translated file for file.
//!
//! **Precision.** Everything is `f64`: Box2D runs in `f32`, but the walker's trajectories are
//! chaotic either way (a one-ulp change diverges within a few hundred steps), so matching
//! Box2D step for step over an episode is out of reach in any precision; `f64` keeps
//! `state()`/`set_state()` exact and the analytic tests tight.
//!
//! **Layout.** Bodies, fixtures, joints and contacts live in `Vec`s of the [`world::World`]
//! and refer to each other by index; the world is a plain value (`Clone`), with no shared or
//! global state. Box2D's lists run newest first; the world walks its vectors backwards where
//! order matters.
//!
//! **Not modelled**: sleeping, sensors, collision groups, shapes other than convex polygons
//! and lone two-sided edges, joints other than revolute, damping.

pub mod body;
pub mod collide;
pub mod contact_solver;
pub mod distance;
pub mod math;
pub mod revolute;
pub mod settings;
pub mod shapes;
pub mod toi;
pub mod world;

pub use body::{Body, BodyKind};
pub use math::{V2, v2};
pub use revolute::{RevoluteDef, RevoluteJoint};
pub use shapes::{Polygon, Shape};
pub use world::{ContactEvent, Filter, FixtureDef, World};
