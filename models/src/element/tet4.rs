//! 4-node linear tetrahedron (constant strain; seed 002 §1.1, seed 003 App. C.3).
//!
//! Shape-function gradients come from inverting the 3×3 edge matrix J = [x₁−x₀, x₂−x₀, x₃−x₀]:
//! ∇N₁..₃ are the rows of J⁻¹ and ∇N₀ = −Σ∇N₁..₃. Volume V = det(J)/6 (positive for a
//! right-handed node order).

use nalgebra::{Matrix3, Matrix6, SMatrix, SVector, Vector3, Vector6};

/// Element displacement vector (u_x0, u_y0, u_z0, …, u_z3).
pub type Dofs = SVector<f64, 12>;
/// Strain–displacement matrix for (ε_xx, ε_yy, ε_zz, γ_xy, γ_yz, γ_zx).
pub type BMatrix = SMatrix<f64, 6, 12>;

fn edges(p: &[[f64; 3]; 4]) -> Matrix3<f64> {
    Matrix3::from_fn(|r, c| p[c + 1][r] - p[0][r])
}

/// Signed volume det(J)/6.
pub fn signed_volume(p: &[[f64; 3]; 4]) -> f64 {
    edges(p).determinant() / 6.0
}

/// Shape-function gradients ∇N_i (one row per node) and the signed volume.
pub fn gradients(p: &[[f64; 3]; 4]) -> (SMatrix<f64, 4, 3>, f64) {
    let j = edges(p);
    let vol = j.determinant() / 6.0;
    // Rows of J⁻¹ are ∇N₁, ∇N₂, ∇N₃ because N_i(x₀ + J ξ) = ξ_i.
    let inv = j.try_inverse().unwrap_or_else(Matrix3::zeros);
    let mut g = SMatrix::<f64, 4, 3>::zeros();
    for i in 0..3 {
        g.set_row(i + 1, &inv.row(i));
    }
    let g0 = -(g.row(1) + g.row(2) + g.row(3));
    g.set_row(0, &g0);
    (g, vol)
}

/// Strain–displacement matrix B and the signed volume.
pub fn b_matrix(p: &[[f64; 3]; 4]) -> (BMatrix, f64) {
    let (g, vol) = gradients(p);
    let mut b = BMatrix::zeros();
    for i in 0..4 {
        let (dx, dy, dz) = (g[(i, 0)], g[(i, 1)], g[(i, 2)]);
        let c = 3 * i;
        b[(0, c)] = dx;
        b[(1, c + 1)] = dy;
        b[(2, c + 2)] = dz;
        b[(3, c)] = dy;
        b[(3, c + 1)] = dx;
        b[(4, c + 1)] = dz;
        b[(4, c + 2)] = dy;
        b[(5, c)] = dz;
        b[(5, c + 2)] = dx;
    }
    (b, vol)
}

/// Stiffness K_e = V Bᵀ D B.
pub fn stiffness(p: &[[f64; 3]; 4], d: &Matrix6<f64>) -> SMatrix<f64, 12, 12> {
    let (b, vol) = b_matrix(p);
    b.transpose() * d * b * vol
}

/// Consistent mass ρV/20 · (1 + δ_ij) ⊗ I₃.
pub fn mass_consistent(p: &[[f64; 3]; 4], density: f64) -> SMatrix<f64, 12, 12> {
    let m = density * signed_volume(p) / 20.0;
    let mut mass = SMatrix::<f64, 12, 12>::zeros();
    for i in 0..4 {
        for j in 0..4 {
            let v = if i == j { 2.0 * m } else { m };
            for k in 0..3 {
                mass[(3 * i + k, 3 * j + k)] = v;
            }
        }
    }
    mass
}

/// Lumped mass ρV/4 on each of the twelve dofs.
pub fn lumped_mass(p: &[[f64; 3]; 4], density: f64) -> SVector<f64, 12> {
    SVector::repeat(density * signed_volume(p) / 4.0)
}

/// Constant strain for element displacements `u`.
pub fn strain(p: &[[f64; 3]; 4], u: &Dofs) -> Vector6<f64> {
    b_matrix(p).0 * u
}

/// Outward normal times area of the triangle (a, b, c) with counter-clockwise order seen from
/// outside: ½ (b − a) × (c − a).
pub fn face_area_normal(a: &[f64; 3], b: &[f64; 3], c: &[f64; 3]) -> Vector3<f64> {
    let (a, b, c) = (Vector3::from(*a), Vector3::from(*b), Vector3::from(*c));
    0.5 * (b - a).cross(&(c - a))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::Elastic;

    const P: [[f64; 3]; 4] = [
        [0.1, 0.0, -0.2],
        [1.3, 0.2, 0.1],
        [0.2, 1.1, 0.0],
        [0.3, 0.4, 1.2],
    ];

    #[test]
    fn six_rigid_modes_in_null_space() {
        let k = stiffness(&P, &Elastic::new("m", 1.0, 0.45).unwrap().solid());
        for mode in 0..6 {
            let u = Dofs::from_fn(|r, _| {
                let x = Vector3::from(P[r / 3]);
                let comp = r % 3;
                if mode < 3 {
                    f64::from(u8::from(comp == mode))
                } else {
                    let mut w = Vector3::zeros();
                    w[mode - 3] = 1.0;
                    w.cross(&x)[comp]
                }
            });
            assert!((k * u).norm() < 1e-12 * k.norm(), "mode {mode}");
        }
    }

    #[test]
    fn volume_and_mass_agree() {
        let v = signed_volume(&P);
        assert!(v > 0.0);
        let m = mass_consistent(&P, 2.0);
        let ux = Dofs::from_fn(|r, _| f64::from(u8::from(r % 3 == 0)));
        assert!(((ux.transpose() * m * ux)[0] - 2.0 * v).abs() < 1e-12);
    }

    #[test]
    fn linear_field_gives_exact_strain() {
        let g = Matrix3::new(0.01, 0.02, -0.01, 0.0, 0.03, 0.005, 0.004, -0.02, 0.02);
        let u = Dofs::from_fn(|r, _| (g * Vector3::from(P[r / 3]))[r % 3]);
        let e = strain(&P, &u);
        let expect = Vector6::new(
            g[(0, 0)],
            g[(1, 1)],
            g[(2, 2)],
            g[(0, 1)] + g[(1, 0)],
            g[(1, 2)] + g[(2, 1)],
            g[(2, 0)] + g[(0, 2)],
        );
        assert!((e - expect).norm() < 1e-14);
    }
}
