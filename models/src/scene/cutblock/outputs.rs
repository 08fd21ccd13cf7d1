//! The cut block's outputs, computed together on the first request after a step.

use super::geometry::Geometry;
use super::profiles::{PROFILE_LINES, PROFILE_STATIONS, PROFILE_STEP};
use super::topology::Topology;
use crate::assembly::tetrahedra::Tetrahedron;
use crate::stress;

/// All outputs of one solved state, in table order, computed together on the first read
/// after a step into buffers kept from step to step: once they have grown to the mesh,
/// reading a step's outputs allocates nothing.
#[derive(Debug, Default)]
pub struct Outputs {
    /// Whether the values are those of the present state.
    fresh: bool,
    scalars: [f64; 9],
    profiles: [Vec<f64>; 3],
    scratch: Scratch,
}

/// What the outputs are computed in.
#[derive(Debug, Default)]
struct Scratch {
    /// Per element: von Mises stress and volume.
    elements: Vec<(f64, f64)>,
    /// Per node: the volume-weighted von Mises average and its weight.
    average: Vec<f64>,
    weight: Vec<f64>,
    /// The bottom line's nodes: (x, u_z).
    line: Vec<(f64, f64)>,
    /// A scan line's sections of the front and the back flank.
    sections: [Vec<[f64; 2]>; 2],
}

impl Outputs {
    /// The state changed: the next read computes the outputs anew.
    pub fn invalidate(&mut self) {
        self.fresh = false;
    }

    /// Output number `index` (table order from the first output) of the state `t`, whose
    /// incision reaches `reached`, into `out`.
    pub fn read(&mut self, g: &Geometry, t: &Topology, reached: f64, index: u32, out: &mut [f64]) {
        if !self.fresh {
            self.compute(g, t, reached);
            self.fresh = true;
        }
        let i = index as usize;
        if i < self.scalars.len() {
            out[0] = self.scalars[i];
        } else {
            out.copy_from_slice(&self.profiles[i - self.scalars.len()]);
        }
    }

    fn compute(&mut self, g: &Geometry, t: &Topology, reached: f64) {
        let s = &mut self.scratch;
        let (von_mises, strain) = stress_and_strain(t, s);
        self.scalars = [
            reaction_force(t),
            cut_opening(g, t),
            bottom_lift(g, t, &mut s.line),
            x_contraction(g, t),
            von_mises,
            reached,
            t.contact.as_ref().map_or(0.0, |c| c.active.len() as f64),
            t.contact.as_ref().map_or(0.0, |c| c.penetration),
            strain,
        ];
        let stations = || (0..PROFILE_STATIONS).map(|i| i as f64 * PROFILE_STEP);
        for (profile, x) in self.profiles.iter_mut().zip(PROFILE_LINES) {
            profile.resize(PROFILE_STATIONS, 0.0);
            t.top.profile(
                t.solid.nodes(),
                &t.eq.u,
                x,
                stations(),
                profile,
                &mut s.sections,
            );
        }
    }
}

/// Σ of the y-components of the internal forces over the pulled face (N): the reaction.
fn reaction_force(t: &Topology) -> f64 {
    t.pulled.iter().map(|n| t.eq.internal[3 * n + 1]).sum()
}

fn deformed(t: &Topology, n: usize) -> [f64; 3] {
    let p = t.solid.nodes()[n];
    [
        p[0] + t.eq.u[3 * n],
        p[1] + t.eq.u[3 * n + 1],
        p[2] + t.eq.u[3 * n + 2],
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

/// Largest u_z along the bottom surface's line on the cut plane (mm): the maximum of the
/// element field along it, whose edges it is made of (y_cut and z = 0 are node planes) —
/// the nodal values for tet4, and for tet10 also the peak of each edge's quadratic through
/// its corners and midpoint, so that the output does not depend on where the nodes fall.
/// Where a cut through the whole height has split the line's nodes (two at one x), the
/// nodal values.
fn bottom_lift(g: &Geometry, t: &Topology, line: &mut Vec<(f64, f64)>) -> f64 {
    let p = t.solid.nodes();
    line.clear();
    line.extend(
        (0..p.len())
            .filter(|&n| p[n][2] == 0.0 && p[n][1] == g.y_cut)
            .map(|n| (p[n][0], t.eq.u[3 * n + 2])),
    );
    let nodal = line
        .iter()
        .map(|&(_, uz)| uz)
        .fold(f64::NEG_INFINITY, f64::max);
    if t.solid.kind() != Tetrahedron::Tet10 {
        return nodal;
    }
    line.sort_unstable_by(|a, b| a.0.total_cmp(&b.0));
    let one_node_per_x = line.windows(2).all(|w| w[0].0 < w[1].0);
    if !one_node_per_x || line.len().is_multiple_of(2) {
        return nodal;
    }
    line.windows(3)
        .step_by(2)
        .filter_map(|w| edge_peak(w[0].1, w[1].1, w[2].1))
        .fold(nodal, f64::max)
}

/// The interior maximum of the quadratic through `u0`, `um`, `u1` at s = 0, ½, 1, if it has
/// one: u(s) = u0 (1 − s)(1 − 2s) + 4 um s (1 − s) + u1 s (2s − 1), u'(s*) = 0.
fn edge_peak(u0: f64, um: f64, u1: f64) -> Option<f64> {
    let curvature = u0 - 2.0 * um + u1;
    if curvature >= 0.0 {
        return None;
    }
    let s = (3.0 * u0 - 4.0 * um + u1) / (4.0 * curvature);
    (s > 0.0 && s < 1.0).then_some(
        u0 * (1.0 - s) * (1.0 - 2.0 * s) + 4.0 * um * s * (1.0 - s) + u1 * s * (2.0 * s - 1.0),
    )
}

/// Largest inward x-displacement of the end faces x = 0 and x = L_x (mm).
fn x_contraction(g: &Geometry, t: &Topology) -> f64 {
    let p = t.solid.nodes();
    (0..p.len())
        .filter_map(|n| {
            if p[n][0] == 0.0 {
                Some(t.eq.u[3 * n])
            } else if p[n][0] == g.size[0] {
                Some(-t.eq.u[3 * n])
            } else {
                None
            }
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

/// The maximum of the volume-weighted corner-node averages of the elements' von Mises
/// stress (MPa; seed 002 eq. 4.4) and the largest principal strain, both at the element
/// centroids ([`stress::solid_centroids`]), computed in one pass over the elements.
fn stress_and_strain(t: &Topology, s: &mut Scratch) -> (f64, f64) {
    let elements = &mut s.elements;
    elements.clear();
    // `largest_eigenvalue` folds over every element, so each is recorded.
    let largest = stress::largest_eigenvalue(stress::solid_centroids(&t.solid, &t.eq.u).map(|c| {
        elements.push((stress::mises(&c.stress), c.volume));
        c.strain
    }));
    let n = t.solid.nodes().len();
    s.average.resize(n, 0.0);
    s.weight.resize(n, 0.0);
    let weighted = (s.elements.iter().enumerate())
        .map(|(e, &(von_mises, volume))| (t.solid.corners(e), volume, von_mises));
    stress::nodal_average(weighted, &mut s.average, &mut s.weight);
    (s.average.iter().copied().fold(0.0, f64::max), largest)
}

/// Whether the largest principal strain of the linear law (ε = sym(F − I) at the element
/// centroids) exceeds `limit`, and the strain if it does: only the elements whose bound
/// ([`stress::largest_eigenvalue_bound`]) exceeds the limit are looked at.
pub fn strain_beyond(t: &Topology, limit: f64) -> Option<f64> {
    let strains = t
        .solid
        .centroids(&t.eq.u)
        .map(|(f, _)| 0.5 * (f + f.transpose()) - nalgebra::Matrix3::identity())
        .filter(|e| stress::largest_eigenvalue_bound(e) > limit);
    Some(stress::largest_eigenvalue(strains)).filter(|&largest| largest > limit)
}

#[cfg(test)]
mod tests {
    use super::edge_peak;

    /// u(s) = 1 − 4 (s − 0.3)² through s = 0, ½, 1 peaks at 1; a monotone or convex edge
    /// has no interior peak.
    #[test]
    fn an_edge_peaks_where_its_quadratic_does() {
        let u = |s: f64| 1.0 - 4.0 * (s - 0.3) * (s - 0.3);
        let peak = edge_peak(u(0.0), u(0.5), u(1.0)).unwrap();
        assert!((peak - 1.0).abs() < 1e-14, "{peak}");
        assert_eq!(edge_peak(0.0, 0.5, 1.0), None);
        assert_eq!(edge_peak(1.0, 0.0, 1.0), None);
        // Peak beyond the edge (at s = 1.2): none inside.
        let v = |s: f64| -(s - 1.2) * (s - 1.2);
        assert_eq!(edge_peak(v(0.0), v(0.5), v(1.0)), None);
    }
}
