//! The model: a tree of bodies (body 0 is the world), their joints, collision geoms, fixed
//! tendons and actuators (MuJoCo's `<general>`: joint or tendon transmission, gain, affine bias,
//! filter activation dynamics), and the simulation options, all with MuJoCo's meaning (`mjModel`'s fields of the
//! same names). Loaders (URDF, fixtures) fill the public description and call [`Model::new`],
//! which checks it (a clear [`ModelError`] for bad input) and derives the layout the engine
//! uses: coordinate addresses, the degree-of-freedom tree, candidate collision pairs with
//! their mixed contact parameters, and MuJoCo's `body_invweight0` / `dof_invweight0` (the
//! diagonal approximations its constraint regularizer uses), computed at `qpos0`.

use crate::math::{Quat, V3, quat_normalize};

/// How a body moves relative to its parent.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Six coordinates of velocity (world linear velocity of the body origin, then local angular
    /// velocity), seven of position (world position, unit quaternion `[w, x, y, z]`).
    Free,
    /// Rotation about `axis` through `pos` (body frame).
    Hinge,
    /// Translation along `axis`.
    Slide,
}

impl JointKind {
    pub fn nq(self) -> usize {
        match self {
            JointKind::Free => 7,
            _ => 1,
        }
    }
    pub fn nv(self) -> usize {
        match self {
            JointKind::Free => 6,
            _ => 1,
        }
    }
}

/// `solref`: `[timeconst, dampratio]`, or `[−stiffness, −damping]` when negative.
pub type SolRef = [f64; 2];
/// `solimp`: `[dmin, dmax, width, midpoint, power]`.
pub type SolImp = [f64; 5];

pub const SOLREF_DEFAULT: SolRef = [0.02, 1.0];
pub const SOLIMP_DEFAULT: SolImp = [0.9, 0.95, 0.001, 0.5, 2.0];

/// One body: pose in its parent's frame and inertial properties in its own frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub name: String,
    /// Index of the parent body (smaller than this body's index; the world's is 0).
    pub parent: usize,
    pub pos: V3,
    pub quat: Quat,
    pub mass: f64,
    /// Centre of mass in the body frame.
    pub ipos: V3,
    /// Orientation of the principal inertia axes in the body frame.
    pub iquat: Quat,
    /// Principal moments of inertia about the centre of mass.
    pub inertia: V3,
    /// Dry friction (N) of the body sliding on a plane normal to gravity that carries its
    /// weight: two bounded rows on its centre of mass's velocity along the plane (a carl
    /// extension for a table under an arm; 0, MuJoCo's, has none).
    pub dryfriction: f64,
}

impl Body {
    /// A body with the given pose and inertia, principal axes along the body frame.
    pub fn new(name: &str, parent: usize, pos: V3, mass: f64, ipos: V3, inertia: V3) -> Body {
        Body {
            name: name.to_string(),
            parent,
            pos,
            quat: crate::math::QUAT_IDENTITY,
            mass,
            ipos,
            iquat: crate::math::QUAT_IDENTITY,
            inertia,
            dryfriction: 0.0,
        }
    }
}

/// One joint of a body (a body may have several, applied in order, as MuJoCo's).
#[derive(Debug, Clone, PartialEq)]
pub struct Joint {
    pub name: String,
    pub body: usize,
    pub kind: JointKind,
    /// Anchor in the body frame.
    pub pos: V3,
    /// Axis in the body frame (normalized by [`Model::new`]); unused by a free joint.
    pub axis: V3,
    /// Reflected rotor inertia added to the mass matrix diagonal.
    pub armature: f64,
    /// Viscous damping (implicit under the Euler integrator).
    pub damping: f64,
    /// Spring `−stiffness · (q − springref)` (hinge and slide).
    pub stiffness: f64,
    pub springref: f64,
    /// MuJoCo's `ref`: the coordinate value of the body's modelled pose.
    pub qpos0: f64,
    /// Limits `[lo, hi]` when limited (hinge and slide).
    pub range: Option<[f64; 2]>,
    /// The limit activates this far inside the range.
    pub margin: f64,
    pub solref_limit: SolRef,
    pub solimp_limit: SolImp,
    /// MuJoCo's `frictionloss`: dry friction (N or N·m) of the coordinate, a row bounded by it
    /// with `solreffriction`/`solimpfriction`.
    pub frictionloss: f64,
    pub solref_friction: SolRef,
    pub solimp_friction: SolImp,
    /// Restitution of the limit rows (a carl extension; 0, MuJoCo's, is inelastic): an
    /// approaching limit's reference acceleration asks for at least this fraction of the
    /// approach speed back as separation speed within the step.
    pub restitution: f64,
}

impl Joint {
    /// A joint with MuJoCo's defaults: no armature, damping, spring or limit.
    pub fn new(name: &str, body: usize, kind: JointKind, axis: V3) -> Joint {
        Joint {
            name: name.to_string(),
            body,
            kind,
            pos: [0.0; 3],
            axis,
            armature: 0.0,
            damping: 0.0,
            stiffness: 0.0,
            springref: 0.0,
            qpos0: 0.0,
            range: None,
            margin: 0.0,
            solref_limit: SOLREF_DEFAULT,
            solimp_limit: SOLIMP_DEFAULT,
            frictionloss: 0.0,
            solref_friction: SOLREF_DEFAULT,
            solimp_friction: SOLIMP_DEFAULT,
            restitution: 0.0,
        }
    }
}

/// Collision shape, in MuJoCo's sizes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Shape {
    /// The plane `z = 0` of the geom frame, normal `+z` (infinite).
    Plane,
    Sphere {
        radius: f64,
    },
    /// A segment along the geom's local z of half-length `half_length`, inflated by `radius`.
    Capsule {
        radius: f64,
        half_length: f64,
    },
    /// A solid cylinder along the geom's local z of radius `radius` and half-height `half_length`.
    Cylinder {
        radius: f64,
        half_length: f64,
    },
    /// Half-sizes along the geom's local axes.
    Box {
        half: V3,
    },
    /// An ellipsoid of semi-axes `radii` along the geom's local axes.
    Ellipsoid {
        radii: V3,
    },
}

impl Shape {
    /// Which [`crate::collision`] routine handles it, in MuJoCo's type order.
    pub(crate) fn order(&self) -> u8 {
        match self {
            Shape::Plane => 0,
            Shape::Sphere { .. } => 2,
            Shape::Capsule { .. } => 3,
            Shape::Ellipsoid { .. } => 4,
            Shape::Cylinder { .. } => 5,
            Shape::Box { .. } => 6,
        }
    }
    /// Radius of a sphere around the geom frame's origin enclosing the shape.
    pub(crate) fn bounding_radius(&self) -> f64 {
        match *self {
            Shape::Plane => f64::INFINITY,
            Shape::Sphere { radius } => radius,
            Shape::Capsule { radius, half_length } => radius + half_length,
            Shape::Cylinder { radius, half_length } => radius.hypot(half_length),
            Shape::Box { half } => crate::math::norm(half),
            Shape::Ellipsoid { radii } => radii[0].max(radii[1]).max(radii[2]),
        }
    }
}

/// One collision geom attached to a body.
#[derive(Debug, Clone, PartialEq)]
pub struct Geom {
    pub name: String,
    pub body: usize,
    pub shape: Shape,
    pub pos: V3,
    pub quat: Quat,
    pub contype: u32,
    pub conaffinity: u32,
    /// 1 (frictionless) or 3 (sliding friction).
    pub condim: u8,
    /// `[slide, spin, roll]` (only the sliding coefficient acts with condim 3).
    pub friction: [f64; 3],
    pub solmix: f64,
    pub solref: SolRef,
    pub solimp: SolImp,
    pub margin: f64,
    pub gap: f64,
    /// Restitution of its contacts (a carl extension; 0, MuJoCo's, is inelastic; a pair takes
    /// the larger), as a joint's [`Joint::restitution`].
    pub restitution: f64,
}

impl Geom {
    /// A geom with MuJoCo's defaults (contype = conaffinity = 1, condim 3, friction 1).
    pub fn new(name: &str, body: usize, shape: Shape, pos: V3) -> Geom {
        Geom {
            name: name.to_string(),
            body,
            shape,
            pos,
            quat: crate::math::QUAT_IDENTITY,
            contype: 1,
            conaffinity: 1,
            condim: 3,
            friction: [1.0, 0.005, 0.0001],
            solmix: 1.0,
            solref: SOLREF_DEFAULT,
            solimp: SOLIMP_DEFAULT,
            margin: 0.0,
            gap: 0.0,
            restitution: 0.0,
        }
    }
}

/// Activation dynamics of an actuator (MuJoCo's `dyntype` with `dynprm[0]` = `tau`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Dynamics {
    /// Stateless: the force acts on the (clamped) control directly.
    None,
    /// A first-order filter: `act_dot = (ctrl − act) / tau`, `act` advanced by the integrator
    /// (Euler: `act += h · act_dot`; RK4: with the stages, as qvel).
    Filter { tau: f64 },
    /// The same filter integrated exactly over a step at the end of it:
    /// `act += act_dot · tau · (1 − exp(−h / tau))` (MuJoCo's `filterexact`).
    FilterExact { tau: f64 },
}

/// MuJoCo's `<general>` actuator (`<motor>` and `<position>` are its shorthands, see
/// [`Actuator::motor`] and [`Actuator::position`]).
///
/// Transmission: the hinge or slide joint `joint`, or the fixed tendon [`Model::with_tendons`]
/// assigns it, with `gear`; MuJoCo's `actuator_length` is `gear · q` (`gear · tendon length`)
/// and its velocity `gear · q̇`. Force: `gain · input + bias[0] + bias[1] · length + bias[2] ·
/// velocity` (gain `fixed`, bias `affine`; all-zero `bias` is `none`), `input` the control
/// clipped to `ctrlrange` (stateless) or the activation (filter dynamics), clipped to
/// `forcerange`; the generalized force is `gear · force` on the joint (`gear · coef · force`
/// on each joint of the tendon).
#[derive(Debug, Clone, PartialEq)]
pub struct Actuator {
    pub name: String,
    pub joint: usize,
    pub gear: f64,
    /// Controls are clipped to it when present (MuJoCo's `ctrllimited`).
    pub ctrlrange: Option<[f64; 2]>,
    /// The force is clipped to it when present (MuJoCo's `forcelimited`).
    pub forcerange: Option<[f64; 2]>,
    /// The activation is clipped to it after each update when present (`actlimited`).
    pub actrange: Option<[f64; 2]>,
    /// `gainprm[0]` (gain type `fixed`).
    pub gain: f64,
    /// `biasprm[0..3]` (bias type `affine`; zeros: `none`).
    pub bias: [f64; 3],
    pub dynamics: Dynamics,
}

impl Actuator {
    /// MuJoCo's `<motor>`: force `ctrl` (gain 1, no bias, no dynamics).
    pub fn motor(name: &str, joint: usize, gear: f64, ctrlrange: Option<[f64; 2]>) -> Actuator {
        Actuator {
            name: name.to_string(),
            joint,
            gear,
            ctrlrange,
            forcerange: None,
            actrange: None,
            gain: 1.0,
            bias: [0.0; 3],
            dynamics: Dynamics::None,
        }
    }

    /// MuJoCo's `<position kp kv>` (gear 1): force `kp · ctrl − kp · length − kv · velocity`.
    pub fn position(name: &str, joint: usize, kp: f64, kv: f64, ctrlrange: Option<[f64; 2]>) -> Actuator {
        Actuator {
            gain: kp,
            bias: [0.0, -kp, -kv],
            ..Actuator::motor(name, joint, 1.0, ctrlrange)
        }
    }

    /// Whether it has an activation state (one entry of [`crate::Data::act`]).
    pub fn stateful(&self) -> bool {
        self.dynamics != Dynamics::None
    }
}

/// A fixed tendon (MuJoCo's `<fixed>`): length `Σ coef · q` over hinge and slide joints. An
/// actuator driving it ([`Model::with_tendons`]) exerts `coef · gear · force` on each joint.
/// Passive (MuJoCo's tendon `stiffness` and `damping`): a spring force `stiffness · (lo − L)`
/// below `lengthspring = [lo, hi]`, `stiffness · (hi − L)` above it, none within (a dead band;
/// `lo = hi` is an ordinary spring), and `−damping · L̇`, each exerted as `coef ·` on the joints.
#[derive(Debug, Clone, PartialEq)]
pub struct Tendon {
    pub name: String,
    /// `(joint, coef)` pairs.
    pub joints: Vec<(usize, f64)>,
    pub stiffness: f64,
    pub damping: f64,
    /// MuJoCo's `tendon_lengthspring`; `None` is its default (`springlength="-1"`): the length at
    /// the joints' spring references (`springref`), both ends.
    pub lengthspring: Option<[f64; 2]>,
}

impl Tendon {
    /// A fixed tendon without passive forces.
    pub fn fixed(name: &str, joints: Vec<(usize, f64)>) -> Tendon {
        Tendon {
            name: name.to_string(),
            joints,
            stiffness: 0.0,
            damping: 0.0,
            lengthspring: None,
        }
    }
}

/// A tendon equality (MuJoCo's `<equality><tendon>`): the soft constraint
/// `l₁ − l₁⁰ = p(l₂ − l₂⁰)`, `p(x) = Σₖ polycoefₖ xᵏ` (`l⁰` the tendon's length at `qpos0`), or
/// `l₁ − l₁⁰ = polycoef₀` without a second tendon; one row with its own `solref`/`solimp`, the
/// force of either sign.
#[derive(Debug, Clone, PartialEq)]
pub struct TendonEquality {
    pub name: String,
    pub tendon1: usize,
    pub tendon2: Option<usize>,
    pub polycoef: [f64; 5],
    pub solref: SolRef,
    pub solimp: SolImp,
}

/// Time integration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Integrator {
    /// MuJoCo's default: semi-implicit Euler, joint damping implicit.
    Euler,
    /// Classic fourth-order Runge–Kutta (every stage runs the full forward dynamics, contacts
    /// included, as MuJoCo's `RK4`).
    Rk4,
}

/// Global options (`mjOption`).
#[derive(Debug, Clone, PartialEq)]
pub struct Options {
    pub timestep: f64,
    pub gravity: V3,
    pub integrator: Integrator,
    /// Ratio of frictional to normal constraint impedance.
    pub impratio: f64,
    /// Medium viscosity (MuJoCo's inertia-box Stokes drag).
    pub viscosity: f64,
    /// Medium density (MuJoCo's inertia-box quadratic drag).
    pub density: f64,
    /// Velocity of the medium (world frame): the fluid forces act on each body's velocity
    /// relative to it.
    pub wind: V3,
    /// Newton iterations (pyramidal cones) or projected Gauss–Seidel sweeps (elliptic) at most.
    pub iterations: usize,
    /// Newton stops once the cost's decrease or the gradient's norm, scaled by
    /// `1 / (mean diag M · nv)`, falls below this (MuJoCo's rule); Gauss–Seidel's sweeps once no
    /// force changes by more than this (relative to the largest force).
    pub tolerance: f64,
    /// The friction cone of contacts with friction (MuJoCo's `cone`).
    pub cone: Cone,
}

/// MuJoCo's friction cone (`<option cone=...>`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Cone {
    /// Four rows `J_n ± μ J_tₖ` per condim-3 contact, each force non-negative (MuJoCo's default).
    #[default]
    Pyramidal,
    /// One normal and two friction rows per condim-3 contact, the forces in
    /// `{f_n ≥ 0, ‖(f_t₁, f_t₂)‖ ≤ μ f_n}`.
    Elliptic,
}

impl Default for Options {
    fn default() -> Options {
        Options {
            timestep: 0.002,
            gravity: [0.0, 0.0, -9.81],
            integrator: Integrator::Euler,
            impratio: 1.0,
            viscosity: 0.0,
            density: 0.0,
            wind: [0.0; 3],
            iterations: 200,
            tolerance: 1e-8,
            cone: Cone::Pyramidal,
        }
    }
}

/// Why a model description was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    #[error("body {index} ({name}): {message}")]
    Body {
        index: usize,
        name: String,
        message: String,
    },
    #[error("joint {index} ({name}): {message}")]
    Joint {
        index: usize,
        name: String,
        message: String,
    },
    #[error("geom {index} ({name}): {message}")]
    Geom {
        index: usize,
        name: String,
        message: String,
    },
    #[error("actuator {index} ({name}): {message}")]
    Actuator {
        index: usize,
        name: String,
        message: String,
    },
    #[error("tendon {index} ({name}): {message}")]
    Tendon {
        index: usize,
        name: String,
        message: String,
    },
    #[error("options: {0}")]
    Options(String),
}

/// A candidate collision pair with MuJoCo's mixed contact parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GeomPair {
    /// The geom of lower MuJoCo type first (the contact normal points from it to `g2`).
    pub g1: usize,
    pub g2: usize,
    pub condim: u8,
    pub friction: f64,
    pub margin: f64,
    pub gap: f64,
    pub solref: SolRef,
    pub solimp: SolImp,
    pub restitution: f64,
    /// Contacts this pair can produce at most.
    pub max_contacts: usize,
}

/// A checked model and its derived layout. Built once, shared (read-only) by every
/// [`crate::Data`] simulating it.
#[derive(Debug, Clone)]
pub struct Model {
    pub opt: Options,
    pub bodies: Vec<Body>,
    pub joints: Vec<Joint>,
    pub geoms: Vec<Geom>,
    pub actuators: Vec<Actuator>,
    /// Fixed tendons ([`Model::with_tendons`]; none unless set).
    pub tendons: Vec<Tendon>,
    /// The tendon each actuator drives instead of its joint (`None`: its joint).
    pub actuator_tendon: Vec<Option<usize>>,
    /// Tendon equalities ([`Model::with_tendon_equalities`]; none unless set).
    pub tendon_equalities: Vec<TendonEquality>,
    /// Each tendon's length at `qpos0` and MuJoCo's `tendon_invweight0` (`J M⁻¹ Jᵀ` at `qpos0`).
    pub tendon_length0: Vec<f64>,
    pub tendon_invweight0: Vec<f64>,
    /// Each actuator's entry in [`crate::Data::act`] (`None`: stateless), MuJoCo's
    /// `actuator_actadr`; `na` entries in all, in actuator order.
    pub actuator_actadr: Vec<Option<usize>>,
    pub na: usize,
    /// Each tendon's spring length band (its `lengthspring`, or the default rule's).
    pub tendon_lengthspring: Vec<[f64; 2]>,
    pub nq: usize,
    pub nv: usize,
    /// First position / velocity coordinate of each joint.
    pub jnt_qposadr: Vec<usize>,
    pub jnt_dofadr: Vec<usize>,
    /// The joints of each body, in order.
    pub body_joints: Vec<std::ops::Range<usize>>,
    /// The body and joint of each degree of freedom.
    pub dof_body: Vec<usize>,
    pub dof_joint: Vec<usize>,
    /// The previous degree of freedom on the path to the root (`usize::MAX` at the root).
    pub dof_parent: Vec<usize>,
    /// Each degree of freedom's path to the root, itself first ([`Model::dof_path`]): the
    /// `dof_parent` chains laid out flat, `dof_paths[dof_path_start[i]..dof_path_start[i + 1]]`.
    pub dof_paths: Vec<usize>,
    pub dof_path_start: Vec<usize>,
    /// The last degree of freedom on the path from the root to each body (`usize::MAX` if none).
    pub body_last_dof: Vec<usize>,
    /// The body that each body is welded to (itself if it has joints; 0 for the world).
    pub body_weld: Vec<usize>,
    pub pairs: Vec<GeomPair>,
    /// MuJoCo's `body_invweight0` (translation, rotation) and `dof_invweight0`.
    pub body_invweight0: Vec<[f64; 2]>,
    pub dof_invweight0: Vec<f64>,
    /// Default coordinates (`qpos0`: joint `ref`s, free joints at the body's modelled pose).
    pub qpos0: Vec<f64>,
    pub max_contacts: usize,
    pub max_rows: usize,
    /// Rotation matrices of each body's `iquat` and each geom's `quat`.
    pub body_imat: Vec<crate::math::M3>,
    pub geom_mat: Vec<crate::math::M3>,
}

fn finite3(v: V3) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl Model {
    /// Whether the constraints are solved by projected Gauss–Seidel on the dual (elliptic
    /// cones) rather than by Newton on the primal.
    pub(crate) fn solves_dual(&self) -> bool {
        self.opt.cone == Cone::Elliptic
    }

    /// The degrees of freedom on `dof`'s path to the root, `dof` first (empty for `usize::MAX`,
    /// a body without degrees of freedom on its path).
    #[inline]
    pub fn dof_path(&self, dof: usize) -> &[usize] {
        if dof >= self.nv {
            return &[];
        }
        &self.dof_paths[self.dof_path_start[dof]..self.dof_path_start[dof + 1]]
    }

    /// Check a description and derive its layout.
    pub fn new(
        opt: Options,
        bodies: Vec<Body>,
        joints: Vec<Joint>,
        geoms: Vec<Geom>,
        actuators: Vec<Actuator>,
    ) -> Result<Model, ModelError> {
        let oerr = |m: &str| Err(ModelError::Options(m.to_string()));
        if !(opt.timestep.is_finite() && opt.timestep > 0.0) {
            return oerr("timestep must be finite and positive");
        }
        if !finite3(opt.gravity) {
            return oerr("gravity must be finite");
        }
        if !(opt.impratio.is_finite() && opt.impratio > 0.0) {
            return oerr("impratio must be finite and positive");
        }
        if !(opt.viscosity.is_finite() && opt.viscosity >= 0.0) {
            return oerr("viscosity must be finite and non-negative");
        }
        if !(opt.density.is_finite() && opt.density >= 0.0) {
            return oerr("density must be finite and non-negative");
        }
        if !finite3(opt.wind) {
            return oerr("wind must be finite");
        }
        if opt.iterations == 0 || !(opt.tolerance.is_finite() && opt.tolerance >= 0.0) {
            return oerr("iterations must be positive and tolerance finite and non-negative");
        }
        let mut bodies = bodies;
        if bodies.is_empty() {
            return Err(ModelError::Body {
                index: 0,
                name: String::new(),
                message: "a model needs the world body (index 0)".into(),
            });
        }
        for (i, b) in bodies.iter_mut().enumerate() {
            let e = |message: &str| ModelError::Body {
                index: i,
                name: b.name.clone(),
                message: message.to_string(),
            };
            if i > 0 && b.parent >= i {
                return Err(e("its parent must come before it"));
            }
            if !(finite3(b.pos) && finite3(b.ipos) && b.quat.iter().all(|x| x.is_finite())) {
                return Err(e("pose must be finite"));
            }
            if !(b.mass.is_finite() && b.mass >= 0.0) {
                return Err(e("mass must be finite and non-negative"));
            }
            if !(b.inertia.iter().all(|x| x.is_finite() && *x >= 0.0) && b.iquat.iter().all(|x| x.is_finite())) {
                return Err(e("inertia must be finite and non-negative"));
            }
            if !(b.dryfriction.is_finite() && b.dryfriction >= 0.0) {
                return Err(e("dryfriction must be finite and non-negative"));
            }
            b.quat = quat_normalize(b.quat);
            b.iquat = quat_normalize(b.iquat);
        }
        let nb = bodies.len();
        let mut joints = joints;
        let mut body_joints = vec![0..0; nb];
        let (mut nq, mut nv) = (0, 0);
        let (mut jnt_qposadr, mut jnt_dofadr) = (Vec::new(), Vec::new());
        let (mut dof_body, mut dof_joint, mut dof_parent) = (Vec::new(), Vec::new(), Vec::new());
        let mut body_last_dof = vec![usize::MAX; nb];
        let mut qpos0 = Vec::new();
        let mut prev_body = 0;
        // Joints must be grouped by body in body order (MuJoCo's layout).
        for (j, jt) in joints.iter_mut().enumerate() {
            let e = |message: String| ModelError::Joint {
                index: j,
                name: jt.name.clone(),
                message,
            };
            if jt.body == 0 || jt.body >= nb {
                return Err(e(format!("body {} is not a moving body", jt.body)));
            }
            if jt.body < prev_body {
                return Err(e("joints must be listed in body order".into()));
            }
            prev_body = jt.body;
            if jt.kind == JointKind::Free && (body_joints[jt.body].end > body_joints[jt.body].start) {
                return Err(e("a free joint must be its body's only joint".into()));
            }
            if jt.kind != JointKind::Free {
                jt.axis = crate::math::normalize(jt.axis).ok_or_else(|| e("axis must be a non-zero vector".into()))?;
            } else if bodies[jt.body].parent != 0 {
                return Err(e("a free joint's body must be a child of the world".into()));
            }
            let nums = [
                jt.armature,
                jt.damping,
                jt.stiffness,
                jt.springref,
                jt.qpos0,
                jt.margin,
                jt.solref_limit[0],
                jt.solref_limit[1],
                jt.frictionloss,
                jt.solref_friction[0],
                jt.solref_friction[1],
                jt.restitution,
            ];
            if !nums.iter().all(|x| x.is_finite())
                || !finite3(jt.pos)
                || !jt.solimp_limit.iter().chain(&jt.solimp_friction).all(|x| x.is_finite())
            {
                return Err(e("parameters must be finite".into()));
            }
            if jt.armature < 0.0
                || jt.damping < 0.0
                || jt.stiffness < 0.0
                || jt.frictionloss < 0.0
                || jt.restitution < 0.0
            {
                return Err(e(
                    "armature, damping, stiffness, frictionloss and restitution must be non-negative".into(),
                ));
            }
            if jt.kind == JointKind::Free && jt.frictionloss > 0.0 {
                return Err(e("a free joint cannot have frictionloss".into()));
            }
            if let Some([lo, hi]) = jt.range {
                if jt.kind == JointKind::Free {
                    return Err(e("a free joint cannot be limited".into()));
                }
                if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
                    return Err(e(format!("range [{lo}, {hi}] must be finite with lo ≤ hi")));
                }
            }
            let r = &mut body_joints[jt.body];
            if r.end == r.start {
                *r = j..j + 1;
            } else {
                r.end = j + 1;
            }
            jnt_qposadr.push(nq);
            jnt_dofadr.push(nv);
            match jt.kind {
                JointKind::Free => {
                    let b = &bodies[jt.body];
                    qpos0.extend_from_slice(&b.pos);
                    qpos0.extend_from_slice(&b.quat);
                }
                _ => qpos0.push(jt.qpos0),
            }
            nq += jt.kind.nq();
            nv += jt.kind.nv();
        }
        // The dof tree: each body's dofs chain after its parent's last dof.
        for b in 1..nb {
            let mut last = body_last_dof[bodies[b].parent];
            for j in body_joints[b].clone() {
                for k in 0..joints[j].kind.nv() {
                    dof_body.push(b);
                    dof_joint.push(j);
                    dof_parent.push(last);
                    last = jnt_dofadr[j] + k;
                }
            }
            body_last_dof[b] = last;
        }
        let mut dof_paths = Vec::new();
        let mut dof_path_start = vec![0];
        for i in 0..nv {
            let mut k = i;
            while k != usize::MAX {
                dof_paths.push(k);
                k = dof_parent[k];
            }
            dof_path_start.push(dof_paths.len());
        }
        let mut body_weld = vec![0; nb];
        for b in 1..nb {
            body_weld[b] = if body_joints[b].is_empty() {
                body_weld[bodies[b].parent]
            } else {
                b
            };
        }
        for (i, g) in geoms.iter().enumerate() {
            let e = |message: &str| ModelError::Geom {
                index: i,
                name: g.name.clone(),
                message: message.to_string(),
            };
            if g.body >= nb {
                return Err(e("its body does not exist"));
            }
            let size_ok = match g.shape {
                Shape::Plane => true,
                Shape::Sphere { radius } => radius.is_finite() && radius > 0.0,
                Shape::Capsule { radius, half_length } => {
                    radius.is_finite() && radius > 0.0 && half_length.is_finite() && half_length >= 0.0
                }
                Shape::Cylinder { radius, half_length } => {
                    radius.is_finite() && radius > 0.0 && half_length.is_finite() && half_length > 0.0
                }
                Shape::Box { half } | Shape::Ellipsoid { radii: half } => {
                    half.iter().all(|x| x.is_finite() && *x > 0.0)
                }
            };
            if !size_ok {
                return Err(e("sizes must be finite and positive"));
            }
            if matches!(g.shape, Shape::Plane) && g.body != 0 {
                return Err(e("a plane must belong to the world body"));
            }
            if g.condim != 1 && g.condim != 3 {
                return Err(e("condim must be 1 or 3"));
            }
            let nums = [g.solmix, g.margin, g.gap, g.solref[0], g.solref[1], g.restitution];
            if !nums.iter().all(|x| x.is_finite())
                || g.restitution < 0.0
                || !g.friction.iter().all(|x| x.is_finite() && *x >= 0.0)
                || !g.solimp.iter().all(|x| x.is_finite())
                || !finite3(g.pos)
                || !g.quat.iter().all(|x| x.is_finite())
            {
                return Err(e("parameters must be finite (friction non-negative)"));
            }
        }
        let mut geoms = geoms;
        for g in &mut geoms {
            g.quat = quat_normalize(g.quat);
        }
        for (i, a) in actuators.iter().enumerate() {
            let e = |message: &str| ModelError::Actuator {
                index: i,
                name: a.name.clone(),
                message: message.to_string(),
            };
            if a.joint >= joints.len() || joints[a.joint].kind == JointKind::Free {
                return Err(e("it must drive a hinge or slide joint"));
            }
            if !a.gear.is_finite() {
                return Err(e("gear must be finite"));
            }
            for (what, r) in [
                ("ctrlrange", a.ctrlrange),
                ("forcerange", a.forcerange),
                ("actrange", a.actrange),
            ] {
                if let Some([lo, hi]) = r
                    && !(lo.is_finite() && hi.is_finite() && lo <= hi)
                {
                    return Err(e(&format!("{what} must be finite with lo ≤ hi")));
                }
            }
            if !a.gain.is_finite() || !a.bias.iter().all(|x| x.is_finite()) {
                return Err(e("gain and bias must be finite"));
            }
            if let Dynamics::Filter { tau } | Dynamics::FilterExact { tau } = a.dynamics
                && !(tau.is_finite() && tau > 0.0)
            {
                return Err(e("a filter's tau must be finite and positive"));
            }
        }
        let nact = actuators.len();
        let mut na = 0;
        let actuator_actadr = actuators
            .iter()
            .map(|a| {
                a.stateful().then(|| {
                    na += 1;
                    na - 1
                })
            })
            .collect();
        let pairs = collision_pairs(&bodies, &body_weld, &geoms);
        let max_contacts: usize = pairs.iter().map(|p| p.max_contacts).sum();
        let contact_rows: usize = pairs
            .iter()
            .map(|p| p.max_contacts * if p.condim == 1 { 1 } else { 4 })
            .sum();
        let limit_rows = 2 * joints.iter().filter(|j| j.range.is_some()).count();
        let friction_rows = joints.iter().filter(|j| j.frictionloss > 0.0).count()
            + 2 * bodies.iter().filter(|b| b.dryfriction > 0.0).count();
        let bodies_imat = bodies.iter().map(|b| crate::math::quat_to_mat(b.iquat)).collect();
        let geom_mat = geoms.iter().map(|g| crate::math::quat_to_mat(g.quat)).collect();
        let mut model = Model {
            opt,
            bodies,
            joints,
            geoms,
            tendons: Vec::new(),
            actuator_tendon: vec![None; nact],
            tendon_equalities: Vec::new(),
            tendon_length0: Vec::new(),
            tendon_invweight0: Vec::new(),
            actuator_actadr,
            na,
            tendon_lengthspring: Vec::new(),
            actuators,
            nq,
            nv,
            jnt_qposadr,
            jnt_dofadr,
            body_joints,
            dof_body,
            dof_joint,
            dof_parent,
            dof_paths,
            dof_path_start,
            body_last_dof,
            body_weld,
            pairs,
            body_invweight0: vec![[0.0; 2]; nb],
            dof_invweight0: vec![0.0; nv],
            qpos0,
            max_contacts,
            max_rows: contact_rows + limit_rows + friction_rows,
            body_imat: bodies_imat,
            geom_mat,
        };
        crate::dynamics::set_invweight0(&mut model);
        Ok(model)
    }

    /// The model with fixed tendons, and the tendon (if any) each actuator drives instead of
    /// its joint (MuJoCo's `actuator_trntype` tendon: the actuator's `joint` is then unused).
    pub fn with_tendons(
        mut self,
        tendons: Vec<Tendon>,
        actuator_tendon: Vec<Option<usize>>,
    ) -> Result<Model, ModelError> {
        for (i, t) in tendons.iter().enumerate() {
            let e = |message: String| ModelError::Tendon {
                index: i,
                name: t.name.clone(),
                message,
            };
            for &(j, coef) in &t.joints {
                if j >= self.joints.len() || self.joints[j].kind == JointKind::Free || !coef.is_finite() {
                    return Err(e(format!(
                        "joint {j} must be a hinge or slide joint with a finite coefficient"
                    )));
                }
            }
            if !(t.stiffness.is_finite() && t.stiffness >= 0.0 && t.damping.is_finite() && t.damping >= 0.0) {
                return Err(e("stiffness and damping must be finite and non-negative".into()));
            }
            if let Some([lo, hi]) = t.lengthspring
                && !(lo.is_finite() && hi.is_finite() && lo <= hi)
            {
                return Err(e("lengthspring must be finite with lo ≤ hi".into()));
            }
        }
        let lengthspring = tendons
            .iter()
            .map(|t| {
                t.lengthspring.unwrap_or_else(|| {
                    let l: f64 = t.joints.iter().map(|&(j, c)| c * self.joints[j].springref).sum();
                    [l, l]
                })
            })
            .collect();
        if actuator_tendon.len() != self.actuators.len() {
            return Err(ModelError::Options(format!(
                "{} actuator transmissions for {} actuators",
                actuator_tendon.len(),
                self.actuators.len()
            )));
        }
        for (a, t) in actuator_tendon.iter().enumerate() {
            if let Some(t) = *t
                && t >= tendons.len()
            {
                return Err(ModelError::Actuator {
                    index: a,
                    name: self.actuators[a].name.clone(),
                    message: format!("tendon {t} does not exist"),
                });
            }
        }
        self.tendon_length0 = tendons
            .iter()
            .map(|t| t.joints.iter().map(|&(j, c)| c * self.qpos0[self.jnt_qposadr[j]]).sum())
            .collect();
        self.tendons = tendons;
        self.tendon_lengthspring = lengthspring;
        self.actuator_tendon = actuator_tendon;
        self.tendon_invweight0 = crate::dynamics::tendon_invweight0(&self);
        Ok(self)
    }

    /// The model with tendon equalities (after [`Model::with_tendons`]: they name its tendons).
    pub fn with_tendon_equalities(mut self, eqs: Vec<TendonEquality>) -> Result<Model, ModelError> {
        for (i, e) in eqs.iter().enumerate() {
            let bad = |message: String| ModelError::Tendon {
                index: i,
                name: e.name.clone(),
                message,
            };
            let nt = self.tendons.len();
            if e.tendon1 >= nt || e.tendon2.is_some_and(|t| t >= nt) {
                return Err(bad(format!(
                    "an equality names a tendon that does not exist ({nt} tendons)"
                )));
            }
            if !(e
                .polycoef
                .iter()
                .chain(&e.solref)
                .chain(&e.solimp)
                .all(|x| x.is_finite()))
            {
                return Err(bad("equality parameters must be finite".into()));
            }
        }
        self.max_rows += eqs.len();
        self.tendon_equalities = eqs;
        Ok(self)
    }

    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.bodies.iter().position(|b| b.name == name)
    }
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }
    pub fn geom_index(&self, name: &str) -> Option<usize> {
        self.geoms.iter().position(|g| g.name == name)
    }
}

/// MuJoCo's mixing of two geoms' `solref`/`solimp` by their `solmix` weights.
fn mix<const N: usize>(a: [f64; N], b: [f64; N], w: f64) -> [f64; N] {
    let mut r = [0.0; N];
    for k in 0..N {
        r[k] = w * a[k] + (1.0 - w) * b[k];
    }
    r
}

/// The geom pairs that may collide, with MuJoCo's filters: different weld bodies, not a
/// parent–child pair of weld bodies (unless the parent is the world), not both static, and
/// `contype & conaffinity` compatible in either direction. Parameters: condim and friction the
/// larger, margin and gap the sum (as MuJoCo 4.0.0 reports them), solref/solimp mixed by
/// `solmix`. Pairs without a collision routine (a box against anything but the plane) are left
/// out: they never make contacts.
fn collision_pairs(bodies: &[Body], weld: &[usize], geoms: &[Geom]) -> Vec<GeomPair> {
    let mut pairs = Vec::new();
    for i in 0..geoms.len() {
        for j in i + 1..geoms.len() {
            let (a, b) = (&geoms[i], &geoms[j]);
            let (wa, wb) = (weld[a.body], weld[b.body]);
            if wa == wb {
                continue;
            }
            if wa != 0 && wb != 0 && (weld[bodies[wa].parent] == wb || weld[bodies[wb].parent] == wa) {
                continue;
            }
            if (a.contype & b.conaffinity) == 0 && (b.contype & a.conaffinity) == 0 {
                continue;
            }
            let (g1, g2) = if a.shape.order() <= b.shape.order() {
                (i, j)
            } else {
                (j, i)
            };
            let (s1, s2) = (geoms[g1].shape, geoms[g2].shape);
            let supported = matches!(
                (s1, s2),
                (
                    Shape::Plane,
                    Shape::Sphere { .. } | Shape::Capsule { .. } | Shape::Box { .. } | Shape::Ellipsoid { .. }
                ) | (Shape::Sphere { .. }, Shape::Sphere { .. } | Shape::Capsule { .. })
                    | (Shape::Capsule { .. }, Shape::Capsule { .. })
                    | (Shape::Sphere { .. } | Shape::Capsule { .. }, Shape::Cylinder { .. })
            );
            if !supported {
                continue;
            }
            let max_contacts = match (s1, s2) {
                (Shape::Plane, Shape::Box { .. }) => 4,
                (Shape::Plane, Shape::Capsule { .. }) | (Shape::Capsule { .. }, Shape::Capsule { .. }) => 2,
                _ => 1,
            };
            let w = if a.solmix + b.solmix > 0.0 {
                a.solmix / (a.solmix + b.solmix)
            } else {
                0.5
            };
            // Mixed solref only when both are of the same sign convention (MuJoCo takes the
            // element-wise minimum otherwise).
            let solref = if (a.solref[0] > 0.0) == (b.solref[0] > 0.0) {
                mix(a.solref, b.solref, w)
            } else {
                [a.solref[0].min(b.solref[0]), a.solref[1].min(b.solref[1])]
            };
            pairs.push(GeomPair {
                g1,
                g2,
                condim: a.condim.max(b.condim),
                friction: a.friction[0].max(b.friction[0]),
                margin: a.margin + b.margin,
                gap: a.gap + b.gap,
                solref,
                solimp: mix(a.solimp, b.solimp, w),
                restitution: a.restitution.max(b.restitution),
                max_contacts,
            });
        }
    }
    pairs
}
