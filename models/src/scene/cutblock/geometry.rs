//! The cut block's geometry: the block's node planes (graded so that the cut plane and the
//! cut bottom are node planes), and the mesh of the block cut up to a crack front at any x
//! (a node plane put there, [`Geometry::x_planes`]).

use crate::error::ModelError;
use crate::mesh::cut::{self, CutMesh, Incision};
use crate::mesh::generate;
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
            _ => Err(ModelError::unknown("cut_strategy", s, "duplicate or delete").into()),
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
            _ => Err(ModelError::unknown("support", s, "clamped, sliding or gripped").into()),
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

/// The block, its node planes and where the incision can go.
#[derive(Debug, Clone)]
pub struct Geometry {
    pub size: [f64; 3],
    /// Cells along x (their planes follow the crack front, [`Self::x_planes`]), and the node
    /// planes in y (one at y_cut) and z (one at the cut bottom).
    cells_x: usize,
    planes_yz: [Vec<f64>; 2],
    /// β of the grading towards the cut plane, the cut bottom and the faces ([`graded`]),
    /// and of the x planes towards the tip ([`Self::x_offset`]).
    grading: f64,
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
/// inside, on a plane: n layers below it and cells − n above, n chosen (1 ≤ n < cells) to
/// make the two uniform thicknesses most alike (smallest |ln(h_below/h_above)|), or the
/// uniform plane the target is on. This is how the shipped data sets place their crack
/// fronts (set C: 10 layers of 1.275 mm below z = 12.75 mm, 4 of 1.0625 mm above).
///
/// Each side (length D, n layers) is graded towards both its ends, the target and the face:
/// its i-th plane lies at the fraction g(i/n) of D, g(ξ) = ξ^β / (ξ^β + (1 − ξ)^β), so that
/// next to either end the planes follow the power law D (i/n)^β. β = 1 gives uniform layers
/// (the same floats as without grading), β = 2 layers that grow linearly away from either
/// end — the grading that restores a linear element's optimal rate next to a crack front,
/// where the displacement goes as r^½ (Babuška's graded meshes), and next to the edges where
/// the clamped face meets the free ones, where it goes as r^0.63 (Williams' clamped–free
/// edge at ν = 0.43); see `docs/theory/cutblock.md`. Without a target inside, uniform
/// layers.
fn graded(length: f64, cells: usize, target: Option<f64>, beta: f64) -> Vec<f64> {
    let uniform = |from: f64, to: f64, n: usize| {
        (0..=n).map(move |i| from + (to - from) * i as f64 / n as f64)
    };
    let Some(t) = target.filter(|&t| t > 0.0 && t < length && cells >= 2) else {
        return uniform(0.0, length, cells).collect();
    };
    let mut p: Vec<f64> = uniform(0.0, length, cells).collect();
    let below = match p.iter().position(|&q| (q - t).abs() <= 1e-12 * length) {
        // A target on a uniform plane keeps the uniform planes (the same floats, bit for bit).
        Some(k) if beta == 1.0 => {
            p[k] = t;
            return p;
        }
        Some(k) => k,
        None => {
            let mismatch = |n: usize| {
                ((t / n as f64) / ((length - t) / (cells - n) as f64))
                    .ln()
                    .abs()
            };
            (1..cells)
                .min_by(|&a, &b| mismatch(a).total_cmp(&mismatch(b)))
                .expect("cells ≥ 2")
        }
    };
    // The fraction g(i/n) of a side's length at its i-th of n planes, graded towards both
    // ends.
    let both_ends = |i: usize, n: usize| {
        let (a, b) = (
            (i as f64 / n as f64).powf(beta),
            ((n - i) as f64 / n as f64).powf(beta),
        );
        a / (a + b)
    };
    p = if beta == 1.0 {
        uniform(0.0, t, below).collect()
    } else {
        (0..=below).map(|i| t * both_ends(i, below)).collect()
    };
    let above = cells - below;
    p.extend((1..=above).map(|i| {
        if beta == 1.0 {
            t + (length - t) * i as f64 / above as f64
        } else {
            t + (length - t) * both_ends(i, above)
        }
    }));
    p[below] = t;
    if beta != 1.0 {
        p[cells] = length;
    }
    p
}

/// The ratio of the thinner to the thicker layer next to `target` in `planes`.
fn layer_ratio(planes: &[f64], target: f64) -> f64 {
    let at = planes.iter().position(|&p| p == target).unwrap_or(0);
    let below = planes[at] - planes[at.saturating_sub(1)];
    let above = planes[(at + 1).min(planes.len() - 1)] - planes[at];
    below.min(above) / below.max(above)
}

/// The thinnest cell, as a fraction of the uniform cell h, that the x planes around a crack
/// front leave at the end faces, and the distance (in h) within which a front is taken as
/// an end face (see [`Geometry::x_planes`]). Such a cell is harmless to the results (the
/// split along x does not lock, [`generate::Split::ExtrudedX`]: a thin cell ties its two
/// planes) but not to the solver: its stiffness grows as 1/width, so Newton's round-off
/// floor rises with h / width, the single-precision factor falls back to double, and
/// below about 1e-7 h (default cells) the mesh check rejects its tetrahedra as
/// degenerate. At 1e-5 h (0.17 µm on the default block) a cold 10 mm pull takes about
/// three times as long as on the uniform cells (BENCHMARKS.md, "The snap distance").
pub const SNAP: f64 = 1e-5;

/// A cell at an end face narrower than this fraction of a move of the front within a cell
/// is a sliver the start on the nodes may invert ([`Geometry::leaves_a_sliver`]). Measured
/// along the accurate setting's blade path in 1 mm advances (BENCHMARKS.md, "Slivers at the
/// end faces"): the 0.032–0.14 mm cells at 53, 85 and 94 mm took 10–11 Newton iterations
/// started on the slid mesh against 18–25 on the nodes; with 1 instead of 0.5 the 0.745 mm
/// one at 98 mm would be a sliver too, and took 14 against 8, and the default's path 427
/// iterations instead of 424.
const SLIVER_FRACTION: f64 = 0.5;

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
        grading: f64,
        options: Options,
    ) -> Result<Self, SceneError> {
        if !(1.0..=4.0).contains(&grading) {
            return Err(SceneError::Config(format!(
                "mesh_grading = {grading} must lie in [1, 4] (1: uniform layers)"
            )));
        }
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
        let y_planes = graded(size[1], cells[1], Some(y_cut), grading);
        let z_planes = graded(size[2], cells[2], z_cut, grading);
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
        Ok(Self {
            size,
            layer: y_cut - y_planes[at - 1],
            cells_x: cells[0],
            planes_yz: [y_planes, z_planes],
            grading,
            y_cut,
            z_cut,
            press_radius,
            options,
            warnings,
        })
    }

    /// The width of a cell along x (mm).
    fn cell_x(&self) -> f64 {
        self.size[0] / self.cells_x as f64
    }

    /// How far the incision reaches when the blade has reached `x` at the furthest: `x`
    /// clamped to the block; 0 without a cut depth (the `cut_length` output).
    pub fn reach(&self, x: f64) -> f64 {
        if self.z_cut.is_none() {
            0.0
        } else {
            x.clamp(0.0, self.size[0])
        }
    }

    /// Where the mesh's incision ends when the blade has reached `x` at the furthest: `x` clamped
    /// to the block, within [`SNAP`] of a cell of an end face taken as that face; 0 without
    /// a cut depth.
    pub fn front(&self, x: f64) -> f64 {
        let (l, snap) = (self.size[0], SNAP * self.cell_x());
        if self.z_cut.is_none() || x < snap {
            0.0
        } else if x > l - snap {
            l
        } else {
            x
        }
    }

    /// Distance from the front of its k-th x plane on either side (k ≤ n = `cells_x`):
    /// k h on the uniform grid (β = 1), L (k/n)^β graded towards the tip — one-sided, over
    /// the block's length L (the y and z layers, [`graded`], are graded towards both ends of
    /// each side), so the cells beside the tip are L / n^β wide and grow away from it.
    fn x_offset(&self, k: usize) -> f64 {
        if self.grading == 1.0 {
            k as f64 * self.cell_x()
        } else {
            self.size[0] * (k as f64 / self.cells_x as f64).powf(self.grading)
        }
    }

    /// The x node planes of the mesh cut up to `front` (a value of [`Self::front`]): a grid
    /// slid along x so that a plane lies at the front, planes at front ± [`Self::x_offset`]
    /// (k) that leave at least [`SNAP`] h to the end faces, and the end faces. Around the
    /// front the mesh is the same wherever the front is, so the tip is resolved alike at
    /// every blade position and the outputs change smoothly with it; the cells at the end
    /// faces grow and shrink, and a cell appears or vanishes there (a cell of width δ → 0
    /// ties its two planes together, which is the mesh without it, since the cubes are
    /// split along x, [`generate::Split::ExtrudedX`]). With the front at 0 or
    /// at the far end the planes are the uniform ones (β = 1) or graded towards that face
    /// (L (k/n)^β from it).
    ///
    /// Also returns whether the x layers' split must be mirrored so that the layer just
    /// ahead of the front is split alike at every blade position (and as the uniform
    /// block's first layer when the front is at the far end).
    pub fn x_planes(&self, front: f64) -> (Vec<f64>, bool) {
        let (l, h) = (self.size[0], self.cell_x());
        let n = self.cells_x;
        let mut planes = vec![0.0];
        let behind = (1..=n).rev().map(|k| front - self.x_offset(k));
        let ahead = (0..=n).map(|k| front + self.x_offset(k));
        planes.extend(
            behind
                .chain(ahead)
                .filter(|&x| x >= SNAP * h && x <= l - SNAP * h),
        );
        planes.push(l);
        planes.dedup();
        let at = planes
            .iter()
            .position(|&x| x == front)
            .expect("the front is a plane");
        (planes, (self.cells_x + at) % 2 == 1)
    }

    /// Whether moving the front from `from` to `to` within a cell leaves the cell at an end
    /// face narrower than `SLIVER_FRACTION` times the move (a node plane approaching that
    /// face by the move, [`Self::x_planes`], has then narrowed the cell to less than a third
    /// of its width). A start extrapolated along each node's path (`path::extrapolate`)
    /// strains that cell by the error of the difference of its two planes' displacements
    /// divided by its width, which can invert a sliver (the accurate setting at a 10 mm
    /// pull: from 52 to 53 mm and from 93 to 94 mm, the 0.096 and 0.032 mm cells left at the
    /// far face by the planes at 99.904 and 99.968 mm). The cell at the face the front moves
    /// away from widens.
    pub fn leaves_a_sliver(&self, from: f64, to: f64) -> bool {
        let (p, _) = self.x_planes(to);
        let end_cells = [p[1] - p[0], p[p.len() - 1] - p[p.len() - 2]];
        end_cells
            .iter()
            .any(|&width| width < SLIVER_FRACTION * (to - from).abs())
    }

    /// The block cut up to `front` made from `previous`, the block cut up to `from`, by
    /// moving its nodes, where both fronts lie within one cell: the same number of x
    /// planes, the front on the same one, the layers split alike — the connectivity
    /// [`Self::cut`] would make. Every node's x is one of the planes' positions, so each
    /// node moves to its plane's new position: the mesh [`Self::cut`] makes, to the bit,
    /// without meshing and cutting anew. `None` where the fronts lie in different cells.
    pub fn moved_cut(
        &self,
        previous: &CutMesh,
        from: f64,
        front: f64,
    ) -> Option<Result<CutMesh, SceneError>> {
        if from <= 0.0 || front <= 0.0 {
            return None;
        }
        let ((old, old_mirror), (new, new_mirror)) = (self.x_planes(from), self.x_planes(front));
        let at = |planes: &[f64], x: f64| planes.iter().position(|&p| p == x);
        if old.len() != new.len() || old_mirror != new_mirror || at(&old, from) != at(&new, front) {
            return None;
        }
        let mut nodes = previous.mesh.nodes().to_vec();
        for p in &mut nodes {
            let k = old.partition_point(|&x| x < p[0]);
            if old.get(k) != Some(&p[0]) {
                return None;
            }
            p[0] = new[k];
        }
        Some(
            previous
                .mesh
                .moved(nodes)
                .map(|mesh| CutMesh {
                    mesh,
                    flank_pairs: previous.flank_pairs.clone(),
                })
                .map_err(SceneError::from),
        )
    }

    /// The block meshed with a node plane at `front` and cut up to it.
    pub fn cut(&self, front: f64) -> Result<CutMesh, SceneError> {
        let [y, z] = &self.planes_yz;
        let (x, mirrored) = self.x_planes(front);
        let mesh = generate::block_on_planes(
            &[x, y.clone(), z.clone()],
            generate::Split::ExtrudedX { mirrored },
        )?;
        let (Some(z0), true) = (self.z_cut, front > 0.0) else {
            return Ok(CutMesh {
                mesh,
                flank_pairs: vec![],
            });
        };
        let incision = Incision {
            y: self.y_cut,
            x: (0.0, front),
            z: (z0, self.size[2]),
        };
        Ok(match self.options.strategy {
            Strategy::Duplicate => cut::split(&mesh, &incision)?,
            Strategy::Delete => cut::delete(&mesh, &incision, self.layer)?,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn graded_planes_put_the_target_on_a_plane_with_alike_layers() {
        // Set C of the shipped data: 17 mm, 14 layers, crack front at 12.75 mm.
        let p = graded(17.0, 14, Some(12.75), 1.0);
        assert_eq!(p.len(), 15);
        assert_eq!(p[10], 12.75);
        assert!((p[1] - 1.275).abs() < 1e-12 && (p[14] - p[13] - 1.0625).abs() < 1e-12);
        // Set A: the front halfway, uniform.
        let p = graded(17.0, 14, Some(8.5), 1.0);
        assert!(p
            .windows(2)
            .all(|w| (w[1] - w[0] - 17.0 / 14.0).abs() < 1e-12));
        // A target at the edge: no move of the nearest plane, one thin layer, flagged.
        let p = graded(80.0, 16, Some(0.1), 1.0);
        assert_eq!((p[0], p[1]), (0.0, 0.1));
        assert!(layer_ratio(&p, 0.1) < SLIVER_RATIO);
        assert_eq!(graded(10.0, 4, None, 2.0), [0.0, 2.5, 5.0, 7.5, 10.0]);
    }

    /// β = 2: each side's layers are finest at both its ends and mirror each other about
    /// its middle (z of set C: 12.75 mm below in 10 layers, 4.25 mm above in 4). The layer at
    /// either end of a side of n layers is D g(1/n) = D / (1 + (n − 1)²): 12.75 / 82 and
    /// 4.25 / 10; the middle ones of the 4 are D (g(1/2) − g(1/4)) = 4.25 (1/2 − 1/10).
    #[test]
    fn power_law_grading_makes_each_side_finest_at_both_ends() {
        let p = graded(17.0, 14, Some(12.75), 2.0);
        assert_eq!((p[0], p[10], p[14]), (0.0, 12.75, 17.0));
        let widths: Vec<f64> = p.windows(2).map(|w| w[1] - w[0]).collect();
        for (k, w) in [
            (0, 12.75 / 82.0),
            (9, 12.75 / 82.0),
            (10, 0.425),
            (13, 0.425),
        ] {
            assert!((widths[k] - w).abs() < 1e-12, "{k}: {widths:?}");
        }
        for k in [11, 12] {
            assert!((widths[k] - 4.25 * 0.4).abs() < 1e-12, "{k}: {widths:?}");
        }
        for k in 0..10 {
            assert!((widths[k] - widths[9 - k]).abs() < 1e-12, "{widths:?}");
        }
        // Growing towards the middle of the side.
        assert!(widths[..5].windows(2).all(|w| w[1] > w[0]), "{widths:?}");
        // A target on a uniform plane is graded too: 7 layers of 8.5 mm on each side.
        let p = graded(17.0, 14, Some(8.5), 2.0);
        assert!((p[1] - 8.5 / 37.0).abs() < 1e-12, "{p:?}");
    }

    /// Wherever the front is, a plane lies on it, the cells within the block around it are
    /// h wide, the cells at the end faces at least SNAP h and at most (1 + SNAP) h; at 0 and
    /// at the far face the planes are the uniform ones.
    #[test]
    fn x_planes_follow_the_front_with_the_grid_around_it() {
        let g = default_block(1.0);
        let h = 100.0 / 6.0;
        let uniform: Vec<f64> = (0..=6).map(|i| 100.0 * f64::from(i) / 6.0).collect();
        for front in [0.0, 100.0] {
            let (p, mirrored) = g.x_planes(front);
            assert!(!mirrored);
            assert!(
                p.iter().zip(&uniform).all(|(a, b)| (a - b).abs() < 1e-12),
                "{p:?}"
            );
        }
        for k in 1..2000 {
            let front = g.front(0.05 * f64::from(k));
            let (p, _) = g.x_planes(front);
            assert!(p.contains(&front), "front {front}: {p:?}");
            for w in p.windows(2) {
                let width = w[1] - w[0];
                let inner = w[0] > 0.0 && w[1] < 100.0;
                assert!(
                    width >= SNAP * h && width <= h * (1.0 + SNAP) + 1e-9,
                    "front {front}: {p:?}"
                );
                assert!(!inner || (width - h).abs() < 1e-9, "front {front}: {p:?}");
            }
        }
        assert_eq!(g.front(SNAP * h * 0.9), 0.0);
        assert_eq!(g.front(SNAP * h * 1.1), SNAP * h * 1.1);
        assert_eq!(g.front(100.0 - SNAP * h * 0.9), 100.0);
        assert_eq!(g.front(250.0), 100.0);
    }

    /// A move of the front leaves a sliver where the cell at an end face ends narrower than
    /// half the move. Uniform (h = 16.67 mm): towards the far face from 82 to 83 mm (0.333
    /// mm) and from 82.5 to 83.2 mm (0.133 mm against 0.35), towards the near face from 18
    /// to 17 mm; not from 82.8 to 83 mm (0.333 mm against 0.1), 81 → 82 mm (1.333 mm),
    /// 82 → 82.5 mm (0.833 mm), nor away from the face (83 → 82 mm: 1.333 mm there, 15.33
    /// mm at the other face). The accurate setting (7 cells, β = 2.25): 52 → 53, 84 → 85 and
    /// 93 → 94 mm (0.096, 0.139, 0.032 mm at the far face), not 97 → 98 mm (0.745 mm) nor
    /// 51 → 52 mm (1.096 mm).
    #[test]
    fn a_move_towards_an_end_face_leaves_a_sliver_where_its_cell_ends_narrower() {
        let uniform = default_block(1.0);
        let accurate = Geometry::new(
            [100.0, 80.0, 17.0],
            [7, 18, 10],
            45.0,
            8.5,
            5.0,
            2.25,
            uniform.options,
        )
        .unwrap();
        // (from, to) pairs of moves that leave a sliver and of moves that do not.
        let cases: [(&Geometry, &[f64], &[f64]); 2] = [
            (
                &uniform,
                &[82.0, 83.0, 82.5, 83.2, 18.0, 17.0],
                &[82.8, 83.0, 81.0, 82.0, 82.0, 82.5, 83.0, 82.0],
            ),
            (
                &accurate,
                &[52.0, 53.0, 84.0, 85.0, 93.0, 94.0],
                &[97.0, 98.0, 51.0, 52.0],
            ),
        ];
        for (g, slivers, others) in cases {
            for (moves, sliver) in [(slivers, true), (others, false)] {
                for m in moves.chunks(2) {
                    let grading = g.grading;
                    let message = format!("β {grading}: {} → {}", m[0], m[1]);
                    assert_eq!(g.leaves_a_sliver(m[0], m[1]), sliver, "{message}");
                }
            }
        }
    }

    /// Within a cell the block cut up to a front is the block cut up to another front with
    /// its nodes moved, to the bit (nodes, tetrahedra, boundary faces, node sets, flank
    /// pairs; with the mid-edge nodes of tet10 too), uniform or graded, and a cut is moved
    /// exactly where the fresh one has the same connectivity (fronts 0.7 mm apart across
    /// the block, and the uncut block, where there is no incision to move).
    #[test]
    fn a_cut_within_a_cell_is_the_last_one_moved() {
        use crate::mesh::QuadraticMesh;
        let bits =
            |n: &[[f64; 3]]| -> Vec<u64> { n.iter().flatten().map(|x| x.to_bits()).collect() };
        for beta in [1.0, 2.0] {
            let g = default_block(beta);
            let fronts: Vec<f64> = (0..=143).map(|k| g.front(0.7 * f64::from(k))).collect();
            let mut moves = 0;
            for w in fronts.windows(2) {
                let (from, front) = (w[0], w[1]);
                let previous = g.cut(from).unwrap();
                let fresh = g.cut(front).unwrap();
                let alike = previous.mesh.tets() == fresh.mesh.tets()
                    && previous.mesh.nodes().len() == fresh.mesh.nodes().len();
                let Some(moved) = g.moved_cut(&previous, from, front) else {
                    assert!(!alike || from == 0.0, "β = {beta}, {from} → {front}");
                    continue;
                };
                moves += 1;
                let moved = moved.unwrap();
                let (a, b) = (&moved.mesh, &fresh.mesh);
                assert_eq!(
                    bits(a.nodes()),
                    bits(b.nodes()),
                    "β = {beta}, {from} → {front}"
                );
                assert_eq!(a.tets(), b.tets());
                assert_eq!(a.boundary(), b.boundary());
                assert_eq!(
                    a.node_sets().iter().collect::<Vec<_>>(),
                    b.node_sets().iter().collect::<Vec<_>>()
                );
                assert_eq!(moved.flank_pairs, fresh.flank_pairs);
                if moves % 10 == 1 {
                    let quadratic = QuadraticMesh::new(&previous.mesh).moved(a);
                    let expected = QuadraticMesh::new(b);
                    assert_eq!(bits(quadratic.nodes()), bits(expected.nodes()));
                    assert_eq!(quadratic.tets(), expected.tets());
                }
            }
            assert!(moves > 100, "β = {beta}: {moves} moves of 143");
        }
    }

    /// The tetrahedra of the cut mesh's first column of cubes ahead of the front (x from
    /// the front to the next plane, y and z in their first layers), each as its corners
    /// relative to (front, 0, 0) in µm, sorted.
    fn split_ahead(g: &Geometry, front: f64) -> Vec<[[i64; 3]; 4]> {
        let (p, _) = g.x_planes(front);
        let at = p.iter().position(|&x| x == front).unwrap();
        let [y, z] = &g.planes_yz;
        let mesh = g.cut(front).unwrap().mesh;
        let mut tets: Vec<[[i64; 3]; 4]> = (0..mesh.tets().len())
            .map(|t| mesh.tet(t))
            .filter(|c| {
                let mid = |d: usize| c.iter().map(|x| x[d]).sum::<f64>() / 4.0;
                mid(0) > p[at] && mid(0) < p[at + 1] && mid(1) < y[1] && mid(2) < z[1]
            })
            .map(|c| {
                let mut c = c.map(|x| {
                    let relative = [x[0] - front, x[1], x[2]];
                    relative.map(|v| (v * 1e3).round() as i64)
                });
                c.sort();
                c
            })
            .collect();
        tets.sort();
        tets
    }

    /// The cube just ahead of the front is split into the same tetrahedra wherever the
    /// front is (the layers' split mirrored with the front's parity), uniform or graded.
    #[test]
    fn the_cube_ahead_of_the_front_is_split_alike() {
        for beta in [1.0, 2.0] {
            let g = default_block(beta);
            let first = split_ahead(&g, 10.3);
            assert_eq!(first.len(), 6, "{first:?}");
            for front in [20.0, 27.7, 33.4, 51.0, 60.05, 81.9] {
                assert_eq!(split_ahead(&g, front), first, "β = {beta}, front {front}");
            }
        }
    }

    /// The default block (100 × 80 × 17 mm, 6 × 16 × 14 cells, cut at y = 45 mm to half
    /// depth) graded with `beta`.
    fn default_block(beta: f64) -> Geometry {
        let options = Options {
            strategy: Strategy::Duplicate,
            support: Support::Clamped,
            contact: true,
        };
        Geometry::new(
            [100.0, 80.0, 17.0],
            [6, 16, 14],
            45.0,
            8.5,
            5.0,
            beta,
            options,
        )
        .unwrap()
    }

    /// β = 2: wherever the front is, the x planes inside the block are the front and the
    /// front ± 100 (k/6)² mm, so the cells beside the tip are 100/36 mm wide (where they
    /// do not reach an end face); the cells at the end faces are at least SNAP h wide. With the full cut the planes are graded towards
    /// the far face: 100 (1 − (k/6)²).
    #[test]
    fn graded_x_planes_are_finest_at_the_tip() {
        let g = default_block(2.0);
        let (h, tip) = (100.0 / 6.0, 100.0 / 36.0);
        let offsets: Vec<f64> = (0..=6)
            .map(|k| 100.0 * (f64::from(k) / 6.0).powi(2))
            .collect();
        for k in 1..2000 {
            let front = g.front(0.05 * f64::from(k));
            let (p, _) = g.x_planes(front);
            let at = p
                .iter()
                .position(|&x| x == front)
                .expect("a plane at the front");
            assert!(
                p.windows(2).all(|w| w[1] - w[0] >= SNAP * h),
                "front {front}: {p:?}"
            );
            for &x in &p[1..p.len() - 1] {
                let on_grid = offsets.iter().any(|d| ((x - front).abs() - d).abs() < 1e-9);
                assert!(on_grid, "front {front}: plane {x} in {p:?}");
            }
            for side in [at.wrapping_sub(1), at + 1] {
                let inner = side > 0 && side + 1 < p.len();
                assert!(
                    !inner || ((p[side] - front).abs() - tip).abs() < 1e-9,
                    "{p:?}"
                );
            }
        }
        let (p, mirrored) = g.x_planes(100.0);
        let expected: Vec<f64> = offsets.iter().rev().map(|d| 100.0 - d).collect();
        assert!(!mirrored);
        assert!(
            p.iter().zip(&expected).all(|(a, b)| (a - b).abs() < 1e-12),
            "{p:?}"
        );
        assert_eq!(p.len(), expected.len());
    }
}
