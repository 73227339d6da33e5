//! MuJoCo's centre-of-mass based body quantities, computed from a rapier world: `subtree_com`
//! of the root (the whole robot's centre of mass), `cinert`, `cvel` and the com-based
//! `cfrc_ext` (see MuJoCo's `mjData` documentation). All are in world axes and refer to the
//! robot's centre of mass `c`:
//! * `cinert` (10 per body): `[Ixx Iyy Izz Ixy Ixz Iyz, m·d, m]`, the body's inertia about `c`
//!   (its own inertia rotated to world axes plus `m(|d|²E − d dᵀ)`), `d` = body com − `c`;
//! * `cvel` (6 per body): `[ω, v]`, the body's angular velocity and the velocity of the point
//!   of the body (rigidly extended) that is at `c`;
//! * `cfrc_ext` (6 per body): `[torque about c, force]` of the contacts on the body.

use rapier3d::prelude::*;

use super::world::RobotWorld;

impl RobotWorld {
    /// Mass-weighted centre of mass of all links (MuJoCo's `subtree_com` of the root).
    pub fn center_of_mass(&self) -> [f64; 3] {
        let mut m = 0.0f64;
        let mut c = [0.0f64; 3];
        for &h in &self.links {
            let b = &self.pw.bodies[h];
            let mi = f64::from(b.mass());
            let p = b.center_of_mass();
            m += mi;
            for k in 0..3 {
                c[k] += mi * f64::from(p[k]);
            }
        }
        if m > 0.0 {
            c.iter_mut().for_each(|x| *x /= m);
        }
        c
    }

    /// `cinert` of the links `bodies` about `c`, 10 values per body.
    pub fn com_inertia(&self, bodies: &[usize], c: [f64; 3], out: &mut [f64]) {
        for (k, &i) in bodies.iter().enumerate() {
            let b = &self.pw.bodies[self.links[i]];
            let mp = &b.mass_properties().local_mprops;
            let m = f64::from(b.mass());
            let r = Matrix::from_quat(*b.rotation());
            let iw = r * mp.reconstruct_inertia_matrix() * r.transpose();
            let p = b.center_of_mass();
            let d = [f64::from(p.x) - c[0], f64::from(p.y) - c[1], f64::from(p.z) - c[2]];
            let at = |row: usize, col: usize| f64::from(iw.col(col)[row]);
            let o = &mut out[10 * k..10 * k + 10];
            o[0] = at(0, 0) + m * (d[1] * d[1] + d[2] * d[2]);
            o[1] = at(1, 1) + m * (d[0] * d[0] + d[2] * d[2]);
            o[2] = at(2, 2) + m * (d[0] * d[0] + d[1] * d[1]);
            o[3] = at(0, 1) - m * d[0] * d[1];
            o[4] = at(0, 2) - m * d[0] * d[2];
            o[5] = at(1, 2) - m * d[1] * d[2];
            for j in 0..3 {
                o[6 + j] = m * d[j];
            }
            o[9] = m;
        }
    }

    /// `cvel` of the links `bodies` at `c`, 6 values per body.
    pub fn com_velocity(&self, bodies: &[usize], c: [f64; 3], out: &mut [f64]) {
        let cv = Vector::new(c[0] as f32, c[1] as f32, c[2] as f32);
        for (k, &i) in bodies.iter().enumerate() {
            let b = &self.pw.bodies[self.links[i]];
            let w = b.angvel();
            let v = b.linvel() + w.cross(cv - b.center_of_mass());
            let o = &mut out[6 * k..6 * k + 6];
            for j in 0..3 {
                o[j] = f64::from(w[j]);
                o[3 + j] = f64::from(v[j]);
            }
        }
    }

    /// Com-based `cfrc_ext` of the links `bodies` from per-link wrenches `link_wrenches` (as
    /// [`RobotWorld::contact_wrenches`] gives them: torque about each link's own centre of mass):
    /// the torque moves to `c`, `τ_c = τ + (com − c) × f`. 6 values per body.
    pub fn com_wrenches(&self, bodies: &[usize], c: [f64; 3], link_wrenches: &[f64], out: &mut [f64]) {
        for (k, &i) in bodies.iter().enumerate() {
            let p = self.pw.bodies[self.links[i]].center_of_mass();
            let d = [f64::from(p.x) - c[0], f64::from(p.y) - c[1], f64::from(p.z) - c[2]];
            let w = &link_wrenches[6 * i..6 * i + 6];
            let f = [w[3], w[4], w[5]];
            let cross = [
                d[1] * f[2] - d[2] * f[1],
                d[2] * f[0] - d[0] * f[2],
                d[0] * f[1] - d[1] * f[0],
            ];
            let o = &mut out[6 * k..6 * k + 6];
            for j in 0..3 {
                o[j] = w[j] + cross[j];
                o[3 + j] = f[j];
            }
        }
    }
}
