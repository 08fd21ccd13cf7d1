//! 2-node line (truss) element in 2D: axial stiffness only (seed 003 App. C.1, rotated from
//! the element axis into the xy plane). Used for diaphragm, abdominal wall and pelvic floor.
//!
//! With direction cosines c = (x₂ − x₁)/L, K_e = (E A / L) · [[c cᵀ, −c cᵀ], [−c cᵀ, c cᵀ]].

use nalgebra::{Matrix2, SMatrix, SVector, Vector2};

use super::membrane::Line;
use super::quadrature::GAUSS_1;

/// Element displacement vector (u_x1, u_y1, u_x2, u_y2).
pub type Dofs = SVector<f64, 4>;

/// Length and unit direction from node 1 to node 2.
pub fn axis(p: &[[f64; 2]; 2]) -> (f64, Vector2<f64>) {
    let d = Vector2::new(p[1][0] - p[0][0], p[1][1] - p[0][1]);
    let len = d.norm();
    (len, d / len)
}

/// Axial stiffness for Young's modulus `young` (MPa) and cross-section `area` (mm²).
pub fn stiffness(p: &[[f64; 2]; 2], young: f64, area: f64) -> SMatrix<f64, 4, 4> {
    let (len, c) = axis(p);
    let kc: Matrix2<f64> = c * c.transpose() * (young * area / len);
    let mut k = SMatrix::<f64, 4, 4>::zeros();
    k.fixed_view_mut::<2, 2>(0, 0).copy_from(&kc);
    k.fixed_view_mut::<2, 2>(2, 2).copy_from(&kc);
    k.fixed_view_mut::<2, 2>(0, 2).copy_from(&(-kc));
    k.fixed_view_mut::<2, 2>(2, 0).copy_from(&(-kc));
    k
}

/// Consistent mass ρAL/6 · [[2, 1], [1, 2]] ⊗ I₂.
pub fn mass_consistent(p: &[[f64; 2]; 2], density: f64, area: f64) -> SMatrix<f64, 4, 4> {
    let m = density * area * axis(p).0 / 6.0;
    let mut mass = SMatrix::<f64, 4, 4>::zeros();
    for i in 0..4 {
        mass[(i, i)] = 2.0 * m;
        mass[(i, (i + 2) % 4)] = m;
    }
    mass
}

/// Lumped mass ρAL/2 on each of the four dofs.
pub fn lumped_mass(p: &[[f64; 2]; 2], density: f64, area: f64) -> SVector<f64, 4> {
    SVector::repeat(density * area * axis(p).0 / 2.0)
}

/// Axial stress σ = E (u₂ − u₁)·c / L (MPa; positive in tension).
pub fn axial_stress(p: &[[f64; 2]; 2], young: f64, u: &Dofs) -> f64 {
    let (len, c) = axis(p);
    let du = Vector2::new(u[2] - u[0], u[3] - u[1]);
    young * du.dot(&c) / len
}

/// The element at finite strain ([`super::membrane`]): linear shape functions, whose
/// stretch is constant, and the one-point rule.
pub fn membrane(p: &[[f64; 2]; 2]) -> Line<'_, 2, 1> {
    Line {
        nodes: p,
        shapes: |xi| [0.5 * (1.0 - xi), 0.5 * (1.0 + xi)],
        derivatives: |_| [-0.5, 0.5],
        rule: &GAUSS_1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axial_stretch_gives_ea_over_l() {
        let p = [[1.0, 1.0], [4.0, 5.0]]; // L = 5, c = (0.6, 0.8)
        let k = stiffness(&p, 200.0, 2.0);
        // Stretch by δ = 0.1 along the axis: the end force is EAδ/L = 8 along the axis.
        let u = Dofs::new(0.0, 0.0, 0.06, 0.08);
        let f = k * u;
        assert!((f[2] - 8.0 * 0.6).abs() < 1e-12 && (f[3] - 8.0 * 0.8).abs() < 1e-12);
        assert!((axial_stress(&p, 200.0, &u) - 4.0).abs() < 1e-12);
        // Transverse motion has no stiffness.
        assert!((k * Dofs::new(0.0, 0.0, -0.8, 0.6)).norm() < 1e-12);
    }
}
