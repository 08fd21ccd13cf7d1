//! Tests of the dynamics: the integrators on one degree of freedom and on small FE models,
//! modal reduction, finite strain in the implicit schemes, the full-order step against a
//! direct solve, and steps that allocate nothing. One module per file, linked as one binary.

mod fe;
mod finite_strain_dynamics;
mod full_order_step;
mod modal;
mod no_alloc;
mod sdof;

/// A sparse matrix as a dense nalgebra one, for the reference eigen solves.
pub fn dense(a: faer::sparse::SparseColMatRef<'_, usize, f64>) -> nalgebra::DMatrix<f64> {
    let d = a.to_dense();
    nalgebra::DMatrix::from_fn(d.nrows(), d.ncols(), |i, j| d[(i, j)])
}
