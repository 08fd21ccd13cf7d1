//! The cut block's outputs, computed together on the first request after a step.

use super::geometry::Geometry;
use super::topology::Topology;
use super::{PROFILE_LINES, PROFILE_STATIONS, PROFILE_STEP};
use crate::stress;

/// All outputs of one solved state, in table order.
#[derive(Debug, Clone)]
pub struct Outputs {
    scalars: [f64; 9],
    profiles: [Vec<f64>; 3],
}

impl Outputs {
    pub fn compute(g: &Geometry, t: &Topology) -> Self {
        let (von_mises, strain) = stress_and_strain(t);
        let scalars = [
            reaction_force(t),
            cut_opening(g, t),
            bottom_lift(g, t),
            x_contraction(g, t),
            von_mises,
            t.front,
            t.contact.as_ref().map_or(0.0, |c| c.active.len() as f64),
            t.contact.as_ref().map_or(0.0, |c| c.penetration),
            strain,
        ];
        let stations = || (0..PROFILE_STATIONS).map(|i| i as f64 * PROFILE_STEP);
        let profiles = PROFILE_LINES.map(|x| t.top.profile(t.solid.nodes(), &t.u, x, stations()));
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

/// Σ of the y-components of the internal forces over the pulled face (N): the reaction.
fn reaction_force(t: &Topology) -> f64 {
    t.pulled.iter().map(|n| t.internal[3 * n + 1]).sum()
}

fn deformed(t: &Topology, n: usize) -> [f64; 3] {
    let p = t.solid.nodes()[n];
    [
        p[0] + t.u[3 * n],
        p[1] + t.u[3 * n + 1],
        p[2] + t.u[3 * n + 2],
    ]
}

/// Largest y-gap between facing flank nodes on the top surface (mm; 0 without a cut).
fn cut_opening(g: &Geometry, t: &Topology) -> f64 {
    let top = g.size[2];
    t.flank_pairs
        .iter()
        .filter(|(f, _)| t.solid.nodes()[*f][2] == top)
        .map(|&(f, b)| deformed(t, b)[1] - deformed(t, f)[1])
        .fold(0.0, f64::max)
}

/// Largest u_z of the bottom-surface nodes on the cut plane (mm).
fn bottom_lift(g: &Geometry, t: &Topology) -> f64 {
    let p = t.solid.nodes();
    (0..p.len())
        .filter(|&n| p[n][2] == 0.0 && p[n][1] == g.y_cut)
        .map(|n| t.u[3 * n + 2])
        .fold(f64::NEG_INFINITY, f64::max)
}

/// Largest inward x-displacement of the end faces x = 0 and x = L_x (mm).
fn x_contraction(g: &Geometry, t: &Topology) -> f64 {
    let p = t.solid.nodes();
    (0..p.len())
        .filter_map(|n| {
            if p[n][0] == 0.0 {
                Some(t.u[3 * n])
            } else if p[n][0] == g.size[0] {
                Some(-t.u[3 * n])
            } else {
                None
            }
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The maximum of the volume-weighted corner-node averages of the elements' von Mises
/// stress (MPa; seed 002 eq. 4.4) and the largest principal strain, both at the element
/// centroids ([`stress::solid_centroids`]).
fn stress_and_strain(t: &Topology) -> (f64, f64) {
    let centroids = stress::solid_centroids(&t.solid, &t.u);
    let largest = centroids
        .iter()
        .map(|c| c.strain.symmetric_eigenvalues().max())
        .fold(f64::NEG_INFINITY, f64::max);
    let von_mises: Vec<f64> = centroids.iter().map(|c| stress::mises(&c.stress)).collect();
    let volume: Vec<f64> = centroids.iter().map(|c| c.volume).collect();
    let corners: Vec<[usize; 4]> = (0..t.solid.len()).map(|e| t.solid.corners(e)).collect();
    let max = stress::nodal_average(t.solid.nodes().len(), &corners, &volume, &von_mises)
        .into_iter()
        .fold(0.0, f64::max);
    (max, largest)
}

/// Whether the largest principal strain of the linear law (ε = sym(F − I) at the element
/// centroids) exceeds `limit`, and the strain if it does. The Frobenius norm bounds every
/// eigenvalue, so only elements whose norm reaches the limit are decomposed.
pub fn strain_beyond(t: &Topology, limit: f64) -> Option<f64> {
    t.solid
        .centroids(&t.u)
        .iter()
        .map(|(f, _)| 0.5 * (f + f.transpose()) - nalgebra::Matrix3::identity())
        .filter(|e| e.norm() > limit)
        .map(|e| e.symmetric_eigenvalues().max())
        .filter(|&largest| largest > limit)
        .reduce(f64::max)
}
