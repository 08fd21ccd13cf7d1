//! The lowest eigenpairs of K φ = λ M φ (K, M symmetric positive definite) by shift-invert
//! Lanczos (Ericsson & Ruhe, Math. Comp. 35 (1980) 1251–1268; Bathe 1996 §11.6): the Lanczos
//! recurrence runs on the operator K⁻¹M, which is self-adjoint in the M-inner product, so
//! its largest Ritz values θ converge first — and they are the lowest eigenvalues λ = 1/θ.
//! Each step is one solve with the Cholesky factor of K, one product with M and a full
//! re-orthogonalization (classical Gram–Schmidt twice, as dense matrix–vector products).
//!
//! The Krylov space grows until the wanted Ritz pairs have converged: the residual of a Ritz
//! pair (θ, Q s) is ‖K⁻¹M Q s − θ Q s‖_M = β_k |s_k|, checked against [`TOL`] · θ. When the
//! space becomes invariant before that (a start vector without components along some
//! modes, or all n vectors found), a new start vector orthogonal to the space continues it.

use faer::linalg::matmul::matmul;
use faer::sparse::SparseColMatRef;
use faer::{Accum, Mat, MatRef, Par};
use nalgebra::{DMatrix, SymmetricEigen};

use crate::assembly::mul_add;
use crate::budget;
use crate::error::ModelError;
use crate::linalg::cholesky::Cholesky;

/// Relative residual β_k |s_k| / θ below which a Ritz pair counts as converged. The Ritz
/// value's own error is of the order of the residual squared over the gap to its neighbour.
pub const TOL: f64 = 1e-10;

/// Steps between convergence checks (each check is a small dense eigen-solve).
const CHECK_EVERY: usize = 8;

/// Eigenpairs of K φ = λ M φ.
#[derive(Debug, Clone)]
pub struct Modes {
    /// Eigenvalues λ = ω² (1/s²), ascending.
    pub values: Vec<f64>,
    /// The eigenvectors as columns, M-orthonormal (φᵢᵀ M φⱼ = δᵢⱼ).
    pub vectors: Mat<f64>,
    /// Lanczos steps taken (= solves with the factor of K).
    pub steps: usize,
}

/// The `count` lowest eigenpairs of K φ = λ M φ. `k_factor` holds the Cholesky factorization
/// of `k`.
pub fn lowest(
    k: SparseColMatRef<'_, usize, f64>,
    m: SparseColMatRef<'_, usize, f64>,
    k_factor: &mut Cholesky,
    count: usize,
) -> Result<Modes, ModelError> {
    let n = k.nrows();
    check_count(count, n)?;
    let mut krylov = Krylov::new(m, (2 * count + 20).min(n))?;
    let mut w = start_vector(n, 0);
    krylov.push_start(&mut w, m)?;
    loop {
        let beta = krylov.expand(&mut w, m, k_factor);
        let done = krylov.len() == n;
        if done || krylov.len() % CHECK_EVERY == 0 {
            if let Some(modes) = krylov.converged(count, if done { 0.0 } else { beta }) {
                return Ok(modes);
            }
        }
        if done {
            // Cannot happen in exact arithmetic: an n-dimensional space holds every mode.
            return Err(ModelError::LinearAlgebra(
                "Lanczos: the Ritz pairs did not converge in the full space".into(),
            ));
        }
        if beta > 1e-10 * krylov.scale() {
            krylov.push(&w, beta, beta)?;
        } else {
            // An invariant subspace: continue from a new direction, uncoupled in T.
            w = start_vector(n, krylov.len());
            krylov.push_start(&mut w, m)?;
        }
    }
}

/// An M-orthonormal basis of the Krylov space span{K⁻¹f, (K⁻¹M)K⁻¹f, (K⁻¹M)²K⁻¹f, …} of
/// dimension `dim`: the load-dependent Ritz vectors of Wilson, Yuan & Dickens (Earthquake
/// Eng. Struct. Dyn. 10 (1982) 813–821), made by the same recurrence started from the static
/// response K⁻¹f. If the space becomes invariant first, the basis is shorter and holds the
/// exact response to every load of pattern f.
pub fn krylov(
    m: SparseColMatRef<'_, usize, f64>,
    k_factor: &mut Cholesky,
    f: &[f64],
    dim: usize,
) -> Result<Mat<f64>, ModelError> {
    let n = m.nrows();
    check_count(dim, n)?;
    let mut krylov = Krylov::new(m, dim)?;
    let mut w = f.to_vec();
    k_factor.solve_in_place(&mut w);
    krylov.push_start(&mut w, m)?;
    while krylov.len() < dim {
        let beta = krylov.expand(&mut w, m, k_factor);
        if beta <= 1e-10 * krylov.scale() {
            break;
        }
        krylov.push(&w, beta, beta)?;
    }
    Ok(krylov.q.subcols(0, krylov.len()).to_owned())
}

/// Refuses a basis size outside 1..=n (the `modes` parameter).
fn check_count(count: usize, n: usize) -> Result<(), ModelError> {
    if count == 0 || count > n {
        return Err(ModelError::InvalidParameter {
            name: "modes".into(),
            value: count as f64,
            reason: "must be at least 1 and at most the number of free dofs",
        });
    }
    Ok(())
}

/// A deterministic start vector with components in every direction; `seed` varies it.
fn start_vector(n: usize, seed: usize) -> Vec<f64> {
    (0..n)
        .map(|i| 1.0 + ((i * 7919 + seed * 104_723) % 104_729) as f64 / 104_729.0)
        .collect()
}

/// ‖u‖_M, with M u left in `mu`.
pub(crate) fn m_norm(m: SparseColMatRef<'_, usize, f64>, u: &[f64], mu: &mut [f64]) -> f64 {
    mu.fill(0.0);
    mul_add(m, u, 1.0, mu);
    u.iter()
        .zip(mu.iter())
        .map(|(a, b)| a * b)
        .sum::<f64>()
        .sqrt()
}

/// The Lanczos vectors Q (M-orthonormal columns), P = M Q and the tridiagonal T.
struct Krylov {
    q: Mat<f64>,
    p: Mat<f64>,
    used: usize,
    alpha: Vec<f64>,
    /// β_j couples columns j and j + 1 (0 where a new start vector was taken).
    beta: Vec<f64>,
    /// M times the vector being pushed.
    mw: Vec<f64>,
}

impl Krylov {
    fn new(m: SparseColMatRef<'_, usize, f64>, capacity: usize) -> Result<Self, ModelError> {
        let n = m.nrows();
        let mut krylov = Self {
            q: Mat::zeros(n, 0),
            p: Mat::zeros(n, 0),
            used: 0,
            alpha: Vec::new(),
            beta: Vec::new(),
            mw: vec![0.0; n],
        };
        krylov.reserve(capacity)?;
        Ok(krylov)
    }

    fn len(&self) -> usize {
        self.used
    }

    /// Grows Q and P to `columns` columns (claimed against the memory budget).
    fn reserve(&mut self, columns: usize) -> Result<(), ModelError> {
        let n = self.q.nrows();
        budget::claim(
            "the Lanczos vectors",
            budget::bytes_of::<f64>(2 * n * (columns - self.q.ncols())),
        )?;
        self.q.resize_with(n, columns, |_, _| 0.0);
        self.p.resize_with(n, columns, |_, _| 0.0);
        Ok(())
    }

    /// One Lanczos step from the last column q_j: w = K⁻¹M q_j, M-orthogonalized against
    /// the columns (α_j recorded); returns β = ‖w‖_M, with M w in `self.mw`.
    fn expand(
        &mut self,
        w: &mut [f64],
        m: SparseColMatRef<'_, usize, f64>,
        k_factor: &mut Cholesky,
    ) -> f64 {
        let j = self.used - 1;
        w.copy_from_slice(self.p.col_as_slice(j));
        k_factor.solve_in_place(w);
        let h = self.orthogonalize(w);
        self.alpha.push(h[j]);
        self.m_norm(w, m)
    }

    /// Largest |α| so far: the scale of T, for the breakdown test.
    fn scale(&self) -> f64 {
        self.alpha.iter().fold(0.0f64, |a, x| a.max(x.abs()))
    }

    /// ‖w‖_M, leaving M w in `self.mw`.
    fn m_norm(&mut self, w: &[f64], m: SparseColMatRef<'_, usize, f64>) -> f64 {
        m_norm(m, w, &mut self.mw)
    }

    /// Makes `w` M-orthogonal to the columns so far (classical Gram–Schmidt twice) and
    /// returns the summed coefficients Qᵀ M w.
    fn orthogonalize(&self, w: &mut [f64]) -> Vec<f64> {
        let j = self.used;
        let (q, p) = (self.q.subcols(0, j), self.p.subcols(0, j));
        let mut total = vec![0.0; j];
        let mut h = Mat::<f64>::zeros(j, 1);
        for _ in 0..2 {
            let wc = MatRef::from_column_major_slice(w, w.len(), 1);
            matmul(&mut h, Accum::Replace, p.transpose(), wc, 1.0, Par::Seq);
            let wm = faer::MatMut::from_column_major_slice_mut(w, q.nrows(), 1);
            matmul(wm, Accum::Add, q, &h, -1.0, Par::Seq);
            total
                .iter_mut()
                .zip(h.col_as_slice(0))
                .for_each(|(t, x)| *t += x);
        }
        total
    }

    /// Appends w / ‖w‖_M (and M w / ‖w‖_M, from the last [`m_norm`](Self::m_norm)),
    /// coupled to the previous column by `coupling` in T.
    fn push(&mut self, w: &[f64], norm: f64, coupling: f64) -> Result<(), ModelError> {
        let j = self.used;
        if j == self.q.ncols() {
            self.reserve((j + j / 2 + 1).min(self.q.nrows()))?;
        }
        for (column, x) in [
            (self.q.col_as_slice_mut(j), w),
            (self.p.col_as_slice_mut(j), &self.mw[..]),
        ] {
            column.iter_mut().zip(x).for_each(|(c, x)| *c = x / norm);
        }
        if j > 0 {
            self.beta.push(coupling);
        }
        self.used += 1;
        Ok(())
    }

    /// Appends the start vector `w` (orthogonalized, M-normalized), uncoupled from the rest.
    fn push_start(
        &mut self,
        w: &mut [f64],
        m: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), ModelError> {
        self.orthogonalize(w);
        let norm = self.m_norm(w, m);
        self.push(w, norm, 0.0)
    }

    /// The `count` largest Ritz pairs if all have converged, given the residual coupling β
    /// of the next (not yet appended) vector.
    fn converged(&self, count: usize, beta: f64) -> Option<Modes> {
        let k = self.used;
        if k < count {
            return None;
        }
        let t = DMatrix::from_fn(k, k, |i, j| match i.abs_diff(j) {
            0 => self.alpha[i],
            1 => self.beta[i.min(j)],
            _ => 0.0,
        });
        let eigen = SymmetricEigen::new(t);
        let mut order: Vec<usize> = (0..k).collect();
        order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
        let wanted = &order[..count];
        let converged = wanted.iter().all(|&i| {
            let theta = eigen.eigenvalues[i];
            theta > 0.0 && beta * eigen.eigenvectors[(k - 1, i)].abs() <= TOL * theta
        });
        if !converged {
            return None;
        }
        let s = Mat::from_fn(k, count, |r, c| eigen.eigenvectors[(r, wanted[c])]);
        let mut vectors = Mat::zeros(self.q.nrows(), count);
        matmul(
            &mut vectors,
            Accum::Replace,
            self.q.subcols(0, k),
            &s,
            1.0,
            Par::Seq,
        );
        Some(Modes {
            values: wanted.iter().map(|&i| 1.0 / eigen.eigenvalues[i]).collect(),
            vectors,
            steps: k,
        })
    }
}
