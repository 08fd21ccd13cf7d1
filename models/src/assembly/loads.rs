//! Consistent nodal loads (Neumann boundary conditions and body forces) for linear elements
//! (and a pressure on the quadratic triangle's edges):
//! the work-equivalent nodal forces f_a = ∫ N_a t dΓ of a traction t that varies linearly
//! along an edge or is constant over a face or element.

use nalgebra::Vector3;

use crate::element::tet4;

/// Adds the consistent nodal forces of a traction varying linearly from `ta` at node `a` to
/// `tb` at node `b` (N/mm per unit thickness along an edge of a 2D mesh):
/// f_a = L(2t_a + t_b)/6, f_b = L(t_a + 2t_b)/6.
pub fn edge_traction(
    nodes: &[[f64; 2]],
    edge: [usize; 2],
    ta: [f64; 2],
    tb: [f64; 2],
    f: &mut [f64],
) {
    let [a, b] = edge;
    let len = (nodes[b][0] - nodes[a][0]).hypot(nodes[b][1] - nodes[a][1]);
    for d in 0..2 {
        f[2 * a + d] += len * (2.0 * ta[d] + tb[d]) / 6.0;
        f[2 * b + d] += len * (ta[d] + 2.0 * tb[d]) / 6.0;
    }
}

/// Adds the consistent nodal forces of a uniform pressure `p` (MPa, positive pushing into
/// the body) on the edge a→b of a 2D mesh whose interior lies to the left of a→b
/// (counter-clockwise boundary): the traction is −p·n with the outward normal n = (t_y, −t_x).
pub fn edge_pressure(nodes: &[[f64; 2]], edge: [usize; 2], p: f64, f: &mut [f64]) {
    let [a, b] = edge;
    let (dx, dy) = (nodes[b][0] - nodes[a][0], nodes[b][1] - nodes[a][1]);
    let len = dx.hypot(dy);
    let t = [-p * dy / len, p * dx / len];
    edge_traction(nodes, edge, t, t, f);
}

/// Adds the consistent nodal forces of a uniform pressure `p` (as [`edge_pressure`]) on the
/// quadratic edge a → m → b (m its mid-edge node, possibly off the chord: a parabolic edge):
/// f_i = ∫ N_i p (−t_y, t_x) dξ over ξ ∈ [0, 1] with N_a = (1 − ξ)(1 − 2ξ), N_m = 4ξ(1 − ξ),
/// N_b = ξ(2ξ − 1) and t = dx/dξ; the integrand is a cubic, so two Gauss points are exact.
pub fn quadratic_edge_pressure(nodes: &[[f64; 2]], edge: [usize; 3], p: f64, f: &mut [f64]) {
    let g = 0.5 / 3f64.sqrt();
    for xi in [0.5 - g, 0.5 + g] {
        let n = [
            (1.0 - xi) * (1.0 - 2.0 * xi),
            4.0 * xi * (1.0 - xi),
            xi * (2.0 * xi - 1.0),
        ];
        let dn = [4.0 * xi - 3.0, 4.0 - 8.0 * xi, 4.0 * xi - 1.0];
        let t = [0, 1].map(|d| (0..3).map(|k| dn[k] * nodes[edge[k]][d]).sum::<f64>());
        for (k, &node) in edge.iter().enumerate() {
            // Weight 1/2 per Gauss point on [0, 1].
            f[2 * node] += 0.5 * n[k] * p * -t[1];
            f[2 * node + 1] += 0.5 * n[k] * p * t[0];
        }
    }
}

/// Adds the consistent nodal forces of a uniform traction `t` (MPa) on triangle face
/// `face` of a 3D mesh: A·t/3 per node.
pub fn face_traction(nodes: &[[f64; 3]], face: [usize; 3], t: [f64; 3], f: &mut [f64]) {
    let [a, b, c] = face.map(|n| nodes[n]);
    let area = tet4::face_area_normal(&a, &b, &c).norm();
    for n in face {
        for d in 0..3 {
            f[3 * n + d] += area * t[d] / 3.0;
        }
    }
}

/// Adds the consistent nodal forces of a uniform pressure `p` on a boundary face whose
/// nodes are ordered counter-clockwise seen from outside: traction −p·n.
pub fn face_pressure(nodes: &[[f64; 3]], face: [usize; 3], p: f64, f: &mut [f64]) {
    let [a, b, c] = face.map(|n| nodes[n]);
    let n: Vector3<f64> = tet4::face_area_normal(&a, &b, &c).normalize();
    face_traction(nodes, face, (-p * n).into(), f);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_edge_traction_resultant_and_moment() {
        // Edge from (0,0) to (3,0), t_y growing from 1 to 4: resultant 7.5, acting at x = 1.8.
        let nodes = [[0.0, 0.0], [3.0, 0.0]];
        let mut f = vec![0.0; 4];
        edge_traction(&nodes, [0, 1], [0.0, 1.0], [0.0, 4.0], &mut f);
        assert!((f[1] + f[3] - 7.5).abs() < 1e-14);
        assert!((f[3] * 3.0 / 7.5 - 1.8).abs() < 1e-14);
    }

    #[test]
    fn pressure_pushes_inward() {
        // Counter-clockwise square: bottom edge (0,0)->(1,0), interior above ⇒ force +y.
        let nodes = [[0.0, 0.0], [1.0, 0.0]];
        let mut f = vec![0.0; 4];
        edge_pressure(&nodes, [0, 1], 2.0, &mut f);
        assert_eq!(f, vec![0.0, 1.0, 0.0, 1.0]);
        let n3 = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        let mut f3 = vec![0.0; 9];
        // Normal of (0,1,2) is +z, so pressure pushes along −z with total 2·area = 4.
        face_pressure(&n3, [0, 1, 2], 2.0, &mut f3);
        assert!((f3[2] + f3[5] + f3[8] + 4.0).abs() < 1e-14);
    }

    #[test]
    fn quadratic_edge_pressure_has_simpsons_weights_and_the_chords_resultant() {
        // Straight: the bottom edge (0,0) → (3,0) with its midpoint, interior above.
        let nodes = [[0.0, 0.0], [1.5, 0.0], [3.0, 0.0]];
        let mut f = vec![0.0; 6];
        quadratic_edge_pressure(&nodes, [0, 1, 2], 2.0, &mut f);
        for (k, w) in [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0].iter().enumerate() {
            assert!(f[2 * k].abs() < 1e-15 && (f[2 * k + 1] - 6.0 * w).abs() < 1e-14);
        }
        // Curved: a uniform pressure's resultant on any curve is p times the chord turned
        // by 90°, here (0,0) → (2,1) through (1.3, −0.4): p (−Δy, Δx).
        let nodes = [[0.0, 0.0], [1.3, -0.4], [2.0, 1.0]];
        let mut f = vec![0.0; 6];
        quadratic_edge_pressure(&nodes, [0, 1, 2], 0.5, &mut f);
        let resultant = [f[0] + f[2] + f[4], f[1] + f[3] + f[5]];
        assert!((resultant[0] + 0.5).abs() < 1e-14 && (resultant[1] - 1.0).abs() < 1e-14);
    }
}
