//! 3-node line (truss) element in 2D, the quadratic counterpart of [`super::line2`] on the
//! edges of 6-node triangles: axial stiffness only, nodes (end a, mid-edge m, end b) on a
//! straight edge with m at its midpoint. With the 1D quadratic shape functions on the axis
//! (ξ ∈ [−1, 1]; N_a = ξ(ξ − 1)/2, N_m = 1 − ξ², N_b = ξ(ξ + 1)/2) and the direction
//! cosines c, the exact integrals are (order a, m, b; Zienkiewicz & Taylor vol. 1, §3.3)
//!
//! K_e = E A / (3 L) · [[7, −8, 1], [−8, 16, −8], [1, −8, 7]] ⊗ c cᵀ,
//! M_e = ρ A L / 30 · [[4, 2, −1], [2, 16, 2], [−1, 2, 4]] ⊗ I₂.

use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector2};

use super::line2;

/// Element displacement vector (u_xa, u_ya, u_xm, u_ym, u_xb, u_yb).
pub type Dofs = SVector<f64, 6>;

/// A 3 × 3 nodal pattern expanded to the six dofs with the 2 × 2 `block`.
fn expand(nodal: &Matrix3<f64>, block: &Matrix2<f64>) -> SMatrix<f64, 6, 6> {
    let mut k = SMatrix::<f64, 6, 6>::zeros();
    for i in 0..3 {
        for j in 0..3 {
            k.fixed_view_mut::<2, 2>(2 * i, 2 * j)
                .copy_from(&(block * nodal[(i, j)]));
        }
    }
    k
}

/// Length and unit direction from end a to end b.
fn axis(p: &[[f64; 2]; 3]) -> (f64, Vector2<f64>) {
    line2::axis(&[p[0], p[2]])
}

/// Axial stiffness for Young's modulus `young` (MPa) and cross-section `area` (mm²).
pub fn stiffness(p: &[[f64; 2]; 3], young: f64, area: f64) -> SMatrix<f64, 6, 6> {
    let (len, c) = axis(p);
    let nodal = Matrix3::new(7.0, -8.0, 1.0, -8.0, 16.0, -8.0, 1.0, -8.0, 7.0);
    expand(
        &(nodal * (young * area / (3.0 * len))),
        &(c * c.transpose()),
    )
}

/// Consistent mass.
pub fn mass_consistent(p: &[[f64; 2]; 3], density: f64, area: f64) -> SMatrix<f64, 6, 6> {
    let nodal = Matrix3::new(4.0, 2.0, -1.0, 2.0, 16.0, 2.0, -1.0, 2.0, 4.0);
    let m = density * area * axis(p).0 / 30.0;
    expand(&(nodal * m), &Matrix2::identity())
}

/// Lumped mass: the HRZ rule (the consistent diagonal scaled to the element's mass), which
/// here is Simpson's 1/6, 2/3, 1/6 of ρAL.
pub fn mass_lumped(p: &[[f64; 2]; 3], density: f64, area: f64) -> Dofs {
    let m = density * area * axis(p).0;
    Dofs::from_fn(|i, _| m * [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0][i / 2])
}

/// Mean axial stress over the element, E (u_b − u_a)·c / L (the axial strain is linear
/// along the element; this is its value at the mid-edge node), MPa, positive in tension.
pub fn axial_stress(p: &[[f64; 2]; 3], young: f64, u: &Dofs) -> f64 {
    let (len, c) = axis(p);
    let du = Vector2::new(u[4] - u[0], u[5] - u[1]);
    young * du.dot(&c) / len
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A bar along 30° from (1, 2), length 3.
    fn bar() -> ([[f64; 2]; 3], Vector2<f64>) {
        let c = Vector2::new(30f64.to_radians().cos(), 30f64.to_radians().sin());
        let at = |s: f64| [1.0 + s * c.x, 2.0 + s * c.y];
        ([at(0.0), at(1.5), at(3.0)], c)
    }

    #[test]
    fn a_quadratic_axial_field_under_a_uniform_load_is_exact() {
        // Fixed at a, a uniform axial load q per length: u(s) = q (L s − s²/2) / (E A) along
        // the axis. The consistent load is (1/6, 2/3, 1/6) q L; with a fixed, solve for m, b.
        let (p, c) = bar();
        let (e, a, q, l) = (2.0, 0.5, 0.3, 3.0);
        let k = stiffness(&p, e, a);
        let f_axial = [2.0 / 3.0 * q * l, 1.0 / 6.0 * q * l];
        // Axial unknowns (m, b): project the 6 × 6 matrix onto the axis.
        let t =
            |i: usize| SVector::<f64, 6>::from_fn(|r, _| if r / 2 == i { c[r % 2] } else { 0.0 });
        let kk = nalgebra::Matrix2::from_fn(|i, j| (t(i + 1).transpose() * k * t(j + 1))[0]);
        let u = kk
            .lu()
            .solve(&Vector2::new(f_axial[0], f_axial[1]))
            .unwrap();
        let exact = |s: f64| q * (l * s - s * s / 2.0) / (e * a);
        assert!((u[0] - exact(1.5)).abs() < 1e-14 && (u[1] - exact(3.0)).abs() < 1e-14);
        // The mean stress is the stress at the midpoint, q (L − L/2)/A.
        let d = Dofs::from_fn(|r, _| [0.0, u[0], u[1]][r / 2] * c[r % 2]);
        assert!((axial_stress(&p, e, &d) - q * l / 2.0 / a).abs() < 1e-14);
    }

    #[test]
    fn rigid_motions_are_free_and_the_masses_sum_to_the_bar_mass() {
        let (p, _) = bar();
        let k = stiffness(&p, 2.0, 0.5);
        let rigid = Dofs::from_fn(|r, _| {
            let [x, y] = p[r / 2];
            if r % 2 == 0 {
                0.3 - 0.2 * y
            } else {
                -0.1 + 0.2 * x
            }
        });
        assert!((k * rigid).amax() < 1e-14);
        let m = mass_consistent(&p, 1.5, 0.5);
        let total = 1.5 * 0.5 * 3.0;
        assert!((m.sum() - 2.0 * total).abs() < 1e-13);
        assert!((mass_lumped(&p, 1.5, 0.5).sum() - 2.0 * total).abs() < 1e-13);
    }
}
