//! The mixed formulation of the 6-node plane-strain triangle ([`super::tri6`]), in which
//! it does not lock as ν → 0.5, beside its displacement formulation ([`Formulation`]).
//!
//! - **small strain** ([`stiffness_mixed`]): mixed P2/P0, an element-wise constant
//!   pressure condensed at element level. With the split D = D_dev + κ m mᵀ (κ = λ + 2μ/3
//!   the bulk modulus, m = (1, 1, 0), D_dev the deviatoric part of the 3D law restricted to
//!   ε_zz = 0), the volumetric term sees only the element's mean volumetric strain
//!   θ̄ = g·u / A with g = ∫ Bᵀ m dA: K = ∫ Bᵀ D_dev B dA + (κ / A) g gᵀ, and the pressure
//!   is p = κ θ̄. This is the Herrmann-type u–p element with discontinuous constant pressure
//!   (mean dilatation, Nagtegaal, Parks & Rice 1974): one volumetric constraint per element
//!   instead of one per quadrature point, so it does not lock, and K stays symmetric
//!   positive definite — the factorization and the integrators are unchanged.
//! - **finite strain** ([`internal_mixed`]): the three-field Hu–Washizu principle of Simo,
//!   Taylor & Pister (CMAME 51 (1985) 177–208) with an element-wise constant dilatation θ
//!   and pressure, which eliminate to θ̄ = (1/V) ∫ J dV, the element's mean volume ratio,
//!   and the modified deformation gradient F̄ = (θ̄ / J)^{1/3} F (det F̄ = θ̄) in any law's
//!   energy: Π_e = ∫ W(F̄) dV. For the linear law at small strain it is the mean
//!   dilatation above; it is a potential of u, so the tangent is symmetric, and a
//!   homogeneous deformation (θ̄ = J) is the displacement formulation's.

use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

use super::quadrature::TRI_3;
use super::total_lagrangian::{self, deformation, Inverted, Shape};
use super::tri6::{self, Dofs, Tri6};
use super::{Elastic, Material};

/// How the 6-node triangle treats the volumetric strain (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Formulation {
    /// ∫ Bᵀ D B dA: locks mildly as ν → 0.5.
    Displacement,
    /// An element-wise constant pressure condensed at element level: no locking.
    Mixed,
}

/// The stiffness in `formulation`.
pub fn stiffness_in(
    formulation: Formulation,
    p: &[[f64; 2]; 6],
    elastic: &Elastic,
) -> SMatrix<f64, 12, 12> {
    match formulation {
        Formulation::Displacement => tri6::stiffness(p, &elastic.plane_strain()),
        Formulation::Mixed => stiffness_mixed(p, elastic),
    }
}

/// The internal force and tangent of `formulation` at finite strain: [`internal`] or
/// [`internal_mixed`].
pub fn internal_in(
    formulation: Formulation,
    p: &[[f64; 2]; 6],
    u: &Dofs,
    material: &Material,
    force: &mut Dofs,
    tangent: Option<&mut SMatrix<f64, 12, 12>>,
) -> Result<(), Inverted> {
    match formulation {
        Formulation::Displacement => {
            total_lagrangian::internal::<Tri6, 6, 2, 12>(p, u, material, force, tangent)
        }
        Formulation::Mixed => internal_mixed(p, u, material, force, tangent),
    }
}

/// The deviatoric part of the plane-strain law, 2μ (I − ⅓ m mᵀ) on the normal strains and μ
/// on the shear strain, and the bulk modulus κ = λ + 2μ/3: D = D_dev + κ m mᵀ.
pub fn split(elastic: &Elastic) -> (Matrix3<f64>, f64) {
    let mu = elastic.shear();
    let (a, b) = (4.0 * mu / 3.0, -2.0 * mu / 3.0);
    let dev = Matrix3::new(a, b, 0.0, b, a, 0.0, 0.0, 0.0, mu);
    (dev, elastic.lambda() + 2.0 * mu / 3.0)
}

/// g = ∫ Bᵀ m dA, the element's volume change per nodal displacement: θ̄ = g·u / A.
pub fn dilatation(p: &[[f64; 2]; 6]) -> (Dofs, f64) {
    let m = Vector3::new(1.0, 1.0, 0.0);
    TRI_3.iter().fold((Dofs::zeros(), 0.0), |(g, a), &(l, w)| {
        let (b, det) = tri6::b_matrix(p, l);
        (g + b.transpose() * m * (0.5 * w * det), a + 0.5 * w * det)
    })
}

/// Mixed P2/P0 stiffness ∫ Bᵀ D_dev B dA + (κ / A) g gᵀ (see the module documentation).
pub fn stiffness_mixed(p: &[[f64; 2]; 6], elastic: &Elastic) -> SMatrix<f64, 12, 12> {
    let (dev, kappa) = split(elastic);
    let (g, a) = dilatation(p);
    tri6::stiffness(p, &dev) + g * g.transpose() * (kappa / a)
}

/// The mixed formulation at finite strain (see the module documentation): Π_e(u) =
/// ∫ W(F̄) dV with F̄ = α F, α = (θ̄/J)^{1/3}, θ̄ = (1/V) ∫ J dV, 3-point rule. With G the
/// map from the element's dofs to the components of F at a point (row 3i + J, in-plane
/// only), v = vec F⁻ᵀ, g = ∫ J Gᵀv dV (so δθ̄ = g·δu / V) and
/// β = ⅓ (g / (V θ̄) − Gᵀv) (so δα = α β·δu), the force and tangent are
///
/// f = ∫ α (Gᵀ vec P̄ + (P̄ : F) β) dV,
/// K = ∫ [𝒥ᵀ A(F̄) 𝒥 + α (P̄ : F)(β βᵀ + ∂β) + α (β rᵀ + r βᵀ)] dV,
///
/// with P̄ = P(F̄), A = ∂P/∂F at F̄, 𝒥 = α (G + vec F βᵀ) = ∂F̄/∂u, r = Gᵀ vec P̄,
/// ∂β = ⅓ (H / (V θ̄) − g gᵀ / (V θ̄)² − Gᵀ D G), H = ∫ J Gᵀ (v vᵀ + D) G dV and
/// D = ∂F⁻ᵀ/∂F (D_iJ,kL = −F⁻¹_Jk F⁻¹_Li). F̄ has F̄_zz = α ≠ 1: the out-of-plane
/// stretch takes the element's volume constraint with the in-plane ones. A finite-strain law
/// refuses J ≤ 0 at a point.
pub fn internal_mixed(
    p: &[[f64; 2]; 6],
    u: &Dofs,
    material: &Material,
    force: &mut Dofs,
    mut tangent: Option<&mut SMatrix<f64, 12, 12>>,
) -> Result<(), Inverted> {
    let points = mixed_points(p, u)?;
    let (volume, theta) = mean_volume_ratio(&points);
    let vt = volume * theta;
    let g = points.iter().fold(Dofs::zeros(), |g, q| {
        g + q.g.transpose() * q.inverse_t * (q.j * q.dv)
    });
    let h = tangent.as_ref().map(|_| {
        points.iter().fold(SMatrix::<f64, 12, 12>::zeros(), |h, q| {
            let vv = q.inverse_t * q.inverse_t.transpose() + q.d;
            h + q.g.transpose() * vv * q.g * (q.j * q.dv)
        })
    });
    for q in &points {
        let alpha = (theta / q.j).cbrt();
        let f_bar = q.f * alpha;
        let p_bar = material.stress(&f_bar);
        let pf = p_bar.dot(&q.f);
        let beta = (g / vt - q.g.transpose() * q.inverse_t) / 3.0;
        let r = q.g.transpose() * vec9(&p_bar);
        *force += (r + beta * pf) * (alpha * q.dv);
        let (Some(k), Some(h)) = (tangent.as_deref_mut(), &h) else {
            continue;
        };
        let jac = (q.g + vec9(&q.f) * beta.transpose()) * alpha;
        let d_beta = (h / vt - g * g.transpose() / (vt * vt) - q.g.transpose() * q.d * q.g) / 3.0;
        let outer = beta * r.transpose();
        *k += (jac.transpose() * material.tangent(&f_bar) * jac
            + (beta * beta.transpose() + d_beta) * (alpha * pf)
            + (outer + outer.transpose()) * alpha)
            * q.dv;
    }
    Ok(())
}

/// What the mixed kernel needs at a quadrature point: the map G from the element's dofs to
/// the components of F (row 3i + J), F, J, vec F⁻ᵀ, D = ∂F⁻ᵀ/∂F and the weight times the
/// area.
pub(super) struct MixedPoint {
    g: SMatrix<f64, 9, 12>,
    f: Matrix3<f64>,
    j: f64,
    inverse_t: SVector<f64, 9>,
    d: SMatrix<f64, 9, 9>,
    dv: f64,
}

/// The quadrature points of the mixed kernel; a point with J ≤ 0 is an error.
pub(super) fn mixed_points(p: &[[f64; 2]; 6], u: &Dofs) -> Result<[MixedPoint; 3], Inverted> {
    let points = TRI_3.map(|(l, w)| {
        let (grads, measure) = Tri6::gradients(p, &l);
        let f = deformation(u, &grads);
        let mut g = SMatrix::<f64, 9, 12>::zeros();
        for a in 0..6 {
            for i in 0..2 {
                for jj in 0..2 {
                    g[(3 * i + jj, 2 * a + i)] = grads[(a, jj)];
                }
            }
        }
        let inv = f.try_inverse().unwrap_or_else(Matrix3::zeros);
        let mut d = SMatrix::<f64, 9, 9>::zeros();
        for i in 0..3 {
            for jj in 0..3 {
                for k in 0..3 {
                    for ll in 0..3 {
                        d[(3 * i + jj, 3 * k + ll)] = -inv[(jj, k)] * inv[(ll, i)];
                    }
                }
            }
        }
        MixedPoint {
            g,
            j: f.determinant(),
            inverse_t: vec9(&inv.transpose()),
            f,
            d,
            dv: w * measure,
        }
    });
    for q in &points {
        Inverted::check(q.j)?;
    }
    Ok(points)
}

/// The element's reference area V and mean volume ratio θ̄ = (1/V) ∫ J dV.
pub(super) fn mean_volume_ratio(points: &[MixedPoint; 3]) -> (f64, f64) {
    let volume: f64 = points.iter().map(|q| q.dv).sum();
    (
        volume,
        points.iter().map(|q| q.j * q.dv).sum::<f64>() / volume,
    )
}

/// The components of a 3 × 3 tensor in the order of the tangent's rows: entry 3i + J holds
/// M_iJ.
fn vec9(m: &Matrix3<f64>) -> SVector<f64, 9> {
    SVector::from_fn(|r, _| m[(r / 3, r % 3)])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::tri6::{stiffness, straight};

    fn element() -> [[f64; 2]; 6] {
        straight(&[[0.3, 0.1], [2.1, 0.4], [0.9, 1.7]])
    }

    #[test]
    fn the_split_law_adds_up_to_the_plane_strain_law() {
        let elastic = Elastic::new("m", 7.0, 0.3).unwrap();
        let (dev, kappa) = split(&elastic);
        let m = Vector3::new(1.0, 1.0, 0.0);
        let d = dev + m * m.transpose() * kappa;
        assert!((d - elastic.plane_strain()).amax() < 1e-13 * d.amax());
        // For a straight-sided element at moderate ν the two formulations differ only in
        // how the volumetric strain is averaged: equal on a constant-strain motion.
        let p = element();
        let u = Dofs::from_fn(|k, _| {
            let [x, y] = p[k / 2];
            if k.is_multiple_of(2) {
                0.01 * x + 0.003 * y
            } else {
                -0.002 * y
            }
        });
        let (k1, k2) = (stiffness(&p, &d), stiffness_mixed(&p, &elastic));
        assert!((k1 * u - k2 * u).amax() < 1e-13 * (k1 * u).amax());
    }

    #[test]
    fn the_finite_strain_kernel_gives_the_linear_stiffness_and_its_own_tangent() {
        use crate::element::material::Law;
        let p = element();
        let elastic = Elastic::new("m", 0.05, 0.43).unwrap();
        let u = Dofs::from_fn(|r, _| 0.2 * (((r * 7919 + 13) % 97) as f64 / 97.0 - 0.5));
        // Linear law: f = K u with K the displacement formulation's stiffness.
        let (mut f, mut k) = (Dofs::zeros(), SMatrix::<f64, 12, 12>::zeros());
        total_lagrangian::internal::<Tri6, 6, 2, 12>(
            &p,
            &u,
            &Material::new(Law::Linear, elastic),
            &mut f,
            Some(&mut k),
        )
        .unwrap();
        let k_lin = stiffness(&p, &elastic.plane_strain());
        assert!((k - k_lin).amax() < 1e-14 * k_lin.amax());
        assert!((f - k_lin * u).amax() < 1e-14 * f.amax());
        // Finite laws: the tangent against central differences of the force.
        for law in [Law::NeoHookean, Law::StVenantKirchhoff] {
            check_tangent(
                Formulation::Displacement,
                &p,
                &u,
                &Material::new(law, elastic),
            );
        }
    }

    /// The tangent of `formulation`'s kernel at `u` against central differences of its force
    /// (to 1e-6 of the tangent's largest entry), and symmetric.
    fn check_tangent(formulation: Formulation, p: &[[f64; 2]; 6], u: &Dofs, m: &Material) {
        let (mut f, mut k) = (Dofs::zeros(), SMatrix::<f64, 12, 12>::zeros());
        internal_in(formulation, p, u, m, &mut f, Some(&mut k)).unwrap();
        assert!((k - k.transpose()).amax() < 1e-10 * k.amax(), "symmetric");
        let h = 1e-6;
        for c in 0..12 {
            let (mut up, mut um) = (*u, *u);
            up[c] += h;
            um[c] -= h;
            let (mut fp, mut fm) = (Dofs::zeros(), Dofs::zeros());
            internal_in(formulation, p, &up, m, &mut fp, None).unwrap();
            internal_in(formulation, p, &um, m, &mut fm, None).unwrap();
            let gap = ((fp - fm) / (2.0 * h) - k.column(c)).amax() / k.amax();
            let nu = m.elastic.poisson();
            assert!(
                gap < 1e-6,
                "{formulation:?} {:?} ν = {nu}, {c}: {gap:e}",
                m.law
            );
        }
    }

    /// The mixed kernel: at rest its tangent is the small-strain mixed stiffness (the mean
    /// dilatation) for every law; its tangent is the derivative of its force; a homogeneous
    /// deformation gives the displacement kernel's force.
    #[test]
    fn the_mixed_finite_strain_kernel_is_the_mean_dilatation_and_its_own_tangent() {
        use crate::element::material::Law;
        let p = element();
        let elastic = Elastic::new("m", 0.05, 0.4999).unwrap();
        let k_mixed = stiffness_mixed(&p, &elastic);
        for law in Law::ALL {
            let m = Material::new(law, elastic);
            let (mut f, mut k) = (Dofs::zeros(), SMatrix::<f64, 12, 12>::zeros());
            internal_mixed(&p, &Dofs::zeros(), &m, &mut f, Some(&mut k)).unwrap();
            assert!((k - k_mixed).amax() < 1e-12 * k_mixed.amax(), "{law:?}");
        }
        let u = Dofs::from_fn(|r, _| 0.2 * (((r * 7919 + 13) % 97) as f64 / 97.0 - 0.5));
        // ν = 0.3: the deviatoric and geometric parts weigh as much as the volumetric one.
        for (law, nu) in [Law::NeoHookean, Law::StVenantKirchhoff]
            .into_iter()
            .flat_map(|l| [(l, 0.3), (l, 0.4999)])
        {
            let m = Material::new(law, Elastic::new("m", 0.05, nu).unwrap());
            check_tangent(Formulation::Mixed, &p, &u, &m);
            // F = diag(1.3, 0.8) + shear: the same J at every point.
            let homogeneous = Dofs::from_fn(|r, _| {
                let [x, y] = p[r / 2];
                [0.3 * x + 0.1 * y, -0.2 * y][r % 2]
            });
            let (mut fd, mut fm) = (Dofs::zeros(), Dofs::zeros());
            total_lagrangian::internal::<Tri6, 6, 2, 12>(&p, &homogeneous, &m, &mut fd, None)
                .unwrap();
            internal_mixed(&p, &homogeneous, &m, &mut fm, None).unwrap();
            assert!((fd - fm).amax() < 1e-12 * fd.amax(), "{law:?} homogeneous");
        }
    }
}
