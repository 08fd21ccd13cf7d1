//! Plane-strain 3-node triangle (constant-strain triangle; seed 003 App. C.2).
//!
//! Thickness is 1 mm (plane strain: quantities per millimetre out of plane) unless a caller
//! scales the result. Shape functions N_i = (a_i + b_i x + c_i y)/(2A) with
//! b_i = y_j − y_k, c_i = x_k − x_j for the cyclic permutation (i, j, k).

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Element displacement vector (u_x1, u_y1, u_x2, u_y2, u_x3, u_y3).
pub type Dofs = SVector<f64, 6>;
/// Strain–displacement matrix for (ε_xx, ε_yy, γ_xy).
pub type BMatrix = SMatrix<f64, 3, 6>;

/// Signed area; positive for counter-clockwise node order.
pub fn signed_area(p: &[[f64; 2]; 3]) -> f64 {
    0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]))
}

/// Strain–displacement matrix B (seed 003 eq. C.17 mapped to nodal values) and the area.
pub fn b_matrix(p: &[[f64; 2]; 3]) -> (BMatrix, f64) {
    let area = signed_area(p);
    let inv2a = 0.5 / area;
    let mut b = BMatrix::zeros();
    for i in 0..3 {
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let dndx = (p[j][1] - p[k][1]) * inv2a;
        let dndy = (p[k][0] - p[j][0]) * inv2a;
        b[(0, 2 * i)] = dndx;
        b[(1, 2 * i + 1)] = dndy;
        b[(2, 2 * i)] = dndy;
        b[(2, 2 * i + 1)] = dndx;
    }
    (b, area)
}

/// Stiffness K_e = A Bᵀ D B (unit thickness).
pub fn stiffness(p: &[[f64; 2]; 3], d: &Matrix3<f64>) -> SMatrix<f64, 6, 6> {
    let (b, area) = b_matrix(p);
    b.transpose() * d * b * area
}

/// Consistent mass ρA/12 · `[[2,1,1],[1,2,1],[1,1,2]]` ⊗ I₂ (unit thickness).
pub fn mass_consistent(p: &[[f64; 2]; 3], density: f64) -> SMatrix<f64, 6, 6> {
    let m = density * signed_area(p) / 12.0;
    let mut mass = SMatrix::<f64, 6, 6>::zeros();
    for i in 0..3 {
        for j in 0..3 {
            let v = if i == j { 2.0 * m } else { m };
            mass[(2 * i, 2 * j)] = v;
            mass[(2 * i + 1, 2 * j + 1)] = v;
        }
    }
    mass
}

/// Lumped (row-sum) mass: ρA/3 on each of the six dofs (unit thickness).
pub fn lumped_mass(p: &[[f64; 2]; 3], density: f64) -> SVector<f64, 6> {
    SVector::repeat(density * signed_area(p) / 3.0)
}

/// Constant strain (ε_xx, ε_yy, γ_xy) for element displacements `u`.
pub fn strain(p: &[[f64; 2]; 3], u: &Dofs) -> Vector3<f64> {
    b_matrix(p).0 * u
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::Elastic;

    const P: [[f64; 2]; 3] = [[0.3, -0.2], [2.1, 0.4], [0.7, 1.9]];

    #[test]
    fn rigid_modes_are_in_the_null_space() {
        let k = stiffness(&P, &Elastic::new("m", 3.0, 0.3).unwrap().plane_strain());
        let modes = [
            Dofs::from_fn(|r, _| if r % 2 == 0 { 1.0 } else { 0.0 }),
            Dofs::from_fn(|r, _| if r % 2 == 1 { 1.0 } else { 0.0 }),
            Dofs::from_fn(|r, _| {
                let n = r / 2;
                if r % 2 == 0 {
                    -P[n][1]
                } else {
                    P[n][0]
                }
            }),
        ];
        for m in modes {
            assert!((k * m).norm() < 1e-12 * k.norm());
        }
        assert!((k - k.transpose()).norm() < 1e-14 * k.norm());
    }

    #[test]
    fn mass_sums_to_element_mass() {
        let rho = 1.1e-9;
        let total = rho * signed_area(&P);
        let mc = mass_consistent(&P, rho);
        // Translational rigid motion in x: total inertia equals the element mass.
        let ux = Dofs::from_fn(|r, _| if r % 2 == 0 { 1.0 } else { 0.0 });
        assert!(((ux.transpose() * mc * ux)[0] - total).abs() < 1e-12 * total);
        assert!((lumped_mass(&P, rho).sum() - 2.0 * total).abs() < 1e-12 * total);
    }

    #[test]
    fn linear_field_gives_its_exact_strain() {
        // u = (a x + b y, c x + d y) ⇒ ε = (a, d, b + c)
        let (a, b, c, d) = (0.01, -0.02, 0.03, 0.005);
        let u = Dofs::from_fn(|r, _| {
            let [x, y] = P[r / 2];
            if r % 2 == 0 {
                a * x + b * y
            } else {
                c * x + d * y
            }
        });
        let e = strain(&P, &u);
        assert!((e - Vector3::new(a, d, b + c)).norm() < 1e-15);
    }
}
