//! Isotropic elastic materials. [`Elastic`] holds E and ν (checked) and gives the linear
//! constitutive matrices (seed 003 App. A.3, eq. C.15 and C.29). [`Material`] adds a law —
//! linear, compressible neo-Hookean or St. Venant–Kirchhoff — and gives the first
//! Piola–Kirchhoff stress P(F) and its derivative ∂P/∂F for a deformation gradient F, which
//! is all the total Lagrangian element kernel needs. All three laws take μ and λ from E and
//! ν by the small-strain relations, so one (E, ν) is the same material in every law: they
//! agree to first order at F = I.

use nalgebra::{Matrix3, Matrix6, SMatrix};

use crate::error::{positive, ModelError};

/// ∂P/∂F as a 9 × 9 matrix: row 3i + J, column 3k + L holds ∂P_iJ/∂F_kL.
pub type Tangent = SMatrix<f64, 9, 9>;

/// An isotropic linear-elastic material: Young's modulus `E` (MPa = N/mm²) and Poisson's
/// ratio `ν`. Construction validates `E > 0` and `−1 < ν < 0.5`, both finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    young: f64,
    poisson: f64,
}

impl Elastic {
    /// Validated constructor; `name` prefixes the variable names in the error message
    /// (e.g. `"cavity"` gives `cavity.E`).
    pub fn new(name: &str, young: f64, poisson: f64) -> Result<Self, ModelError> {
        positive(&format!("{name}.E"), young)?;
        if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
            return Err(ModelError::InvalidParameter {
                name: format!("{name}.nu"),
                value: poisson,
                reason: "Poisson's ratio must be finite and in (-1, 0.5)",
            });
        }
        Ok(Self { young, poisson })
    }

    /// Young's modulus E in MPa.
    pub fn young(&self) -> f64 {
        self.young
    }

    /// Poisson's ratio ν.
    pub fn poisson(&self) -> f64 {
        self.poisson
    }

    /// Lamé's first parameter λ = Eν / ((1+ν)(1−2ν)).
    pub fn lambda(&self) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// Shear modulus μ = E / (2(1+ν)).
    pub fn shear(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// Plane-strain constitutive matrix for (ε_xx, ε_yy, γ_xy) (seed 003 eq. C.15).
    pub fn plane_strain(&self) -> Matrix3<f64> {
        let (l, m) = (self.lambda(), self.shear());
        Matrix3::new(l + 2.0 * m, l, 0.0, l, l + 2.0 * m, 0.0, 0.0, 0.0, m)
    }

    /// 3D constitutive matrix for (ε_xx, ε_yy, ε_zz, γ_xy, γ_yz, γ_zx) (seed 003 eq. C.29).
    pub fn solid(&self) -> Matrix6<f64> {
        let (l, m) = (self.lambda(), self.shear());
        let mut d = Matrix6::zeros();
        for i in 0..3 {
            for j in 0..3 {
                d[(i, j)] = l;
            }
            d[(i, i)] = l + 2.0 * m;
            d[(i + 3, i + 3)] = m;
        }
        d
    }
}

/// A material law (the scene parameter `material`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Law {
    /// Small strain: ε = sym(F − I), P = σ = λ tr(ε) I + 2μ ε (seed 003 App. A.3). Not
    /// rotation invariant; valid for small strains and rotations.
    Linear,
    /// Compressible neo-Hookean: W = μ/2 (tr(FᵀF) − 3) − μ ln J + λ/2 (ln J)²,
    /// P = μ F + (λ ln J − μ) F⁻ᵀ. Defined for J = det F > 0 only; W → ∞ as J → 0.
    NeoHookean,
    /// St. Venant–Kirchhoff (seed 003 App. A.1, eq. A.3): Hooke's law on the Green strain
    /// E = ½ (FᵀF − I): S = λ tr(E) I + 2μ E, P = F S. Rotation invariant, but soft in
    /// compression (no barrier at J → 0: a strongly compressed element can invert).
    StVenantKirchhoff,
}

impl Law {
    /// Every law ([`parse`](Self::parse) searches them).
    pub const ALL: [Self; 3] = [Self::Linear, Self::NeoHookean, Self::StVenantKirchhoff];

    /// The name used by the scenes' `material` parameter.
    pub fn name(self) -> &'static str {
        match self {
            Self::Linear => "linear",
            Self::NeoHookean => "neo-hookean",
            Self::StVenantKirchhoff => "stvk",
        }
    }

    /// Parses a name as given by [`name`](Self::name).
    pub fn parse(name: &str) -> Result<Self, ModelError> {
        Self::ALL
            .into_iter()
            .find(|l| l.name() == name)
            .ok_or_else(|| ModelError::UnknownChoice {
                what: "material",
                value: name.to_string(),
                choices: "linear, neo-hookean or stvk",
            })
    }

    /// Whether the law is geometrically nonlinear (finite strain, total Lagrangian).
    pub fn finite(self) -> bool {
        self != Self::Linear
    }
}

/// A law with its Lamé parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// The material law.
    pub law: Law,
    /// The elastic constants, from which the Lamé parameters λ and μ follow.
    pub elastic: Elastic,
    lambda: f64,
    mu: f64,
}

impl Material {
    /// The law `law` with the Lamé parameters of `elastic`.
    pub fn new(law: Law, elastic: Elastic) -> Self {
        Self {
            law,
            elastic,
            lambda: elastic.lambda(),
            mu: elastic.shear(),
        }
    }

    /// The derivative of this material in Poisson's ratio at fixed E: the same law with the
    /// Lamé parameters' derivatives, ∂λ/∂ν = E (1 + 2ν²) / ((1 + ν)² (1 − 2ν)²) and
    /// ∂μ/∂ν = −E / (2 (1 + ν)²). Every law's stress is linear in λ and μ, so this
    /// material's [`stress`](Self::stress) is ∂P/∂ν at fixed F, and the internal forces an
    /// element kernel computes with it are ∂f_int/∂ν at fixed displacements (what the
    /// direct differentiation of an equilibrium in ν needs: `Newton::sensitivity`).
    /// `elastic` stays the material's own; only the stress and tangent use the derivatives.
    pub fn poisson_derivative(&self) -> Self {
        let (e, nu) = (self.elastic.young(), self.elastic.poisson());
        Self {
            lambda: e * (1.0 + 2.0 * nu * nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)).powi(2),
            mu: -e / (2.0 * (1.0 + nu).powi(2)),
            ..*self
        }
    }

    /// First Piola–Kirchhoff stress P(F) (MPa). For the neo-Hookean law, F must have
    /// det F > 0 (the kernel checks before calling).
    pub fn stress(&self, f: &Matrix3<f64>) -> Matrix3<f64> {
        let (l, m) = (self.lambda, self.mu);
        let id = Matrix3::identity();
        match self.law {
            Law::Linear => {
                let eps = 0.5 * (f + f.transpose()) - id;
                id * (l * eps.trace()) + eps * (2.0 * m)
            }
            Law::NeoHookean => {
                let f_inv_t = inverse(f).transpose();
                f * m + f_inv_t * (l * f.determinant().ln() - m)
            }
            Law::StVenantKirchhoff => {
                let e = 0.5 * (f.transpose() * f - id);
                f * (id * (l * e.trace()) + e * (2.0 * m))
            }
        }
    }

    /// ∂P/∂F (see [`Tangent`] for the layout), for the same F as [`stress`](Self::stress).
    pub fn tangent(&self, f: &Matrix3<f64>) -> Tangent {
        let (l, m) = (self.lambda, self.mu);
        let d = |a: usize, b: usize| f64::from(u8::from(a == b));
        let mut t = Tangent::zeros();
        match self.law {
            Law::Linear => fill(&mut t, |i, jj, k, ll| {
                l * d(i, jj) * d(k, ll) + m * (d(i, k) * d(jj, ll) + d(i, ll) * d(jj, k))
            }),
            Law::NeoHookean => {
                // A = μ δ_ik δ_JL + λ F⁻ᵀ_iJ F⁻ᵀ_kL − (λ ln J − μ) F⁻¹_Li F⁻¹_Jk
                let inv = inverse(f);
                let c = l * f.determinant().ln() - m;
                fill(&mut t, |i, jj, k, ll| {
                    m * d(i, k) * d(jj, ll) + l * inv[(jj, i)] * inv[(ll, k)]
                        - c * inv[(ll, i)] * inv[(jj, k)]
                });
            }
            Law::StVenantKirchhoff => {
                // A = δ_ik S_LJ + λ F_iJ F_kL + μ (F_iL F_kJ + (F Fᵀ)_ik δ_JL)
                let id = Matrix3::identity();
                let e = 0.5 * (f.transpose() * f - id);
                let s = id * (l * e.trace()) + e * (2.0 * m);
                let f_ft = f * f.transpose();
                fill(&mut t, |i, jj, k, ll| {
                    d(i, k) * s[(ll, jj)]
                        + l * f[(i, jj)] * f[(k, ll)]
                        + m * (f[(i, ll)] * f[(k, jj)] + f_ft[(i, k)] * d(jj, ll))
                });
            }
        }
        t
    }

    /// Strain energy density W(F) (mJ/mm³ = MPa); +∞ for the neo-Hookean law at J ≤ 0.
    pub fn energy(&self, f: &Matrix3<f64>) -> f64 {
        let (l, m) = (self.lambda, self.mu);
        let id = Matrix3::identity();
        match self.law {
            Law::Linear => {
                let eps = 0.5 * (f + f.transpose()) - id;
                0.5 * l * eps.trace().powi(2) + m * eps.norm_squared()
            }
            Law::NeoHookean => {
                let j = f.determinant();
                if j <= 0.0 {
                    return f64::INFINITY;
                }
                let ln_j = j.ln();
                0.5 * m * ((f.transpose() * f).trace() - 3.0) - m * ln_j + 0.5 * l * ln_j * ln_j
            }
            Law::StVenantKirchhoff => {
                let e = 0.5 * (f.transpose() * f - id);
                0.5 * l * e.trace().powi(2) + m * e.norm_squared()
            }
        }
    }
}

/// F⁻¹ of a deformation gradient the caller has checked to be invertible (zeros otherwise).
fn inverse(f: &Matrix3<f64>) -> Matrix3<f64> {
    f.try_inverse().unwrap_or_else(Matrix3::zeros)
}

/// t[(3i + J, 3k + L)] = a(i, J, k, L).
fn fill(t: &mut Tangent, a: impl Fn(usize, usize, usize, usize) -> f64) {
    for i in 0..3 {
        for jj in 0..3 {
            for k in 0..3 {
                for ll in 0..3 {
                    t[(3 * i + jj, 3 * k + ll)] = a(i, jj, k, ll);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deformation gradient with stretch, shear and rotation (det > 0).
    fn some_f() -> Matrix3<f64> {
        Matrix3::new(1.12, 0.07, -0.04, -0.05, 0.93, 0.08, 0.03, -0.06, 1.21)
    }

    fn materials() -> Vec<Material> {
        let e = Elastic::new("m", 0.05, 0.43).unwrap();
        Law::ALL.iter().map(|&l| Material::new(l, e)).collect()
    }

    /// The tangent against central differences of the stress, and the stress against
    /// central differences of the energy.
    #[test]
    fn tangent_and_stress_are_the_derivatives_of_stress_and_energy() {
        let f = some_f();
        let h = 1e-6;
        for m in materials() {
            let t = m.tangent(&f);
            let p = m.stress(&f);
            for k in 0..3 {
                for ll in 0..3 {
                    let mut fp = f;
                    let mut fm = f;
                    fp[(k, ll)] += h;
                    fm[(k, ll)] -= h;
                    let dp = (m.stress(&fp) - m.stress(&fm)) / (2.0 * h);
                    for i in 0..3 {
                        for jj in 0..3 {
                            let (fd, an) = (dp[(i, jj)], t[(3 * i + jj, 3 * k + ll)]);
                            assert!(
                                (fd - an).abs() <= 1e-6 * t.amax(),
                                "{:?} {i}{jj}{k}{ll}: {fd} vs {an}",
                                m.law
                            );
                        }
                    }
                    let dw = (m.energy(&fp) - m.energy(&fm)) / (2.0 * h);
                    assert!(
                        (dw - p[(k, ll)]).abs() <= 1e-6 * p.amax(),
                        "{:?} dW/dF_{k}{ll}",
                        m.law
                    );
                }
            }
        }
    }

    /// At F = I all laws have the linear tangent (one E, ν: one material); under a rigid
    /// rotation the finite-strain laws give zero stress and the linear law does not.
    /// The derivative material's stress is the central difference of the stress in ν (at
    /// fixed E and F) for every law, near incompressibility too.
    #[test]
    fn poisson_derivative_is_the_derivative_of_the_stress_in_nu() {
        let f = some_f();
        for law in Law::ALL {
            for nu in [0.3, 0.45, 0.499] {
                let at = |nu: f64| Material::new(law, Elastic::new("m", 0.04, nu).unwrap());
                let h = 1e-6;
                let difference = (at(nu + h).stress(&f) - at(nu - h).stress(&f)) / (2.0 * h);
                let derivative = at(nu).poisson_derivative().stress(&f);
                let error = (derivative - difference).norm() / difference.norm();
                assert!(error < 1e-6, "{law:?} ν = {nu}: {error:e}");
            }
        }
    }

    #[test]
    fn laws_agree_at_small_strain_and_finite_ones_are_rotation_invariant() {
        let ms = materials();
        let id = Matrix3::identity();
        let linear = ms[0].tangent(&id);
        for m in &ms {
            assert!(
                (m.tangent(&id) - linear).amax() < 1e-14 * linear.amax(),
                "{:?}",
                m.law
            );
            assert!(m.stress(&id).amax() < 1e-16);
        }
        let r = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 0.7).into_inner();
        for m in &ms {
            let p = m.stress(&r).amax();
            if m.law.finite() {
                assert!(p < 1e-15, "{:?}: {p}", m.law);
            } else {
                assert!(p > 1e-3 * m.elastic.young(), "{:?}: {p}", m.law);
            }
        }
    }

    #[test]
    fn names_round_trip_and_unknown_laws_are_named() {
        for l in Law::ALL {
            assert_eq!(Law::parse(l.name()).unwrap(), l);
        }
        let e = Law::parse("mooney").unwrap_err().to_string();
        assert!(e.contains("mooney") && e.contains("neo-hookean"), "{e}");
    }

    #[test]
    fn rejects_bad_values_and_names_them() {
        for (e, nu, var) in [
            (0.0, 0.3, "wall.E"),
            (-1.0, 0.3, "wall.E"),
            (f64::NAN, 0.3, "wall.E"),
            (1.0, 0.5, "wall.nu"),
            (1.0, -1.0, "wall.nu"),
            (1.0, f64::INFINITY, "wall.nu"),
        ] {
            let err = Elastic::new("wall", e, nu).unwrap_err().to_string();
            assert!(err.contains(var), "{err}");
        }
        assert!(Elastic::new("wall", 1.0, 0.499).is_ok());
    }

    #[test]
    fn plane_strain_matches_textbook_form() {
        // D = E/((1+ν)(1−2ν)) [[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, (1−2ν)/2]]
        let m = Elastic::new("m", 210.0, 0.3).unwrap();
        let f = 210.0 / (1.3 * 0.4);
        let d = m.plane_strain();
        assert!((d[(0, 0)] - f * 0.7).abs() < 1e-12);
        assert!((d[(0, 1)] - f * 0.3).abs() < 1e-12);
        assert!((d[(2, 2)] - f * 0.2).abs() < 1e-12);
    }
}
