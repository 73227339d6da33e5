//! The world and its step (Box2D 2.3's `b2World::Step`): update contacts (begin/end events),
//! then per island integrate velocities, warm start, velocity iterations (joints, then
//! contacts), integrate positions with the per-step motion caps, position iterations with early
//! exit; then move the broad-phase boxes and find new contacts.

use super::body::{Body, BodyKind};
use super::collide::{Manifold, collide_edge_polygon, collide_polygons};
use super::contact_solver::{self as cs, ContactConstraint};
use super::distance::DistanceProxy;
use super::math::{V2, Xf, v2};
use super::revolute::{RevoluteDef, RevoluteJoint};
use super::settings::{
    AABB_EXTENSION, AABB_MULTIPLIER, BAUMGARTE, EPSILON, MAX_ROTATION, MAX_SUB_STEPS, MAX_TOI_CONTACTS,
    MAX_TRANSLATION, TOI_BAUMGARTE,
};
use super::shapes::{Aabb, Shape};
use super::toi::{self, ToiState};

/// Collision filtering (Box2D's `b2Filter` without groups).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Filter {
    pub category: u16,
    pub mask: u16,
}

impl Default for Filter {
    fn default() -> Self {
        Filter {
            category: 1,
            mask: 0xFFFF,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FixtureDef {
    pub shape: Shape,
    pub density: f64,
    pub friction: f64,
    pub restitution: f64,
    pub filter: Filter,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Fixture {
    pub body: usize,
    pub def: FixtureDef,
    /// The broad-phase box: the shape's box fattened by `AABB_EXTENSION` and stretched ahead
    /// of the motion; it moves only when the shape leaves it.
    pub fat_aabb: Aabb,
    moved: bool,
    /// The shape for the time-of-impact routines (`None` if they reject it).
    proxy: Option<DistanceProxy>,
}

/// A potential contact between two fixtures whose broad-phase boxes overlap.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    pub fixture_a: usize,
    pub fixture_b: usize,
    pub manifold: Manifold,
    /// The manifold has points (the shapes are within two skins).
    pub touching: bool,
    pub friction: f64,
    pub restitution: f64,
    /// Re-enabled by every manifold update; a failed time-of-impact sub-step disables it.
    pub enabled: bool,
    /// Cached time of impact within the current continuous-collision pass.
    pub toi: Option<f64>,
    pub toi_count: u32,
}

/// A contact began or ended touching (Box2D's `BeginContact` / `EndContact`), in the order
/// Box2D's listener would see them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ContactEvent {
    pub fixture_a: usize,
    pub fixture_b: usize,
    pub begin: bool,
}

impl ContactEvent {
    /// Whether `fixture` is one of the contact's two.
    pub fn involves(&self, fixture: usize) -> bool {
        self.fixture_a == fixture || self.fixture_b == fixture
    }
}

/// Reused buffers of the island solver (no allocation per step once warm).
#[derive(Debug, Clone, Default)]
struct Scratch {
    stack: Vec<usize>,
    bodies: Vec<usize>,
    contacts: Vec<usize>,
    joints: Vec<usize>,
    constraints: Vec<ContactConstraint>,
    body_flag: Vec<bool>,
    contact_flag: Vec<bool>,
    joint_flag: Vec<bool>,
    pairs: Vec<(usize, usize)>,
}

/// A 2-D world with Box2D 2.3's semantics. Bodies, fixtures and joints are indices into its
/// vectors in creation order; Box2D's lists run newest first, so wherever order matters
/// (islands, contact updates, events) these vectors are walked backwards.
#[derive(Debug, Clone)]
pub struct World {
    pub gravity: V2,
    pub bodies: Vec<Body>,
    pub fixtures: Vec<Fixture>,
    pub joints: Vec<RevoluteJoint>,
    /// Oldest first.
    pub contacts: Vec<Contact>,
    /// Events of the last step.
    pub events: Vec<ContactEvent>,
    /// Whether continuous collision (time of impact) runs after each step's solve.
    pub continuous: bool,
    inv_dt0: f64,
    new_fixture: bool,
    scratch: Scratch,
}

impl World {
    pub fn new(gravity: V2) -> World {
        World {
            gravity,
            bodies: Vec::new(),
            fixtures: Vec::new(),
            joints: Vec::new(),
            contacts: Vec::new(),
            events: Vec::new(),
            continuous: true,
            inv_dt0: 0.0,
            new_fixture: false,
            scratch: Scratch::default(),
        }
    }

    pub fn add_body(&mut self, kind: BodyKind, position: V2, angle: f64) -> usize {
        self.bodies.push(Body::new(kind, position, angle));
        self.bodies.len() - 1
    }

    /// Attach a fixture; a dynamic body's mass is recomputed from all its fixtures.
    pub fn add_fixture(&mut self, body: usize, def: FixtureDef) -> usize {
        let aabb = def.shape.aabb(&self.bodies[body].xf);
        let e = v2(AABB_EXTENSION, AABB_EXTENSION);
        let verts = def.shape.core_vertices().into_iter().map(V2::tuple).collect();
        let proxy = DistanceProxy::new(verts, def.shape.radius()).ok();
        self.fixtures.push(Fixture {
            body,
            def,
            fat_aabb: Aabb {
                lo: aabb.lo - e,
                hi: aabb.hi + e,
            },
            moved: true,
            proxy,
        });
        self.new_fixture = true;
        self.reset_mass(body);
        self.fixtures.len() - 1
    }

    /// A dynamic body with one fixture, its origin at `position`, turned `angle`, moving with
    /// centre-of-mass velocity `v` and angular velocity `w`: `(body, fixture)`. The velocities are
    /// set after the mass, which the fixture determines.
    pub fn add_dynamic(&mut self, position: V2, angle: f64, v: V2, w: f64, def: FixtureDef) -> (usize, usize) {
        let body = self.add_body(BodyKind::Dynamic, position, angle);
        let fixture = self.add_fixture(body, def);
        self.bodies[body].v = v;
        self.bodies[body].w = w;
        (body, fixture)
    }

    fn reset_mass(&mut self, body: usize) {
        let (mut mass, mut center, mut inertia) = (0.0, V2::ZERO, 0.0);
        for f in self.fixtures.iter().filter(|f| f.body == body) {
            let md = f.def.shape.mass(f.def.density);
            mass += md.mass;
            center += md.mass * md.center;
            inertia += md.inertia_center + md.mass * md.center.length_squared();
        }
        if mass > 0.0 {
            center = center * (1.0 / mass);
        }
        inertia -= mass * center.length_squared();
        self.bodies[body].set_mass(mass, center, inertia);
    }

    pub fn add_revolute(&mut self, def: RevoluteDef) -> usize {
        self.joints.push(RevoluteJoint::new(def));
        self.joints.len() - 1
    }

    /// Fixtures `a`, `b` are in a contact whose manifold has points.
    pub fn touching_fixtures(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.contacts
            .iter()
            .filter(|c| c.touching)
            .map(|c| (c.fixture_a, c.fixture_b))
    }

    fn should_collide(&self, fa: usize, fb: usize) -> bool {
        let (a, b) = (&self.fixtures[fa], &self.fixtures[fb]);
        if a.body == b.body || !(self.bodies[a.body].is_dynamic() || self.bodies[b.body].is_dynamic()) {
            return false;
        }
        let (x, y) = (a.def.filter, b.def.filter);
        if x.mask & y.category == 0 || y.mask & x.category == 0 {
            return false;
        }
        // Joined bodies do not collide (`collideConnected = false`).
        !self.joints.iter().any(|j| {
            (j.def.body_a == a.body && j.def.body_b == b.body) || (j.def.body_a == b.body && j.def.body_b == a.body)
        })
    }

    fn fixture_xf(&self, f: usize) -> Xf {
        self.bodies[self.fixtures[f].body].xf
    }

    /// Recompute contact `k`'s manifold, carry impulses over by feature id, record events.
    pub(crate) fn update_contact(&mut self, k: usize) {
        let c = &self.contacts[k];
        let (fa, fb) = (c.fixture_a, c.fixture_b);
        let old = c.manifold;
        let was_touching = c.touching;
        let (xfa, xfb) = (self.fixture_xf(fa), self.fixture_xf(fb));
        let (sa, sb) = (self.fixtures[fa].def.shape, self.fixtures[fb].def.shape);
        let mut m = Manifold::default();
        let r = sa.radius() + sb.radius();
        match (sa, sb) {
            (Shape::Polygon(pa), Shape::Polygon(pb)) => collide_polygons(&mut m, &pa, &xfa, &pb, &xfb, r),
            (Shape::Edge(e1, e2), Shape::Polygon(pb)) => collide_edge_polygon(&mut m, e1, e2, &xfa, &pb, &xfb, r),
            // Contacts are created with the edge as fixture A; edges never collide with edges.
            _ => {}
        }
        for mp in &mut m.points[..m.count] {
            mp.normal_impulse = 0.0;
            mp.tangent_impulse = 0.0;
            if let Some(op) = old.points[..old.count].iter().find(|op| op.id == mp.id) {
                mp.normal_impulse = op.normal_impulse;
                mp.tangent_impulse = op.tangent_impulse;
            }
        }
        let touching = m.count > 0;
        let c = &mut self.contacts[k];
        c.manifold = m;
        c.touching = touching;
        c.enabled = true;
        if touching != was_touching {
            self.events.push(ContactEvent {
                fixture_a: fa,
                fixture_b: fb,
                begin: touching,
            });
        }
    }

    /// Box2D's `b2ContactManager::Collide`: drop contacts whose boxes separated, update the rest.
    fn collide(&mut self) {
        let mut k = self.contacts.len();
        while k > 0 {
            k -= 1;
            let c = &self.contacts[k];
            let (fa, fb) = (c.fixture_a, c.fixture_b);
            if !self.fixtures[fa].fat_aabb.overlaps(&self.fixtures[fb].fat_aabb) {
                if c.touching {
                    self.events.push(ContactEvent {
                        fixture_a: fa,
                        fixture_b: fb,
                        begin: false,
                    });
                }
                self.contacts.remove(k);
                continue;
            }
            self.update_contact(k);
        }
    }

    /// Pairs of a moved box with any box it overlaps become contacts. Only pairs with a dynamic
    /// body can collide ([`Self::should_collide`]), so a moved fixture of a static or kinematic
    /// body is tested against the dynamic bodies' fixtures only: building a world of `n` static
    /// fixtures (a long terrain) costs O(n · dynamic fixtures), not O(n²), with the same pairs.
    pub fn find_new_contacts(&mut self) {
        let mut pairs = std::mem::take(&mut self.scratch.pairs);
        pairs.clear();
        let dynamic: Vec<usize> = (0..self.fixtures.len())
            .filter(|&j| self.bodies[self.fixtures[j].body].is_dynamic())
            .collect();
        for (i, f) in self.fixtures.iter().enumerate() {
            if !f.moved {
                continue;
            }
            let mut test = |j: usize| {
                if i != j && f.fat_aabb.overlaps(&self.fixtures[j].fat_aabb) {
                    pairs.push((i.min(j), i.max(j)));
                }
            };
            if self.bodies[f.body].is_dynamic() {
                (0..self.fixtures.len()).for_each(&mut test);
            } else {
                dynamic.iter().for_each(|&j| test(j));
            }
        }
        pairs.sort_unstable();
        pairs.dedup();
        for f in &mut self.fixtures {
            f.moved = false;
        }
        for &(i, j) in &pairs {
            if !self.should_collide(i, j) {
                continue;
            }
            // Edge first, as Box2D registers the edge-polygon contact.
            let (fa, fb) = match (self.fixtures[i].def.shape, self.fixtures[j].def.shape) {
                (Shape::Polygon(_), Shape::Edge(..)) => (j, i),
                (Shape::Edge(..), Shape::Edge(..)) => continue,
                _ => (i, j),
            };
            if self.contacts.iter().any(|c| c.fixture_a == fa && c.fixture_b == fb) {
                continue;
            }
            let (da, db) = (&self.fixtures[fa].def, &self.fixtures[fb].def);
            self.contacts.push(Contact {
                fixture_a: fa,
                fixture_b: fb,
                manifold: Manifold::default(),
                touching: false,
                friction: (da.friction * db.friction).sqrt(),
                restitution: da.restitution.max(db.restitution),
                enabled: true,
                toi: None,
                toi_count: 0,
            });
        }
        self.scratch.pairs = pairs;
    }

    /// Move body `b`'s broad-phase boxes to cover its sweep over the step.
    pub fn synchronize_fixtures(&mut self, b: usize) {
        let body = &self.bodies[b];
        let xf1 = Xf::from_center(body.sweep.c0, body.sweep.a0, body.sweep.local_center);
        let xf2 = body.xf;
        let d = xf2.p - xf1.p;
        for f in self.fixtures.iter_mut().filter(|f| f.body == b) {
            let aabb = f.def.shape.aabb(&xf1).union(&f.def.shape.aabb(&xf2));
            if f.fat_aabb.contains(&aabb) {
                continue;
            }
            let e = v2(AABB_EXTENSION, AABB_EXTENSION);
            let mut fat = Aabb {
                lo: aabb.lo - e,
                hi: aabb.hi + e,
            };
            let d = AABB_MULTIPLIER * d;
            if d.x < 0.0 {
                fat.lo.x += d.x;
            } else {
                fat.hi.x += d.x;
            }
            if d.y < 0.0 {
                fat.lo.y += d.y;
            } else {
                fat.hi.y += d.y;
            }
            f.fat_aabb = fat;
            f.moved = true;
        }
    }

    /// Advance the world by `dt` with Box2D's iteration counts.
    pub fn step(&mut self, dt: f64, velocity_iterations: usize, position_iterations: usize) {
        self.events.clear();
        if self.new_fixture {
            self.find_new_contacts();
            self.new_fixture = false;
        }
        self.collide();
        if dt > 0.0 {
            let dt_ratio = self.inv_dt0 * dt;
            self.solve(dt, dt_ratio, velocity_iterations, position_iterations);
            if self.continuous {
                self.solve_toi(dt, velocity_iterations);
            }
            self.inv_dt0 = 1.0 / dt;
        }
        for b in &mut self.bodies {
            b.force = V2::ZERO;
            b.torque = 0.0;
        }
    }

    /// Time of impact of contact `k` in the current pass (Box2D's cached `m_toi`), computing it
    /// if needed; `None` if the pair takes no continuous collision (two dynamic bodies: Box2D
    /// sweeps them only against static ones, or as bullets, which are not modelled).
    fn contact_toi(&mut self, k: usize) -> Option<f64> {
        if let Some(t) = self.contacts[k].toi {
            return Some(t);
        }
        let (fa, fb) = (self.contacts[k].fixture_a, self.contacts[k].fixture_b);
        let (ba, bb) = (self.fixtures[fa].body, self.fixtures[fb].body);
        let (da, db) = (self.bodies[ba].is_dynamic(), self.bodies[bb].is_dynamic());
        if (da && db) || !(da || db) {
            return None;
        }
        // Put both sweeps on the same time interval.
        let (a0a, a0b) = (self.bodies[ba].sweep.alpha0, self.bodies[bb].sweep.alpha0);
        let alpha0 = if a0a < a0b {
            self.bodies[ba].sweep.advance(a0b);
            a0b
        } else {
            if a0b < a0a {
                self.bodies[bb].sweep.advance(a0a);
            }
            a0a
        };
        let alpha = match (&self.fixtures[fa].proxy, &self.fixtures[fb].proxy) {
            (Some(pa), Some(pb)) => {
                let out = toi::time_of_impact(
                    pa,
                    &toi_sweep(&self.bodies[ba].sweep),
                    pb,
                    &toi_sweep(&self.bodies[bb].sweep),
                    1.0,
                );
                if out.state == ToiState::Touching {
                    (alpha0 + (1.0 - alpha0) * out.t).min(1.0)
                } else {
                    1.0
                }
            }
            _ => 1.0,
        };
        self.contacts[k].toi = Some(alpha);
        Some(alpha)
    }

    /// Box2D's `SolveTOI`: repeatedly take the earliest time of impact of a dynamic body with a
    /// static one, move the pair there, and solve a sub-step for the rest of the step on an
    /// island of those two bodies and their touching static contacts (no joints, no warm start;
    /// the position solve with `TOI_BAUMGARTE` moves only the two bodies of the impact).
    fn solve_toi(&mut self, dt: f64, velocity_iterations: usize) {
        for b in &mut self.bodies {
            b.sweep.alpha0 = 0.0;
        }
        for c in &mut self.contacts {
            c.toi = None;
            c.toi_count = 0;
        }
        let mut s = std::mem::take(&mut self.scratch);
        loop {
            let mut min: Option<usize> = None;
            let mut min_alpha = 1.0;
            for k in (0..self.contacts.len()).rev() {
                let c = &self.contacts[k];
                if !c.enabled || c.toi_count > MAX_SUB_STEPS {
                    continue;
                }
                if let Some(alpha) = self.contact_toi(k)
                    && alpha < min_alpha
                {
                    min = Some(k);
                    min_alpha = alpha;
                }
            }
            let Some(k) = min else { break };
            if 1.0 - 10.0 * EPSILON < min_alpha {
                break;
            }
            let (ba, bb) = self.contact_bodies(k);
            let backup = (self.bodies[ba].sweep, self.bodies[bb].sweep);
            self.bodies[ba].advance(min_alpha);
            self.bodies[bb].advance(min_alpha);
            self.update_contact(k);
            self.contacts[k].toi = None;
            self.contacts[k].toi_count += 1;
            if !self.contacts[k].touching {
                // The shapes do not quite touch there: skip this pair for the rest of the pass.
                self.contacts[k].enabled = false;
                self.bodies[ba].sweep = backup.0;
                self.bodies[bb].sweep = backup.1;
                self.bodies[ba].synchronize_transform();
                self.bodies[bb].synchronize_transform();
                continue;
            }
            s.bodies.clear();
            s.contacts.clear();
            s.bodies.extend([ba, bb]);
            s.contacts.push(k);
            for body in [ba, bb] {
                if !self.bodies[body].is_dynamic() {
                    continue;
                }
                for ck in (0..self.contacts.len()).rev() {
                    if s.bodies.len() == 2 * MAX_TOI_CONTACTS || s.contacts.len() == MAX_TOI_CONTACTS {
                        break;
                    }
                    let (ca, cb) = self.contact_bodies(ck);
                    if (ca != body && cb != body) || s.contacts.contains(&ck) {
                        continue;
                    }
                    let other = if ca == body { cb } else { ca };
                    if self.bodies[other].is_dynamic() {
                        continue;
                    }
                    let saved = self.bodies[other].sweep;
                    if !s.bodies.contains(&other) {
                        self.bodies[other].advance(min_alpha);
                    }
                    self.update_contact(ck);
                    if !self.contacts[ck].touching {
                        self.bodies[other].sweep = saved;
                        self.bodies[other].synchronize_transform();
                        continue;
                    }
                    s.contacts.push(ck);
                    if !s.bodies.contains(&other) {
                        s.bodies.push(other);
                    }
                }
            }
            self.solve_toi_island(&mut s, (1.0 - min_alpha) * dt, velocity_iterations, (ba, bb));
            for i in 0..s.bodies.len() {
                let b = s.bodies[i];
                if !self.bodies[b].is_dynamic() {
                    continue;
                }
                self.synchronize_fixtures(b);
                for c in 0..self.contacts.len() {
                    let (ca, cb) = self.contact_bodies(c);
                    if ca == b || cb == b {
                        self.contacts[c].toi = None;
                    }
                }
            }
            self.find_new_contacts();
        }
        self.scratch = s;
    }

    fn contact_bodies(&self, k: usize) -> (usize, usize) {
        let c = &self.contacts[k];
        (self.fixtures[c.fixture_a].body, self.fixtures[c.fixture_b].body)
    }

    /// The island's contact constraints into `s.constraints`; `dt_ratio` scales the warm start
    /// (`None`: a TOI sub-step, which Box2D solves without warm starting).
    fn contact_constraints(&self, s: &mut Scratch, dt_ratio: Option<f64>) {
        s.constraints.clear();
        for &k in &s.contacts {
            let c = &self.contacts[k];
            let (fa, fb) = (&self.fixtures[c.fixture_a], &self.fixtures[c.fixture_b]);
            s.constraints.push(ContactConstraint::new(
                k,
                (fa.body, fb.body),
                &c.manifold,
                c.friction,
                c.restitution,
                (fa.def.shape.radius(), fb.def.shape.radius()),
                dt_ratio,
            ));
        }
    }

    fn solve_toi_island(&mut self, s: &mut Scratch, h: f64, vel_iters: usize, toi_pair: (usize, usize)) {
        self.contact_constraints(s, None);
        for _ in 0..20 {
            if cs::solve_position(&s.constraints, &mut self.bodies, TOI_BAUMGARTE, Some(toi_pair), 1.5) {
                break;
            }
        }
        // The corrected placement is the sub-step's start.
        for b in [toi_pair.0, toi_pair.1] {
            let body = &mut self.bodies[b];
            body.sweep.c0 = body.sweep.c;
            body.sweep.a0 = body.sweep.a;
        }
        cs::init_velocity(&mut s.constraints, &self.bodies);
        for _ in 0..vel_iters {
            cs::solve_velocity(&mut s.constraints, &mut self.bodies);
        }
        for &b in &s.bodies {
            if self.bodies[b].is_dynamic() {
                integrate_position(&mut self.bodies[b], h);
                self.bodies[b].synchronize_transform();
            }
        }
    }

    /// Build the islands (Box2D's depth-first order) and solve each.
    fn solve(&mut self, dt: f64, dt_ratio: f64, vel_iters: usize, pos_iters: usize) {
        let mut s = std::mem::take(&mut self.scratch);
        s.body_flag.clear();
        s.body_flag.resize(self.bodies.len(), false);
        s.contact_flag.clear();
        s.contact_flag.resize(self.contacts.len(), false);
        s.joint_flag.clear();
        s.joint_flag.resize(self.joints.len(), false);
        for seed in (0..self.bodies.len()).rev() {
            if s.body_flag[seed] || !self.bodies[seed].is_dynamic() {
                continue;
            }
            s.bodies.clear();
            s.contacts.clear();
            s.joints.clear();
            s.stack.clear();
            s.stack.push(seed);
            s.body_flag[seed] = true;
            while let Some(b) = s.stack.pop() {
                s.bodies.push(b);
                if !self.bodies[b].is_dynamic() {
                    continue;
                }
                for k in (0..self.contacts.len()).rev() {
                    let c = &self.contacts[k];
                    let (ba, bb) = (self.fixtures[c.fixture_a].body, self.fixtures[c.fixture_b].body);
                    if (ba != b && bb != b) || s.contact_flag[k] || !c.enabled || !c.touching {
                        continue;
                    }
                    s.contacts.push(k);
                    s.contact_flag[k] = true;
                    let other = if ba == b { bb } else { ba };
                    if !s.body_flag[other] {
                        s.stack.push(other);
                        s.body_flag[other] = true;
                    }
                }
                for k in (0..self.joints.len()).rev() {
                    let j = &self.joints[k].def;
                    if (j.body_a != b && j.body_b != b) || s.joint_flag[k] {
                        continue;
                    }
                    s.joints.push(k);
                    s.joint_flag[k] = true;
                    let other = if j.body_a == b { j.body_b } else { j.body_a };
                    if !s.body_flag[other] {
                        s.stack.push(other);
                        s.body_flag[other] = true;
                    }
                }
            }
            self.solve_island(&mut s, dt, dt_ratio, vel_iters, pos_iters);
            // Static bodies may join other islands.
            for &b in &s.bodies {
                if !self.bodies[b].is_dynamic() {
                    s.body_flag[b] = false;
                }
            }
        }
        for b in 0..self.bodies.len() {
            if s.body_flag[b] && self.bodies[b].is_dynamic() {
                self.synchronize_fixtures(b);
            }
        }
        self.scratch = s;
        self.find_new_contacts();
    }

    fn solve_island(&mut self, s: &mut Scratch, h: f64, dt_ratio: f64, vel_iters: usize, pos_iters: usize) {
        let g = self.gravity;
        for &b in &s.bodies {
            let body = &mut self.bodies[b];
            if !body.is_dynamic() {
                continue;
            }
            body.sweep.c0 = body.sweep.c;
            body.sweep.a0 = body.sweep.a;
            body.v += h * (g + body.inv_mass * body.force);
            body.w += h * body.inv_inertia * body.torque;
        }
        self.contact_constraints(s, Some(dt_ratio));
        cs::init_velocity(&mut s.constraints, &self.bodies);
        cs::warm_start(&s.constraints, &mut self.bodies);
        for &j in &s.joints {
            self.joints[j].init_velocity(&mut self.bodies, dt_ratio, true);
        }
        for _ in 0..vel_iters {
            for &j in &s.joints {
                self.joints[j].solve_velocity(&mut self.bodies, h);
            }
            cs::solve_velocity(&mut s.constraints, &mut self.bodies);
        }
        for c in &s.constraints {
            let m = &mut self.contacts[c.contact].manifold;
            for (mp, vp) in m.points.iter_mut().zip(&c.points).take(c.count) {
                mp.normal_impulse = vp.normal_impulse;
                mp.tangent_impulse = vp.tangent_impulse;
            }
        }
        for &b in &s.bodies {
            integrate_position(&mut self.bodies[b], h);
        }
        for _ in 0..pos_iters {
            let contacts_ok = cs::solve_position(&s.constraints, &mut self.bodies, BAUMGARTE, None, 3.0);
            let mut joints_ok = true;
            for &j in &s.joints {
                joints_ok &= self.joints[j].solve_position(&mut self.bodies);
            }
            if contacts_ok && joints_ok {
                break;
            }
        }
        for &b in &s.bodies {
            if self.bodies[b].is_dynamic() {
                self.bodies[b].synchronize_transform();
            }
        }
    }
}

fn toi_sweep(s: &super::body::Sweep) -> toi::Sweep {
    toi::Sweep {
        local_center: s.local_center.tuple(),
        c0: s.c0.tuple(),
        c: s.c.tuple(),
        a0: s.a0,
        a: s.a,
        alpha0: s.alpha0,
    }
}

/// Move a dynamic body by its velocity, capping the step's motion at `MAX_TRANSLATION` and
/// `MAX_ROTATION` (the velocity is scaled down with it).
pub(crate) fn integrate_position(body: &mut Body, h: f64) {
    if !body.is_dynamic() {
        return;
    }
    let t = h * body.v;
    if t.length_squared() > MAX_TRANSLATION * MAX_TRANSLATION {
        body.v = body.v * (MAX_TRANSLATION / t.length());
    }
    let r = h * body.w;
    if r * r > MAX_ROTATION * MAX_ROTATION {
        body.w *= MAX_ROTATION / r.abs();
    }
    body.sweep.c += h * body.v;
    body.sweep.a += h * body.w;
}

impl World {
    /// Find and evaluate the contacts of the current placement without reporting events: for
    /// a world rebuilt from a saved state, what touches now is the baseline, not news.
    pub fn prime_contacts(&mut self) {
        self.find_new_contacts();
        self.new_fixture = false;
        for k in (0..self.contacts.len()).rev() {
            self.update_contact(k);
        }
        self.events.clear();
    }

    /// Whether any contact of fixture `f` touches.
    pub fn fixture_touches(&self, f: usize) -> bool {
        self.contacts
            .iter()
            .any(|c| c.touching && (c.fixture_a == f || c.fixture_b == f))
    }
}
