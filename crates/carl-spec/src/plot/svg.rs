//! SVG output: the scene as plain text, no dependencies. Numbers are printed with at most two
//! decimals, so the same scene always gives the same bytes.

use std::fmt::Write as _;

use super::scene::{Anchor, Scene, Shape};

fn num(x: f64) -> String {
    let s = format!("{x:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" { "0".into() } else { s.to_string() }
}

/// Escape text for XML character data and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if (c as u32) < 0x20 && c != '\n' && c != '\t' => {}
            c => out.push(c),
        }
    }
    out
}

pub fn render(scene: &Scene) -> String {
    let (w, h) = (scene.width, scene.height);
    let mut s = String::new();
    let _ = writeln!(s, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        s,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="DejaVu Sans Mono, Menlo, Consolas, monospace">"#
    );
    let _ = writeln!(s, "<title>{}</title>", escape(&scene.title));
    let _ = writeln!(s, "<desc>{}</desc>", escape(&scene.description));
    let _ = writeln!(s, r#"<rect class="background" width="{w}" height="{h}" fill="white"/>"#);
    for item in &scene.items {
        let mut attrs = String::new();
        if !item.class.is_empty() {
            let _ = write!(attrs, r#" class="{}""#, item.class);
        }
        for (k, v) in &item.data {
            let _ = write!(attrs, r#" data-{k}="{}""#, escape(v));
        }
        match &item.shape {
            Shape::GroupStart => {
                let _ = writeln!(s, "<g{attrs}>");
            }
            Shape::GroupEnd => s.push_str("</g>\n"),
            Shape::Rect {
                x,
                y,
                w,
                h,
                fill,
                opacity,
            } => {
                let op = if *opacity < 1.0 {
                    format!(r#" fill-opacity="{}""#, num(*opacity))
                } else {
                    String::new()
                };
                let _ = writeln!(
                    s,
                    r#"<rect{attrs} x="{}" y="{}" width="{}" height="{}" fill="{}"{op}/>"#,
                    num(*x),
                    num(*y),
                    num(*w),
                    num(*h),
                    fill.hex()
                );
            }
            Shape::Line { x1, y1, x2, y2, stroke } => {
                let dash = stroke
                    .dash
                    .map(|d| format!(r#" stroke-dasharray="{} {}""#, num(d), num(d)))
                    .unwrap_or_default();
                let _ = writeln!(
                    s,
                    r#"<line{attrs} x1="{}" y1="{}" x2="{}" y2="{}" stroke="{}" stroke-width="{}"{dash}/>"#,
                    num(*x1),
                    num(*y1),
                    num(*x2),
                    num(*y2),
                    stroke.color.hex(),
                    num(stroke.width)
                );
            }
            Shape::Polygon { points, fill } => {
                let pts: Vec<String> = points.iter().map(|(x, y)| format!("{},{}", num(*x), num(*y))).collect();
                let _ = writeln!(
                    s,
                    r#"<polygon{attrs} points="{}" fill="{}"/>"#,
                    pts.join(" "),
                    fill.hex()
                );
            }
            Shape::Text {
                x,
                y,
                text,
                scale,
                anchor,
                color,
                bold,
                vertical,
            } => {
                let anchor = match anchor {
                    Anchor::Start => "start",
                    Anchor::Middle => "middle",
                    Anchor::End => "end",
                };
                let weight = if *bold { r#" font-weight="bold""# } else { "" };
                let rotate = if *vertical {
                    format!(r#" transform="rotate(-90 {} {})""#, num(*x), num(*y))
                } else {
                    String::new()
                };
                let _ = writeln!(
                    s,
                    r#"<text{attrs} x="{}" y="{}" font-size="{}" text-anchor="{anchor}" fill="{}"{weight}{rotate}>{}</text>"#,
                    num(*x),
                    num(*y),
                    scale * 10,
                    color.hex(),
                    escape(text)
                );
            }
        }
    }
    s.push_str("</svg>\n");
    s
}
