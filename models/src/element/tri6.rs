//! Plane-strain 6-node triangle (quadratic, isoparametric), unit thickness. Corner nodes 0, 1,
//! 2 counter-clockwise, mid-edge nodes 3 (edge 0–1), 4 (edge 1–2), 5 (edge 2–0). Shape
//! functions in area coordinates (L₀, L₁, L₂): N_i = L_i (2 L_i − 1) at the corners,
//! N = 4 L_i L_j at the mid-edge nodes (Zienkiewicz & Taylor, The Finite Element Method,
//! vol. 1, §8.8); mid-edge nodes off the straight edge give curved edges.
//!
//! Two formulations of the stiffness:
//!
//! - **displacement** ([`stiffness`]): ∫ Bᵀ D B dA with the 3-point rule, exact for straight
//!   edges (the integrand is of degree 2);
//! - **mixed P2/P0** ([`stiffness_mixed`]): an element-wise constant pressure, condensed at
//!   element level. With the split D = D_dev + κ m mᵀ (κ = λ + 2μ/3 the bulk modulus,
//!   m = (1, 1, 0), D_dev the deviatoric part of the 3D law restricted to ε_zz = 0), the
//!   volumetric term sees only the element's mean volumetric strain θ̄ = g·u / A with
//!   g = ∫ Bᵀ m dA: K = ∫ Bᵀ D_dev B dA + (κ / A) g gᵀ, and the pressure is p = κ θ̄. This is
//!   the Herrmann-type u–p element with discontinuous constant pressure (mean dilatation,
//!   Nagtegaal, Parks & Rice 1974): one volumetric constraint per element instead of one per
//!   quadrature point, so it does not lock as ν → 0.5, and K stays symmetric positive
//!   definite — the factorization and the integrators are unchanged.
//!
//! At finite strain ([`internal_in`]) the same two: the displacement formulation
//! ([`internal`]), and the mixed one in its finite-strain form ([`internal_mixed`]): the
//! three-field Hu–Washizu principle of Simo, Taylor & Pister (CMAME 51 (1985) 177–208) with
//! an element-wise constant dilatation θ and pressure, which eliminate to θ̄ = (1/V) ∫ J dV,
//! the element's mean volume ratio, and the modified deformation gradient
//! F̄ = (θ̄ / J)^{1/3} F (det F̄ = θ̄) in any law's energy: Π_e = ∫ W(F̄) dV. For the linear
//! law at small strain it is the mean dilatation above; it is a potential of u, so the
//! tangent is symmetric, and a homogeneous deformation (θ̄ = J) is the displacement
//! formulation's.

use nalgebra::{Matrix2, Matrix3, SMatrix, SVector, Vector3};

use super::solid::Inverted;
use super::{Elastic, Material};

/// Element displacement vector (u_x0, u_y0, …, u_x5, u_y5).
pub type Dofs = SVector<f64, 12>;
/// Strain–displacement matrix for (ε_xx, ε_yy, γ_xy).
pub type BMatrix = SMatrix<f64, 3, 12>;
/// A quadrature point: area coordinates and a weight (the weights sum to 1; multiply by the
/// area).
pub type Point = ([f64; 3], f64);

/// Corners of each edge, in the order of the mid-edge nodes 3, 4, 5.
pub const EDGES: [[usize; 2]; 3] = [[0, 1], [1, 2], [2, 0]];

/// The 3-point rule at the edge midpoints' interior images (Strang & Fix), exact for degree 2.
pub const TRI_3: [Point; 3] = [
    ([2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0], 1.0 / 3.0),
    ([1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0], 1.0 / 3.0),
    ([1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0], 1.0 / 3.0),
];

/// The 6-point rule of Dunavant (1985), exact for degree 4 (the consistent mass NᵀN).
pub const TRI_6: [Point; 6] = {
    const A: f64 = 0.445_948_490_915_965;
    const WA: f64 = 0.223_381_589_678_011;
    const B: f64 = 0.091_576_213_509_771;
    const WB: f64 = 0.109_951_743_655_322;
    [
        ([1.0 - 2.0 * A, A, A], WA),
        ([A, 1.0 - 2.0 * A, A], WA),
        ([A, A, 1.0 - 2.0 * A], WA),
        ([1.0 - 2.0 * B, B, B], WB),
        ([B, 1.0 - 2.0 * B, B], WB),
        ([B, B, 1.0 - 2.0 * B], WB),
    ]
};

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

/// Plane-strain total Lagrangian internal force and, when asked, tangent of one element with
/// node-major displacements `u` (the 2D counterpart of [`super::solid::internal`], 3-point
/// rule): F = I + Σ_a u_a ⊗ ∇N_a in the plane with F_zz = 1, f_a = ∫ P(F) ∇N_a dA and
/// K_ab,ik = ∫ Σ_JL ∇N_a,J (∂P_iJ/∂F_kL) ∇N_b,L dA over the in-plane indices. For the linear
/// law this is [`stiffness`] (f = K u). A finite-strain law refuses J = det F ≤ 0.
pub fn internal(
    p: &[[f64; 2]; 6],
    u: &Dofs,
    material: &Material,
    force: &mut Dofs,
    mut tangent: Option<&mut SMatrix<f64, 12, 12>>,
) -> Result<(), Inverted> {
    for &(l, w) in &TRI_3 {
        let (g, det) = gradients(p, l);
        let f = deformation_gradient(&g, u);
        if material.law.finite() {
            Inverted::check(f.determinant())?;
        }
        let scale = 0.5 * w * det;
        let stress = material.stress(&f) * scale;
        for (a, ga) in g.iter().enumerate() {
            for i in 0..2 {
                force[2 * a + i] += stress[(i, 0)] * ga[0] + stress[(i, 1)] * ga[1];
            }
        }
        if let Some(k) = tangent.as_deref_mut() {
            let t = material.tangent(&f) * scale;
            for (a, ga) in g.iter().enumerate() {
                for (b, gb) in g.iter().enumerate() {
                    for i in 0..2 {
                        for kk in 0..2 {
                            let mut s = 0.0;
                            for jj in 0..2 {
                                for ll in 0..2 {
                                    s += ga[jj] * t[(3 * i + jj, 3 * kk + ll)] * gb[ll];
                                }
                            }
                            k[(2 * a + i, 2 * b + kk)] += s;
                        }
                    }
                }
            }
        }
    }
    Ok(())
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
struct MixedPoint {
    g: SMatrix<f64, 9, 12>,
    f: Matrix3<f64>,
    j: f64,
    inverse_t: SVector<f64, 9>,
    d: SMatrix<f64, 9, 9>,
    dv: f64,
}

/// The quadrature points of the mixed kernel; a point with J ≤ 0 is an error.
fn mixed_points(p: &[[f64; 2]; 6], u: &Dofs) -> Result<[MixedPoint; 3], Inverted> {
    let points = TRI_3.map(|(l, w)| {
        let (grads, det) = gradients(p, l);
        let f = deformation_gradient(&grads, u);
        let mut g = SMatrix::<f64, 9, 12>::zeros();
        for (a, ga) in grads.iter().enumerate() {
            for i in 0..2 {
                for jj in 0..2 {
                    g[(3 * i + jj, 2 * a + i)] = ga[jj];
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
            dv: 0.5 * w * det,
        }
    });
    for q in &points {
        Inverted::check(q.j)?;
    }
    Ok(points)
}

/// The element's reference area V and mean volume ratio θ̄ = (1/V) ∫ J dV.
fn mean_volume_ratio(points: &[MixedPoint; 3]) -> (f64, f64) {
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
        Formulation::Displacement => internal(p, u, material, force, tangent),
        Formulation::Mixed => internal_mixed(p, u, material, force, tangent),
    }
}

/// F = I + Σ_a u_a ⊗ ∇N_a in the plane, F_zz = 1 (plane strain), for the shape-function
/// gradients `g` at a point.
fn deformation_gradient(g: &[[f64; 2]; 6], u: &Dofs) -> Matrix3<f64> {
    let mut f = Matrix3::<f64>::identity();
    for (a, ga) in g.iter().enumerate() {
        for i in 0..2 {
            for j in 0..2 {
                f[(i, j)] += u[2 * a + i] * ga[j];
            }
        }
    }
    f
}

/// The Cauchy stress σ = J⁻¹ P Fᵀ at area coordinates `l` for a finite-strain `material` in
/// `formulation` (for the linear law σ = P, the small-strain stress): the mixed formulation
/// takes F̄ = (θ̄/J)^{1/3} F with the element's mean volume ratio θ̄ ([`internal_mixed`]),
/// so σ = P(F̄) F̄ᵀ / θ̄. An inverted point is an error.
pub fn cauchy(
    formulation: Formulation,
    p: &[[f64; 2]; 6],
    l: [f64; 3],
    u: &Dofs,
    material: &Material,
) -> Result<Matrix3<f64>, Inverted> {
    let mut f = deformation_gradient(&gradients(p, l).0, u);
    if formulation == Formulation::Mixed {
        let theta = mean_volume_ratio(&mixed_points(p, u)?).1;
        f *= (theta / f.determinant()).cbrt();
    }
    let stress = material.stress(&f);
    if !material.law.finite() {
        return Ok(stress);
    }
    let j = Inverted::check(f.determinant())?;
    Ok(stress * f.transpose() / j)
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
        let (b, det) = b_matrix(p, l);
        (g + b.transpose() * m * (0.5 * w * det), a + 0.5 * w * det)
    })
}

/// Mixed P2/P0 stiffness ∫ Bᵀ D_dev B dA + (κ / A) g gᵀ (see the module documentation).
pub fn stiffness_mixed(p: &[[f64; 2]; 6], elastic: &Elastic) -> SMatrix<f64, 12, 12> {
    let (dev, kappa) = split(elastic);
    let (g, a) = dilatation(p);
    stiffness(p, &dev) + g * g.transpose() * (kappa / a)
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
        Formulation::Displacement => stiffness(p, &elastic.plane_strain()),
        Formulation::Mixed => stiffness_mixed(p, elastic),
    }
}

/// The stress operator S at area coordinates `l`: (σ_xx, σ_yy, σ_xy, σ_zz) = S u for the
/// element displacements u. Displacement formulation: D B, and σ_zz = λ (ε_xx + ε_yy) for
/// ε_zz = 0. Mixed: D_dev B plus the element's pressure p = κ θ̄ = κ g·u / A on the normal
/// stresses, and σ_zz = −(2μ/3)(ε_xx + ε_yy) + p (the deviatoric part of the 3D law at
/// ε_zz = 0, plus p).
pub fn stress_operator(
    formulation: Formulation,
    p: &[[f64; 2]; 6],
    l: [f64; 3],
    elastic: &Elastic,
) -> SMatrix<f64, 4, 12> {
    let b = b_matrix(p, l).0;
    let volumetric = b.row(0) + b.row(1);
    let mut s = SMatrix::<f64, 4, 12>::zeros();
    match formulation {
        Formulation::Displacement => {
            s.fixed_rows_mut::<3>(0)
                .copy_from(&(elastic.plane_strain() * b));
            s.set_row(3, &(volumetric * elastic.lambda()));
        }
        Formulation::Mixed => {
            let (dev, kappa) = split(elastic);
            let (g, a) = dilatation(p);
            let pressure = g.transpose() * (kappa / a);
            s.fixed_rows_mut::<3>(0).copy_from(&(dev * b));
            for r in 0..2 {
                let row = s.row(r) + pressure;
                s.set_row(r, &row);
            }
            s.set_row(3, &(volumetric * (-2.0 * elastic.shear() / 3.0) + pressure));
        }
    }
    s
}

/// Stress (σ_xx, σ_yy, σ_xy) at area coordinates `l` for the element displacements `u`
/// (the first rows of [`stress_operator`]).
pub fn stress(
    formulation: Formulation,
    p: &[[f64; 2]; 6],
    l: [f64; 3],
    u: &Dofs,
    elastic: &Elastic,
) -> Vector3<f64> {
    (stress_operator(formulation, p, l, elastic) * u)
        .fixed_rows::<3>(0)
        .into()
}

/// Lumped mass by the HRZ rule (Hinton, Rock & Zienkiewicz 1976): the consistent mass's
/// diagonal scaled to the element's mass (row sums would leave the corners without mass;
/// on a straight-sided element the corners get 3/57 and the mid-edge nodes 16/57 of it).
pub fn mass_lumped(p: &[[f64; 2]; 6], density: f64) -> Dofs {
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

    /// On a constant strain both formulations give Hooke's 3D law at ε_zz = 0, σ_zz included
    /// (σ_zz = ν (σ_xx + σ_yy)); the neo-Hookean Cauchy stress approaches it as the strain
    /// shrinks (the difference is second order).
    #[test]
    fn stress_operators_give_the_plane_strain_law_on_a_constant_strain() {
        use crate::element::material::Law;
        let p = element();
        let elastic = Elastic::new("m", 7.0, 0.45).unwrap();
        let (exx, eyy, gxy) = (0.01, -0.004, 0.006);
        let motion = |scale: f64| {
            Dofs::from_fn(|k, _| {
                let [x, y] = p[k / 2];
                scale
                    * if k.is_multiple_of(2) {
                        exx * x + gxy * y
                    } else {
                        eyy * y
                    }
            })
        };
        let (l, m) = (elastic.lambda(), elastic.shear());
        let hooke = [
            l * (exx + eyy) + 2.0 * m * exx,
            l * (exx + eyy) + 2.0 * m * eyy,
            m * gxy,
            l * (exx + eyy),
        ];
        let u = motion(1.0);
        for formulation in [Formulation::Displacement, Formulation::Mixed] {
            let s = stress_operator(formulation, &p, [0.2, 0.3, 0.5], &elastic) * u;
            for (a, b) in s.iter().zip(hooke) {
                assert!((a - b).abs() < 1e-12, "{formulation:?}: {a} vs {b}");
            }
            assert!((s[3] - 0.45 * (s[0] + s[1])).abs() < 1e-12);
        }
        let neo = Material::new(Law::NeoHookean, elastic);
        let gap = |scale: f64| {
            let c = cauchy(
                Formulation::Displacement,
                &p,
                [0.2, 0.3, 0.5],
                &motion(scale),
                &neo,
            )
            .unwrap();
            let linear = [hooke[0], hooke[1], hooke[2], hooke[3]].map(|x| x * scale);
            let got = [c[(0, 0)], c[(1, 1)], c[(0, 1)], c[(2, 2)]];
            got.iter()
                .zip(linear)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                / scale
        };
        let (coarse, fine) = (gap(1e-2), gap(1e-3));
        assert!(
            coarse < 2e-3 && (fine / coarse - 0.1).abs() < 0.02,
            "{coarse} {fine}"
        );
    }

    #[test]
    fn the_finite_strain_kernel_gives_the_linear_stiffness_and_its_own_tangent() {
        use crate::element::material::Law;
        let p = element();
        let elastic = Elastic::new("m", 0.05, 0.43).unwrap();
        let u = Dofs::from_fn(|r, _| 0.2 * (((r * 7919 + 13) % 97) as f64 / 97.0 - 0.5));
        // Linear law: f = K u with K the displacement formulation's stiffness.
        let (mut f, mut k) = (Dofs::zeros(), SMatrix::<f64, 12, 12>::zeros());
        internal(
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
            internal(&p, &homogeneous, &m, &mut fd, None).unwrap();
            internal_mixed(&p, &homogeneous, &m, &mut fm, None).unwrap();
            assert!((fd - fm).amax() < 1e-12 * fd.amax(), "{law:?} homogeneous");
        }
    }
}
