//! Reduced-order dynamics by superposition of a few basis vectors (Craig & Kurdila,
//! Fundamentals of Structural Dynamics, 2nd ed. 2006, ch. 14; Bathe 1996 §9.3): the
//! displacement is sought as u ≈ Φ q with Φ M-orthonormal, and the Galerkin projection
//!
//! (ΦᵀMΦ) q̈ + (ΦᵀCΦ) q̇ + (ΦᵀKΦ) q = Φᵀ f(t)
//!
//! is integrated instead of the full system. Three bases ([`Reduction`]):
//!
//! - **load-dependent Ritz vectors** (the default): the Krylov space span{K⁻¹f, (K⁻¹M)K⁻¹f,
//!   …} of the load's spatial pattern f ([`lanczos::krylov`]). It holds the static response
//!   exactly and, step by step, the dynamic corrections a load of that pattern excites;
//! - **eigenmodes with static correction**: the lowest eigenvectors of K φ = λ M φ
//!   ([`lanczos::lowest`]) plus K⁻¹f M-orthogonalized against them (the quasi-static response
//!   of the truncated modes);
//! - **truncated eigenmodes**: the modes alone.
//!
//! Every basis is finally Ritz-diagonalized: the small eigenproblem of ΦᵀKΦ is solved and Φ
//! rotated, so that ΦᵀMΦ = I and ΦᵀKΦ = diag(ω²) to round-off. With mass-proportional
//! damping the reduced system is then diagonal, and [`ModalBasis::reduce`] stores only its
//! non-zero entries: a reduced step costs O(dim). With all n vectors the reduced run is the
//! full run in another basis.

use std::time::Instant;

use faer::linalg::matmul::matmul;
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::sparse::SparseColMatRef;
use faer::{Accum, Mat, MatMut, MatRef, Par};
use nalgebra::{DMatrix, SymmetricEigen};

use super::lanczos::{self, m_norm};
use super::structure::Structure;
use crate::assembly::mul_add;
use crate::error::ModelError;
use crate::linalg::cholesky::Cholesky;

/// A static-correction vector is kept only if this share of the static response (M-norm)
/// lies outside the span of the modes; below it the modes already hold it.
const CORRECTION_TOL: f64 = 1e-8;

/// Off-diagonal entries of a projected matrix below this share of √(a_ii a_jj) are the
/// round-off of the projection (the Ritz-diagonalized basis makes them zero exactly) and
/// are dropped.
const ROUND_OFF: f64 = 1e-12;

/// Which basis a [`ModalBasis`] is built from (see the module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reduction {
    /// Load-dependent Ritz vectors: the Krylov space of the load pattern.
    Ritz,
    /// The lowest eigenmodes plus the load pattern's static correction.
    Eigenmodes,
    /// The lowest eigenmodes alone.
    Truncated,
}

/// An M-orthonormal, K-orthogonal reduction basis.
#[derive(Debug, Clone)]
pub struct ModalBasis {
    /// The basis vectors as columns (free dofs × dimension).
    vectors: Mat<f64>,
    /// Ritz values ω² = φᵀKφ of the columns (1/s²), ascending: for eigenmodes their
    /// eigenvalues.
    pub values: Vec<f64>,
    /// Wall time of the construction (s).
    pub seconds: f64,
}

impl ModalBasis {
    /// A basis of `count` vectors (eigenmodes: `count` modes plus the correction) for loads
    /// of spatial pattern `load` (free dofs), and for a `carried` state if given.
    pub fn new(
        s: &Structure,
        reduction: Reduction,
        count: usize,
        load: &[f64],
        carried: Option<&Carried<'_>>,
    ) -> Result<Self, ModelError> {
        s.require_linear("a modal reduction")?;
        let clock = Instant::now();
        let mut chol = s.analyze()?;
        chol.factorize(s.stiffness())?;
        let mut vectors = match reduction {
            Reduction::Ritz => lanczos::krylov(s.mass(), &mut chol, load, count)?,
            Reduction::Eigenmodes | Reduction::Truncated => {
                let mut modes = lanczos::lowest(s.stiffness(), s.mass(), &mut chol, count)?.vectors;
                if reduction == Reduction::Eigenmodes {
                    let mut u = load.to_vec();
                    chol.solve_in_place(&mut u);
                    append_orthogonal(s.mass(), &mut modes, u);
                }
                modes
            }
        };
        if let Some(carried) = carried {
            carry(s, &mut chol, carried, count, &mut vectors)?;
        }
        let (vectors, values) = ritz_diagonalized(s.stiffness(), vectors);
        Ok(Self {
            vectors,
            values,
            seconds: clock.elapsed().as_secs_f64(),
        })
    }

    /// A basis of given M-orthonormal, K-orthogonal columns with their Ritz values.
    pub(super) fn from_parts(vectors: Mat<f64>, values: Vec<f64>, seconds: f64) -> Self {
        Self {
            vectors,
            values,
            seconds,
        }
    }

    /// Number of basis vectors.
    pub fn dim(&self) -> usize {
        self.vectors.ncols()
    }

    /// Number of free dofs.
    pub fn n(&self) -> usize {
        self.vectors.nrows()
    }

    /// Basis vector `j` (free dofs).
    pub fn column(&self, j: usize) -> &[f64] {
        self.vectors.col_as_slice(j)
    }

    /// The Galerkin projection (ΦᵀKΦ, ΦᵀMΦ, ΦᵀCΦ) as a [`Structure`] of its non-zero
    /// entries.
    pub fn reduce(&self, s: &Structure) -> Result<Structure, ModelError> {
        let (mut k, mut m, mut c) = (
            self.galerkin(s.stiffness()),
            self.galerkin(s.mass()),
            self.galerkin(s.damping_matrix()),
        );
        for a in [&mut k, &mut m, &mut c] {
            drop_round_off(a);
        }
        Structure::dense(k.as_ref(), m.as_ref(), c.as_ref())
    }

    /// Φᵀ A Φ for a sparse symmetric A on the free dofs, exactly symmetric.
    pub fn galerkin(&self, a: SparseColMatRef<'_, usize, f64>) -> Mat<f64> {
        galerkin(a, &self.vectors)
    }

    /// out = Φᵀ f (the generalized forces of a load on the free dofs).
    pub fn project(&self, f: &[f64], out: &mut [f64]) {
        let f = MatRef::from_column_major_slice(f, f.len(), 1);
        let out = MatMut::from_column_major_slice_mut(out, self.dim(), 1);
        matmul(
            out,
            Accum::Replace,
            self.vectors.transpose(),
            f,
            1.0,
            Par::Seq,
        );
    }

    /// u = Φ q (free dofs). Allocates nothing.
    pub fn expand(&self, q: &[f64], u: &mut [f64]) {
        let q = MatRef::from_column_major_slice(q, q.len(), 1);
        let u = MatMut::from_column_major_slice_mut(u, self.n(), 1);
        matmul(u, Accum::Replace, &self.vectors, q, 1.0, Par::Seq);
    }

    /// The coordinates q = Φᵀ M u of a displacement (free dofs): its M-orthogonal
    /// projection onto the basis.
    pub fn coordinates(&self, m: SparseColMatRef<'_, usize, f64>, u: &[f64], q: &mut [f64]) {
        let mut mu = vec![0.0; u.len()];
        mul_add(m, u, 1.0, &mut mu);
        self.project(&mu, q);
    }
}

/// A state a basis is built to carry: a reduced model's, when its matrices change mid-run.
pub struct Carried<'a> {
    /// Displacement and velocity (free dofs): held, with the Krylov sequences K⁻¹Mw,
    /// (K⁻¹M)²w, … of each (`count` vectors long), in which the free vibration from them
    /// under the new matrices lies. Without these, a basis for the load alone misses that
    /// vibration (the abdomen's floor stiffened fourfold mid-press: 15 % of the floor
    /// stress, `abdomen_modal` tests).
    pub vibrating: [&'a [f64]; 2],
    /// The state's other vectors (acceleration, the scheme's history): held exactly.
    pub others: Vec<&'a [f64]>,
}

/// Appends what `carried` needs ([`Carried`]) to the M-orthonormal columns of `basis`.
fn carry(
    s: &Structure,
    chol: &mut Cholesky,
    carried: &Carried<'_>,
    count: usize,
    basis: &mut Mat<f64>,
) -> Result<(), ModelError> {
    for w in carried.vibrating {
        append_orthogonal(s.mass(), basis, w.to_vec());
        let mut mw = vec![0.0; w.len()];
        mul_add(s.mass(), w, 1.0, &mut mw);
        if mw.iter().any(|&x| x != 0.0) {
            let sequence = lanczos::krylov(s.mass(), chol, &mw, count)?;
            for j in 0..sequence.ncols() {
                append_orthogonal(s.mass(), basis, sequence.col(j).iter().copied().collect());
            }
        }
    }
    for w in &carried.others {
        append_orthogonal(s.mass(), basis, w.to_vec());
    }
    Ok(())
}

/// Appends `u` (the static correction, a state) to the M-orthonormal columns of `basis`,
/// M-orthogonalized against them (Gram–Schmidt twice), unless the columns already hold it.
fn append_orthogonal(m: SparseColMatRef<'_, usize, f64>, basis: &mut Mat<f64>, mut u: Vec<f64>) {
    let (n, j) = (basis.nrows(), basis.ncols());
    let mut mu = vec![0.0; n];
    let whole = m_norm(m, &u, &mut mu);
    let mut c = Mat::<f64>::zeros(j, 1);
    for _ in 0..2 {
        m_norm(m, &u, &mut mu);
        let mu = MatRef::from_column_major_slice(&mu, n, 1);
        matmul(&mut c, Accum::Replace, basis.transpose(), mu, 1.0, Par::Seq);
        let um = MatMut::from_column_major_slice_mut(&mut u, n, 1);
        matmul(um, Accum::Add, &*basis, &c, -1.0, Par::Seq);
    }
    let rest = m_norm(m, &u, &mut mu);
    if rest > CORRECTION_TOL * whole {
        basis.resize_with(n, j + 1, |i, _| u[i] / rest);
    }
}

/// Vᵀ A V for a sparse symmetric A, exactly symmetric.
pub(super) fn galerkin(a: SparseColMatRef<'_, usize, f64>, v: &Mat<f64>) -> Mat<f64> {
    let r = v.ncols();
    let mut av = Mat::zeros(v.nrows(), r);
    sparse_dense_matmul(av.as_mut(), Accum::Replace, a, v.as_ref(), 1.0, Par::Seq);
    let mut p = Mat::zeros(r, r);
    matmul(&mut p, Accum::Replace, v.transpose(), &av, 1.0, Par::Seq);
    Mat::from_fn(r, r, |i, j| 0.5 * (p[(i, j)] + p[(j, i)]))
}

/// Rotates the M-orthonormal columns of `v` onto the eigenvectors of VᵀKV (ascending
/// eigenvalues), so that the result is K-orthogonal too; returns it with the Ritz values.
fn ritz_diagonalized(k: SparseColMatRef<'_, usize, f64>, v: Mat<f64>) -> (Mat<f64>, Vec<f64>) {
    let kr = galerkin(k, &v);
    let r = v.ncols();
    let eigen = SymmetricEigen::new(DMatrix::from_fn(r, r, |i, j| kr[(i, j)]));
    let mut order: Vec<usize> = (0..r).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let s = Mat::from_fn(r, r, |i, j| eigen.eigenvectors[(i, order[j])]);
    let mut rotated = Mat::zeros(v.nrows(), r);
    matmul(&mut rotated, Accum::Replace, &v, &s, 1.0, Par::Seq);
    let values = order.iter().map(|&i| eigen.eigenvalues[i]).collect();
    (rotated, values)
}

/// Zeroes off-diagonal entries below [`ROUND_OFF`] · √(a_ii a_jj).
fn drop_round_off(a: &mut Mat<f64>) {
    let r = a.nrows();
    let diag: Vec<f64> = (0..r).map(|i| a[(i, i)].abs()).collect();
    for j in 0..r {
        for i in (0..r).filter(|&i| i != j) {
            if a[(i, j)].abs() <= ROUND_OFF * (diag[i] * diag[j]).sqrt() {
                a[(i, j)] = 0.0;
            }
        }
    }
}
