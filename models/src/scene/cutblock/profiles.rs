//! The top surface of the cut block: its faces (3-node triangles, or 6-node ones on
//! quadratic tetrahedra, read with their quadratic shape functions), the press load on
//! them, and the laser profiles as a line scanner sees them (seed 002 §3.5).
//!
//! The scanner model is the one the shipped data sets were made with
//! (`experiments/data/cutblock/README.md`): the reference top face is sampled every
//! [`SAMPLE_X`] mm in x and [`SAMPLE_Y`] mm in y, each sample is mapped to the deformed
//! configuration, the samples of each reference row are cut by the plane x = const (linear
//! interpolation between the two samples that bracket it), which gives the section polyline
//! of each flank (the faces in front of the cut plane and behind it), and the height at a
//! lab-frame station y is the linear interpolation on that polyline; NaN where neither
//! polyline covers the station (the open cut), the higher one where both do.

use super::geometry::Geometry;
use crate::assembly::loads;
use crate::element::tri6;
use crate::mesh::{Mesh3d, QuadraticMesh};

/// Laser-profile stations: y = 0, 0.5, …, 90 mm in lab coordinates (the default block
/// pulled by up to 10 mm).
pub const PROFILE_STATIONS: usize = 181;
/// Spacing of the profile stations (mm).
pub const PROFILE_STEP: f64 = 0.5;
/// The scanner lines x = 25, 50, 75 mm (seed 002 §3.5, Fig. 4.7).
pub const PROFILE_LINES: [f64; 3] = [25.0, 50.0, 75.0];

/// Sample spacing of the reference top face along x and y (mm).
pub const SAMPLE_X: f64 = 0.25;
pub const SAMPLE_Y: f64 = 0.1;

/// Half-width (mm) of the window of reference x around a scan line that is searched for
/// the section: the largest x-displacement of the top surface it allows.
const WINDOW: f64 = 15.0;

/// The top faces and where they lie.
#[derive(Debug, Clone)]
pub struct TopSurface {
    /// Node lists: 3 corners, or 3 corners and the mid-edge nodes of the edges first–second,
    /// second–third, third–first.
    faces: Vec<Vec<usize>>,
    /// Whether each face lies in front of the cut plane (centroid y < y_cut).
    front: Vec<bool>,
    /// Faces by reference cell of the top grid: `cells[i · ny + j]`.
    cells: Vec<Vec<usize>>,
    x_planes: Vec<f64>,
    y_planes: Vec<f64>,
    top: f64,
    y_cut: f64,
    size_y: f64,
}

impl TopSurface {
    pub fn new(mesh: &Mesh3d, g: &Geometry, quadratic: Option<&QuadraticMesh>) -> Self {
        let top = g.size[2];
        let tol = 1e-9 * mesh.extent();
        let p = mesh.nodes();
        let corners: Vec<[usize; 3]> = mesh
            .boundary()
            .iter()
            .map(|f| f.nodes)
            .filter(|f| f.iter().all(|&n| (p[n][2] - top).abs() <= tol))
            .collect();
        let planes = |d: usize| {
            let mut v: Vec<f64> = p
                .iter()
                .filter(|q| (q[2] - top).abs() <= tol)
                .map(|q| q[d])
                .collect();
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        };
        let (x_planes, y_planes) = (planes(0), planes(1));
        let (nx, ny) = (x_planes.len() - 1, y_planes.len() - 1);
        let mut cells = vec![Vec::new(); nx * ny];
        let cell = |planes: &[f64], v: f64| {
            planes
                .partition_point(|&q| q <= v)
                .saturating_sub(1)
                .min(planes.len() - 2)
        };
        let mut front = Vec::with_capacity(corners.len());
        for (k, f) in corners.iter().enumerate() {
            let c = |d: usize| f.iter().map(|&n| p[n][d]).sum::<f64>() / 3.0;
            let (cx, cy) = (c(0), c(1));
            cells[cell(&x_planes, cx) * ny + cell(&y_planes, cy)].push(k);
            front.push(cy < g.y_cut);
        }
        let faces = corners
            .iter()
            .map(|&f| match quadratic {
                Some(q) => q.face(f).to_vec(),
                None => f.to_vec(),
            })
            .collect();
        Self {
            faces,
            front,
            cells,
            x_planes,
            y_planes,
            top,
            y_cut: g.y_cut,
            size_y: g.size[1],
        }
    }

    /// The press force as a uniform pressure over the top faces whose centroid lies within
    /// `press_radius` of the tip (scalpel_x, y_cut), or over the nearest face if none does;
    /// consistent nodal loads, direction −z, total exactly `force` (added to `f`).
    pub fn press_load(
        &self,
        nodes: &[[f64; 3]],
        g: &Geometry,
        force: f64,
        scalpel_x: f64,
        f: &mut [f64],
    ) {
        let tip = [scalpel_x.min(g.size[0]), g.y_cut];
        let distance = |face: &[usize]| {
            let c = |d: usize| face[..3].iter().map(|&n| nodes[n][d]).sum::<f64>() / 3.0;
            (c(0) - tip[0]).hypot(c(1) - tip[1])
        };
        let mut patch: Vec<&[usize]> = self
            .faces
            .iter()
            .map(Vec::as_slice)
            .filter(|face| distance(face) <= g.press_radius)
            .collect();
        if patch.is_empty() {
            patch.extend(
                self.faces
                    .iter()
                    .map(Vec::as_slice)
                    .min_by(|a, b| distance(a).total_cmp(&distance(b))),
            );
        }
        let area = |face: &[usize]| {
            crate::element::tet4::face_area_normal(
                &nodes[face[0]],
                &nodes[face[1]],
                &nodes[face[2]],
            )
            .norm()
        };
        let total: f64 = patch.iter().map(|face| area(face)).sum();
        for face in patch {
            face_traction(nodes, face, [0.0, 0.0, -force / total], f);
        }
    }

    /// The deformed position of the reference top point (x, y) on a face of the given side,
    /// if one covers it.
    fn deformed(
        &self,
        nodes: &[[f64; 3]],
        u: &[f64],
        x: f64,
        y: f64,
        front: bool,
    ) -> Option<[f64; 3]> {
        let locate = |planes: &[f64], v: f64| planes.partition_point(|&q| q <= v).saturating_sub(1);
        let (i0, j0) = (locate(&self.x_planes, x), locate(&self.y_planes, y));
        let ny = self.y_planes.len() - 1;
        let nx = self.x_planes.len() - 1;
        for i in i0.saturating_sub(1)..(i0 + 2).min(nx) {
            for j in j0.saturating_sub(1)..(j0 + 2).min(ny) {
                for &k in &self.cells[i * ny + j] {
                    if self.front[k] != front {
                        continue;
                    }
                    if let Some(l) = barycentric(nodes, &self.faces[k], x, y) {
                        let face = &self.faces[k];
                        let mut p = [x, y, self.top];
                        for (a, w) in shape(&l, face.len() == 6)
                            .iter()
                            .take(face.len())
                            .enumerate()
                        {
                            for d in 0..3 {
                                p[d] += w * u[3 * face[a] + d];
                            }
                        }
                        return Some(p);
                    }
                }
            }
        }
        None
    }

    /// The section polyline of one flank with the plane x = `line`: deformed (y, z) points
    /// in order of reference y. Each row of reference y is sampled every [`SAMPLE_X`]
    /// within [`WINDOW`] of the line; the crossing is interpolated between the two samples
    /// whose deformed x straddle the line, searched outwards from the previous row's
    /// crossing (the first row's from x = `line`), so a row costs a few samples. Into `out`
    /// (cleared first).
    fn section(
        &self,
        nodes: &[[f64; 3]],
        u: &[f64],
        line: f64,
        front: bool,
        out: &mut Vec<[f64; 2]>,
    ) {
        let (from, to) = if front {
            (0.0, self.y_cut)
        } else {
            (self.y_cut, self.size_y)
        };
        let rows = ((to - from) / SAMPLE_Y).round() as usize;
        let x_max = *self.x_planes.last().unwrap_or(&0.0);
        let (lo, hi) = ((line - WINDOW).max(0.0), (line + WINDOW).min(x_max));
        let columns = ((hi - lo) / SAMPLE_X).round() as usize;
        let column_x = |c: usize| lo + (hi - lo) * c as f64 / columns.max(1) as f64;
        let mut guess = (((line - lo) / (hi - lo).max(1e-300)) * columns as f64).round() as usize;
        out.clear();
        for r in 0..=rows {
            let y = from + (to - from) * r as f64 / rows.max(1) as f64;
            // The segment between columns c − 1 and c, if it crosses the line.
            let crossing = |c: usize| {
                let q = self.deformed(nodes, u, column_x(c - 1), y, front)?;
                let p = self.deformed(nodes, u, column_x(c), y, front)?;
                ((q[0] - line) * (p[0] - line) <= 0.0 && q[0] != p[0]).then(|| {
                    let w = (line - q[0]) / (p[0] - q[0]);
                    [q[1] + w * (p[1] - q[1]), q[2] + w * (p[2] - q[2])]
                })
            };
            let start = guess.clamp(1, columns.max(1));
            let outwards = (0..=columns).flat_map(|k| [start + k, start.wrapping_sub(k + 1)]);
            let found = outwards
                .filter(|&c| (1..=columns).contains(&c))
                .find_map(|c| crossing(c).map(|point| (c, point)));
            if let Some((c, point)) = found {
                guess = c;
                out.push(point);
            }
        }
    }

    /// Heights at lab-frame stations `ys` along the scan line x = `line` (NaN: no surface),
    /// into `heights` (one per station), the two flanks' sections made in `sections`
    /// (allocating only while they grow).
    pub fn profile(
        &self,
        nodes: &[[f64; 3]],
        u: &[f64],
        line: f64,
        ys: impl ExactSizeIterator<Item = f64>,
        heights: &mut [f64],
        sections: &mut [Vec<[f64; 2]>; 2],
    ) {
        debug_assert_eq!(heights.len(), ys.len(), "one height per station");
        let [front, back] = sections;
        self.section(nodes, u, line, true, front);
        self.section(nodes, u, line, false, back);
        for (h, y) in heights.iter_mut().zip(ys) {
            *h = [&*front, &*back]
                .iter()
                .filter_map(|s| height(s, y))
                .fold(f64::NAN, |a, b| if a.is_nan() || b > a { b } else { a });
        }
    }
}

/// The height of a polyline (y, z) at y: linear interpolation on the first segment that
/// spans y.
fn height(polyline: &[[f64; 2]], y: f64) -> Option<f64> {
    polyline.windows(2).find_map(|w| {
        let ([y0, z0], [y1, z1]) = (w[0], w[1]);
        let (lo, hi) = (y0.min(y1), y0.max(y1));
        if y < lo || y > hi {
            return None;
        }
        Some(if y1 == y0 {
            z0.max(z1)
        } else {
            z0 + (y - y0) / (y1 - y0) * (z1 - z0)
        })
    })
}

/// Barycentric coordinates of (x, y) in the reference triangle of a face's first three
/// nodes (projected on the top plane), if inside.
fn barycentric(nodes: &[[f64; 3]], face: &[usize], x: f64, y: f64) -> Option<[f64; 3]> {
    let [a, b, c] = [nodes[face[0]], nodes[face[1]], nodes[face[2]]];
    let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
    if det == 0.0 {
        return None;
    }
    let l1 = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det;
    let l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
    let l0 = 1.0 - l1 - l2;
    const EPS: f64 = -1e-12;
    (l0 >= EPS && l1 >= EPS && l2 >= EPS).then_some([l0, l1, l2])
}

/// Shape functions at barycentric `l` in a face's node order: the linear triangle's three,
/// or the quadratic triangle's six.
fn shape(l: &[f64; 3], quadratic: bool) -> [f64; 6] {
    let [a, b, c] = *l;
    if quadratic {
        tri6::shape(*l)
    } else {
        [a, b, c, 0.0, 0.0, 0.0]
    }
}

/// Consistent loads of a uniform traction `t` (N/mm²) on a flat triangle: the linear one
/// shares its force equally among the corners, the quadratic one gives it all to the
/// mid-edge nodes, a third each (∫N dA of the 6-node triangle: 0 at corners, A/3 at mids).
fn face_traction(nodes: &[[f64; 3]], face: &[usize], t: [f64; 3], f: &mut [f64]) {
    match face {
        [a, b, c] => loads::face_traction(nodes, [*a, *b, *c], t, f),
        [a, b, c, ab, bc, ca] => {
            let area =
                crate::element::tet4::face_area_normal(&nodes[*a], &nodes[*b], &nodes[*c]).norm();
            for &m in [ab, bc, ca] {
                for d in 0..3 {
                    f[3 * m + d] += t[d] * area / 3.0;
                }
            }
        }
        _ => unreachable!("triangles have 3 or 6 nodes"),
    }
}
