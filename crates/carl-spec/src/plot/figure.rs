//! What a plot shows (one panel per varied feature) and its layout as a [`Scene`].

use super::histogram::{Bins, bin, fmt_num, fmt_sig, ticks};
use super::scene::{Anchor, Color, Scene, Shape, Stroke};
use crate::pixels::font::text_width;

/// How a named instance is coloured: by its split, if it has one.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum MarkKind {
    InDistribution,
    OutOfDistribution,
    Named,
}

impl MarkKind {
    fn color(self) -> Color {
        match self {
            MarkKind::InDistribution => IN_COLOR,
            MarkKind::OutOfDistribution => OUT_COLOR,
            MarkKind::Named => NAMED_COLOR,
        }
    }
    fn legend(self) -> &'static str {
        match self {
            MarkKind::InDistribution => "in distribution",
            MarkKind::OutOfDistribution => "out of distribution",
            MarkKind::Named => "named instances",
        }
    }
    pub fn as_str(self) -> &'static str {
        match self {
            MarkKind::InDistribution => "in_distribution",
            MarkKind::OutOfDistribution => "out_of_distribution",
            MarkKind::Named => "none",
        }
    }
}

/// A labelled marker: one named instance's value of the panel's feature.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    pub label: String,
    pub value: f64,
    pub kind: MarkKind,
    /// The set it comes from (`env/set`).
    pub set: String,
}

/// A whole set's values as short ticks along the bottom of the panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Rug {
    pub set: String,
    pub values: Vec<f64>,
}

/// One varied feature.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    pub feature: String,
    pub unit: Option<String>,
    /// `[lower, upper]`, `None` = open side.
    pub bounds: [Option<f64>; 2],
    /// Integer-valued feature: bins centred on whole numbers.
    pub integer: bool,
    pub values: Vec<f64>,
    pub marks: Vec<Mark>,
    pub rugs: Vec<Rug>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// `env/set` of the plotted set.
    pub title: String,
    pub description: String,
    pub panels: Vec<Panel>,
    /// Force this many bins (default: Freedman–Diaconis, see [`super::histogram`]).
    pub bins: Option<usize>,
}

const WIDTH: f64 = 1000.0;
const MARGIN_LEFT: f64 = 84.0;
const MARGIN_RIGHT: f64 = 36.0;
const PLOT_HEIGHT: f64 = 250.0;
const LEVEL_HEIGHT: f64 = 22.0;
const RUG_HEIGHT: f64 = 12.0;

const TEXT: Color = Color(0x22, 0x22, 0x22);
const MUTED: Color = Color(0x5f, 0x5f, 0x5f);
const BAR_COLOR: Color = Color(0x4c, 0x78, 0xa8);
const IN_COLOR: Color = Color(0x1a, 0x8a, 0x4a);
const OUT_COLOR: Color = Color(0xd7, 0x30, 0x27);
const NAMED_COLOR: Color = Color(0x75, 0x70, 0xb3);
const BOUND_COLOR: Color = Color(0x33, 0x33, 0x33);
const SHADE: Color = Color(0xec, 0xec, 0xec);
const GRID: Color = Color(0xe2, 0xe2, 0xe2);
const RUG_COLORS: [Color; 4] = [
    Color(0xe6, 0x9f, 0x00),
    Color(0x00, 0x72, 0xb2),
    Color(0xcc, 0x79, 0xa7),
    Color(0x00, 0x9e, 0x73),
];

/// Greedy word wrap to at most `max` characters a line (longer words stay whole).
pub fn wrap(text: &str, max: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        if !line.is_empty() && line.chars().count() + 1 + word.chars().count() > max {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push(' ');
        }
        line.push_str(word);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// Legend entries, figure-wide, in order of first appearance.
#[derive(Debug, Clone, PartialEq)]
enum Swatch {
    Bar,
    Marker(Color),
    Rug(Color),
    Bound,
    Shade,
}

fn set_short(name: &str) -> &str {
    name.rsplit('/').next().unwrap_or(name)
}

struct PanelLayout {
    lo: f64,
    hi: f64,
    bins: Bins,
}

impl Panel {
    fn extent(&self) -> Option<(f64, f64)> {
        let all = self
            .values
            .iter()
            .chain(self.marks.iter().map(|m| &m.value))
            .chain(self.rugs.iter().flat_map(|r| r.values.iter()))
            .copied()
            .filter(|x| x.is_finite());
        all.fold(None, |acc, x| match acc {
            None => Some((x, x)),
            Some((a, b)) => Some((a.min(x), b.max(x))),
        })
    }

    fn layout(&self, fixed_bins: Option<usize>) -> PanelLayout {
        let bins = bin(&self.values, self.integer, fixed_bins);
        let (dmin, dmax) = self.extent().unwrap_or((0.0, 1.0));
        let mut span = dmax - dmin;
        if span == 0.0 {
            span = (dmin.abs() * 0.1).max(1.0);
        }
        let (mut lo, mut hi) = (dmin, dmax);
        if !bins.counts.is_empty() {
            lo = lo.min(bins.start);
            hi = hi.max(bins.end());
        }
        // A finite bound is drawn in place when it lies within one data span of the data;
        // farther bounds get an arrow note at the edge instead of squeezing the histogram.
        for b in self.bounds.iter().flatten() {
            if *b >= dmin - span && *b <= dmax + span {
                lo = lo.min(*b);
                hi = hi.max(*b);
            }
        }
        if hi == lo {
            lo -= 0.5;
            hi += 0.5;
        }
        let pad = (hi - lo) * 0.04;
        PanelLayout {
            lo: lo - pad,
            hi: hi + pad,
            bins,
        }
    }
}

/// Place labels above the plot: each wants to be centred on its mark (`desired`, in value
/// order). Labels are spread over as many rows as their total width needs (round robin), and
/// within a row pushed apart just enough not to overlap, keeping each group of touching labels
/// centred on its marks (and inside `[left, right]`). Returns (centre x, row) per label.
fn place_labels(desired: &[f64], widths: &[f64], left: f64, right: f64) -> Vec<(f64, usize)> {
    const GAP: f64 = 12.0;
    let total: f64 = widths.iter().map(|w| w + GAP).sum();
    let rows = ((total / (right - left)).ceil() as usize).max(1);
    let mut out = vec![(0.0, 0); desired.len()];
    for row in 0..rows {
        let idx: Vec<usize> = (0..desired.len()).filter(|i| i % rows == row).collect();
        let d: Vec<f64> = idx.iter().map(|&i| desired[i]).collect();
        let w: Vec<f64> = idx.iter().map(|&i| widths[i]).collect();
        for (k, x) in spread(&d, &w, GAP, left, right).into_iter().enumerate() {
            out[idx[k]] = (x, row);
        }
    }
    out
}

/// Centres for labels of widths `w` wanting centres `d` (ascending): touching labels form a
/// cluster placed at the mean of its members' wishes, clusters merge until none overlap.
fn spread(d: &[f64], w: &[f64], gap: f64, left: f64, right: f64) -> Vec<f64> {
    struct Cluster {
        first: usize,
        last: usize,
        /// Sum over members of (wish - offset from the first member's centre).
        sum: f64,
        n: f64,
        pos: f64,
    }
    let place = |c: &Cluster, off: &[f64]| {
        let lo = left + w[c.first] / 2.0;
        let hi = right - w[c.last] / 2.0 - off[c.last];
        if lo > hi { lo } else { (c.sum / c.n).clamp(lo, hi) }
    };
    let mut off = vec![0.0; d.len()];
    let mut clusters: Vec<Cluster> = Vec::new();
    for (i, &wish) in d.iter().enumerate() {
        let mut c = Cluster {
            first: i,
            last: i,
            sum: wish,
            n: 1.0,
            pos: 0.0,
        };
        c.pos = place(&c, &off);
        clusters.push(c);
        while clusters.len() >= 2 {
            let (a, b) = (&clusters[clusters.len() - 2], &clusters[clusters.len() - 1]);
            if a.pos + off[a.last] + w[a.last] / 2.0 + gap <= b.pos - w[b.first] / 2.0 {
                break;
            }
            let Some(b) = clusters.pop() else { break };
            let Some(a) = clusters.last_mut() else { break };
            let shift = off[a.last] + w[a.last] / 2.0 + gap + w[b.first] / 2.0;
            for o in &mut off[b.first..=b.last] {
                *o += shift;
            }
            a.sum += b.sum - shift * b.n;
            a.n += b.n;
            a.last = b.last;
            a.pos = place(a, &off);
        }
    }
    let mut centres = vec![0.0; d.len()];
    for c in &clusters {
        for j in c.first..=c.last {
            centres[j] = c.pos + off[j];
        }
    }
    centres
}

fn num_attr(x: f64) -> String {
    format!("{x}")
}

/// Lay the figure out as a scene (deterministic: no clocks, no hashing, no randomness).
pub fn layout(fig: &Figure) -> Scene {
    let mut scene = Scene {
        width: WIDTH as u32,
        height: 0,
        title: fig.title.clone(),
        description: fig.description.clone(),
        items: Vec::new(),
    };
    let mut legend: Vec<(Swatch, String)> = Vec::new();
    let add_legend = |legend: &mut Vec<(Swatch, String)>, s: Swatch, t: String| {
        if !legend.iter().any(|(_, l)| *l == t) {
            legend.push((s, t));
        }
    };

    // Title and description.
    let mut y = 38.0;
    scene.push(
        "title",
        Shape::Text {
            x: 24.0,
            y,
            text: fig.title.clone(),
            scale: 3,
            anchor: Anchor::Start,
            color: TEXT,
            bold: true,
            vertical: false,
        },
    );
    let max_chars = ((WIDTH - 48.0) / 12.0) as usize;
    for line in wrap(&fig.description, max_chars) {
        y += 22.0;
        scene.text("description", 24.0, y, &line, 2, Anchor::Start, MUTED);
    }
    y += 10.0;

    let plot_w = WIDTH - MARGIN_LEFT - MARGIN_RIGHT;
    let (left, right) = (MARGIN_LEFT, WIDTH - MARGIN_RIGHT);
    for panel in &fig.panels {
        let PanelLayout { lo, hi, bins } = panel.layout(fig.bins);
        let sx = |v: f64| left + (v - lo) / (hi - lo) * plot_w;

        // Mark labels, in value order, stacked in rows above the plot.
        let mut marks: Vec<&Mark> = panel.marks.iter().filter(|m| m.value.is_finite()).collect();
        marks.sort_by(|a, b| a.value.total_cmp(&b.value).then_with(|| a.label.cmp(&b.label)));
        let widths: Vec<f64> = marks.iter().map(|m| text_width(&m.label, 2)).collect();
        let wishes: Vec<f64> = marks.iter().map(|m| sx(m.value)).collect();
        let placed = place_labels(&wishes, &widths, left, right);
        let n_levels = placed.iter().map(|(_, l)| l + 1).max().unwrap_or(0);
        let top = y + 14.0 + n_levels as f64 * LEVEL_HEIGHT + if n_levels > 0 { 18.0 } else { 0.0 };
        let bottom = top + PLOT_HEIGHT;

        scene.push_data("panel", vec![("feature", panel.feature.clone())], Shape::GroupStart);

        // Shade outside the bounds.
        if let Some(b) = panel.bounds[0].filter(|b| *b > lo) {
            let x = sx(b.min(hi));
            scene.push(
                "out-of-bounds",
                Shape::Rect {
                    x: left,
                    y: top,
                    w: x - left,
                    h: PLOT_HEIGHT,
                    fill: SHADE,
                    opacity: 1.0,
                },
            );
            add_legend(&mut legend, Swatch::Shade, "outside the feature's bounds".into());
        }
        if let Some(b) = panel.bounds[1].filter(|b| *b < hi) {
            let x = sx(b.max(lo));
            scene.push(
                "out-of-bounds",
                Shape::Rect {
                    x,
                    y: top,
                    w: right - x,
                    h: PLOT_HEIGHT,
                    fill: SHADE,
                    opacity: 1.0,
                },
            );
            add_legend(&mut legend, Swatch::Shade, "outside the feature's bounds".into());
        }

        // Count axis: integer ticks with headroom.
        let max_count = bins.max_count().max(1) as f64;
        let (yt, _) = ticks(0.0, max_count * 1.08, 5);
        let step = if yt.len() > 1 {
            (yt[1] - yt[0]).max(1.0).round()
        } else {
            1.0
        };
        let y_top = ((max_count * 1.08) / step).ceil() * step;
        let sy = |c: f64| bottom - c / y_top * PLOT_HEIGHT;
        let mut c = 0.0;
        while c <= y_top + 1e-9 {
            let yy = sy(c);
            if c > 0.0 {
                scene.line("grid", (left, yy), (right, yy), Stroke::solid(GRID, 1.0));
            }
            scene.line("tick", (left - 5.0, yy), (left, yy), Stroke::solid(TEXT, 1.0));
            scene.text("tick-label", left - 9.0, yy + 7.0, &fmt_num(c, 0), 2, Anchor::End, TEXT);
            c += step;
        }

        // Bars (empty bins are not drawn).
        for (i, &count) in bins.counts.iter().enumerate() {
            if count == 0 {
                continue;
            }
            let (x0, x1) = (sx(bins.edge(i)), sx(bins.edge(i + 1)));
            let gap = if x1 - x0 > 4.0 { 0.5 } else { 0.0 };
            scene.push_data(
                "bar",
                vec![
                    ("count", count.to_string()),
                    ("from", num_attr(bins.edge(i))),
                    ("to", num_attr(bins.edge(i + 1))),
                ],
                Shape::Rect {
                    x: x0 + gap,
                    y: sy(count as f64),
                    w: x1 - x0 - 2.0 * gap,
                    h: bottom - sy(count as f64),
                    fill: BAR_COLOR,
                    opacity: 1.0,
                },
            );
        }
        if !bins.counts.is_empty() {
            add_legend(
                &mut legend,
                Swatch::Bar,
                format!("{} ({} instances)", set_short(&fig.title), panel.values.len()),
            );
        }

        // Rugs, stacked up from the bottom.
        for (k, rug) in panel.rugs.iter().enumerate() {
            let color = RUG_COLORS[k % RUG_COLORS.len()];
            let (y0, y1) = (
                bottom - k as f64 * RUG_HEIGHT,
                bottom - (k + 1) as f64 * RUG_HEIGHT + 2.0,
            );
            scene.push_data("rug", vec![("set", rug.set.clone())], Shape::GroupStart);
            for &v in rug.values.iter().filter(|v| v.is_finite()) {
                let x = sx(v);
                scene.push_data(
                    "rug-tick",
                    vec![("value", num_attr(v))],
                    Shape::Line {
                        x1: x,
                        y1: y0,
                        x2: x,
                        y2: y1,
                        stroke: Stroke::solid(color, 1.5),
                    },
                );
            }
            scene.push("", Shape::GroupEnd);
            add_legend(
                &mut legend,
                Swatch::Rug(color),
                format!("{} (rug, {} values)", set_short(&rug.set), rug.values.len()),
            );
        }

        // Bounds: a line where the bound is in view, an arrow note at the edge otherwise.
        for (side, bound) in [("lower", panel.bounds[0]), ("upper", panel.bounds[1])] {
            let lower = side == "lower";
            let note_y = top + 18.0;
            match bound {
                Some(b) if b >= lo && b <= hi => {
                    let x = sx(b);
                    scene.push_data(
                        "bound",
                        vec![("side", side.into()), ("value", num_attr(b))],
                        Shape::Line {
                            x1: x,
                            y1: top,
                            x2: x,
                            y2: bottom,
                            stroke: Stroke::solid(BOUND_COLOR, 2.0),
                        },
                    );
                    // Vertical, just inside the line, so it stays clear of bars and mark lines.
                    let tx = if lower { x + 19.0 } else { x - 6.0 };
                    scene.push(
                        "bound-label",
                        Shape::Text {
                            x: tx,
                            y: top + 6.0,
                            text: format!("{side} bound {}", fmt_sig(b)),
                            scale: 2,
                            anchor: Anchor::End,
                            color: BOUND_COLOR,
                            bold: false,
                            vertical: true,
                        },
                    );
                    add_legend(&mut legend, Swatch::Bound, "feature bounds".into());
                }
                _ => {
                    let (class, text) = match bound {
                        None if lower => ("bound-open", "← no lower bound (-∞)".to_string()),
                        None => ("bound-open", "no upper bound (+∞) →".to_string()),
                        Some(b) if lower => ("bound-offscale", format!("← lower bound {}", fmt_sig(b))),
                        Some(b) => ("bound-offscale", format!("upper bound {} →", fmt_sig(b))),
                    };
                    let (tx, anchor) = if lower {
                        (left + 6.0, Anchor::Start)
                    } else {
                        (right - 6.0, Anchor::End)
                    };
                    let mut data = vec![("side", side.to_string())];
                    if let Some(b) = bound {
                        data.push(("value", num_attr(b)));
                    }
                    scene.push_data(
                        class,
                        data,
                        Shape::Text {
                            x: tx,
                            y: note_y,
                            text,
                            scale: 2,
                            anchor,
                            color: BOUND_COLOR,
                            bold: false,
                            vertical: false,
                        },
                    );
                }
            }
        }

        // Marks: dashed line through the plot, a triangle at its top, the label above.
        for (m, (lx, level)) in marks.iter().zip(&placed) {
            let x = sx(m.value);
            let color = m.kind.color();
            scene.push_data(
                "mark",
                vec![
                    ("name", m.label.clone()),
                    ("value", num_attr(m.value)),
                    ("split", m.kind.as_str().into()),
                    ("set", m.set.clone()),
                ],
                Shape::GroupStart,
            );
            scene.line("mark-line", (x, bottom), (x, top), Stroke::dashed(color, 1.5, 4.0));
            scene.push(
                "mark-marker",
                Shape::Polygon {
                    points: vec![(x - 6.0, top - 10.0), (x + 6.0, top - 10.0), (x, top)],
                    fill: color,
                },
            );
            let label_y = top - 30.0 - *level as f64 * LEVEL_HEIGHT;
            scene.line(
                "mark-leader",
                (x, top - 10.0),
                (*lx, label_y + 5.0),
                Stroke::solid(color, 1.5),
            );
            scene.push(
                "mark-label",
                Shape::Text {
                    x: *lx,
                    y: label_y,
                    text: m.label.clone(),
                    scale: 2,
                    anchor: Anchor::Middle,
                    color,
                    bold: true,
                    vertical: false,
                },
            );
            scene.push("", Shape::GroupEnd);
            add_legend(
                &mut legend,
                Swatch::Marker(color),
                if m.kind == MarkKind::Named {
                    set_short(&m.set).to_string()
                } else {
                    format!("{}: {}", set_short(&m.set), m.kind.legend())
                },
            );
        }

        // Axes, x ticks and labels.
        scene.line("axis", (left, bottom), (right, bottom), Stroke::solid(TEXT, 1.5));
        scene.line("axis", (left, top), (left, bottom), Stroke::solid(TEXT, 1.5));
        let (xt, decimals) = ticks(lo, hi, 10);
        for t in xt {
            let x = sx(t);
            scene.line("tick", (x, bottom), (x, bottom + 5.0), Stroke::solid(TEXT, 1.0));
            scene.text(
                "tick-label",
                x,
                bottom + 24.0,
                &fmt_num(t, decimals),
                2,
                Anchor::Middle,
                TEXT,
            );
        }
        let axis_label = match &panel.unit {
            Some(u) => format!("{} [{u}]", panel.feature),
            None => panel.feature.clone(),
        };
        scene.push(
            "axis-label",
            Shape::Text {
                x: left + plot_w / 2.0,
                y: bottom + 52.0,
                text: axis_label,
                scale: 2,
                anchor: Anchor::Middle,
                color: TEXT,
                bold: true,
                vertical: false,
            },
        );
        scene.push(
            "axis-label",
            Shape::Text {
                x: 30.0,
                y: top + PLOT_HEIGHT / 2.0,
                text: "count".into(),
                scale: 2,
                anchor: Anchor::Middle,
                color: TEXT,
                bold: true,
                vertical: true,
            },
        );
        let rule = match bins.rule {
            "freedman-diaconis" => " (Freedman-Diaconis)",
            "sqrt" => " (square-root rule)",
            "fixed" => " (--bins)",
            "inseparable" => " (values too close to tell apart)",
            _ => "",
        };
        let note = format!(
            "{} values in {} bins of width {}{rule}",
            panel.values.len(),
            bins.counts.len(),
            fmt_sig(bins.width)
        );
        scene.text("note", left, bottom + 76.0, &note, 2, Anchor::Start, MUTED);
        scene.push("", Shape::GroupEnd);
        y = bottom + 92.0;
    }

    // Legend, flowing left to right: histogram, markers (in, out, named), rugs, bounds.
    legend.sort_by_key(|(s, _)| match s {
        Swatch::Bar => 0,
        Swatch::Marker(c) if *c == IN_COLOR => 1,
        Swatch::Marker(c) if *c == OUT_COLOR => 2,
        Swatch::Marker(_) => 3,
        Swatch::Rug(_) => 4,
        Swatch::Bound => 5,
        Swatch::Shade => 6,
    });
    let (mut x, mut ly) = (MARGIN_LEFT, y + 8.0);
    for (swatch, text) in &legend {
        let w = 26.0 + text_width(text, 2) + 28.0;
        if x + w > WIDTH - 16.0 && x > MARGIN_LEFT {
            x = MARGIN_LEFT;
            ly += 26.0;
        }
        let (cx, cy) = (x + 9.0, ly - 5.0);
        match swatch {
            Swatch::Bar => scene.push(
                "legend-swatch",
                Shape::Rect {
                    x: cx - 8.0,
                    y: cy - 8.0,
                    w: 16.0,
                    h: 16.0,
                    fill: BAR_COLOR,
                    opacity: 1.0,
                },
            ),
            Swatch::Shade => scene.push(
                "legend-swatch",
                Shape::Rect {
                    x: cx - 8.0,
                    y: cy - 8.0,
                    w: 16.0,
                    h: 16.0,
                    fill: Color(0xd8, 0xd8, 0xd8),
                    opacity: 1.0,
                },
            ),
            Swatch::Marker(c) => scene.push(
                "legend-swatch",
                Shape::Polygon {
                    points: vec![(cx - 7.0, cy - 6.0), (cx + 7.0, cy - 6.0), (cx, cy + 6.0)],
                    fill: *c,
                },
            ),
            Swatch::Rug(c) => {
                for dx in [-6.0, -1.0, 4.0] {
                    scene.line(
                        "legend-swatch",
                        (cx + dx, cy - 8.0),
                        (cx + dx, cy + 8.0),
                        Stroke::solid(*c, 1.5),
                    );
                }
            }
            Swatch::Bound => scene.line(
                "legend-swatch",
                (cx, cy - 9.0),
                (cx, cy + 9.0),
                Stroke::solid(BOUND_COLOR, 2.0),
            ),
        }
        scene.text("legend", x + 26.0, ly + 2.0, text, 2, Anchor::Start, TEXT);
        x += w;
    }
    scene.height = (ly + 20.0).ceil() as u32;
    scene
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wraps_on_words() {
        assert_eq!(wrap("aa bb cc", 5), vec!["aa bb", "cc"]);
        assert_eq!(wrap("", 5), Vec::<String>::new());
    }

    #[test]
    fn close_labels_are_pushed_apart() {
        let p = place_labels(&[100.0, 110.0, 500.0], &[40.0, 40.0, 40.0], 0.0, 1000.0);
        assert_eq!(p, vec![(79.0, 0), (131.0, 0), (500.0, 0)]);
        // Clamped into the drawing area.
        assert_eq!(place_labels(&[0.0], &[40.0], 0.0, 1000.0), vec![(20.0, 0)]);
        // Too wide for one row: round robin over two.
        let p = place_labels(&[10.0, 20.0, 30.0], &[400.0, 400.0, 400.0], 0.0, 1000.0);
        assert_eq!(p.iter().map(|(_, l)| *l).collect::<Vec<_>>(), vec![0, 1, 0]);
    }
}
