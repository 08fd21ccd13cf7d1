//! The cut block's outputs, computed together on the first request after a step.

use super::topology::{Geometry, Topology};
use super::{PROFILE_LINES, PROFILE_STATIONS, PROFILE_STEP};
use crate::mesh::Mesh3d;
use crate::solve::statics::reactions;
use crate::stress;

/// All outputs of one solved state, in table order.
#[derive(Debug, Clone)]
pub struct Outputs {
    scalars: [f64; 8],
    profiles: [Vec<f64>; 3],
}

impl Outputs {
    pub fn compute(g: &Geometry, t: &Topology) -> Self {
        let scalars = [
            reaction_force(t),
            cut_opening(g, t),
            bottom_lift(g, t),
            x_contraction(t),
            max_von_mises(t),
            g.x_planes[t.cut_cells],
            t.contact.as_ref().map_or(0.0, |c| c.active.len() as f64),
            t.contact.as_ref().map_or(0.0, |c| c.penetration),
        ];
        let surface = DeformedSurface::new(&t.mesh, &t.top_faces, &t.u);
        let profiles = PROFILE_LINES.map(|x| {
            (0..PROFILE_STATIONS)
                .map(|i| surface.height(x, i as f64 * PROFILE_STEP))
                .collect()
        });
        Self { scalars, profiles }
    }

    /// Output number `index` (table order from the first output) into `out`.
    pub fn read(&self, index: u32, out: &mut [f64]) {
        let i = index as usize;
        if i < self.scalars.len() {
            out[0] = self.scalars[i];
        } else {
            out.copy_from_slice(&self.profiles[i - self.scalars.len()]);
        }
    }
}

/// Σ of the y-reactions K u − f over the pulled face (N).
fn reaction_force(t: &Topology) -> f64 {
    let mut r = vec![0.0; t.u.len()];
    reactions(t.asm.matrix(&t.k), &t.u, &t.f, &mut r);
    t.pulled.iter().map(|n| r[3 * n + 1]).sum()
}

fn deformed(mesh: &Mesh3d, u: &[f64], n: usize) -> [f64; 3] {
    let p = mesh.nodes()[n];
    [p[0] + u[3 * n], p[1] + u[3 * n + 1], p[2] + u[3 * n + 2]]
}

/// Largest y-gap between facing flank nodes on the top surface (mm; 0 without a cut).
fn cut_opening(g: &Geometry, t: &Topology) -> f64 {
    let top = g.size[2];
    t.flank_pairs
        .iter()
        .filter(|(f, _)| t.mesh.nodes()[*f][2] == top)
        .map(|&(f, b)| deformed(&t.mesh, &t.u, b)[1] - deformed(&t.mesh, &t.u, f)[1])
        .fold(0.0, f64::max)
}

/// Largest u_z of the bottom-surface nodes on the cut plane (mm).
fn bottom_lift(g: &Geometry, t: &Topology) -> f64 {
    let p = t.mesh.nodes();
    (0..p.len())
        .filter(|&n| p[n][2] == 0.0 && p[n][1] == g.y_cut)
        .map(|n| t.u[3 * n + 2])
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Largest inward x-displacement of the end faces x = 0 and x = L_x (mm).
fn x_contraction(t: &Topology) -> f64 {
    let sets = t.mesh.node_sets();
    let inward = |set: &str, sign: f64| -> f64 {
        sets.get(set)
            .map(|nodes| {
                nodes
                    .iter()
                    .map(|n| sign * t.u[3 * n])
                    .fold(f64::NEG_INFINITY, f64::max)
            })
            .unwrap_or(0.0)
    };
    inward("x0", 1.0).max(inward("x1", -1.0))
}

/// Maximum of the volume-weighted nodal averages of element von Mises stress (MPa).
fn max_von_mises(t: &Topology) -> f64 {
    let s = stress::tet_stresses(&t.mesh, &t.material, &t.u);
    let vm: Vec<f64> = s.iter().map(stress::von_mises).collect();
    let vol: Vec<f64> = (0..t.mesh.tets().len())
        .map(|i| crate::element::tet4::signed_volume(&t.mesh.tet(i)))
        .collect();
    stress::nodal_average(t.mesh.nodes().len(), t.mesh.tets(), &vol, &vm)
        .into_iter()
        .fold(0.0, f64::max)
}

/// The deformed top surface as a set of triangles, for vertical ray casts.
struct DeformedSurface {
    triangles: Vec<[[f64; 3]; 3]>,
}

impl DeformedSurface {
    fn new(mesh: &Mesh3d, faces: &[[usize; 3]], u: &[f64]) -> Self {
        Self {
            triangles: faces
                .iter()
                .map(|f| f.map(|n| deformed(mesh, u, n)))
                .collect(),
        }
    }

    /// Height of the highest surface point above (x, y), or NaN where there is none (as a
    /// laser line scanner sees it: seed 002 §3.5).
    fn height(&self, x: f64, y: f64) -> f64 {
        let mut best = f64::NAN;
        for [a, b, c] in &self.triangles {
            let det = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            if det == 0.0 {
                continue;
            }
            let l1 = ((x - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (y - a[1])) / det;
            let l2 = ((b[0] - a[0]) * (y - a[1]) - (x - a[0]) * (b[1] - a[1])) / det;
            let l0 = 1.0 - l1 - l2;
            const EPS: f64 = -1e-12;
            if l0 >= EPS && l1 >= EPS && l2 >= EPS {
                let z = l0 * a[2] + l1 * b[2] + l2 * c[2];
                if best.is_nan() || z > best {
                    best = z;
                }
            }
        }
        best
    }
}
