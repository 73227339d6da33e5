//! The classic-control family's integration tests: bit-exact parity with Gymnasium 1.4 and
//! behaviour under contexts.

mod envs_behaviour;
mod parity;
