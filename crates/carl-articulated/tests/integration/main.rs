//! carl-articulated's integration tests: analytic checks of the dynamics ([`analytic`]) and
//! parity with the real MuJoCo on fixtures written by `scripts/articulated_mujoco_fixtures.py`
//! ([`parity`], models built by [`fixture`]); the quadruped's ellipsoid, tendon equalities and site
//! sensors against `scripts/articulated_quadruped_fixture.py`'s fixture ([`sensors`]).

mod analytic;
mod fixture;
mod parity;
mod sensors;
