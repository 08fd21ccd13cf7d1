//! 3-node line (truss) element in 2D, the quadratic counterpart of [`super::line2`] on the
//! edges of 6-node triangles: axial stiffness only, nodes (end a, mid-edge m, end b); a
//! mid-edge node off the chord makes the element the parabola through the three (the
//! abdomen puts its boundary mid-edge nodes on the boundary curve). With the 1D quadratic
//! shape functions (ξ ∈ [−1, 1]; N_a = ξ(ξ − 1)/2, N_m = 1 − ξ², N_b = ξ(ξ + 1)/2), the
//! reference tangent t₀ = X'/|X'| and dS = |X'| dξ, the small-strain matrices are
//!
//! K_e = E A ∫ N_a,S N_b,S t₀ t₀ᵀ dS (the tangent at rest of [`membrane`]),
//! M_e = ρ A ∫ N_a N_b dS ⊗ I₂,
//!
//! by the three-point Gauss rule. On a straight element with m at the midpoint they are the
//! closed forms (Zienkiewicz & Taylor vol. 1, §3.3; tested)
//! K_e = E A / (3 L) · [[7, −8, 1], [−8, 16, −8], [1, −8, 7]] ⊗ c cᵀ and
//! M_e = ρ A L / 30 · [[4, 2, −1], [2, 16, 2], [−1, 2, 4]] ⊗ I₂.

use nalgebra::{SMatrix, SVector, Vector2};

use super::membrane::{Line, Section};
use super::quadrature::GAUSS_3;

/// Element displacement vector (u_xa, u_ya, u_xm, u_ym, u_xb, u_yb).
pub type Dofs = SVector<f64, 6>;

/// The shape functions at ξ.
fn shape(xi: f64) -> [f64; 3] {
    [0.5 * xi * (xi - 1.0), 1.0 - xi * xi, 0.5 * xi * (xi + 1.0)]
}

/// dN/dξ at ξ.
fn derivatives(xi: f64) -> [f64; 3] {
    [xi - 0.5, -2.0 * xi, xi + 0.5]
}

/// |X'(ξ)| and t₀ at ξ.
fn reference(p: &[[f64; 2]; 3], xi: f64) -> (f64, Vector2<f64>) {
    let d: Vector2<f64> = derivatives(xi)
        .iter()
        .zip(p)
        .map(|(d, x)| Vector2::from(*x) * *d)
        .sum();
    (d.norm(), d / d.norm())
}

/// The small-strain stiffness of a line of `section` (its active tension ignored): the
/// tangent at rest of [`membrane`] — axial, and the elastic foundation E A κ₂² of a
/// transverse curvature.
pub fn stiffness(p: &[[f64; 2]; 3], section: Section) -> SMatrix<f64, 6, 6> {
    let (mut f, mut k) = (Dofs::zeros(), SMatrix::zeros());
    let passive = Section {
        tension: 0.0,
        ..section
    };
    // At rest nothing can fold: the kernel cannot fail.
    let _ = membrane(p).internal(&Dofs::zeros(), passive, &mut f, Some(&mut k));
    k
}

/// Consistent mass.
pub fn mass_consistent(p: &[[f64; 2]; 3], density: f64, area: f64) -> SMatrix<f64, 6, 6> {
    let mut m = SMatrix::<f64, 6, 6>::zeros();
    for &(xi, w) in &GAUSS_3 {
        let n = shape(xi);
        let scale = density * area * w * reference(p, xi).0;
        for a in 0..3 {
            for b in 0..3 {
                for i in 0..2 {
                    m[(2 * a + i, 2 * b + i)] += scale * n[a] * n[b];
                }
            }
        }
    }
    m
}

/// Lumped mass: the HRZ rule (the consistent diagonal scaled to the element's mass ρ A L),
/// on a straight element Simpson's 1/6, 2/3, 1/6 of ρAL.
pub fn lumped_mass(p: &[[f64; 2]; 3], density: f64, area: f64) -> Dofs {
    let m = mass_consistent(p, density, area);
    let length: f64 = GAUSS_3.iter().map(|&(xi, w)| w * reference(p, xi).0).sum();
    let diagonal: f64 = (0..6).step_by(2).map(|i| m[(i, i)]).sum();
    let scale = density * area * length / diagonal;
    Dofs::from_fn(|i, _| m[(i, i)] * scale)
}

/// Mean axial stress over the element at small strain, (E / L) ∫ t₀ · du/dS dS (MPa,
/// positive in tension); on a straight element E (u_b − u_a)·c / L.
pub fn axial_stress(p: &[[f64; 2]; 3], young: f64, u: &Dofs) -> f64 {
    let (mut integral, mut length) = (0.0, 0.0);
    for &(xi, w) in &GAUSS_3 {
        let (j, t) = reference(p, xi);
        let du: Vector2<f64> = derivatives(xi)
            .iter()
            .enumerate()
            .map(|(a, d)| Vector2::new(u[2 * a], u[2 * a + 1]) * *d)
            .sum();
        integral += w * t.dot(&du);
        length += w * j;
    }
    young * integral / length
}

/// The element at finite strain ([`super::membrane`]): the quadratic shape functions above
/// (dN/dξ = ξ − ½, −2ξ, ξ + ½ for a, m, b) and the three-point Gauss rule.
pub fn membrane(p: &[[f64; 2]; 3]) -> Line<'_, 3, 3> {
    Line {
        nodes: p,
        shapes: shape,
        derivatives,
        rule: &GAUSS_3,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::membrane::Law;

    /// A passive section, flat across the slice.
    fn plain(young: f64, area: f64) -> Section {
        Section {
            law: Law::Hencky,
            young,
            area,
            tension: 0.0,
            transverse_curvature: 0.0,
        }
    }

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
        let k = stiffness(&p, plain(e, a));
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

    /// On a straight element the quadrature gives the closed forms of the module
    /// documentation.
    #[test]
    fn a_straight_element_has_the_closed_form_matrices() {
        use nalgebra::{Matrix2, Matrix3};
        let (p, c) = bar();
        let (e, a, rho, l) = (2.0, 0.5, 1.5, 3.0);
        let expand = |nodal: Matrix3<f64>, block: Matrix2<f64>| {
            SMatrix::<f64, 6, 6>::from_fn(|r, col| {
                nodal[(r / 2, col / 2)] * block[(r % 2, col % 2)]
            })
        };
        let k = expand(
            Matrix3::new(7.0, -8.0, 1.0, -8.0, 16.0, -8.0, 1.0, -8.0, 7.0) * (e * a / (3.0 * l)),
            c * c.transpose(),
        );
        let m = expand(
            Matrix3::new(4.0, 2.0, -1.0, 2.0, 16.0, 2.0, -1.0, 2.0, 4.0) * (rho * a * l / 30.0),
            Matrix2::identity(),
        );
        assert!((stiffness(&p, plain(e, a)) - k).amax() < 1e-14 * k.amax());
        assert!((mass_consistent(&p, rho, a) - m).amax() < 1e-14 * m.amax());
    }

    /// A curved element: rigid motions stay free, and a uniform stretch about the centre of
    /// its arc (u = ε (x − centre)) gives the mean axial stress E ε.
    #[test]
    fn a_curved_element_stretches_and_moves_rigidly_as_its_arc() {
        let (r, centre) = (5.0, [1.0, -2.0]);
        let p = [-0.4, 0.1, 0.6].map(|a: f64| [centre[0] + r * a.cos(), centre[1] + r * a.sin()]);
        let k = stiffness(&p, plain(2.0, 0.5));
        let rigid = Dofs::from_fn(|row, _| {
            let [x, y] = p[row / 2];
            if row % 2 == 0 {
                0.3 - 0.2 * y
            } else {
                -0.1 + 0.2 * x
            }
        });
        assert!((k * rigid).amax() < 1e-14 * k.amax());
        let eps = 1e-3;
        let stretch = Dofs::from_fn(|row, _| eps * (p[row / 2][row % 2] - centre[row % 2]));
        // The parabola through three points of the arc is not the arc: 1e-4 of it.
        assert!((axial_stress(&p, 2.0, &stretch) / (2.0 * eps) - 1.0).abs() < 1e-4);
    }

    #[test]
    fn rigid_motions_are_free_and_the_masses_sum_to_the_bar_mass() {
        let (p, _) = bar();
        let k = stiffness(&p, plain(2.0, 0.5));
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
        assert!((lumped_mass(&p, 1.5, 0.5).sum() - 2.0 * total).abs() < 1e-13);
    }
}
