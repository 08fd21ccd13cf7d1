//! y ← y + A x for the symmetric matrices of a `Structure` (`solve`) (stiffness, mass and
//! damping share one pattern). By symmetry column j of A is row j, so every y_j is gathered
//! from its column ([`super::sweeps::gather`]): no scattered stores, several partial sums,
//! 32-bit indices, and consecutive columns with the same rows (the two dofs of a node of a 2D
//! mesh) gathered together, loading each row index and x_i once for both. On the default
//! abdomen's mass matrix this replaced faer's general product; see BENCHMARKS.md,
//! "Full-order step".

use faer::sparse::{SymbolicSparseColMat, SymbolicSparseColMatRef};

use super::cholesky::narrow;
use super::ordering;
use super::sweeps::gather;
use crate::error::ModelError;

/// The pattern of a symmetric matrix (both triangles stored) in 32-bit indices, with its
/// columns grouped: `groups` holds the first column of every group of one or two columns with
/// the same rows, then n.
#[derive(Debug, Clone)]
pub struct SymmetricProduct {
    pattern: SymbolicSparseColMat<u32>,
    groups: Vec<u32>,
}

impl SymmetricProduct {
    /// The product for a symmetric pattern; refused if its entries do not fit 32-bit indices.
    pub fn new(pattern: SymbolicSparseColMatRef<'_, usize>) -> Result<Self, ModelError> {
        let groups = ordering::groups(pattern, 2);
        let pattern = narrow(pattern)?;
        // Column indices fit 32 bits: `narrow` accepted the pattern.
        let groups = groups.into_iter().map(|j| j as u32).collect();
        Ok(Self { pattern, groups })
    }

    /// y ← y + α A x for the values `a` of a symmetric matrix on this pattern. Allocates
    /// nothing.
    pub fn mul_add(&self, a: &[f64], x: &[f64], alpha: f64, y: &mut [f64]) {
        let column = |j: usize| self.pattern.col_range(j);
        for g in self.groups.windows(2) {
            let j = g[0] as usize;
            let rows = self.pattern.row_idx_of_col_raw(j);
            if g[1] - g[0] == 2 {
                let (a0, a1) = (&a[column(j)], &a[column(j + 1)]);
                let [s0, s1] = gather::<2, 2>(rows, |b, t| [a0, a1][b][t], x);
                y[j] += alpha * s0;
                y[j + 1] += alpha * s1;
            } else {
                let a0 = &a[column(j)];
                let [s] = gather::<1, 4>(rows, |_, t| a0[t], x);
                y[j] += alpha * s;
            }
        }
    }
}

/// The dot product aᵀb.
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
