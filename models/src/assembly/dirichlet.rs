//! Prescribed displacements by elimination (seed 002 eq. 3.3): the constrained dofs are
//! removed from the system, and their prescribed values move to the right-hand side,
//!
//! K_ff u_f = f_f − K_fc u_c.
//!
//! The reduced (free–free) matrices get their own pattern, built once; their values are
//! gathered from the full matrices' values through a precomputed index list.

use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};

use super::Assembler;
use crate::error::ModelError;

const CONSTRAINED: usize = usize::MAX;

/// The split of dofs into free and constrained ones, and the reduced pattern.
#[derive(Debug, Clone)]
pub struct Dirichlet {
    constrained: Vec<usize>,
    equation: Vec<usize>,
    free: Vec<usize>,
    symbolic: SymbolicSparseColMat<usize>,
    gather: Vec<usize>,
    /// Stored entries of the full pattern.
    full_nnz: usize,
    /// K_fc: for each constrained dof (in `constrained` order) its entries in free rows,
    /// as (index into the full values, equation), from `coupling[ptr[i]..ptr[i + 1]]`.
    coupling: Vec<(usize, usize)>,
    coupling_ptr: Vec<usize>,
}

impl Dirichlet {
    /// Splits the dofs of `asm` into free and `constrained` ones (duplicates allowed).
    pub fn new(asm: &Assembler, constrained: &[usize]) -> Result<Self, ModelError> {
        let n = asm.n_dofs();
        let mut equation = vec![0; n];
        for &d in constrained {
            if d >= n {
                return Err(ModelError::InvalidParameter {
                    name: "constrained dof".into(),
                    value: d as f64,
                    reason: "is out of range",
                });
            }
            equation[d] = CONSTRAINED;
        }
        let mut free = Vec::with_capacity(n);
        for (dof, eq) in equation.iter_mut().enumerate() {
            if *eq != CONSTRAINED {
                *eq = free.len();
                free.push(dof);
            }
        }
        let full = asm.symbolic();
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut gather = Vec::new();
        for &col in &free {
            for k in full.col_ptr()[col]..full.col_ptr()[col + 1] {
                let eq = equation[full.row_idx()[k]];
                if eq != CONSTRAINED {
                    row_idx.push(eq);
                    gather.push(k);
                }
            }
            col_ptr.push(row_idx.len());
        }
        let symbolic =
            SymbolicSparseColMat::new_checked(free.len(), free.len(), col_ptr, None, row_idx);
        let mut constrained = constrained.to_vec();
        constrained.sort_unstable();
        constrained.dedup();
        let (mut coupling, mut coupling_ptr) = (Vec::new(), vec![0]);
        for &c in &constrained {
            for k in full.col_ptr()[c]..full.col_ptr()[c + 1] {
                let eq = equation[full.row_idx()[k]];
                if eq != CONSTRAINED {
                    coupling.push((k, eq));
                }
            }
            coupling_ptr.push(coupling.len());
        }
        Ok(Self {
            full_nnz: asm.nnz(),
            constrained,
            equation,
            free,
            symbolic,
            gather,
            coupling,
            coupling_ptr,
        })
    }

    /// Dofs of the full system.
    pub fn n_dofs(&self) -> usize {
        self.equation.len()
    }

    /// Stored entries of the full pattern (the assembler's).
    pub fn full_nnz(&self) -> usize {
        self.full_nnz
    }

    /// Number of free dofs (equations).
    pub fn n_free(&self) -> usize {
        self.free.len()
    }

    /// The constrained dofs, sorted.
    pub fn constrained(&self) -> &[usize] {
        &self.constrained
    }

    /// Global dof of each equation.
    pub fn free(&self) -> &[usize] {
        &self.free
    }

    /// Equation number of global dof `dof`, or `None` if constrained.
    pub fn equation(&self, dof: usize) -> Option<usize> {
        Some(self.equation[dof]).filter(|&e| e != CONSTRAINED)
    }

    /// Pattern of the reduced matrices.
    pub fn symbolic(&self) -> &SymbolicSparseColMat<usize> {
        &self.symbolic
    }

    /// Number of stored entries of a reduced matrix.
    pub fn nnz(&self) -> usize {
        self.gather.len()
    }

    /// Views reduced `values` as a matrix.
    pub fn matrix<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        SparseColMatRef::new(self.symbolic.as_ref(), values)
    }

    /// out = Σ cᵢ · (full matrix i restricted to the free dofs), for matrices on the full
    /// pattern (e.g. an effective matrix a·M + b·C + K).
    pub fn combine(&self, terms: &[(f64, &[f64])], out: &mut [f64]) {
        for (o, &k) in out.iter_mut().zip(&self.gather) {
            *o = terms.iter().map(|(c, v)| c * v[k]).sum();
        }
    }

    /// Restricts a full-length vector to the free dofs.
    pub fn reduce(&self, full: &[f64], out: &mut [f64]) {
        for (o, &d) in out.iter_mut().zip(&self.free) {
            *o = full[d];
        }
    }

    /// Writes free values into a full-length vector (constrained entries untouched).
    pub fn expand(&self, reduced: &[f64], full: &mut [f64]) {
        for (&r, &d) in reduced.iter().zip(&self.free) {
            full[d] = r;
        }
    }

    /// out_c ← out_c + Σ_f K_cf x_f at the constrained dofs of the full-length `out`, for
    /// full values `k_full` of a symmetric matrix (K_cf = K_fcᵀ, read from the coupling
    /// entries) and free values `x`: the forces at the held dofs of a displacement of the
    /// free ones (a reaction's change).
    pub fn add_coupled(&self, k_full: &[f64], x: &[f64], out: &mut [f64]) {
        for (i, &c) in self.constrained.iter().enumerate() {
            out[c] += self.coupling[self.coupling_ptr[i]..self.coupling_ptr[i + 1]]
                .iter()
                .map(|&(k, eq)| k_full[k] * x[eq])
                .sum::<f64>();
        }
    }

    /// out ← out − K_fc u_c, for full stiffness values `k_full` (on the pattern this split
    /// was made for), reading the prescribed values u_c from the constrained entries of the
    /// full-length vector `u` (seed 002 eq. 3.3). Visits only the coupling entries.
    pub fn subtract_prescribed(&self, k_full: &[f64], u: &[f64], out: &mut [f64]) {
        for (i, &c) in self.constrained.iter().enumerate() {
            let uc = u[c];
            if uc == 0.0 {
                continue;
            }
            for &(k, eq) in &self.coupling[self.coupling_ptr[i]..self.coupling_ptr[i + 1]] {
                out[eq] -= k_full[k] * uc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn reduced_system_of_a_spring_chain() {
        // 0 -k1- 1 -k2- 2, dof 0 prescribed to 0.5, dof 2 prescribed to 0: u1 = k1·0.5/(k1+k2).
        let asm = Assembler::new(3, 1, &[[0, 1], [1, 2]]);
        let mut k = asm.zeros();
        asm.add(&mut k, 0, &(Matrix2::new(1.0, -1.0, -1.0, 1.0) * 2.0));
        asm.add(&mut k, 1, &(Matrix2::new(1.0, -1.0, -1.0, 1.0) * 3.0));
        let bc = Dirichlet::new(&asm, &[2, 0, 2]).unwrap();
        assert_eq!(bc.n_free(), 1);
        assert_eq!(bc.constrained(), &[0, 2]);
        let mut kr = vec![0.0; bc.nnz()];
        bc.combine(&[(1.0, &k)], &mut kr);
        assert_eq!(kr, vec![5.0]);
        let mut rhs = vec![0.0];
        bc.subtract_prescribed(&k, &[0.5, 99.0, 0.0], &mut rhs);
        assert_eq!(rhs[0] / kr[0], 0.2);
        // The held ends feel −k1 and −k2 per unit displacement of the middle.
        let mut reactions = vec![0.0; 3];
        bc.add_coupled(&k, &[1.0], &mut reactions);
        assert_eq!(reactions, vec![-2.0, 0.0, -3.0]);
        assert!(Dirichlet::new(&asm, &[3])
            .unwrap_err()
            .to_string()
            .contains("constrained dof"));
    }
}
