//! MuJoCo's sensors at sites: `velocimeter`, `gyro`, `accelerometer`, `force`, `torque`, and
//! `subtreecom`. A [`Site`] is a frame fixed in a body; every reading is in the site's frame
//! (but `subtreecom`, world).
//!
//! The acceleration sensors need MuJoCo's `mj_rnePostConstraint`
//! ([`Data::rne_post_constraint`], after [`Data::forward`]): each body's spatial acceleration
//! `cacc` from the constrained `qacc` (the world accelerating by `−gravity`, so a body at rest
//! reads `+g` upward) and the interaction force `cfrc_int` its parent exerts on its subtree,
//! `I a + v ×* I v − f_ext` summed over the subtree, `f_ext` the contact forces. As in MuJoCo:
//! the accelerometer is the site point's linear acceleration plus `ω × v` (`cacc` moved to the
//! point), the force and torque sensors are `cfrc_int` of the site's body with the torque taken
//! about the site.

use crate::data::Data;
use crate::math::{
    M3, V3, V6, ZERO3, add, add6, cross, cross_force, join, mat_mul, mat_t_vec, mat_vec, scale, split, sub,
};

/// A frame fixed in `body`: origin `pos` and orientation `mat` in the body's frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site {
    pub body: usize,
    pub pos: V3,
    pub mat: M3,
}

impl Site {
    /// A site at `pos` of `body`, its axes the body's.
    pub fn at(body: usize, pos: V3) -> Site {
        Site {
            body,
            pos,
            mat: crate::math::IDENTITY,
        }
    }
}

impl Data {
    /// World position and orientation of `site`.
    pub fn site_pose(&self, site: &Site) -> (V3, M3) {
        let b = site.body;
        (
            add(self.xpos[b], mat_vec(&self.xmat[b], site.pos)),
            mat_mul(&self.xmat[b], &site.mat),
        )
    }

    /// MuJoCo's `mj_rnePostConstraint` (see the module doc), after [`Data::forward`].
    pub fn rne_post_constraint(&mut self) {
        let model = std::sync::Arc::clone(&self.model);
        let m = &*model;
        let nb = m.bodies.len();
        // f_ext: contact forces as world spatial forces about the origin.
        self.cfrc_int.iter_mut().for_each(|f| *f = [0.0; 6]);
        for ci in 0..self.ncon {
            let c = self.contacts[ci];
            let f = self.contact_force(ci);
            let pair = &m.pairs[c.pair];
            for (g, s) in [(pair.g2, 1.0), (pair.g1, -1.0)] {
                let b = m.geoms[g].body;
                if b == 0 {
                    continue;
                }
                let fs = scale(f, s);
                // cfrc_int starts as −f_ext.
                add6(&mut self.cfrc_int[b], &join(cross(c.pos, fs), fs), -1.0);
            }
        }
        self.post_cacc[0] = join(ZERO3, scale(m.opt.gravity, -1.0));
        for b in 1..nb {
            let mut a = self.post_cacc[m.bodies[b].parent];
            for j in m.body_joints[b].clone() {
                let da = m.jnt_dofadr[j];
                for d in da..da + m.joints[j].kind.nv() {
                    add6(&mut a, &self.cdof_dot[d], self.qvel[d]);
                    add6(&mut a, &self.cdof[d], self.qacc[d]);
                }
            }
            self.post_cacc[b] = a;
            let i = &self.cinert[b];
            let mut f = i.mul(&a);
            let h = i.mul(&self.cvel[b]);
            add6(&mut f, &cross_force(&self.cvel[b], &h), 1.0);
            add6(&mut self.cfrc_int[b], &f, 1.0);
        }
        for b in (1..nb).rev() {
            let p = m.bodies[b].parent;
            if p != 0 {
                let f = self.cfrc_int[b];
                add6(&mut self.cfrc_int[p], &f, 1.0);
            }
        }
    }

    /// A motion vector about the origin moved to point `p` and rotated into frame `r`:
    /// `(angular, linear at p)`.
    fn motion_at(v: &V6, p: V3, r: &M3) -> (V3, V3) {
        let (w, v0) = split(v);
        (mat_t_vec(r, w), mat_t_vec(r, add(v0, cross(w, p))))
    }

    /// `velocimeter`: the site's linear velocity in its frame.
    pub fn velocimeter(&self, site: &Site) -> V3 {
        let (p, r) = self.site_pose(site);
        Self::motion_at(&self.cvel[site.body], p, &r).1
    }

    /// `gyro`: the site's angular velocity in its frame.
    pub fn gyro(&self, site: &Site) -> V3 {
        let (p, r) = self.site_pose(site);
        Self::motion_at(&self.cvel[site.body], p, &r).0
    }

    /// `accelerometer` (after [`Data::rne_post_constraint`]).
    pub fn accelerometer(&self, site: &Site) -> V3 {
        let (p, r) = self.site_pose(site);
        let (w, v) = Self::motion_at(&self.cvel[site.body], p, &r);
        let (_, a) = Self::motion_at(&self.post_cacc[site.body], p, &r);
        add(a, cross(w, v))
    }

    /// `force`: the interaction force on the site's body's subtree, in the site's frame (after
    /// [`Data::rne_post_constraint`]).
    pub fn force_sensor(&self, site: &Site) -> V3 {
        let (_, r) = self.site_pose(site);
        let (_, f) = split(&self.cfrc_int[site.body]);
        mat_t_vec(&r, f)
    }

    /// `torque`: the interaction torque about the site, in its frame (after
    /// [`Data::rne_post_constraint`]).
    pub fn torque_sensor(&self, site: &Site) -> V3 {
        let (p, r) = self.site_pose(site);
        let (t, f) = split(&self.cfrc_int[site.body]);
        mat_t_vec(&r, sub(t, cross(p, f)))
    }

    /// `subtreecom`: the centre of mass of `body` and its descendants (world frame).
    pub fn subtree_com(&self, body: usize) -> V3 {
        let m = &*self.model;
        let (mut c, mut mass) = (ZERO3, 0.0);
        for b in body.max(1)..m.bodies.len() {
            let mut a = b;
            while a > body {
                a = m.bodies[a].parent;
            }
            if a == body {
                c = add(c, scale(self.xipos[b], m.bodies[b].mass));
                mass += m.bodies[b].mass;
            }
        }
        if mass > 0.0 {
            scale(c, 1.0 / mass)
        } else {
            self.xipos[body]
        }
    }
}
