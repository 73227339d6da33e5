//! Finished images.

/// An RGB image, 3 bytes per pixel, rows top to bottom (Gymnasium's `rgb_array` layout).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub rgb: Vec<u8>,
}

impl Frame {
    /// The frame of a finished canvas.
    pub fn from_canvas(canvas: &super::canvas::Canvas) -> Frame {
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
