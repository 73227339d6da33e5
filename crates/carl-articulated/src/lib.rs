//! A reduced-coordinate 3-D articulated-body engine with MuJoCo's semantics, in f64.
//!
//! A [`Model`] is a tree of bodies with free, hinge and slide joints, collision geoms (plane,
//! sphere, capsule, cylinder, box, ellipsoid), fixed tendons and MuJoCo's general actuators, read by loaders kept apart from the engine; a [`Data`]
//! is one instance's state and preallocated buffers (`Clone + Send`, no global state, no
//! allocation per step). One step is MuJoCo's pipeline:
//!
//! * [`dynamics`]: forward kinematics (quaternions for free joints), composite-rigid-body mass
//!   matrix with armature, recursive Newton–Euler bias forces, passive forces;
//! * [`collision`]: contacts with MuJoCo's pair filters, margins and contact frames;
//! * [`constraint`]: soft contacts and joint limits from `solref`/`solimp`, pyramidal or elliptic
//!   friction cones, Newton on the primal (pyramidal) or projected Gauss–Seidel on the dual
//!   (elliptic), warm-started;
//! * [`sensors`]: MuJoCo's site sensors (velocimeter, gyro, accelerometer, force, torque,
//!   subtree centre of mass) and `mj_rnePostConstraint`;
//! * [`data`]: semi-implicit Euler with implicit joint damping, or RK4.
//!
//! [`math`] holds the small vector, quaternion and spatial-algebra helpers.

pub mod collision;
pub mod constraint;
pub mod data;
pub mod dynamics;
pub mod math;
pub mod model;
pub mod sensors;

pub use collision::Contact;
pub use data::Data;
pub use model::{
    Actuator, Body, Cone, Dynamics, Geom, Integrator, Joint, JointKind, Model, ModelError, Options, Shape, Tendon,
    TendonEquality,
};
pub use sensors::Site;
