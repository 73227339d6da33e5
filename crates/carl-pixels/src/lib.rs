//! Pixels: the lowest drawing layer, shared by the environments' renderers and by `plot`.
//!
//! It sits below everything else on purpose: an environment that draws itself must not depend
//! on the histogram code, and `plot` must not depend on the environments. This module imports
//! nothing from the rest of the crate.
//!
//! * [`color`]: an opaque sRGB colour.
//! * [`canvas`]: a software rasteriser (anti-aliased rectangles, polygons, lines, bitmap text)
//!   with the stroke and text-anchor types it draws with.
//! * [`font`]: the built-in 5×7 bitmap font, so no system font is involved.
//! * [`frame`]: an RGB8 image, what `Env::render` returns.
//! * [`encode`]: frames to PNG or animated GIF bytes (pure-Rust encoders, pinned versions).
//!
//! Everything is deterministic: the same drawing calls give the same bytes on every machine.

pub mod canvas;
pub mod color;
pub mod encode;
pub mod font;
pub mod frame;

pub use canvas::{Anchor, Canvas, Stroke};
pub use color::Color;
pub use frame::Frame;
