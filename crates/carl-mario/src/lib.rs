//! Clean-room Mario runtime for carl-spec.
//!
//! * [`toad_gan`]: TOAD-GAN level generation (CARL's `generate_level`) without an ML framework,
//!   including torch's `randn` bit for bit.
//! * [`data`]: where the user-supplied data (levels, converted generator weights) lives.
//!
//! Nothing Nintendo-derived is embedded: levels and weights are read from a data directory laid
//! out as the data guide says (see [`data::DataDir`]).

pub mod data;
pub mod engine;
pub mod error;
pub mod game;
pub mod render;
pub mod toad_gan;

pub use data::DataDir;
pub use error::MarioError;
