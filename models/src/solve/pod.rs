//! A reduced basis by proper orthogonal decomposition of training states (the method of
//! snapshots, Sirovich, Q. Appl. Math. 45 (1987) 561–571; Kerschen, Golinval, Vakakis &
//! Bergman, Nonlinear Dyn. 41 (2005) 147–169) in the energy inner product of K, the tangent
//! at rest: with the snapshots as the columns of S, the correlation C = Sᵀ K S has
//! eigenpairs (λ_i, v_i), descending, and φ_i = S v_i / √λ_i are K-orthonormal. The fewest r
//! vectors are kept for which the snapshots' part outside their span is at most `tolerance`
//! of the whole in the energy norm: Σ_{i>r} λ_i ≤ tolerance² · Σ λ_i. The energy norm
//! weighs strain, which the stresses are read from: on the abdomen it gave a smaller basis
//! a far smaller error in the floor's stress than the M-norm (BENCHMARKS.md, "The
//! hyper-reduced abdomen's training"). The basis is then rotated by the Rayleigh–Ritz problem of (Φᵀ K Φ, Φᵀ M Φ):
//! M-orthonormal to round-off and K-orthogonal, like the modal bases ([`super::modal`]).

use std::time::Instant;

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};
use nalgebra::{DMatrix, SymmetricEigen};

use super::modal::{galerkin, ModalBasis};
use super::structure::Structure;
use crate::error::ModelError;

/// Eigenvalues of the correlation below this share of the largest are round-off: their
/// vectors are never kept.
const ROUND_OFF: f64 = 1e-13;

/// The POD basis of `snapshots` (free dofs each) on the structure `s` (its stiffness at
/// rest and its mass), of at most `max` vectors.
pub fn basis(
    s: &Structure,
    snapshots: &[Vec<f64>],
    tolerance: f64,
    max: usize,
) -> Result<ModalBasis, ModelError> {
    let clock = Instant::now();
    let (n, k) = (s.n(), snapshots.len());
    if let Some(i) = snapshots.iter().position(|x| x.len() != n) {
        return Err(ModelError::SizeMismatch {
            name: "snapshot",
            expected: n,
            got: snapshots[i].len(),
        });
    }
    let sm = Mat::from_fn(n, k, |i, j| snapshots[j][i]);
    let c = galerkin(s.stiffness(), &sm);
    let eigen = SymmetricEigen::new(DMatrix::from_fn(k, k, |i, j| c[(i, j)]));
    let mut order: Vec<usize> = (0..k).collect();
    order.sort_by(|&a, &b| eigen.eigenvalues[b].total_cmp(&eigen.eigenvalues[a]));
    let lambda: Vec<f64> = order
        .iter()
        .map(|&i| eigen.eigenvalues[i].max(0.0))
        .collect();
    let total: f64 = lambda.iter().sum();
    if total.is_nan() || total <= 0.0 {
        return Err(ModelError::LinearAlgebra(
            "the training states are all zero: nothing to build a POD basis from".into(),
        ));
    }
    let r = kept(&lambda, tolerance).min(max).max(1);
    let v = Mat::from_fn(k, r, |i, j| {
        eigen.eigenvectors[(i, order[j])] / lambda[j].sqrt()
    });
    let mut phi = Mat::zeros(n, r);
    matmul(&mut phi, Accum::Replace, &sm, &v, 1.0, Par::Seq);
    let (vectors, values) = rayleigh_ritz(s, phi)?;
    Ok(ModalBasis::from_parts(
        vectors,
        values,
        clock.elapsed().as_secs_f64(),
    ))
}

/// The fewest leading eigenvalues whose remainder is at most tolerance² of the sum (and
/// none of round-off size).
fn kept(lambda: &[f64], tolerance: f64) -> usize {
    let total: f64 = lambda.iter().sum();
    let mut rest = total;
    for (r, &l) in lambda.iter().enumerate() {
        if rest <= tolerance * tolerance * total || l <= ROUND_OFF * lambda[0] {
            return r;
        }
        rest -= l;
    }
    lambda.len()
}

/// Rotates the columns of `phi` onto the solutions of (Φᵀ K Φ) y = θ (Φᵀ M Φ) y, ascending:
/// the result is M-orthonormal and K-orthogonal; returns it with the θ.
fn rayleigh_ritz(s: &Structure, phi: Mat<f64>) -> Result<(Mat<f64>, Vec<f64>), ModelError> {
    let r = phi.ncols();
    let dense = |a: Mat<f64>| DMatrix::from_fn(r, r, |i, j| a[(i, j)]);
    let m = dense(galerkin(s.mass(), &phi));
    let k = dense(galerkin(s.stiffness(), &phi));
    let l = m
        .cholesky()
        .ok_or_else(|| {
            ModelError::LinearAlgebra("the POD vectors are not linearly independent".into())
        })?
        .l();
    let l_inv = l
        .clone()
        .try_inverse()
        .ok_or_else(|| ModelError::LinearAlgebra("singular POD mass".into()))?;
    let a = &l_inv * k * l_inv.transpose();
    let eigen = SymmetricEigen::new(0.5 * (&a + a.transpose()));
    let mut order: Vec<usize> = (0..r).collect();
    order.sort_by(|&x, &y| eigen.eigenvalues[x].total_cmp(&eigen.eigenvalues[y]));
    let rotation = l_inv.transpose() * &eigen.eigenvectors;
    let rot = Mat::from_fn(r, r, |i, j| rotation[(i, order[j])]);
    let mut out = Mat::zeros(phi.nrows(), r);
    matmul(&mut out, Accum::Replace, &phi, &rot, 1.0, Par::Seq);
    let values = order.iter().map(|&i| eigen.eigenvalues[i]).collect();
    Ok((out, values))
}
