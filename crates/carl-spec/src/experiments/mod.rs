//! End-to-end experiments of the CARL paper, runnable as `carl-spec run EXPERIMENT`.
//!
//! * [`landing_in_space`]: LunarLander across planetary gravities (test bodies and a train sample).

pub mod landing_in_space;
