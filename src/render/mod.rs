//! Pictures of environment states for humans: `Env::render` returns a [`Frame`] (RGB8, row-major,
//! top row first, like Gymnasium's `rgb_array`), drawn in software with
//! [`crate::plot::png::Canvas`] so no system library or font is involved and the same state
//! always gives the same bytes. [`encode`] writes frames as PNG files or an animated GIF.

pub mod encode;
pub mod lunar_lander;

/// An RGB image, 3 bytes per pixel, rows top to bottom.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Frame {
    /// The frame of a finished canvas.
    pub fn from_canvas(canvas: &crate::plot::png::Canvas) -> Frame {
        Frame {
            width: canvas.width,
            height: canvas.height,
            rgb: canvas.to_rgb8(),
        }
    }

    /// The pixel at column `x`, row `y` (panics outside the frame, like slice indexing).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 3] {
        let i = 3 * (y as usize * self.width as usize + x as usize);
        [self.rgb[i], self.rgb[i + 1], self.rgb[i + 2]]
    }
}
