//! Planar forward kinematics: link poses from the coordinates, link velocities and the
//! velocity-product ("bias") accelerations the links would have with zero joint
//! accelerations, and the Jacobian columns of points on links.
//!
//! Conventions: a link's pose is the origin `p = [x, z]` and the pitch `θ` about +y; a
//! rotation by `θ` maps `[x, z]` to `[x cosθ + z sinθ, −x sinθ + z cosθ]`, so an angular
//! velocity `ω` (about +y) moves a point at offset `r` from the axis with `ω × r = ω·[r_z, −r_x]`.

use super::tree::{JointKind, PlanarTree, V2, rotate};

/// `ω × r` for an angular velocity `w` about +y and an in-plane offset `r`.
pub fn cross(w: f64, r: V2) -> V2 {
    [w * r[1], -w * r[0]]
}

pub fn sub(a: V2, b: V2) -> V2 {
    [a[0] - b[0], a[1] - b[1]]
}

pub fn add(a: V2, b: V2) -> V2 {
    [a[0] + b[0], a[1] + b[1]]
}

pub fn dot(a: V2, b: V2) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// The state of one link: pose, velocity and bias acceleration (of its origin), and its
/// centre of mass in world coordinates.
#[derive(Debug, Clone, Copy, Default)]
pub struct LinkState {
    pub pos: V2,
    pub angle: f64,
    /// `(cos θ, sin θ)`.
    pub cs: (f64, f64),
    pub com: V2,
    pub vel: V2,
    pub omega: f64,
    pub acc: V2,
    pub alpha: f64,
}

/// The joint of one coordinate in world terms: for a hinge, the point on its axis; for a
/// slide, its direction.
#[derive(Debug, Clone, Copy, Default)]
pub struct DofAxis {
    pub hinge: bool,
    /// Hinge sign (±1) or 0 for a slide.
    pub sign: f64,
    pub point: V2,
    pub dir: V2,
}

impl DofAxis {
    /// Velocity of world point `p` (rigidly attached beyond this joint) per unit joint rate,
    /// and the angular velocity per unit rate.
    pub fn point_column(&self, p: V2) -> (V2, f64) {
        if self.hinge {
            (cross(self.sign, sub(p, self.point)), self.sign)
        } else {
            (self.dir, 0.0)
        }
    }
}

/// Poses of all links and the world axes of all joints from the coordinates `q`.
pub fn positions(tree: &PlanarTree, q: &[f64], links: &mut [LinkState], axes: &mut [DofAxis]) {
    for &i in &tree.order {
        let l = &tree.links[i];
        let (pos, angle) = match l.parent {
            None => ([0.0, 0.0], 0.0),
            Some(p) => {
                let parent = &links[p];
                let joint_pos = add(parent.pos, rotate(parent.cs, l.offset));
                let joint_angle = parent.angle + l.offset_angle;
                match (l.kind, l.dof) {
                    (JointKind::Hinge { sign }, Some(d)) => {
                        axes[d] = DofAxis {
                            hinge: true,
                            sign,
                            point: joint_pos,
                            dir: [0.0; 2],
                        };
                        (joint_pos, joint_angle + sign * q[d])
                    }
                    (JointKind::Slide { dir }, Some(d)) => {
                        let u = rotate(joint_angle.sin_cos_pair(), dir);
                        axes[d] = DofAxis {
                            hinge: false,
                            sign: 0.0,
                            point: joint_pos,
                            dir: u,
                        };
                        (add(joint_pos, [u[0] * q[d], u[1] * q[d]]), joint_angle)
                    }
                    _ => (joint_pos, joint_angle),
                }
            }
        };
        let (s, c) = angle.sin_cos();
        let st = &mut links[i];
        st.pos = pos;
        st.angle = angle;
        st.cs = (c, s);
        st.com = add(pos, rotate((c, s), l.com));
    }
}

/// Link velocities and bias accelerations (zero joint accelerations) from the rates `v`,
/// with the poses of [`positions`] in place.
pub fn velocities(tree: &PlanarTree, v: &[f64], links: &mut [LinkState], axes: &[DofAxis]) {
    for &i in &tree.order {
        let l = &tree.links[i];
        let Some(p) = l.parent else {
            let st = &mut links[i];
            (st.vel, st.omega, st.acc, st.alpha) = ([0.0; 2], 0.0, [0.0; 2], 0.0);
            continue;
        };
        let parent = links[p];
        let r = sub(links[i].pos, parent.pos);
        // Rigidly carried by the parent.
        let mut vel = add(parent.vel, cross(parent.omega, r));
        let mut omega = parent.omega;
        let w2 = parent.omega * parent.omega;
        let ar = cross(parent.alpha, r);
        let mut acc = [parent.acc[0] + ar[0] - w2 * r[0], parent.acc[1] + ar[1] - w2 * r[1]];
        if let Some(d) = l.dof {
            let ax = &axes[d];
            if ax.hinge {
                omega += ax.sign * v[d];
            } else {
                let u = [ax.dir[0] * v[d], ax.dir[1] * v[d]];
                vel = add(vel, u);
                // Coriolis: the slide's rate seen from the turning parent.
                let cor = cross(2.0 * parent.omega, u);
                acc = add(acc, cor);
            }
        }
        let st = &mut links[i];
        st.vel = vel;
        st.omega = omega;
        st.acc = acc;
        st.alpha = parent.alpha;
    }
}

/// Velocity of a world point `p` rigidly attached to link state `s`.
pub fn point_velocity(s: &LinkState, p: V2) -> V2 {
    add(s.vel, cross(s.omega, sub(p, s.pos)))
}

/// Bias acceleration of a world point `p` rigidly attached to link state `s`.
pub fn point_bias_acceleration(s: &LinkState, p: V2) -> V2 {
    let r = sub(p, s.pos);
    let ar = cross(s.alpha, r);
    let w2 = s.omega * s.omega;
    [s.acc[0] + ar[0] - w2 * r[0], s.acc[1] + ar[1] - w2 * r[1]]
}

trait SinCosPair {
    fn sin_cos_pair(self) -> (f64, f64);
}

impl SinCosPair for f64 {
    /// `(cos, sin)`, the order [`rotate`] takes.
    fn sin_cos_pair(self) -> (f64, f64) {
        let (s, c) = self.sin_cos();
        (c, s)
    }
}
