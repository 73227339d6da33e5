//! The planar kinematic tree of a robot, read from its URDF: every link moves in the world's
//! x-z plane (prismatic joints along directions of that plane, hinges about ±y), so a link's
//! pose is `(x, z, θ)` with `θ` its pitch about +y.
//!
//! [`PlanarTree::from_model`] checks that the robot is planar and says why not otherwise; the
//! context's masses enter in [`PlanarTree::with_masses`].

use rapier3d_urdf::urdf_rs;

use super::super::model::{RobotModel, RootKind, SideFile};
use super::super::params::{RobotParams, finite_or};

/// A vector of the x-z plane, `[x, z]`.
pub type V2 = [f64; 2];

/// Tolerance of the planarity checks (m, rad, and unit-vector components).
const PLANAR_TOL: f64 = 1e-6;

/// How a link moves relative to its parent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    /// Welded to the parent.
    Fixed,
    /// Rotation by `sign · q` about +y (`sign` = −1 for an axis along −y).
    Hinge { sign: f64 },
    /// Translation by `q` along `dir`, a unit vector of the joint frame's x-z plane.
    Slide { dir: V2 },
}

/// One link of the tree.
#[derive(Debug, Clone)]
pub struct PlanarLink {
    /// Parent link (`None` for the root, which is welded to the world).
    pub parent: Option<usize>,
    pub kind: JointKind,
    /// The generalized coordinate of the joint to the parent (movable joints only).
    pub dof: Option<usize>,
    /// Joint frame in the parent's frame: origin and pitch.
    pub offset: V2,
    pub offset_angle: f64,
    pub mass: f64,
    /// Centre of mass in the link frame.
    pub com: V2,
    /// Moment of inertia about the y axis through the centre of mass (kg·m²).
    pub inertia: f64,
    /// Mean side of the link's equivalent inertia box (m): MuJoCo's diameter for viscous drag.
    pub box_diameter: f64,
    /// Generalized coordinates on the path from the root to this link (root first).
    pub ancestors: Vec<usize>,
}

/// One generalized coordinate (a movable joint, URDF order).
#[derive(Debug, Clone)]
pub struct PlanarDof {
    /// The link the joint moves.
    pub link: usize,
    pub hinge: bool,
    /// Joint limits (`None`: continuous or unlimited).
    pub limits: Option<(f64, f64)>,
    /// Reflected rotor inertia (kg·m²; kg for a slide).
    pub armature: f64,
    /// Passive spring towards 0 (N·m/rad).
    pub spring: f64,
    /// A root coordinate (a slide or the pitch hinge of the root): not damped as a robot joint.
    pub root: bool,
}

/// A capsule (or sphere) collider: a segment `a`–`b` in the link frame, inflated by `radius`.
#[derive(Debug, Clone, Copy)]
pub struct PlanarCapsule {
    pub link: usize,
    pub a: V2,
    pub b: V2,
    pub radius: f64,
    /// Whether it touches the ground (the side file's `ground_contacts` and `ground_links`).
    pub ground: bool,
}

/// The tree: links in URDF order, a parent-first visiting order, the generalized
/// coordinates and the colliders.
#[derive(Debug, Clone)]
pub struct PlanarTree {
    pub links: Vec<PlanarLink>,
    /// Link indices, every parent before its children.
    pub order: Vec<usize>,
    pub dofs: Vec<PlanarDof>,
    pub capsules: Vec<PlanarCapsule>,
}

/// URDF rotation `Rz(yaw)·Ry(pitch)·Rx(roll)` applied to `v`.
fn rpy_apply(rpy: [f64; 3], v: [f64; 3]) -> [f64; 3] {
    let (sr, cr) = rpy[0].sin_cos();
    let (sp, cp) = rpy[1].sin_cos();
    let (sy, cy) = rpy[2].sin_cos();
    let x = [v[0], cr * v[1] - sr * v[2], sr * v[1] + cr * v[2]];
    let y = [cp * x[0] + sp * x[2], x[1], -sp * x[0] + cp * x[2]];
    [cy * y[0] - sy * y[1], sy * y[0] + cy * y[1], y[2]]
}

/// The pitch of a URDF origin whose rotation is about y only.
fn planar_pitch(what: &str, rpy: [f64; 3]) -> Result<f64, String> {
    // A rotation about y maps ŷ to ŷ; its pitch is the angle of the rotated x axis.
    let y = rpy_apply(rpy, [0.0, 1.0, 0.0]);
    if (y[1] - 1.0).abs() > PLANAR_TOL {
        return Err(format!("{what} rotates out of the x-z plane (rpy {rpy:?})"));
    }
    let x = rpy_apply(rpy, [1.0, 0.0, 0.0]);
    Ok((-x[2]).atan2(x[0]))
}

fn in_plane(what: &str, xyz: [f64; 3]) -> Result<V2, String> {
    if xyz[1].abs() > PLANAR_TOL {
        return Err(format!("{what} lies off the x-z plane (y = {})", xyz[1]));
    }
    Ok([xyz[0], xyz[2]])
}

/// Apply a pitch rotation `θ` (about +y) to a vector of the x-z plane.
pub fn rotate(cs: (f64, f64), v: V2) -> V2 {
    let (c, s) = cs;
    [c * v[0] + s * v[1], -s * v[0] + c * v[1]]
}

impl PlanarTree {
    /// Read the planar tree of `model`, or say why the robot is not planar.
    pub fn from_model(model: &RobotModel) -> Result<PlanarTree, String> {
        let side: &SideFile = &model.side;
        let urdf = &model.urdf;
        if side.root != RootKind::Fixed {
            return Err(
                "a planar robot needs \"root\": \"fixed\" (its root slides and pitch hinge are URDF joints)".into(),
            );
        }
        if side.self_collisions {
            return Err("the planar engine has no self-collisions (\"self_collisions\": true)".into());
        }
        let n_links = urdf.links.len();
        let link_index = |name: &str| urdf.links.iter().position(|l| l.name == name);
        let mut links: Vec<PlanarLink> = Vec::with_capacity(n_links);
        for l in &urdf.links {
            let what = format!("link {}", l.name);
            let inertial = &l.inertial;
            // Only checked: a rotation about y leaves the y moment of inertia unchanged.
            planar_pitch(&format!("{what}'s inertial frame"), inertial.origin.rpy.0)?;
            let ine = &inertial.inertia;
            if ine.ixy.abs() > PLANAR_TOL || ine.iyz.abs() > PLANAR_TOL {
                return Err(format!("{what}'s inertia couples y with x or z (ixy, iyz ≠ 0)"));
            }
            // MuJoCo's inertia box: sides √(6 (I_j + I_k − I_i) / m) (diagonal moments).
            let m = inertial.mass.value;
            let (ix, iy, iz) = (ine.ixx, ine.iyy, ine.izz);
            let side = |a: f64, b: f64, c: f64| (6.0 * (a + b - c).max(1e-12) / m).sqrt();
            let box_diameter = (side(iy, iz, ix) + side(ix, iz, iy) + side(ix, iy, iz)) / 3.0;
            links.push(PlanarLink {
                parent: None,
                kind: JointKind::Fixed,
                dof: None,
                offset: [0.0; 2],
                offset_angle: 0.0,
                mass: inertial.mass.value,
                com: in_plane(&format!("{what}'s centre of mass"), inertial.origin.xyz.0)?,
                inertia: ine.iyy,
                box_diameter,
                ancestors: Vec::new(),
            });
        }
        let mut dofs = Vec::new();
        for j in &urdf.joints {
            let what = format!("joint {}", j.name);
            let (Some(p), Some(c)) = (link_index(&j.parent.link), link_index(&j.child.link)) else {
                return Err(format!("{what} names a link that does not exist"));
            };
            if links[c].parent.is_some() {
                return Err(format!("link {} has two parent joints", j.child.link));
            }
            let axis = j.axis.xyz.0;
            let kind = match j.joint_type {
                urdf_rs::JointType::Fixed => JointKind::Fixed,
                urdf_rs::JointType::Revolute | urdf_rs::JointType::Continuous => {
                    if axis[0].abs() > PLANAR_TOL || axis[2].abs() > PLANAR_TOL || axis[1].abs() < PLANAR_TOL {
                        return Err(format!("{what} turns about {axis:?}, not about ±y"));
                    }
                    JointKind::Hinge { sign: axis[1].signum() }
                }
                urdf_rs::JointType::Prismatic => {
                    let n = (axis[0] * axis[0] + axis[2] * axis[2]).sqrt();
                    if axis[1].abs() > PLANAR_TOL || n < PLANAR_TOL {
                        return Err(format!("{what} slides along {axis:?}, not within the x-z plane"));
                    }
                    JointKind::Slide {
                        dir: [axis[0] / n, axis[2] / n],
                    }
                }
                ref other => {
                    return Err(format!(
                        "{what} is a {other:?} joint; the planar engine has hinges and slides"
                    ));
                }
            };
            let offset = in_plane(&format!("{what}'s origin"), j.origin.xyz.0)?;
            let offset_angle = planar_pitch(&format!("{what}'s origin"), j.origin.rpy.0)?;
            let dof = if kind == JointKind::Fixed {
                None
            } else {
                let name = &j.name;
                let limits = match j.joint_type {
                    urdf_rs::JointType::Continuous => None,
                    _ => Some((j.limit.lower, j.limit.upper)),
                };
                let armature = side
                    .joint_armatures
                    .iter()
                    .find(|a| a.joint == *name)
                    .map_or(side.joint_armature, |a| a.armature);
                let root = side.root_joints.contains(name);
                dofs.push(PlanarDof {
                    link: c,
                    hinge: matches!(kind, JointKind::Hinge { .. }),
                    limits,
                    armature: if root { 0.0 } else { armature },
                    spring: side
                        .joint_springs
                        .iter()
                        .find(|s| s.joint == *name)
                        .map_or(0.0, |s| s.stiffness),
                    root,
                });
                Some(dofs.len() - 1)
            };
            let l = &mut links[c];
            l.parent = Some(p);
            l.kind = kind;
            l.dof = dof;
            l.offset = offset;
            l.offset_angle = offset_angle;
        }
        // Parent-first order from the root (the first link, welded to the world).
        let roots: Vec<usize> = (0..n_links).filter(|&i| links[i].parent.is_none()).collect();
        if roots != [0] {
            return Err("the URDF must form one tree rooted at its first link".into());
        }
        let mut order = vec![0];
        let mut k = 0;
        while k < order.len() {
            let p = order[k];
            order.extend((0..n_links).filter(|&i| links[i].parent == Some(p)));
            k += 1;
        }
        if order.len() != n_links {
            return Err("the URDF's joints form a loop".into());
        }
        for &i in &order[1..] {
            let p = links[i].parent.expect("non-root");
            let mut anc = links[p].ancestors.clone();
            anc.extend(links[i].dof);
            links[i].ancestors = anc;
        }
        // Colliders: capsules and spheres whose axes lie in the plane.
        let mut capsules = Vec::new();
        let ground_ok = |name: &str| {
            side.ground_contacts && (side.ground_links.is_empty() || side.ground_links.iter().any(|g| g == name))
        };
        for (i, l) in urdf.links.iter().enumerate() {
            for c in &l.collision {
                let what = format!("a collider of link {}", l.name);
                let centre = in_plane(&what, c.origin.xyz.0)?;
                let (half, radius) = match c.geometry {
                    urdf_rs::Geometry::Capsule { radius, length } => (length / 2.0, radius),
                    urdf_rs::Geometry::Sphere { radius } => (0.0, radius),
                    ref g => return Err(format!("{what} is a {g:?}; the planar engine has capsules and spheres")),
                };
                let axis = rpy_apply(c.origin.rpy.0, [0.0, 0.0, 1.0]);
                if half > 0.0 && axis[1].abs() > PLANAR_TOL {
                    return Err(format!("{what} points out of the x-z plane"));
                }
                capsules.push(PlanarCapsule {
                    link: i,
                    a: [centre[0] - half * axis[0], centre[1] - half * axis[2]],
                    b: [centre[0] + half * axis[0], centre[1] + half * axis[2]],
                    radius,
                    ground: ground_ok(&l.name),
                });
            }
        }
        if dofs.is_empty() {
            return Err("the robot has no movable joint".into());
        }
        Ok(PlanarTree {
            links,
            order,
            dofs,
            capsules,
        })
    }

    /// The tree with the context's masses (torso and `mass_<link>` overrides; a link's inertia
    /// scales with its mass), as the rapier world applies them.
    pub fn with_masses(mut self, model: &RobotModel, params: &RobotParams) -> PlanarTree {
        for (i, link) in self.links.iter_mut().enumerate() {
            let base = link.mass;
            let mut m = base;
            if i == model.torso
                && let Some(t) = params.torso_mass
            {
                m = t;
            }
            if let Some((_, v)) = params.link_masses.iter().find(|(n, _)| *n == model.link_names[i]) {
                m = *v;
            }
            let m = finite_or(m, base).max(1e-6);
            link.inertia *= m / base;
            link.mass = m;
        }
        self
    }
}
