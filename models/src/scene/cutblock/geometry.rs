//! The cut block's geometry: the block's node planes (graded so that the cut plane and the
//! crack front are node planes), the uncut mesh, and the incision the scalpel makes.

use crate::mesh::cut::{self, CutMesh, Incision};
use crate::mesh::{generate, Mesh3d};
use crate::scene::SceneError;

/// How the incision is made (seed 002 §1.4 / §3.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    Duplicate,
    Delete,
}

impl Strategy {
    pub fn parse(s: &str) -> Result<Self, SceneError> {
        match s {
            "duplicate" => Ok(Self::Duplicate),
            "delete" => Ok(Self::Delete),
            _ => Err(SceneError::Config(format!(
                "cut_strategy `{s}`: use `duplicate` or `delete`"
            ))),
        }
    }
}

/// Supports of the end faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Support {
    /// The experiment (seed 002 §2.1): y = 0 clamped; y = L u_y prescribed, u_x, u_z free.
    Clamped,
    /// Only u_y on both end faces, plus the three constraints that remove rigid motions
    /// (u_x, u_z at the origin, u_z at (L_x, 0, 0)): a state of exact uniaxial tension.
    Sliding,
    /// Both faces held in rigid grips: y = 0 clamped; y = L moved in y with u_x = u_z = 0.
    Gripped,
}

impl Support {
    pub fn parse(s: &str) -> Result<Self, SceneError> {
        match s {
            "clamped" => Ok(Self::Clamped),
            "sliding" => Ok(Self::Sliding),
            "gripped" => Ok(Self::Gripped),
            _ => Err(SceneError::Config(format!(
                "support `{s}`: use `clamped`, `sliding` or `gripped`"
            ))),
        }
    }
}

/// The choices of how the block is cut, held and kept from interpenetrating.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Options {
    pub strategy: Strategy,
    pub support: Support,
    /// Whether closing flanks are kept apart (penalty contact).
    pub contact: bool,
}

/// The uncut block and where the incision can go.
#[derive(Debug, Clone)]
pub struct Geometry {
    pub size: [f64; 3],
    pub base: Mesh3d,
    pub x_planes: Vec<f64>,
    /// Incision plane and the bottom of the incision (z); `None` for depth 0.
    pub y_cut: f64,
    pub z_cut: Option<f64>,
    /// Thickness of the element layer removed by the deletion strategy.
    pub layer: f64,
    pub press_radius: f64,
    pub options: Options,
    /// Where the mesh makes the model less trustworthy (sliver layers at the cut).
    pub warnings: Vec<String>,
}

/// Node planes over [0, length] in `cells` layers with `target`, if it lies strictly
/// inside, on a plane: n layers of equal thickness below it and cells − n above, n chosen
/// (1 ≤ n < cells) to make the two thicknesses most alike (smallest |ln(h_below/h_above)|).
/// This is how the shipped data sets place their crack fronts (set C: 10 layers of 1.275 mm
/// below z = 12.75 mm, 4 of 1.0625 mm above). Without a target inside, uniform layers.
fn graded(length: f64, cells: usize, target: Option<f64>) -> Vec<f64> {
    let uniform = |from: f64, to: f64, n: usize| {
        (0..=n).map(move |i| from + (to - from) * i as f64 / n as f64)
    };
    let Some(t) = target.filter(|&t| t > 0.0 && t < length && cells >= 2) else {
        return uniform(0.0, length, cells).collect();
    };
    // A target on a uniform plane keeps the uniform planes (the same floats, bit for bit).
    let mut p: Vec<f64> = uniform(0.0, length, cells).collect();
    if let Some(k) = p.iter().position(|&q| (q - t).abs() <= 1e-12 * length) {
        p[k] = t;
        return p;
    }
    let mismatch = |n: usize| {
        ((t / n as f64) / ((length - t) / (cells - n) as f64))
            .ln()
            .abs()
    };
    let below = (1..cells)
        .min_by(|&a, &b| mismatch(a).total_cmp(&mismatch(b)))
        .expect("cells ≥ 2");
    p = uniform(0.0, t, below).collect();
    p.extend(uniform(t, length, cells - below).skip(1));
    p[below] = t;
    p
}

/// The ratio of the thinner to the thicker layer next to `target` in `planes`.
fn layer_ratio(planes: &[f64], target: f64) -> f64 {
    let at = planes.iter().position(|&p| p == target).unwrap_or(0);
    let below = planes[at] - planes[at.saturating_sub(1)];
    let above = planes[(at + 1).min(planes.len() - 1)] - planes[at];
    below.min(above) / below.max(above)
}

/// Below this ratio of adjacent layer thicknesses at the cut, the scene warns that the mesh
/// there is too anisotropic for its results to be trusted.
pub const SLIVER_RATIO: f64 = 0.25;

impl Geometry {
    pub fn new(
        size: [f64; 3],
        cells: [usize; 3],
        y_cut: f64,
        depth: f64,
        press_radius: f64,
        options: Options,
    ) -> Result<Self, SceneError> {
        if !(y_cut > 0.0 && y_cut < size[1]) {
            return Err(SceneError::Config(format!(
                "y_cut = {y_cut} mm must lie inside the block (0, {})",
                size[1]
            )));
        }
        if cells[1] < 2 {
            return Err(SceneError::Config(
                "cells_y must be at least 2 to place a node plane at y_cut".into(),
            ));
        }
        let z_cut = (depth > 0.0).then(|| (size[2] - depth).max(0.0));
        if z_cut.is_some_and(|z| z > 0.0) && cells[2] < 2 {
            return Err(SceneError::Config(format!(
                "cut_depth = {depth} mm ends inside the block: cells_z must be at least 2 to \
                 place a node plane at the crack front (got {})",
                cells[2]
            )));
        }
        let x_planes = graded(size[0], cells[0], None);
        let y_planes = graded(size[1], cells[1], Some(y_cut));
        let z_planes = graded(size[2], cells[2], z_cut);
        let at = y_planes
            .iter()
            .position(|&y| y == y_cut)
            .expect("a plane at y_cut");
        let mut warnings = Vec::new();
        for (name, planes, target) in [
            ("y_cut", &y_planes, Some(y_cut)),
            ("cut_depth", &z_planes, z_cut),
        ] {
            if let Some(t) = target.filter(|&t| t > 0.0) {
                let ratio = layer_ratio(planes, t);
                if ratio < SLIVER_RATIO {
                    warnings.push(format!(
                        "{name}: the element layers beside the cut differ in thickness by a \
                         factor {:.1} (more than {:.0}): results near the cut depend on the mesh \
                         there; choose cells so that the cut falls nearer a uniform plane",
                        1.0 / ratio,
                        1.0 / SLIVER_RATIO
                    ));
                }
            }
        }
        let base = generate::block_on_planes(&[x_planes.clone(), y_planes.clone(), z_planes])?;
        Ok(Self {
            size,
            base,
            x_planes,
            y_cut,
            z_cut,
            layer: y_cut - y_planes[at - 1],
            press_radius,
            options,
            warnings,
        })
    }

    /// Whole x-cells behind the scalpel at `x` (0 without a cut).
    pub fn cut_cells(&self, x: f64) -> usize {
        if self.z_cut.is_none() {
            return 0;
        }
        let tol = 1e-9 * self.size[0];
        self.x_planes[1..]
            .iter()
            .take_while(|&&p| p <= x + tol)
            .count()
    }

    /// The base mesh cut by `cells` x-cells.
    pub fn cut(&self, cells: usize) -> Result<CutMesh, SceneError> {
        let (Some(z0), true) = (self.z_cut, cells > 0) else {
            return Ok(CutMesh {
                mesh: self.base.clone(),
                flank_pairs: vec![],
            });
        };
        let incision = Incision {
            y: self.y_cut,
            x: (0.0, self.x_planes[cells]),
            z: (z0, self.size[2]),
        };
        Ok(match self.options.strategy {
            Strategy::Duplicate => cut::split(&self.base, &incision)?,
            Strategy::Delete => cut::delete(&self.base, &incision, self.layer)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_planes_put_the_target_on_a_plane_with_alike_layers() {
        // Set C of the shipped data: 17 mm, 14 layers, crack front at 12.75 mm.
        let p = graded(17.0, 14, Some(12.75));
        assert_eq!(p.len(), 15);
        assert_eq!(p[10], 12.75);
        assert!((p[1] - 1.275).abs() < 1e-12 && (p[14] - p[13] - 1.0625).abs() < 1e-12);
        // Set A: the front halfway, uniform.
        let p = graded(17.0, 14, Some(8.5));
        assert!(p
            .windows(2)
            .all(|w| (w[1] - w[0] - 17.0 / 14.0).abs() < 1e-12));
        // A target at the edge: no move of the nearest plane, one thin layer, flagged.
        let p = graded(80.0, 16, Some(0.1));
        assert_eq!((p[0], p[1]), (0.0, 0.1));
        assert!(layer_ratio(&p, 0.1) < SLIVER_RATIO);
        assert_eq!(graded(10.0, 4, None), [0.0, 2.5, 5.0, 7.5, 10.0]);
    }
}
