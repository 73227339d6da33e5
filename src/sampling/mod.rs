//! Portable, reproducible sampling: PCG64 plus samplers written here with `libm` maths only.
pub mod pcg64;
