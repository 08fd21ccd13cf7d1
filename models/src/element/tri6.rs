//! Plane-strain 6-node triangle (quadratic, isoparametric), unit thickness. Corner nodes 0, 1,
//! 2 counter-clockwise, mid-edge nodes 3 (edge 0–1), 4 (edge 1–2), 5 (edge 2–0). Shape
//! functions in area coordinates (L₀, L₁, L₂): N_i = L_i (2 L_i − 1) at the corners,
//! N = 4 L_i L_j at the mid-edge nodes (Zienkiewicz & Taylor, The Finite Element Method,
//! vol. 1, §8.8); mid-edge nodes off the straight edge give curved edges.
//!
//! Here: the shape functions and their gradients (the element's [`Shape`] for the total
//! Lagrangian kernel, [`super::total_lagrangian`], with the 3-point rule), the
//! displacement formulation's small-strain stiffness ∫ Bᵀ D B dA ([`stiffness`], exact for
//! straight edges: the integrand is of degree 2), the consistent and lumped masses. The
//! mixed formulation is in `mixed`, the stresses at a point in `recovery`.

use nalgebra::{Matrix2, Matrix3, SMatrix, SVector};

use super::quadrature::{TriPoint, TRI_3, TRI_6};
use super::total_lagrangian::Shape;

/// Element displacement vector (u_x0, u_y0, …, u_x5, u_y5).
pub type Dofs = SVector<f64, 12>;
/// Strain–displacement matrix for (ε_xx, ε_yy, γ_xy).
pub type BMatrix = SMatrix<f64, 3, 12>;
/// Corners of each edge, in the order of the mid-edge nodes 3, 4, 5.
pub const EDGES: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];

/// The shape functions at area coordinates `l`.
pub fn shape(l: [f64; 3]) -> [f64; 6] {
    let [a, b, c] = l;
    [
        a * (2.0 * a - 1.0),
        b * (2.0 * b - 1.0),
        c * (2.0 * c - 1.0),
        4.0 * a * b,
        4.0 * b * c,
        4.0 * c * a,
    ]
}

/// ∂N/∂(ξ, η) with ξ = L₁, η = L₂ (so L₀ = 1 − ξ − η).
fn reference_gradients(l: [f64; 3]) -> [[f64; 2]; 6] {
    let [a, b, c] = l;
    let da = 1.0 - 4.0 * a; // ∂N₀/∂ξ = ∂N₀/∂η = (4L₀ − 1)·(−1)
    [
        [da, da],
        [4.0 * b - 1.0, 0.0],
        [0.0, 4.0 * c - 1.0],
        [4.0 * (a - b), -4.0 * b],
        [4.0 * c, 4.0 * b],
        [-4.0 * c, 4.0 * (a - c)],
    ]
}

/// ∇N_a = (∂N_a/∂x, ∂N_a/∂y) at area coordinates `l` and the Jacobian determinant there
/// (twice the area of a straight-sided element; positive for counter-clockwise corners).
pub fn gradients(p: &[[f64; 2]; 6], l: [f64; 3]) -> ([[f64; 2]; 6], f64) {
    let g = reference_gradients(l);
    let mut j = Matrix2::zeros();
    for (gi, pi) in g.iter().zip(p) {
        for r in 0..2 {
            for c in 0..2 {
                j[(r, c)] += gi[r] * pi[c];
            }
        }
    }
    let det = j.determinant();
    let inv = j.try_inverse().unwrap_or_else(Matrix2::zeros);
    let grads = g.map(|gi| {
        [
            inv[(0, 0)] * gi[0] + inv[(0, 1)] * gi[1],
            inv[(1, 0)] * gi[0] + inv[(1, 1)] * gi[1],
        ]
    });
    (grads, det)
}

/// B at area coordinates `l` and the Jacobian determinant there.
pub fn b_matrix(p: &[[f64; 2]; 6], l: [f64; 3]) -> (BMatrix, f64) {
    let (grads, det) = gradients(p, l);
    let mut b = BMatrix::zeros();
    for (i, [dx, dy]) in grads.into_iter().enumerate() {
        b[(0, 2 * i)] = dx;
        b[(1, 2 * i + 1)] = dy;
        b[(2, 2 * i)] = dy;
        b[(2, 2 * i + 1)] = dx;
    }
    (b, det)
}

/// The 6-node triangle for the total Lagrangian kernel: its node coordinates as its
/// reference, the 3-point rule, and the isoparametric gradients (curved edges allowed).
#[derive(Debug, Clone, Copy)]
pub struct Tri6;

impl Shape<6, 2> for Tri6 {
    type Reference = [[f64; 2]; 6];
    type At = [f64; 3];
    const RULE: &'static [TriPoint] = &TRI_3;
    /// ∇N_a (rows) at area coordinates `l` and half the Jacobian determinant (the area
    /// per unit weight).
    fn gradients(p: &[[f64; 2]; 6], l: &[f64; 3]) -> (SMatrix<f64, 6, 2>, f64) {
        let (g, det) = gradients(p, *l);
        (SMatrix::from_fn(|a, d| g[a][d]), 0.5 * det)
    }
}

/// Area ∫ dA (exact for straight edges and for parabolic edges, whose det J is linear).
pub fn area(p: &[[f64; 2]; 6]) -> f64 {
    TRI_3.iter().map(|&(l, w)| 0.5 * w * b_matrix(p, l).1).sum()
}

/// Displacement-formulation stiffness ∫ Bᵀ D B dA (3-point rule).
pub fn stiffness(p: &[[f64; 2]; 6], d: &Matrix3<f64>) -> SMatrix<f64, 12, 12> {
    TRI_3.iter().fold(SMatrix::zeros(), |k, &(l, w)| {
        let (b, det) = b_matrix(p, l);
        k + b.transpose() * d * b * (0.5 * w * det)
    })
}

/// Consistent mass ρ ∫ Nᵀ N dA ⊗ I₂ (6-point rule, exact for straight and parabolic edges'
/// polynomial part).
pub fn mass_consistent(p: &[[f64; 2]; 6], density: f64) -> SMatrix<f64, 12, 12> {
    let mut mass = SMatrix::<f64, 12, 12>::zeros();
    for &(l, w) in &TRI_6 {
        let n = shape(l);
        let scale = density * 0.5 * w * b_matrix(p, l).1;
        for i in 0..6 {
            for j in 0..6 {
                let v = scale * n[i] * n[j];
                mass[(2 * i, 2 * j)] += v;
                mass[(2 * i + 1, 2 * j + 1)] += v;
            }
        }
    }
    mass
}

/// Lumped mass by the HRZ rule (Hinton, Rock & Zienkiewicz 1976): the consistent mass's
/// diagonal scaled to the element's mass (row sums would leave the corners without mass;
/// on a straight-sided element the corners get 3/57 and the mid-edge nodes 16/57 of it).
pub fn lumped_mass(p: &[[f64; 2]; 6], density: f64) -> Dofs {
    let m = mass_consistent(p, density);
    let diagonal: f64 = (0..12).step_by(2).map(|i| m[(i, i)]).sum();
    let scale = density * area(p) / diagonal;
    Dofs::from_fn(|i, _| m[(i, i)] * scale)
}

/// The corners of a straight-sided element with its mid-edge nodes at the midpoints.
pub fn straight(corners: &[[f64; 2]; 3]) -> [[f64; 2]; 6] {
    let mid = |[a, b]: [usize; 2]| {
        [
            0.5 * (corners[a][0] + corners[b][0]),
            0.5 * (corners[a][1] + corners[b][1]),
        ]
    };
    [
        corners[0],
        corners[1],
        corners[2],
        mid(EDGES[0]),
        mid(EDGES[1]),
        mid(EDGES[2]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::mixed::stiffness_mixed;
    use crate::element::Elastic;

    fn element() -> [[f64; 2]; 6] {
        straight(&[[0.3, 0.1], [2.1, 0.4], [0.9, 1.7]])
    }

    #[test]
    fn the_shape_functions_are_a_partition_of_unity_and_interpolate_the_nodes() {
        let nodes = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.5],
            [0.5, 0.0, 0.5],
        ];
        for (i, l) in nodes.iter().enumerate() {
            let n = shape(*l);
            for (j, v) in n.iter().enumerate() {
                assert!((v - f64::from(u8::from(i == j))).abs() < 1e-15);
            }
        }
        for &(l, _) in &TRI_6 {
            assert!((shape(l).iter().sum::<f64>() - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn quadratic_displacements_give_their_exact_strains() {
        // u = (x² + 2xy, 3y² − x) has ε_xx = 2x + 2y, ε_yy = 6y, γ_xy = 2x − 1.
        let p = element();
        let u: Dofs = Dofs::from_fn(|k, _| {
            let [x, y] = p[k / 2];
            if k.is_multiple_of(2) {
                x * x + 2.0 * x * y
            } else {
                3.0 * y * y - x
            }
        });
        for &(l, _) in &TRI_6 {
            let n = shape(l);
            let x = (0..6).map(|i| n[i] * p[i][0]).sum::<f64>();
            let y = (0..6).map(|i| n[i] * p[i][1]).sum::<f64>();
            let eps = b_matrix(&p, l).0 * u;
            let exact = [2.0 * x + 2.0 * y, 6.0 * y, 2.0 * x - 1.0];
            for (e, x) in eps.iter().zip(exact) {
                assert!((e - x).abs() < 1e-12, "{e} {x}");
            }
        }
    }

    #[test]
    fn rigid_motions_are_stress_free_and_the_mass_sums_to_the_element_mass() {
        let p = element();
        let elastic = Elastic::new("m", 3.0, 0.4999).unwrap();
        let d = elastic.plane_strain();
        let rigid = |k: usize| -> f64 {
            let [x, y] = p[k / 2];
            if k.is_multiple_of(2) {
                0.2 - 0.7 * y
            } else {
                -0.4 + 0.7 * x
            }
        };
        let u = Dofs::from_fn(|k, _| rigid(k));
        for k in [stiffness(&p, &d), stiffness_mixed(&p, &elastic)] {
            assert!((k * u).amax() < 1e-12 * k.amax());
            assert!((k - k.transpose()).amax() < 1e-12 * k.amax());
        }
        let a = area(&p);
        let straight_area = 0.5 * ((2.1 - 0.3) * (1.7 - 0.1) - (0.9 - 0.3) * (0.4 - 0.1));
        assert!((a - straight_area).abs() < 1e-14);
        let m = mass_consistent(&p, 2.0);
        assert!((m.sum() - 2.0 * 2.0 * a).abs() < 1e-13);
    }
}
