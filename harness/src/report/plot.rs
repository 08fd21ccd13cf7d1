//! Plots with plotters, each written as PNG and SVG (atomically). Text uses the DejaVu Sans
//! font embedded by the `dejavu` crate, so no system font library is needed.
//!
//! [`chart`] draws x–y curves and markers (log axes are drawn as log10 of the data with
//! labels 10^k); [`mesh_map`] draws a false-colour map of a triangle field with
//! displacement arrows and the line elements on top (seed 003 Fig. 5.8/5.9).

use std::path::Path;
use std::sync::Once;

use anyhow::{anyhow, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

use crate::atomic::temporary;

fn register_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The embedded font is a valid TrueType file; a failure would show as missing text.
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
    });
}

/// How a curve is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mark {
    /// A line through the points.
    Line,
    /// A dot at every point, without a line.
    Dots,
    /// A line with a dot at every point.
    LineDots,
}

/// One labelled set of points.
#[derive(Debug, Clone)]
pub struct Curve {
    /// The legend's text.
    pub label: String,
    /// The (x, y) points in data units; non-finite ones are not drawn.
    pub points: Vec<(f64, f64)>,
    /// How the curve is drawn.
    pub mark: Mark,
    /// Palette index; curves that belong together (data and model of one line) share one.
    pub colour: usize,
}

/// Dots grouped into one curve per label, coloured in order of first appearance.
pub fn grouped(points: impl IntoIterator<Item = (String, (f64, f64))>) -> Vec<Curve> {
    let mut curves: Vec<Curve> = Vec::new();
    for (label, point) in points {
        match curves.iter_mut().find(|k| k.label == label) {
            Some(k) => k.points.push(point),
            None => {
                let colour = curves.len();
                curves.push(Curve::new(&label, vec![point], Mark::Dots).colour(colour));
            }
        }
    }
    curves
}

impl Curve {
    /// A curve; its colour is set by [`Curve::colour`] or defaults to palette entry 0.
    pub fn new(label: &str, points: Vec<(f64, f64)>, mark: Mark) -> Self {
        Self {
            label: label.into(),
            points,
            mark,
            colour: 0,
        }
    }

    /// The curve with palette entry `index`.
    pub fn colour(mut self, index: usize) -> Self {
        self.colour = index;
        self
    }
}

/// An axis: its label (with unit) and scale.
#[derive(Debug, Clone, Default)]
pub struct Axis {
    /// The axis title, with unit.
    pub label: String,
    /// Log scale: the data are drawn as log10, the ticks labelled in exponent form.
    pub log: bool,
    /// Names for the integer positions 0, 1, … (a categorical axis).
    pub categories: Option<Vec<String>>,
}

impl Axis {
    /// A linear axis titled `label`.
    pub fn linear(label: &str) -> Self {
        Self {
            label: label.into(),
            ..Self::default()
        }
    }

    /// A log axis titled `label`.
    pub fn log(label: &str) -> Self {
        Self {
            label: label.into(),
            log: true,
            ..Self::default()
        }
    }

    fn map(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    fn tick(&self, v: f64) -> String {
        if let Some(names) = &self.categories {
            let i = v.round();
            return if (v - i).abs() < 1e-6 && i >= 0.0 {
                names.get(i as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            };
        }
        let x = if self.log { 10f64.powf(v) } else { v };
        if self.log {
            format!("{x:.1e}")
        } else if x != 0.0 && (x.abs() >= 1e4 || x.abs() < 1e-2) {
            format!("{x:.2e}")
        } else {
            format!("{}", (x * 1e4).round() / 1e4)
        }
    }
}

/// A chart: title, axes and curves.
#[derive(Debug, Clone)]
pub struct Chart {
    /// The chart's caption.
    pub title: String,
    /// The horizontal axis.
    pub x: Axis,
    /// The vertical axis.
    pub y: Axis,
    /// The curves, drawn in order and listed in the legend.
    pub curves: Vec<Curve>,
}

/// Writes `<stem>.png` and `<stem>.svg`.
pub fn chart(stem: &Path, c: &Chart) -> Result<()> {
    both(
        stem,
        (900, 600),
        |r| draw_chart(&r, c),
        |r| draw_chart(&r, c),
    )
}

fn fail<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow!("plotting failed: {e:?}")
}

/// The upper or lower, left or right corner with the fewest data points in it (a third of
/// each axis), for the legend.
fn emptiest_corner(c: &Chart, (x0, x1): (f64, f64), (y0, y1): (f64, f64)) -> SeriesLabelPosition {
    let count = |right: bool, upper: bool| {
        c.curves
            .iter()
            .flat_map(|k| &k.points)
            .filter(|p| {
                let fx = (c.x.map(p.0) - x0) / (x1 - x0);
                let fy = (c.y.map(p.1) - y0) / (y1 - y0);
                (if right { fx > 0.55 } else { fx < 0.45 })
                    && (if upper { fy > 0.6 } else { fy < 0.4 })
            })
            .count()
    };
    [
        (SeriesLabelPosition::UpperRight, true, true),
        (SeriesLabelPosition::UpperLeft, false, true),
        (SeriesLabelPosition::LowerRight, true, false),
        (SeriesLabelPosition::LowerLeft, false, false),
    ]
    .into_iter()
    .min_by_key(|&(_, right, upper)| count(right, upper))
    .map_or(SeriesLabelPosition::UpperRight, |c| c.0)
}

/// Renders a picture with the bitmap and the SVG backend, each through a temporary file.
fn both(
    stem: &Path,
    size: (u32, u32),
    png: impl FnOnce(DrawingArea<BitMapBackend<'_>, Shift>) -> Result<()>,
    svg: impl FnOnce(DrawingArea<SVGBackend<'_>, Shift>) -> Result<()>,
) -> Result<()> {
    register_font();
    let (png_path, svg_path) = (stem.with_extension("png"), stem.with_extension("svg"));
    let (png_tmp, svg_tmp) = (temporary(&png_path), temporary(&svg_path));
    png(BitMapBackend::new(&png_tmp, size).into_drawing_area())?;
    svg(SVGBackend::new(&svg_tmp, size).into_drawing_area())?;
    std::fs::rename(&png_tmp, &png_path)?;
    std::fs::rename(&svg_tmp, &svg_path)?;
    Ok(())
}

/// The data range of the mapped values, padded by 5 % (or ±0.5 around a single value).
fn bounds(values: impl Iterator<Item = f64>) -> (f64, f64) {
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
    if !lo.is_finite() {
        return (0.0, 1.0);
    }
    let pad = if hi > lo {
        0.05 * (hi - lo)
    } else {
        0.5 * lo.abs().max(1.0)
    };
    (lo - pad, hi + pad)
}

fn draw_chart<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, c: &Chart) -> Result<()> {
    root.fill(&WHITE).map_err(fail)?;
    let points = || c.curves.iter().flat_map(|k| k.points.iter());
    let (x0, x1) = bounds(points().map(|p| c.x.map(p.0)));
    let (y0, y1) = bounds(points().map(|p| c.y.map(p.1)));
    let mut chart = ChartBuilder::on(root)
        .caption(&c.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(50)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(fail)?;
    let x_fmt = |v: &f64| c.x.tick(*v);
    let y_fmt = |v: &f64| c.y.tick(*v);
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(&c.x.label)
        .y_desc(&c.y.label)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&y_fmt)
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 14));
    if let Some(names) = &c.x.categories {
        mesh.x_labels(names.len() * 4 + 1);
    }
    mesh.draw().map_err(fail)?;
    for curve in &c.curves {
        let colour = Palette99::pick(curve.colour).to_rgba();
        let pts: Vec<(f64, f64)> = curve
            .points
            .iter()
            .map(|&(x, y)| (c.x.map(x), c.y.map(y)))
            .filter(|(x, y)| x.is_finite() && y.is_finite())
            .collect();
        if curve.mark != Mark::Line {
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                .map_err(fail)?;
        }
        let legend = if curve.mark == Mark::Dots {
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(fail)?
        } else {
            chart
                .draw_series(LineSeries::new(pts, colour.stroke_width(2)))
                .map_err(fail)?
        };
        legend
            .label(curve.label.clone())
            .legend(move |(x, y)| Rectangle::new([(x, y - 4), (x + 16, y + 4)], colour.filled()));
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .position(emptiest_corner(c, (x0, x1), (y0, y1)))
        .draw()
        .map_err(fail)?;
    root.present().map_err(fail)
}

/// A false-colour map of a per-triangle value on a 2D mesh, with line elements and
/// displacement arrows on top.
#[derive(Debug, Clone)]
pub struct MeshMap<'a> {
    /// The map's caption.
    pub title: String,
    /// Node positions (mm), undeformed.
    pub nodes: &'a [[f64; 2]],
    /// The triangles as indices into `nodes`.
    pub triangles: &'a [[usize; 3]],
    /// One value per triangle.
    pub values: &'a [f64],
    /// Label of the colour bar, with unit.
    pub value_label: String,
    /// Line elements as node pairs, drawn in black.
    pub lines: &'a [[usize; 2]],
    /// Arrows: node and displacement (mm), drawn `arrow_scale` times longer.
    pub arrows: Vec<(usize, [f64; 2])>,
    /// How many times longer than the displacement the arrows are drawn.
    pub arrow_scale: f64,
}

/// Writes `<stem>.png` and `<stem>.svg`.
pub fn mesh_map(stem: &Path, m: &MeshMap) -> Result<()> {
    both(stem, (900, 1000), |r| draw_map(&r, m), |r| draw_map(&r, m))
}

fn draw_map<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, m: &MeshMap) -> Result<()> {
    root.fill(&WHITE).map_err(fail)?;
    let (plot, bar) = root.split_horizontally(770);
    let (x0, x1) = bounds(m.nodes.iter().map(|p| p[0]));
    let (y0, y1) = bounds(m.nodes.iter().map(|p| p[1]));
    // Equal scales: widen the narrower extent.
    let (w, h) = (x1 - x0, y1 - y0);
    let (pw, ph) = plot.dim_in_pixel();
    let (pw, ph) = (f64::from(pw) - 90.0, f64::from(ph) - 110.0);
    let s = (w / pw).max(h / ph);
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let mut chart = ChartBuilder::on(&plot)
        .caption(&m.title, ("sans-serif", 20))
        .margin(10)
        .x_label_area_size(45)
        .y_label_area_size(55)
        .build_cartesian_2d(
            cx - 0.5 * s * pw..cx + 0.5 * s * pw,
            cy - 0.5 * s * ph..cy + 0.5 * s * ph,
        )
        .map_err(fail)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x, anterior (mm)")
        .y_desc("y, superior (mm)")
        .axis_desc_style(("sans-serif", 16))
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(fail)?;
    let (v0, v1) = m
        .values
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    let colour = |v: f64| ViridisRGB::get_color_normalized(v, v0, v1);
    let at = |n: usize| (m.nodes[n][0], m.nodes[n][1]);
    chart
        .draw_series(m.triangles.iter().zip(m.values).map(|(t, &v)| {
            Polygon::new(
                t.iter().map(|&n| at(n)).collect::<Vec<_>>(),
                colour(v).filled(),
            )
        }))
        .map_err(fail)?;
    chart
        .draw_series(
            m.lines
                .iter()
                .map(|l| PathElement::new(vec![at(l[0]), at(l[1])], BLACK.stroke_width(3))),
        )
        .map_err(fail)?;
    let red = RGBColor(220, 30, 30);
    for &(n, d) in &m.arrows {
        let (x, y) = at(n);
        let (dx, dy) = (m.arrow_scale * d[0], m.arrow_scale * d[1]);
        let len = dx.hypot(dy);
        if len < 1e-9 * s {
            continue;
        }
        let (ux, uy) = (dx / len, dy / len);
        let head = (0.3 * len).min(6.0 * s);
        let tip = (x + dx, y + dy);
        let wing = |sign: f64| {
            (
                tip.0 - head * (ux + sign * 0.5 * uy),
                tip.1 - head * (uy - sign * 0.5 * ux),
            )
        };
        chart
            .draw_series([
                PathElement::new(vec![(x, y), tip], red.stroke_width(2)),
                PathElement::new(vec![wing(1.0), tip, wing(-1.0)], red.stroke_width(2)),
            ])
            .map_err(fail)?;
    }
    draw_colour_bar(&bar, (v0, v1), &m.value_label)?;
    root.present().map_err(fail)
}

fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    (v0, v1): (f64, f64),
    label: &str,
) -> Result<()> {
    let mut chart = ChartBuilder::on(area)
        .margin_top(60)
        .margin_bottom(55)
        .margin_left(5)
        .set_label_area_size(LabelAreaPosition::Right, 75)
        .build_cartesian_2d(0.0..1.0, v0..v1)
        .map_err(fail)?;
    let fmt = |v: &f64| format!("{v:.2e}");
    chart
        .configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_desc(label)
        .y_label_formatter(&fmt)
        .axis_desc_style(("sans-serif", 15))
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(fail)?;
    let n = 100;
    chart
        .draw_series((0..n).map(|i| {
            let a = v0 + (v1 - v0) * i as f64 / n as f64;
            let b = v0 + (v1 - v0) * (i + 1) as f64 / n as f64;
            Rectangle::new(
                [(0.0, a), (1.0, b)],
                ViridisRGB::get_color_normalized(0.5 * (a + b), v0, v1).filled(),
            )
        }))
        .map_err(fail)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn files(stem: &Path) -> (Vec<u8>, String) {
        (
            std::fs::read(stem.with_extension("png")).unwrap(),
            std::fs::read_to_string(stem.with_extension("svg")).unwrap(),
        )
    }

    #[test]
    fn charts_are_written_as_png_and_svg_with_their_labels() {
        let dir = tempfile::tempdir().unwrap();
        let stem = dir.path().join("c");
        let line: Vec<(f64, f64)> = (1..20)
            .map(|i| (f64::from(i), 1.0 / f64::from(i)))
            .collect();
        chart(
            &stem,
            &Chart {
                title: "decay".into(),
                x: Axis::log("run time (ms)"),
                y: Axis::log("error (1)"),
                curves: vec![Curve::new("1/x", line, Mark::LineDots)],
            },
        )
        .unwrap();
        let (png, svg) = files(&stem);
        assert_eq!(&png[1..4], b"PNG");
        for text in ["decay", "run time (ms)", "error (1)", "1/x", "1.0e1"] {
            assert!(svg.contains(text), "{text} missing from the SVG");
        }
        assert_eq!(
            std::fs::read_dir(dir.path()).unwrap().count(),
            2,
            "no temporaries left"
        );
    }

    #[test]
    fn categorical_axes_name_their_positions() {
        let a = Axis {
            categories: Some(vec!["normal".into(), "wide".into()]),
            ..Axis::linear("configuration")
        };
        assert_eq!(a.tick(1.0), "wide");
        assert_eq!(a.tick(0.5), "");
        assert_eq!(Axis::linear("x").tick(0.0055), "5.50e-3");
    }

    #[test]
    fn mesh_maps_colour_every_triangle() {
        let dir = tempfile::tempdir().unwrap();
        let stem = dir.path().join("m");
        let nodes = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        mesh_map(
            &stem,
            &MeshMap {
                title: "square".into(),
                nodes: &nodes,
                triangles: &[[0, 1, 2], [0, 2, 3]],
                values: &[1.0, 2.0],
                value_label: "stress (MPa)".into(),
                lines: &[[0, 1]],
                arrows: vec![(2, [0.1, 0.1])],
                arrow_scale: 1.0,
            },
        )
        .unwrap();
        let (_, svg) = files(&stem);
        assert!(svg.matches("<polygon").count() >= 2, "two triangles");
        assert!(svg.contains("stress (MPa)"));
    }
}
