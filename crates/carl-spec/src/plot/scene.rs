//! A backend-neutral drawing: shapes in pixel coordinates (origin top left), rendered to SVG text
//! by [`super::svg`] and rasterized to PNG by [`super::png`]. Layout happens once, independent of
//! the format, so both formats show the same figure. Colours, strokes and text anchors are the
//! pixel layer's ([`crate::pixels`]).

pub use crate::pixels::{Anchor, Color, Stroke};

#[derive(Debug, Clone, PartialEq)]
pub enum Shape {
    Rect {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: Color,
        /// Fill opacity, 0..=1.
        opacity: f64,
    },
    Line {
        x1: f64,
        y1: f64,
        x2: f64,
        y2: f64,
        stroke: Stroke,
    },
    Polygon {
        points: Vec<(f64, f64)>,
        fill: Color,
    },
    /// `y` is the baseline; `scale` multiplies the built-in font's units (see [`crate::pixels::font`]).
    /// `vertical` text reads bottom to top, rotated about (x, y).
    Text {
        x: f64,
        y: f64,
        text: String,
        scale: u32,
        anchor: Anchor,
        color: Color,
        bold: bool,
        vertical: bool,
    },
    /// Start of a group (SVG `<g>`); ignored by the rasterizer.
    GroupStart,
    GroupEnd,
}

/// A shape with the SVG class and `data-*` attributes that describe what it shows.
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    pub shape: Shape,
    pub class: &'static str,
    pub data: Vec<(&'static str, String)>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    pub width: u32,
    pub height: u32,
    pub title: String,
    pub description: String,
    pub items: Vec<Item>,
}

impl Scene {
    /// An error naming the first shape with a non-finite coordinate or size (NaN or ±inf would
    /// give an SVG that viewers reject and a PNG with shapes missing).
    pub fn check_finite(&self) -> Result<(), String> {
        for item in &self.items {
            let numbers: Vec<f64> = match &item.shape {
                Shape::Rect {
                    x, y, w, h, opacity, ..
                } => vec![*x, *y, *w, *h, *opacity],
                Shape::Line { x1, y1, x2, y2, stroke } => vec![*x1, *y1, *x2, *y2, stroke.width],
                Shape::Polygon { points, .. } => points.iter().flat_map(|&(x, y)| [x, y]).collect(),
                Shape::Text { x, y, .. } => vec![*x, *y],
                Shape::GroupStart | Shape::GroupEnd => Vec::new(),
            };
            if numbers.iter().any(|v| !v.is_finite()) {
                let what = if item.class.is_empty() { "shape" } else { item.class };
                return Err(format!(
                    "cannot draw \"{}\": a {what} would have a non-finite coordinate (the values are too far apart or too large to draw)",
                    self.title
                ));
            }
        }
        Ok(())
    }

    pub fn push(&mut self, class: &'static str, shape: Shape) {
        self.items.push(Item {
            shape,
            class,
            data: Vec::new(),
        });
    }
    pub fn push_data(&mut self, class: &'static str, data: Vec<(&'static str, String)>, shape: Shape) {
        self.items.push(Item { shape, class, data });
    }
    #[allow(clippy::too_many_arguments)]
    pub fn text(&mut self, class: &'static str, x: f64, y: f64, text: &str, scale: u32, anchor: Anchor, color: Color) {
        self.push(
            class,
            Shape::Text {
                x,
                y,
                text: text.to_string(),
                scale,
                anchor,
                color,
                bold: false,
                vertical: false,
            },
        );
    }
    pub fn line(&mut self, class: &'static str, (x1, y1): (f64, f64), (x2, y2): (f64, f64), stroke: Stroke) {
        self.push(class, Shape::Line { x1, y1, x2, y2, stroke });
    }
}
