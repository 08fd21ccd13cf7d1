//! Static equilibrium K u = f with prescribed displacements by elimination (seed 002 §3.3,
//! eq. 3.3): K_ff u_f = f_f − K_fc u_c, solved by sparse Cholesky. The reduced matrix is
//! factorized once per stiffness; a new load or new prescribed values cost one solve.

use faer::sparse::SparseColMatRef;

use crate::assembly::{mul_add, Assembler, Dirichlet};
use crate::error::ModelError;
use crate::linalg::cholesky::{Cholesky, Factorization};

/// A static solver for one mesh and one set of constrained dofs.
#[derive(Debug)]
pub struct Statics {
    bc: Dirichlet,
    reduced: Vec<f64>,
    chol: Cholesky,
    rhs: Vec<f64>,
}

impl Statics {
    /// Symbolic analysis for the free–free part of `asm`'s pattern.
    pub fn new(
        asm: &Assembler,
        constrained: &[usize],
        factorization: Factorization,
    ) -> Result<Self, ModelError> {
        let bc = Dirichlet::new(asm, constrained)?;
        let chol = Cholesky::analyze(bc.symbolic().as_ref(), factorization)?;
        Ok(Self {
            reduced: vec![0.0; bc.nnz()],
            rhs: vec![0.0; bc.n_free()],
            bc,
            chol,
        })
    }

    /// A solver for another stiffness of the same pattern and constrained dofs: the
    /// symbolic analysis shared.
    pub fn same_pattern(&self) -> Result<Self, ModelError> {
        Ok(Self {
            bc: self.bc.clone(),
            reduced: vec![0.0; self.reduced.len()],
            chol: self.chol.same_pattern()?,
            rhs: vec![0.0; self.rhs.len()],
        })
    }

    /// Whether `other` solves with this one's symbolic analysis.
    pub fn shares_analysis(&self, other: &Statics) -> bool {
        self.chol.shares_analysis(&other.chol)
    }

    /// Forgets the factorization (its storage kept) until the next [`Self::factorize`].
    pub fn invalidate(&mut self) {
        self.chol.invalidate();
    }

    /// The dof split.
    pub fn dirichlet(&self) -> &Dirichlet {
        &self.bc
    }

    /// Numeric factorization of K_ff for the full stiffness values `k_full`.
    pub fn factorize(&mut self, k_full: &[f64]) -> Result<(), ModelError> {
        self.bc.combine(&[(1.0, k_full)], &mut self.reduced);
        self.chol.factorize(self.bc.matrix(&self.reduced))
    }

    /// Solves for the free dofs. On entry `u` (all dofs) holds the prescribed values at the
    /// constrained dofs; on return it holds the full solution. `k` is the full stiffness
    /// that was factorized; `f` the full load vector (entries at constrained dofs unused).
    pub fn solve(&mut self, k: SparseColMatRef<'_, usize, f64>, f: &[f64], u: &mut [f64]) {
        self.bc.reduce(f, &mut self.rhs);
        self.bc.subtract_prescribed(k.val(), u, &mut self.rhs);
        self.chol.solve_in_place(&mut self.rhs);
        self.bc.expand(&self.rhs, u);
    }
}

/// Nodal reaction forces r = K u − f (non-zero only at constrained dofs in equilibrium).
pub fn reactions(k: SparseColMatRef<'_, usize, f64>, u: &[f64], f: &[f64], r: &mut [f64]) {
    for (ri, fi) in r.iter_mut().zip(f) {
        *ri = -fi;
    }
    mul_add(k, u, 1.0, r);
}
