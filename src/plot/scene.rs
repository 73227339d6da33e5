//! A backend-neutral drawing: shapes in pixel coordinates (origin top left), rendered to SVG text
//! by [`super::svg`] and rasterized to PNG by [`super::png`]. Layout happens once, here-independent,
//! so both formats show the same figure.

/// An opaque sRGB colour.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Color(pub u8, pub u8, pub u8);

impl Color {
    pub const WHITE: Color = Color(255, 255, 255);
    pub const BLACK: Color = Color(0, 0, 0);
    pub fn hex(self) -> String {
        format!("#{:02x}{:02x}{:02x}", self.0, self.1, self.2)
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stroke {
    pub color: Color,
    pub width: f64,
    /// Dash and gap length; `None` = solid.
    pub dash: Option<f64>,
}

impl Stroke {
    pub fn solid(color: Color, width: f64) -> Self {
        Stroke {
            color,
            width,
            dash: None,
        }
    }
    pub fn dashed(color: Color, width: f64, dash: f64) -> Self {
        Stroke {
            color,
            width,
            dash: Some(dash),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

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
    /// `y` is the baseline; `scale` multiplies the built-in font's units (see [`super::font`]).
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
