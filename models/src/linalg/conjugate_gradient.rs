//! Conjugate gradients (faer's `matrix_free::conjugate_gradient`) on a sparse symmetric
//! positive definite matrix A, preconditioned by the Cholesky factor of a nearby matrix —
//! Newton's kept tangent, factorized at an earlier iterate or in single precision: the
//! solution of A itself, at the cost of a few back-substitutions with the factor there is
//! and products with A, instead of a factorization of A.

use std::sync::Mutex;

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::matrix_free::conjugate_gradient::{
    conjugate_gradient, conjugate_gradient_scratch, CgError, CgParams,
};
use faer::matrix_free::{InitialGuessStatus, LinOp, Precond};
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::sparse::SparseColMatRef;
use faer::{Accum, ColMut, ColRef, MatMut, MatRef, Par};

use super::Cholesky;
use crate::error::ModelError;

/// The matrix as faer's linear operator.
#[derive(Debug)]
struct Operator<'a>(SparseColMatRef<'a, usize, f64>);

impl LinOp<f64> for Operator<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.0.nrows()
    }

    fn ncols(&self) -> usize {
        self.0.ncols()
    }

    fn apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, _: &mut MemStack) {
        sparse_dense_matmul(out, Accum::Replace, self.0, rhs, 1.0, par);
    }

    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, s: &mut MemStack) {
        self.apply(out, rhs, par, s);
    }
}

/// The factor as faer's preconditioner (its solve works in buffers of its own, hence the
/// lock: faer applies preconditioners through shared references).
#[derive(Debug)]
struct Factor<'a>(Mutex<&'a mut Cholesky>);

impl LinOp<f64> for Factor<'_> {
    fn apply_scratch(&self, _rhs_ncols: usize, _par: Par) -> StackReq {
        StackReq::EMPTY
    }

    fn nrows(&self) -> usize {
        self.0.lock().map_or(0, |c| c.n())
    }

    fn ncols(&self) -> usize {
        self.nrows()
    }

    fn apply(&self, mut out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, _: Par, _: &mut MemStack) {
        out.copy_from(rhs);
        let mut factor = self
            .0
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        for j in 0..out.ncols() {
            let column = out.as_mut().col_mut(j).try_as_col_major_mut();
            factor.solve_in_place(column.expect("a column of faer's workspace").as_slice_mut());
        }
    }

    fn conj_apply(&self, out: MatMut<'_, f64>, rhs: MatRef<'_, f64>, par: Par, s: &mut MemStack) {
        self.apply(out, rhs, par, s);
    }
}

impl Precond<f64> for Factor<'_> {}

/// Solves A x = b to ‖A x − b‖ ≤ `tolerance` ‖b‖ from the start `x` (its content on entry),
/// preconditioned by `factor` (factorized, of A's size). Returns the iterations taken. A
/// matrix or factor found not positive definite, or no convergence in `max_iterations`, is
/// an error naming the residual reached.
pub fn solve(
    a: SparseColMatRef<'_, usize, f64>,
    factor: &mut Cholesky,
    b: &[f64],
    x: &mut [f64],
    tolerance: f64,
    max_iterations: usize,
) -> Result<usize, ModelError> {
    let (operator, precond) = (Operator(a), Factor(Mutex::new(factor)));
    let par = Par::Seq;
    let mut buffer = MemBuffer::new(conjugate_gradient_scratch(&precond, &operator, 1, par));
    let params = CgParams {
        initial_guess: InitialGuessStatus::MaybeNonZero,
        abs_tolerance: 0.0,
        rel_tolerance: tolerance,
        max_iters: max_iterations,
        ..Default::default()
    };
    let result = conjugate_gradient(
        ColMut::from_slice_mut(x).as_mat_mut(),
        &precond,
        &operator,
        ColRef::from_slice(b).as_mat(),
        params,
        |_| {},
        par,
        MemStack::new(&mut buffer),
    );
    result.map(|info| info.iter_count).map_err(|e| {
        ModelError::LinearAlgebra(match e {
            CgError::NonPositiveDefiniteOperator => {
                "conjugate gradients: the matrix is not positive definite".into()
            }
            CgError::NonPositiveDefinitePreconditioner => {
                "conjugate gradients: the preconditioner is not positive definite".into()
            }
            CgError::NoConvergence { rel_residual, .. } => format!(
                "conjugate gradients did not converge in {max_iterations} iterations \
                 (relative residual {rel_residual:.1e}, asked {tolerance:.1e})"
            ),
        })
    })
}
