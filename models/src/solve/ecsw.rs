//! Hyper-reduction of finite-strain internal forces by energy-conserving sampling and
//! weighting (ECSW: Farhat, Avery, Chapman & Cortial, IJNME 98 (2014) 625–662; Farhat,
//! Chapman & Avery, IJNME 102 (2015) 1077–1110).
//!
//! In a reduced basis Φ (u ≈ Φ q, [`ModalBasis`]) the reduced internal force is a sum over the
//! elements, Φᵀ f_int(Φ q) = Σ_e Φ_eᵀ f_e(Φ_e q), Φ_e the rows of Φ at element e's dofs.
//! ECSW replaces it by Σ_{e∈S} w_e Φ_eᵀ f_e(Φ_e q) over a few sampled elements S with
//! positive weights, fitted to the reduced forces of training states ([`nnls`]):
//! ‖G w − b‖ ≤ τ ‖b‖, column e of G holding element e's reduced forces at every training
//! state (each state's block scaled by its own ‖b_s‖), b = G·1. Positive weights keep the
//! hyper-reduced force the gradient of a positive combination of element energies: the
//! reduced tangent is symmetric and the scheme keeps the energy balance of the full one (the
//! "energy-conserving" of the name). Online a force and tangent evaluation costs the sampled
//! elements only, nothing proportional to the full mesh.

use std::sync::{Arc, Mutex};

use faer::linalg::matmul::matmul;
use faer::linalg::matmul::triangular::{self, BlockStructure};
use faer::sparse::SymbolicSparseColMat;
use faer::{Accum, Mat, MatRef, Par};
use rayon::prelude::*;

use super::modal::ModalBasis;
use super::newton::norm_of;
use super::structure::Structure;
use crate::assembly::{ElementForces, InternalForces};
use crate::error::ModelError;

/// A sampled element: its weight and where its dofs' rows lie in the stacked Φ_S.
#[derive(Debug)]
struct Sampled {
    element: usize,
    weight: f64,
    first: usize,
    dofs: usize,
}

/// Work arrays of one evaluation.
#[derive(Debug)]
struct Scratch {
    /// Φ_S q and the weighted element forces, stacked like Φ_S.
    u: Vec<f64>,
    f: Vec<f64>,
    /// One element's tangent (column-major).
    ke: Vec<f64>,
    /// w_e K_e Φ_e, stacked like Φ_S.
    kphi: Mat<f64>,
    /// The reduced tangent Φ_Sᵀ (w K Φ)_S, r × r.
    kr: Mat<f64>,
}

/// What a training found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fit {
    /// Training states the weights were fitted on.
    pub states: usize,
    /// Elements sampled (weights > 0) of all.
    pub sampled: usize,
    /// Elements in all: the candidates the sampling chose from.
    pub elements: usize,
    /// ‖G w − b‖ / ‖b‖ reached.
    pub residual: f64,
}

/// The hyper-reduced internal forces q ↦ Σ_{e∈S} w_e Φ_eᵀ f_e(Φ_e q) with their tangent.
/// The rows Φ_e of the sampled elements are stacked into one matrix Φ_S (zero rows for
/// constrained dofs), so that gathering the element displacements, scattering the weighted
/// forces and projecting the tangents are each one dense product.
pub struct HyperReduced {
    elements: Arc<dyn ElementForces>,
    sampled: Vec<Sampled>,
    phi: Mat<f64>,
    scratch: Mutex<Scratch>,
}

impl std::fmt::Debug for HyperReduced {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("HyperReduced")
            .field("r", &self.dim())
            .field("sampled", &self.sampled.len())
            .finish()
    }
}

impl HyperReduced {
    /// Every element at weight one: the Galerkin projection Φᵀ f_int(Φ q) itself.
    pub fn galerkin(
        elements: Arc<dyn ElementForces>,
        basis: &ModalBasis,
        full: &Structure,
    ) -> Self {
        let weights = vec![1.0; elements.count()];
        Self::with_weights(elements, basis, full, &weights)
    }

    /// ECSW fitted to the reduced forces at `states` (displacements of all dofs, projected
    /// onto the basis first: the fit is made where the reduced model will evaluate) to the
    /// relative tolerance `tolerance`; `before(i)` sets what the forces read besides the
    /// displacement at state i (the abdomen: the diaphragm's active tension).
    pub fn train(
        elements: Arc<dyn ElementForces>,
        basis: &ModalBasis,
        full: &Structure,
        states: &[Vec<f64>],
        mut before: impl FnMut(usize),
        tolerance: f64,
    ) -> Result<(Self, Fit), ModelError> {
        let all = Self::galerkin(elements.clone(), basis, full);
        let (r, n_el) = (basis.dim(), elements.count());
        let rows = r.saturating_mul(states.len());
        // G, and GᵀG in the NNLS.
        crate::budget::claim(
            "the hyper-reduction's fit (G and GᵀG)",
            crate::budget::bytes_of::<f64>(n_el.saturating_mul(rows.saturating_add(n_el))),
        )?;
        let mut g = Mat::<f64>::zeros(rows, n_el);
        let (mut free, mut q) = (vec![0.0; full.n()], vec![0.0; r]);
        for (s, u) in states.iter().enumerate() {
            full.dirichlet().reduce(u, &mut free);
            basis.coordinates(full.mass(), &free, &mut q);
            before(s);
            let blocks = all.element_forces(&q)?;
            let scale = block_norm(&blocks, r);
            for (e, block) in blocks.chunks(r).enumerate() {
                for (i, x) in block.iter().enumerate() {
                    g[(s * r + i, e)] = x / scale;
                }
            }
        }
        let b: Vec<f64> = (0..g.nrows()).map(|i| g.row(i).iter().sum()).collect();
        let weights = nnls(g.as_ref(), &b, tolerance);
        let residual = relative_residual(g.as_ref(), &weights, &b);
        if residual > tolerance {
            return Err(ModelError::NotConverged {
                reached: residual,
                reason: format!(
                    "the hyper-reduction's weights fit the training forces to {residual:e} \
                     only, not to the tolerance {tolerance:e}"
                ),
            });
        }
        let hyper = Self::with_weights(elements, basis, full, &weights);
        let fit = Fit {
            states: states.len(),
            sampled: hyper.sampled.len(),
            elements: n_el,
            residual,
        };
        Ok((hyper, fit))
    }

    /// The elements of positive weight with their rows of Φ.
    fn with_weights(
        elements: Arc<dyn ElementForces>,
        basis: &ModalBasis,
        full: &Structure,
        weights: &[f64],
    ) -> Self {
        let r = basis.dim();
        let bc = full.dirichlet();
        let mut dofs = Vec::new();
        let mut rows: Vec<Option<usize>> = Vec::new();
        let mut sampled = Vec::new();
        let mut largest = 0;
        for e in (0..elements.count()).filter(|&e| weights[e] > 0.0) {
            elements.dofs(e, &mut dofs);
            largest = largest.max(dofs.len());
            sampled.push(Sampled {
                element: e,
                weight: weights[e],
                first: rows.len(),
                dofs: dofs.len(),
            });
            rows.extend(dofs.iter().map(|&d| bc.equation(d)));
        }
        let phi = Mat::from_fn(rows.len(), r, |i, j| {
            rows[i].map_or(0.0, |row| basis.column(j)[row])
        });
        let scratch = Scratch {
            u: vec![0.0; rows.len()],
            f: vec![0.0; rows.len()],
            ke: vec![0.0; largest * largest],
            kphi: Mat::zeros(rows.len(), r),
            kr: Mat::zeros(r, r),
        };
        Self {
            elements,
            sampled,
            phi,
            scratch: Mutex::new(scratch),
        }
    }

    /// The number of sampled elements.
    pub fn sampled(&self) -> usize {
        self.sampled.len()
    }

    /// The reduced dimension r.
    pub fn dim(&self) -> usize {
        self.phi.ncols()
    }

    /// Each sampled element's unweighted reduced force Φ_eᵀ f_e(Φ_e q), r values each
    /// (training; in parallel).
    fn element_forces(&self, q: &[f64]) -> Result<Vec<f64>, ModelError> {
        let r = self.dim();
        let mut u = vec![0.0; self.phi.nrows()];
        gather(self.phi.as_ref(), q, &mut u);
        let mut out = vec![0.0; r * self.sampled.len()];
        out.par_chunks_mut(r)
            .zip(&self.sampled)
            .try_for_each(|(out, s)| {
                let rows = s.first..s.first + s.dofs;
                let mut fe = vec![0.0; s.dofs];
                self.elements
                    .evaluate(s.element, &u[rows.clone()], &mut fe, None)?;
                let phi_e = self.phi.subrows(s.first, s.dofs);
                for (j, o) in out.iter_mut().enumerate() {
                    *o = phi_e.col(j).iter().zip(&fe).map(|(p, f)| p * f).sum();
                }
                Ok(())
            })?;
        Ok(out)
    }

    /// f = Σ w_e Φ_eᵀ f_e(Φ_e q) and, when asked, the tangent K = Σ w_e Φ_eᵀ K_e Φ_e
    /// (r × r, column-major). Allocates nothing.
    pub fn evaluate(
        &self,
        q: &[f64],
        f: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        let r = self.dim();
        let mut guard = self.scratch.lock().unwrap_or_else(|p| p.into_inner());
        let w = &mut *guard;
        gather(self.phi.as_ref(), q, &mut w.u);
        let tangent = k.is_some();
        for s in &self.sampled {
            let rows = s.first..s.first + s.dofs;
            let ke = tangent.then_some(&mut w.ke[..s.dofs * s.dofs]);
            self.elements
                .evaluate(s.element, &w.u[rows.clone()], &mut w.f[rows.clone()], ke)?;
            w.f[rows].iter_mut().for_each(|x| *x *= s.weight);
            if tangent {
                let ke = MatRef::from_column_major_slice(&w.ke[..s.dofs * s.dofs], s.dofs, s.dofs);
                let dst = w.kphi.as_mut().subrows_mut(s.first, s.dofs);
                let phi_e = self.phi.subrows(s.first, s.dofs);
                matmul(dst, Accum::Replace, ke, phi_e, s.weight, Par::Seq);
            }
        }
        let fm = MatRef::from_column_major_slice(&w.f, w.f.len(), 1);
        let out = faer::MatMut::from_column_major_slice_mut(f, r, 1);
        matmul(out, Accum::Replace, self.phi.transpose(), fm, 1.0, Par::Seq);
        if let Some(k) = k {
            // Φ_Sᵀ (K Φ)_S is symmetric: its lower triangle, mirrored.
            triangular::matmul(
                &mut w.kr,
                BlockStructure::TriangularLower,
                Accum::Replace,
                self.phi.transpose(),
                BlockStructure::Rectangular,
                &w.kphi,
                BlockStructure::Rectangular,
                1.0,
                Par::Seq,
            );
            for j in 0..r {
                for i in 0..r {
                    k[i + r * j] = w.kr[(i.max(j), i.min(j))];
                }
            }
        }
        Ok(())
    }

    /// The internal forces of the reduced structure (r dofs, none constrained) whose
    /// pattern is `pattern`: the tangent's entries outside the pattern are left out (a
    /// pattern holding every entry gives the exact tangent).
    pub fn internal_forces(
        self: Arc<Self>,
        pattern: &SymbolicSparseColMat<usize>,
    ) -> Arc<dyn InternalForces> {
        let r = self.dim();
        Arc::new(OnPattern {
            col_ptr: pattern.col_ptr().to_vec(),
            row_idx: pattern.row_idx().to_vec(),
            dense: Mutex::new(vec![0.0; r * r]),
            hyper: self,
        })
    }
}

/// The hyper-reduced forces with their tangent on a sparse pattern of the r × r matrix.
struct OnPattern {
    hyper: Arc<HyperReduced>,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    /// The dense tangent the pattern's entries are read from.
    dense: Mutex<Vec<f64>>,
}

impl InternalForces for OnPattern {
    fn internal(&self, q: &[f64], f: &mut [f64], k: Option<&mut [f64]>) -> Result<(), ModelError> {
        let Some(k) = k else {
            return self.hyper.evaluate(q, f, None);
        };
        let r = self.hyper.dim();
        let mut kr = self.dense.lock().unwrap_or_else(|p| p.into_inner());
        self.hyper.evaluate(q, f, Some(&mut kr))?;
        for j in 0..r {
            for p in self.col_ptr[j]..self.col_ptr[j + 1] {
                k[p] = kr[self.row_idx[p] + r * j];
            }
        }
        Ok(())
    }
}

/// u = Φ q.
fn gather(phi: MatRef<'_, f64>, q: &[f64], u: &mut [f64]) {
    let q = MatRef::from_column_major_slice(q, q.len(), 1);
    let out = faer::MatMut::from_column_major_slice_mut(u, phi.nrows(), 1);
    matmul(out, Accum::Replace, phi, q, 1.0, Par::Seq);
}

/// The norm of the sum of a state's element blocks (1 where it vanishes: an unloaded
/// state).
fn block_norm(blocks: &[f64], r: usize) -> f64 {
    let mut sum = vec![0.0; r];
    for block in blocks.chunks(r) {
        sum.iter_mut().zip(block).for_each(|(s, x)| *s += x);
    }
    let norm = norm_of(&sum);
    if norm > 0.0 {
        norm
    } else {
        1.0
    }
}

/// ‖G w − b‖ / ‖b‖.
fn relative_residual(g: MatRef<'_, f64>, w: &[f64], b: &[f64]) -> f64 {
    let r = residual(g, w, b);
    norm_of(&r) / norm_of(b)
}

/// b − G w.
fn residual(g: MatRef<'_, f64>, w: &[f64], b: &[f64]) -> Vec<f64> {
    let mut r = b.to_vec();
    let w = MatRef::from_column_major_slice(w, w.len(), 1);
    let out = faer::MatMut::from_column_major_slice_mut(&mut r, b.len(), 1);
    matmul(out, Accum::Add, g, w, -1.0, Par::Seq);
    r
}

/// Lawson & Hanson's active-set algorithm for min ‖G w − b‖ subject to w ≥ 0 (Solving
/// Least Squares Problems, 1974, ch. 23, algorithm NNLS), stopped as soon as
/// ‖G w − b‖ ≤ `tolerance` · ‖b‖ (the sparse NNLS of ECSW, Chapman, Avery, Collins & Farhat,
/// IJNME 109 (2017) 1623–1654): columns enter the passive set one at a time, the one of
/// largest gradient Gᵀ(b − G w) first, so the weights stay sparse. The least-squares
/// problems on the passive set are solved with its QR factorization (`PassiveQr`), grown a
/// column at a time and shrunk by Givens rotations. Without a tolerance it stops at the
/// optimum (no column with a positive gradient left); the caller checks the residual.
pub fn nnls(g: MatRef<'_, f64>, b: &[f64], tolerance: f64) -> Vec<f64> {
    let n = g.ncols();
    let gram = Gram::new(g, b);
    let target = tolerance * tolerance * gram.btb;
    let mut w = vec![0.0; n];
    let mut qr = PassiveQr::new(b);
    // Columns that cannot enter the passive set as it is (dependent on it, or entering at
    // zero weight); free again once another column leaves it.
    let mut barred = vec![false; n];
    let mut gradient = vec![0.0; n];
    for _ in 0..ENTRIES_PER_COLUMN * n {
        if gram.gradient(&qr.passive, &w, &mut gradient) <= target {
            break;
        }
        let entering = (0..n)
            .filter(|&j| !barred[j] && w[j] == 0.0 && !qr.passive.contains(&j))
            .max_by(|&a, &b| gradient[a].total_cmp(&gradient[b]));
        let Some(j) = entering.filter(|&j| gradient[j] > 0.0) else {
            break;
        };
        if !qr.push(j, g.col(j).iter().copied().collect()) {
            barred[j] = true;
            continue;
        }
        while !qr.passive.is_empty() {
            let z = qr.solve();
            if z.iter().all(|&z| z > 0.0) {
                for (&k, z) in qr.passive.iter().zip(&z) {
                    w[k] = *z;
                }
                break;
            }
            // The longest step from w towards z that keeps w ≥ 0, and whose weight it zeroes.
            let (leaving, alpha) = qr
                .passive
                .iter()
                .zip(&z)
                .enumerate()
                .filter(|(_, (_, &z))| z <= 0.0)
                .map(|(i, (&k, &z))| {
                    let drop = w[k] - z;
                    (i, if drop > 0.0 { w[k] / drop } else { 0.0 })
                })
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .expect("some z is not positive");
            for (&k, z) in qr.passive.iter().zip(&z) {
                w[k] += alpha * (z - w[k]);
            }
            w[qr.passive[leaving]] = 0.0;
            let mut others_left = false;
            for i in (0..qr.passive.len()).rev() {
                let k = qr.passive[i];
                if w[k] <= 0.0 {
                    w[k] = 0.0;
                    qr.remove(i);
                    others_left |= k != j;
                }
            }
            if others_left {
                barred.fill(false);
            } else {
                barred[j] = true; // it left at once: it cannot help this passive set
            }
        }
    }
    w
}

/// The normal equations' data of min ‖G w − b‖: GᵀG, Gᵀb and bᵀb, so that an iteration of
/// [`nnls`] costs O(n p) for p passive columns instead of two passes over G (a third of
/// the training on the abdomen: BENCHMARKS.md, "The hyper-reduced abdomen's training").
/// GᵀG holds n² values (claimed with G by [`HyperReduced::train`]). The residual from
/// them, bᵀb − wᵀGᵀb − wᵀGᵀ(b − Gw), cancels: it resolves relative residuals down to about
/// 10⁻⁷ (√ of round-off); a smaller tolerance runs the NNLS to its optimum, and the caller
/// checks the true residual with G.
struct Gram {
    gtg: Mat<f64>,
    gtb: Vec<f64>,
    btb: f64,
}

impl Gram {
    fn new(g: MatRef<'_, f64>, b: &[f64]) -> Self {
        let n = g.ncols();
        let mut gtg = Mat::zeros(n, n);
        matmul(
            &mut gtg,
            Accum::Replace,
            g.transpose(),
            g,
            1.0,
            Par::rayon(0),
        );
        let mut gtb = vec![0.0; n];
        let bm = MatRef::from_column_major_slice(b, b.len(), 1);
        let out = faer::MatMut::from_column_major_slice_mut(&mut gtb, n, 1);
        matmul(out, Accum::Replace, g.transpose(), bm, 1.0, Par::Seq);
        Self {
            gtg,
            gtb,
            btb: b.iter().map(|x| x * x).sum(),
        }
    }

    /// Writes the gradient Gᵀ(b − G w) for weights `w`, non-zero on `passive` only, and
    /// returns ‖G w − b‖² = bᵀb − wᵀGᵀb − wᵀ Gᵀ(b − G w).
    fn gradient(&self, passive: &[usize], w: &[f64], out: &mut [f64]) -> f64 {
        out.copy_from_slice(&self.gtb);
        for &k in passive {
            let col = self.gtg.col(k);
            out.iter_mut()
                .zip(col.iter())
                .for_each(|(o, x)| *o -= w[k] * x);
        }
        let wg: f64 = passive.iter().map(|&k| w[k] * (self.gtb[k] + out[k])).sum();
        self.btb - wg
    }
}

/// Bounds the entries into the passive set (Lawson and Hanson's algorithm ends after
/// finitely many in exact arithmetic; this guards against round-off cycling).
const ENTRIES_PER_COLUMN: usize = 3;

/// A column below this share of its norm outside the passive columns' span is dependent on
/// them.
const DEPENDENT: f64 = 1e-10;

/// The QR factorization of the passive columns of G by Gram–Schmidt (twice, which keeps Q
/// orthonormal to round-off), with Qᵀ b: a column is added in O(m p), and the least-squares
/// solution R⁻¹ Qᵀ b costs O(p²).
struct PassiveQr<'a> {
    b: &'a [f64],
    passive: Vec<usize>,
    q: Vec<Vec<f64>>,
    /// R by columns (column k has k + 1 entries).
    r: Vec<Vec<f64>>,
    qtb: Vec<f64>,
}

impl<'a> PassiveQr<'a> {
    fn new(b: &'a [f64]) -> Self {
        Self {
            b,
            passive: Vec::new(),
            q: Vec::new(),
            r: Vec::new(),
            qtb: Vec::new(),
        }
    }

    /// Adds column `j` with values `col`; false (and nothing added) when it is dependent.
    fn push(&mut self, j: usize, mut col: Vec<f64>) -> bool {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let whole = norm_of(&col);
        let mut rcol = vec![0.0; self.q.len() + 1];
        for _ in 0..2 {
            for (k, q) in self.q.iter().enumerate() {
                let c = dot(q, &col);
                rcol[k] += c;
                col.iter_mut().zip(q).for_each(|(x, q)| *x -= c * q);
            }
        }
        let rest = norm_of(&col);
        if rest.is_nan() || rest <= DEPENDENT * whole {
            return false;
        }
        col.iter_mut().for_each(|x| *x /= rest);
        rcol[self.q.len()] = rest;
        self.qtb.push(dot(&col, self.b));
        self.q.push(col);
        self.r.push(rcol);
        self.passive.push(j);
        true
    }

    /// Removes the `i`-th passive column: R without it is upper Hessenberg from column i on,
    /// made triangular again by Givens rotations of rows (k, k + 1), applied to Q's columns
    /// and to Qᵀ b as well (Golub & Van Loan, Matrix Computations, 4th ed., §6.5.2).
    fn remove(&mut self, i: usize) {
        self.passive.remove(i);
        self.r.remove(i);
        for k in i..self.passive.len() {
            let (a, b) = (self.r[k][k], self.r[k][k + 1]);
            let rho = a.hypot(b);
            let (c, s) = (a / rho, b / rho);
            for col in &mut self.r[k..] {
                let (x, y) = (col[k], col[k + 1]);
                col[k] = c * x + s * y;
                col[k + 1] = c * y - s * x;
            }
            self.r[k].truncate(k + 1);
            let (x, y) = (self.qtb[k], self.qtb[k + 1]);
            self.qtb[k] = c * x + s * y;
            self.qtb[k + 1] = c * y - s * x;
            let (left, right) = self.q.split_at_mut(k + 1);
            for (x, y) in left[k].iter_mut().zip(right[0].iter_mut()) {
                (*x, *y) = (c * *x + s * *y, c * *y - s * *x);
            }
        }
        self.q.pop();
        self.qtb.pop();
    }

    /// z = R⁻¹ Qᵀ b, the least-squares solution on the passive columns.
    fn solve(&self) -> Vec<f64> {
        let p = self.passive.len();
        let mut z = self.qtb.clone();
        for k in (0..p).rev() {
            z[k] /= self.r[k][k];
            for i in 0..k {
                z[i] -= self.r[k][i] * z[k];
            }
        }
        z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A problem whose unconstrained least-squares solution has a negative entry: NNLS
    /// without a tolerance returns the constrained optimum, checked by the KKT conditions
    /// (w ≥ 0, gradient Gᵀ(b − G w) ≤ 0 where w = 0 and = 0 where w > 0).
    #[test]
    fn nnls_meets_the_kkt_conditions() {
        let g = Mat::from_fn(6, 4, |i, j| {
            ((i * 7 + j * 3) % 5) as f64 + 0.3 * f64::from(u8::from(i == j))
        });
        let b = [1.0, -2.0, 3.0, 0.5, -1.0, 2.0];
        let w = nnls(g.as_ref(), &b, 0.0);
        let r = residual(g.as_ref(), &w, &b);
        for (j, &wj) in w.iter().enumerate() {
            let grad: f64 = g.col(j).iter().zip(&r).map(|(g, r)| g * r).sum();
            assert!(wj >= 0.0);
            if wj > 0.0 {
                assert!(grad.abs() < 1e-12, "column {j}: {grad}");
            } else {
                assert!(grad <= 1e-12, "column {j}: {grad}");
            }
        }
        assert!(w.contains(&0.0), "the constraint is active: {w:?}");
        assert!(norm_of(&r) > 1.0, "b is outside the cone: {w:?}");
    }

    /// b in the cone of 60 pseudo-random columns of length 30 (b = G·1): a loose tolerance
    /// is met with fewer columns than a tight one, each to its tolerance.
    #[test]
    fn nnls_stops_at_its_tolerance_with_fewer_columns() {
        let (m, n) = (30, 60);
        let mut state = 12345_u64;
        let g = Mat::from_fn(m, n, |_, _| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1_u64 << 53) as f64
        });
        let b: Vec<f64> = (0..m).map(|i| g.row(i).iter().sum()).collect();
        let used = |w: &[f64]| w.iter().filter(|&&w| w > 0.0).count();
        let loose = nnls(g.as_ref(), &b, 1e-2);
        let tight = nnls(g.as_ref(), &b, 1e-10);
        assert!(relative_residual(g.as_ref(), &loose, &b) <= 1e-2);
        assert!(relative_residual(g.as_ref(), &tight, &b) <= 1e-10);
        assert!(
            used(&loose) < used(&tight),
            "{} and {}",
            used(&loose),
            used(&tight)
        );
    }
}
