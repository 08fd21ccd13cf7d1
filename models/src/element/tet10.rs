//! 10-node quadratic tetrahedron (seed 003 App. C; node order as VTK's quadratic tetra: the
//! corners 0–3, then the mid-edge nodes of the edges 01, 12, 20, 03, 13, 23).
//!
//! In barycentric coordinates λ₀…λ₃: corner N_i = λ_i (2λ_i − 1), mid-edge N_ij = 4 λ_i λ_j.
//! The elements have straight edges (mid-edge nodes at the midpoints in the reference
//! configuration), so the map from λ to X is affine and the corner gradients ∇λ_k are
//! constant per element: ∇N_i = (4λ_i − 1) ∇λ_i, ∇N_ij = 4 (λ_j ∇λ_i + λ_i ∇λ_j).

use nalgebra::{SMatrix, SVector};

/// The corner pairs of the mid-edge nodes 4–9.
pub const EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [2, 0], [0, 3], [1, 3], [2, 3]];

/// The six nodes of each face of the tetrahedron, in the order of the linear element's
/// faces (face k opposite corner k, outward for a positive volume): three corners
/// counter-clockwise seen from outside, then the mid-edge nodes of the edges between them
/// (first–second, second–third, third–first).
pub const FACES: [[usize; 6]; 4] = [
    [1, 2, 3, 5, 9, 8],
    [0, 3, 2, 7, 9, 6],
    [0, 1, 3, 4, 8, 7],
    [0, 2, 1, 6, 5, 4],
];

/// Shape function values at barycentric λ.
pub fn values(l: &[f64; 4]) -> SVector<f64, 10> {
    let mut n = SVector::<f64, 10>::zeros();
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
    }
    for (k, [i, j]) in EDGES.iter().enumerate() {
        n[4 + k] = 4.0 * l[*i] * l[*j];
    }
    n
}

/// Shape function gradients (rows) at λ from the corner gradients ∇λ_k (rows of `g`).
pub fn gradients(l: &[f64; 4], g: &SMatrix<f64, 4, 3>) -> SMatrix<f64, 10, 3> {
    let mut out = SMatrix::<f64, 10, 3>::zeros();
    for (i, li) in l.iter().enumerate() {
        out.set_row(i, &(g.row(i) * (4.0 * li - 1.0)));
    }
    for (k, [i, j]) in EDGES.iter().enumerate() {
        out.set_row(4 + k, &((g.row(*i) * l[*j] + g.row(*j) * l[*i]) * 4.0));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shape_functions_are_nodal_and_sum_to_one() {
        let corner = |i: usize| {
            let mut l = [0.0; 4];
            l[i] = 1.0;
            l
        };
        let nodes: Vec<[f64; 4]> = (0..4)
            .map(corner)
            .chain(EDGES.iter().map(|[i, j]| {
                let mut l = [0.0; 4];
                l[*i] = 0.5;
                l[*j] = 0.5;
                l
            }))
            .collect();
        for (a, l) in nodes.iter().enumerate() {
            let n = values(l);
            for b in 0..10 {
                assert!(
                    (n[b] - f64::from(u8::from(a == b))).abs() < 1e-15,
                    "{a} {b}"
                );
            }
        }
        let g = SMatrix::<f64, 4, 3>::new(
            -1.0, -1.0, -1.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0,
        );
        let l = [0.1, 0.2, 0.3, 0.4];
        assert!((values(&l).sum() - 1.0).abs() < 1e-15);
        // Gradients sum to zero (a rigid translation has no strain).
        let s = gradients(&l, &g).row_sum();
        assert!(s.norm() < 1e-14, "{s}");
    }

    #[test]
    fn face_nodes_are_those_of_the_faces() {
        for (k, face) in FACES.iter().enumerate() {
            assert!(!face[..3].contains(&k), "face {k} is opposite corner {k}");
            for (m, &node) in face[3..].iter().enumerate() {
                let (a, b) = (face[m], face[(m + 1) % 3]);
                let [i, j] = EDGES[node - 4];
                assert!(
                    (i == a && j == b) || (i == b && j == a),
                    "face {k} node {node}"
                );
            }
        }
    }
}
