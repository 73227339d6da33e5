//! The Mario context: a plain value, checked into engine types before use.

use carl_mario::MarioError;
use carl_mario::toad_gan::{MAX_WIDTH, MIN_WIDTH};

use carl_env::api::context_features;

/// Mario context. `Default` is carl-bench 1.1.1's default context (generator 1-1, seed 0,
/// width 100, σ = 1, small Mario, inertia 0.89).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MarioParams {
    pub level_index: f64,
    pub noise_seed: f64,
    pub level_width: f64,
    pub noise: f64,
    pub mario_state: f64,
    pub mario_inertia: f64,
}

impl Default for MarioParams {
    fn default() -> Self {
        MarioParams {
            level_index: 0.0,
            noise_seed: 0.0,
            level_width: 100.0,
            noise: 1.0,
            mario_state: 0.0,
            mario_inertia: 0.89,
        }
    }
}

context_features!(MarioParams, "mario", {
    level_index: "level_index",
    noise_seed: "noise_seed",
    level_width: "level_width",
    noise: "noise",
    mario_state: "mario_state",
    mario_inertia: "mario_inertia",
});

/// The context in engine types.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Checked {
    pub level_index: usize,
    pub noise_seed: u32,
    pub level_width: usize,
    pub noise: f32,
    pub mario_state: u8,
    pub inertia: f32,
}

impl MarioParams {
    /// Checks every value (integers where the engine needs them, ranges the engine can run).
    /// The spec's bounds are enforced by `make`; these are the hard limits beyond them.
    pub(crate) fn checked(&self) -> Result<Checked, MarioError> {
        let bad = |name: &str, value: f64, want: &str| MarioError::BadLevel {
            origin: "mario context".into(),
            reason: format!("{name} = {value} must be {want}"),
        };
        let int = |name: &str, v: f64, lo: f64, hi: f64| -> Result<f64, MarioError> {
            if v.fract() == 0.0 && (lo..=hi).contains(&v) {
                Ok(v)
            } else {
                Err(bad(name, v, &format!("an integer in [{lo}, {hi}]")))
            }
        };
        let level_index = int("level_index", self.level_index, 0.0, 255.0)? as usize;
        let noise_seed = int("noise_seed", self.noise_seed, 0.0, f64::from(u32::MAX))? as u32;
        let level_width = int("level_width", self.level_width, MIN_WIDTH as f64, MAX_WIDTH as f64)? as usize;
        let mario_state = int("mario_state", self.mario_state, 0.0, 2.0)? as u8;
        if !self.noise.is_finite() || self.noise.abs() > 1e6 {
            return Err(bad("noise", self.noise, "a finite noise scale"));
        }
        if !(self.mario_inertia.is_finite() && self.mario_inertia > 0.0 && self.mario_inertia <= 16.0) {
            return Err(bad("mario_inertia", self.mario_inertia, "in (0, 16]"));
        }
        Ok(Checked {
            level_index,
            noise_seed,
            level_width,
            noise: self.noise as f32,
            mario_state,
            inertia: self.mario_inertia as f32,
        })
    }
}
