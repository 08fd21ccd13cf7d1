//! Sparse linear algebra on the assemblers' patterns, below the assembly and the solvers:
//! the Cholesky factorization (faer's, with the symbolic analysis made once; a simplicial
//! factor swept by [`sweeps`]), conjugate gradients preconditioned by a factor, its fill-reducing orderings (AMD, METIS nested dissection),
//! the symmetric sparse products of the structures' matrices, and the reset of the
//! vector-register state before element kernels and sweeps.

pub mod cholesky;
pub mod conjugate_gradient;
pub mod ordering;
pub(crate) mod product;
mod sweeps;
pub(crate) mod vector_state;

pub use cholesky::{Cholesky, Factorization, Ordering};
