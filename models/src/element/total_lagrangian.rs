//! The total Lagrangian kernel of the solid elements, in 2D (plane strain) and 3D: one
//! function serves every element shape × material law × quadrature (as fenris's local
//! elliptic assembler does).
//!
//! With X the reference and x = X + u the current positions, the deformation gradient at a
//! quadrature point is F = I + Σ_a u_a ⊗ ∇N_a (∇ with respect to X; in 2D the in-plane
//! block, F_zz = 1), the internal force of node a is f_a = Σ_q w_q V_q P(F_q) ∇N_a, and the
//! tangent is K_ab,ik = Σ_q w_q V_q Σ_JL ∇N_a,J (∂P_iJ/∂F_kL) ∇N_b,L over the element's
//! dimensions, with P the first Piola–Kirchhoff stress of the [`Material`] (a 3D law; plane
//! strain reads its in-plane part) and V_q the reference measure at the point (the volume,
//! or the area of unit thickness). For the linear law P depends on sym(F − I) only, so the
//! same kernel gives the small-strain stiffness K = ∫ Bᵀ D B and f = K u.
//!
//! A finite-strain law refuses a quadrature point with J = det F ≤ 0 (an inverted element):
//! the nonlinear solver cuts its load increment back.

use nalgebra::{Matrix3, SMatrix, SVector};

use super::material::Material;
use super::quadrature::{TetPoint, TET_1, TET_14};
use super::{tet10, tet4};

/// An element shape with N nodes in DIM dimensions: where the kernel integrates, and the
/// shape-function gradients there.
pub trait Shape<const N: usize, const DIM: usize> {
    /// What an element keeps of its reference configuration.
    type Reference;
    /// A point of the element in its natural coordinates.
    type At: Copy + 'static;
    /// The quadrature the kernel uses: points and weights (summing to 1).
    const RULE: &'static [(Self::At, f64)];
    /// ∇N_a (rows, with respect to the reference coordinates) at `at`, and the reference
    /// measure there (volume or area per unit weight).
    fn gradients(reference: &Self::Reference, at: &Self::At) -> (SMatrix<f64, N, DIM>, f64);
}

/// A tetrahedron's reference configuration: the corner gradients ∇λ_k (rows, constant on a
/// straight-edged tetrahedron) and the volume.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TetReference {
    /// The corner gradients ∇λ_k, one row per corner (1/mm).
    pub gradients: SMatrix<f64, 4, 3>,
    /// The reference volume (mm³).
    pub volume: f64,
}

impl TetReference {
    /// The reference configuration of the tetrahedron with corners `corners`.
    pub fn new(corners: &[[f64; 3]; 4]) -> Self {
        let (gradients, volume) = tet4::gradients(corners);
        Self { gradients, volume }
    }
}

/// The 4-node linear tetrahedron: constant gradients, one quadrature point.
#[derive(Debug, Clone, Copy)]
pub struct Tet4;

impl Shape<4, 3> for Tet4 {
    type Reference = TetReference;
    type At = [f64; 4];
    const RULE: &'static [TetPoint] = &TET_1;
    fn gradients(r: &TetReference, _: &[f64; 4]) -> (SMatrix<f64, 4, 3>, f64) {
        (r.gradients, r.volume)
    }
}

/// The 10-node quadratic tetrahedron with the 14-point rule.
#[derive(Debug, Clone, Copy)]
pub struct Tet10;

impl Shape<10, 3> for Tet10 {
    type Reference = TetReference;
    type At = [f64; 4];
    const RULE: &'static [TetPoint] = &TET_14;
    fn gradients(r: &TetReference, l: &[f64; 4]) -> (SMatrix<f64, 10, 3>, f64) {
        (tet10::gradients(l, &r.gradients), r.volume)
    }
}

/// An inverted element: the smallest J = det F found at its quadrature points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inverted {
    /// The offending J ≤ 0: det F at a quadrature point (for a membrane line, its
    /// stretch λ).
    pub j: f64,
}

impl Inverted {
    /// J = det F itself if the point is admissible (J > 0), else the error.
    pub fn check(j: f64) -> Result<f64, Inverted> {
        if j > 0.0 {
            Ok(j)
        } else {
            Err(Inverted { j })
        }
    }
}

/// The deformation gradient F = I + Σ_a u_a ⊗ ∇N_a (in 2D the in-plane block, F_zz = 1).
pub fn deformation<const N: usize, const DIM: usize, const D: usize>(
    u: &SVector<f64, D>,
    grads: &SMatrix<f64, N, DIM>,
) -> Matrix3<f64> {
    let mut f = Matrix3::identity();
    for a in 0..N {
        for i in 0..DIM {
            for jj in 0..DIM {
                f[(i, jj)] += u[DIM * a + i] * grads[(a, jj)];
            }
        }
    }
    f
}

/// The deformation gradient of one element at the point `at` of its natural coordinates.
pub fn deformation_at<S: Shape<N, DIM>, const N: usize, const DIM: usize, const D: usize>(
    reference: &S::Reference,
    u: &SVector<f64, D>,
    at: &S::At,
) -> Matrix3<f64> {
    deformation(u, &S::gradients(reference, at).0)
}

/// Adds the internal force of one element (reference configuration `reference`, node-major
/// displacements `u`) to `force`, and its tangent to `tangent` when given (symmetric on
/// entry, as the assembly's zeros are: its blocks below the diagonal are copied from above,
/// [`mirror`]). D = DIM · N.
pub fn internal<S: Shape<N, DIM>, const N: usize, const DIM: usize, const D: usize>(
    reference: &S::Reference,
    u: &SVector<f64, D>,
    material: &Material,
    force: &mut SVector<f64, D>,
    mut tangent: Option<&mut SMatrix<f64, D, D>>,
) -> Result<(), Inverted> {
    debug_assert_eq!(D, DIM * N);
    for (at, w) in S::RULE {
        let (grads, measure) = S::gradients(reference, at);
        let f = deformation(u, &grads);
        if material.law.finite() {
            Inverted::check(f.determinant())?;
        }
        let scale = w * measure;
        let p = material.stress(&f) * scale;
        for a in 0..N {
            for i in 0..DIM {
                let mut s = 0.0;
                for jj in 0..DIM {
                    s += p[(i, jj)] * grads[(a, jj)];
                }
                force[DIM * a + i] += s;
            }
        }
        if let Some(k) = tangent.as_deref_mut() {
            add_tangent(k, &grads, &(material.tangent(&f) * scale));
        }
    }
    if let Some(k) = tangent {
        mirror::<DIM, D>(k);
    }
    Ok(())
}

/// The small-strain stiffness of one element of the linear law (`material`'s λ, μ):
/// K_ab,ik = Σ_q w_q V [λ ∇N_a,i ∇N_b,k + μ ∇N_a,k ∇N_b,i + μ δ_ik (∇N_a · ∇N_b)], the
/// kernel's tangent with the isotropic A_(iJ)(kL) = λ δ_iJ δ_kL + μ (δ_ik δ_JL + δ_iL δ_Jk)
/// contracted by hand (seed 003 App. C: Bᵀ D B), added to `k` (symmetric on entry, as the
/// assembly's zeros are: its blocks below the diagonal are copied from above, [`mirror`]).
pub fn small_strain_stiffness<
    S: Shape<N, DIM>,
    const N: usize,
    const DIM: usize,
    const D: usize,
>(
    reference: &S::Reference,
    material: &Material,
    k: &mut SMatrix<f64, D, D>,
) {
    let (lambda, mu) = (material.elastic.lambda(), material.elastic.shear());
    for (at, w) in S::RULE {
        let (g, measure) = S::gradients(reference, at);
        let scale = w * measure;
        for b in 0..N {
            for a in 0..=b {
                let dot = scale * mu * (0..DIM).map(|d| g[(a, d)] * g[(b, d)]).sum::<f64>();
                for i in 0..DIM {
                    for kk in 0..DIM {
                        k[(DIM * a + i, DIM * b + kk)] +=
                            scale * (lambda * g[(a, i)] * g[(b, kk)] + mu * g[(a, kk)] * g[(b, i)]);
                    }
                    k[(DIM * a + i, DIM * b + i)] += dot;
                }
            }
        }
    }
    mirror::<DIM, D>(k);
}

/// K_ab,ik += Σ_JL ∇N_a,J A_(iJ)(kL) ∇N_b,L for the blocks a ≤ b, through
/// T_b = A (∇N_b ⊗ I) (per node, the rows iJ and columns k of the element's dimensions);
/// the blocks below follow by [`mirror`].
fn add_tangent<const N: usize, const DIM: usize, const D: usize>(
    k: &mut SMatrix<f64, D, D>,
    grads: &SMatrix<f64, N, DIM>,
    a: &super::material::Tangent,
) {
    for b in 0..N {
        let mut t = [[0.0; 3]; 9];
        for i in 0..DIM {
            for jj in 0..DIM {
                let row = 3 * i + jj;
                for (kk, tk) in t[row].iter_mut().enumerate().take(DIM) {
                    *tk = (0..DIM)
                        .map(|ll| a[(row, 3 * kk + ll)] * grads[(b, ll)])
                        .sum();
                }
            }
        }
        for n in 0..=b {
            for i in 0..DIM {
                for kk in 0..DIM {
                    let s: f64 = (0..DIM).map(|jj| grads[(n, jj)] * t[3 * i + jj][kk]).sum();
                    k[(DIM * n + i, DIM * b + kk)] += s;
                }
            }
        }
    }
}

/// K_ba = K_abᵀ for the blocks below the diagonal: every law here is hyperelastic, so
/// A_(iJ)(kL) = ∂²W/∂F_iJ∂F_kL = A_(kL)(iJ) and the element tangent is symmetric; it is
/// computed above the diagonal only (a third fewer products for tet10) and copied below.
fn mirror<const DIM: usize, const D: usize>(k: &mut SMatrix<f64, D, D>) {
    for column in 0..D {
        for row in DIM * (column / DIM + 1)..D {
            k[(row, column)] = k[(column, row)];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::material::{Elastic, Law};

    const P: [[f64; 3]; 4] = [
        [0.1, 0.0, -0.2],
        [1.3, 0.2, 0.1],
        [0.2, 1.1, 0.0],
        [0.3, 0.4, 1.2],
    ];

    fn material(law: Law) -> Material {
        Material::new(law, Elastic::new("m", 0.05, 0.43).unwrap())
    }

    /// Randomly distorted displacements (deterministic), small enough to keep J > 0.
    fn distorted<const D: usize>(scale: f64) -> SVector<f64, D> {
        SVector::from_fn(|r, _| scale * (((r * 7919 + 13) % 97) as f64 / 97.0 - 0.5))
    }

    /// The tangent against central differences of the internal force, 1e-6 relative, for
    /// both shapes and all laws.
    fn tangent_matches_differences<
        S: Shape<N, 3, Reference = TetReference, At = [f64; 4]>,
        const N: usize,
        const D: usize,
    >() {
        let u: SVector<f64, D> = distorted(0.2);
        for law in Law::ALL {
            let m = material(law);
            let mut f = SVector::zeros();
            let mut k = SMatrix::<f64, D, D>::zeros();
            internal::<S, N, 3, D>(&TetReference::new(&P), &u, &m, &mut f, Some(&mut k)).unwrap();
            let h = 1e-6;
            for c in 0..D {
                let (mut up, mut um) = (u, u);
                up[c] += h;
                um[c] -= h;
                let (mut fp, mut fm) = (SVector::zeros(), SVector::zeros());
                internal::<S, N, 3, D>(&TetReference::new(&P), &up, &m, &mut fp, None).unwrap();
                internal::<S, N, 3, D>(&TetReference::new(&P), &um, &m, &mut fm, None).unwrap();
                let fd = (fp - fm) / (2.0 * h);
                let err = (fd - k.column(c)).amax();
                assert!(err <= 1e-6 * k.amax(), "{law:?} column {c}: {err:e}");
            }
            assert!(
                (k - k.transpose()).amax() <= 1e-12 * k.amax(),
                "{law:?}: symmetric"
            );
        }
    }

    #[test]
    fn tangents_are_the_derivatives_of_the_internal_forces() {
        tangent_matches_differences::<Tet4, 4, 12>();
        tangent_matches_differences::<Tet10, 10, 30>();
    }

    /// The linear law through the kernel is the closed-form small-strain stiffness.
    #[test]
    fn linear_tet4_equals_the_closed_form_stiffness() {
        let m = material(Law::Linear);
        let (mut f, mut k) = (SVector::<f64, 12>::zeros(), SMatrix::<f64, 12, 12>::zeros());
        let u: SVector<f64, 12> = distorted(0.3);
        internal::<Tet4, 4, 3, 12>(&TetReference::new(&P), &u, &m, &mut f, Some(&mut k)).unwrap();
        let closed = tet4::stiffness(&P, &m.elastic.solid());
        assert!((k - closed).amax() < 1e-13 * closed.amax());
        assert!((f - closed * u).amax() < 1e-13 * f.amax());
    }

    /// The closed-form small-strain stiffness is the kernel's tangent of the linear law,
    /// for both shapes.
    #[test]
    fn the_small_strain_stiffness_is_the_linear_laws_tangent() {
        fn check<
            S: Shape<N, 3, Reference = TetReference, At = [f64; 4]>,
            const N: usize,
            const D: usize,
        >() {
            let m = material(Law::Linear);
            let r = TetReference::new(&P);
            let (mut f, mut k) = (SVector::<f64, D>::zeros(), SMatrix::<f64, D, D>::zeros());
            internal::<S, N, 3, D>(&r, &SVector::zeros(), &m, &mut f, Some(&mut k)).unwrap();
            let mut closed = SMatrix::<f64, D, D>::zeros();
            small_strain_stiffness::<S, N, 3, D>(&r, &m, &mut closed);
            assert!(
                (k - closed).amax() < 1e-14 * k.amax(),
                "{}",
                (k - closed).amax()
            );
        }
        check::<Tet4, 4, 12>();
        check::<Tet10, 10, 30>();
    }

    /// A collapsed element is refused by the finite-strain laws, not by the linear one.
    #[test]
    fn inverted_elements_are_refused_at_finite_strain() {
        let mut u = SVector::<f64, 12>::zeros();
        u[11] = -2.5; // node 3 pushed through the opposite face
        for law in Law::ALL {
            let mut f = SVector::zeros();
            let r = internal::<Tet4, 4, 3, 12>(
                &TetReference::new(&P),
                &u,
                &material(law),
                &mut f,
                None,
            );
            assert_eq!(r.is_err(), law.finite(), "{law:?}");
        }
    }
}
