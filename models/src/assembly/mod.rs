//! Sparse assembly (seed 002 §3.3): the symmetric pattern of the global matrices is computed
//! once from element connectivity, together with a scatter map from each element's node pairs
//! to their dof blocks in the value array (one entry per node pair rather than per matrix
//! entry: for tet10, 100 pairs of 16 bytes instead of 900 indices of 8 bytes per element).
//! Re-assembling after a parameter change only rewrites values.
//!
//! All global matrices of one mesh (stiffness, mass, damping, effective matrices) share one
//! pattern and differ only in their value arrays.

pub mod dirichlet;
pub mod forces;
pub mod loads;
pub mod plane;
pub mod quadratic_plane;
pub mod tetrahedra;

pub use dirichlet::Dirichlet;
pub use forces::{ElementForces, InternalForces};

use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use nalgebra::{Const, Matrix, SMatrix, SMatrixView, SVector, Storage};
use rayon::prelude::*;

/// Sparse pattern over all dofs and the element scatter map.
#[derive(Debug, Clone)]
pub struct Assembler {
    symbolic: SymbolicSparseColMat<usize>,
    dofs_per_node: usize,
    /// For element e, `scatter[offsets[e]..offsets[e + 1]]` holds, for its node pair
    /// (a, b) at position a·n_nodes + b, the value index of the entry (dof 0 of a, dof 0 of
    /// b) and the distance between the columns of b's dofs: entry (dof i of a, dof j of b)
    /// is at index + j · distance + i (a node's rows are consecutive in every column).
    scatter: Vec<(usize, usize)>,
    offsets: Vec<usize>,
}

impl Assembler {
    /// Builds the pattern for `n_nodes` nodes with `dofs_per_node` dofs each (dof
    /// d of node n is `dofs_per_node · n + d`) from each element's node list. The coupling
    /// is worked out per node pair and expanded to dof blocks, which is ~9× less sorting
    /// than per dof in 3D. Element matrices use node-major local dof order.
    pub fn new<E: AsRef<[usize]>>(n_nodes: usize, dofs_per_node: usize, elements: &[E]) -> Self {
        let dpn = dofs_per_node;
        let mut adjacent: Vec<Vec<usize>> = vec![Vec::new(); n_nodes];
        for e in elements {
            let nodes = e.as_ref();
            for &a in nodes {
                adjacent[a].extend_from_slice(nodes);
            }
        }
        for list in &mut adjacent {
            list.sort_unstable();
            list.dedup();
        }
        let mut col_ptr = Vec::with_capacity(n_nodes * dpn + 1);
        let mut row_idx =
            Vec::with_capacity(adjacent.iter().map(Vec::len).sum::<usize>() * dpn * dpn);
        col_ptr.push(0);
        for list in &adjacent {
            for _ in 0..dpn {
                row_idx.extend(
                    list.iter()
                        .flat_map(|&m| (0..dpn).map(move |r| dpn * m + r)),
                );
                col_ptr.push(row_idx.len());
            }
        }
        let n_dofs = n_nodes * dpn;
        let symbolic = SymbolicSparseColMat::new_checked(n_dofs, n_dofs, col_ptr, None, row_idx);
        let mut scatter =
            Vec::with_capacity(elements.iter().map(|e| e.as_ref().len().pow(2)).sum());
        let mut offsets = Vec::with_capacity(elements.len() + 1);
        offsets.push(0);
        for e in elements {
            let nodes = e.as_ref();
            for &a in nodes {
                for &b in nodes {
                    let pos = adjacent[b]
                        .binary_search(&a)
                        .expect("a and b share an element");
                    let distance = adjacent[b].len() * dpn;
                    scatter.push((symbolic.col_ptr()[dpn * b] + pos * dpn, distance));
                }
            }
            offsets.push(scatter.len());
        }
        Self {
            symbolic,
            dofs_per_node: dpn,
            scatter,
            offsets,
        }
    }

    /// The pattern (all dofs, both triangles).
    pub fn symbolic(&self) -> &SymbolicSparseColMat<usize> {
        &self.symbolic
    }

    /// Number of stored entries.
    pub fn nnz(&self) -> usize {
        self.symbolic.row_idx().len()
    }

    /// Number of dofs.
    pub fn n_dofs(&self) -> usize {
        self.symbolic.ncols()
    }

    /// A zeroed value array for this pattern.
    pub fn zeros(&self) -> Vec<f64> {
        vec![0.0; self.nnz()]
    }

    /// Adds element matrix `ke` of element `element` into `values`.
    #[inline]
    pub fn add<const N: usize, S: Storage<f64, Const<N>, Const<N>>>(
        &self,
        values: &mut [f64],
        element: usize,
        ke: &Matrix<f64, Const<N>, Const<N>, S>,
    ) {
        let map = &self.scatter[self.offsets[element]..self.offsets[element + 1]];
        let dpn = self.dofs_per_node;
        let nodes = N / dpn;
        assert!(
            N.is_multiple_of(dpn) && map.len() == nodes * nodes,
            "an element matrix of {N} rows for element {element} of {} nodes",
            map.len().isqrt()
        );
        for (pair, &(start, distance)) in map.iter().enumerate() {
            let (a, b) = (dpn * (pair / nodes), dpn * (pair % nodes));
            for j in 0..dpn {
                let column = start + j * distance;
                for i in 0..dpn {
                    values[column + i] += ke[(a + i, b + j)];
                }
            }
        }
    }

    /// Views `values` as a matrix on this pattern.
    pub fn matrix<'a>(&'a self, values: &'a [f64]) -> SparseColMatRef<'a, usize, f64> {
        SparseColMatRef::new(self.symbolic.as_ref(), values)
    }
}

/// Index of entry (row, col) in the value array of `symbolic` (the entry must exist).
#[cfg(test)]
pub(crate) fn slot(symbolic: &SymbolicSparseColMat<usize>, row: usize, col: usize) -> usize {
    let start = symbolic.col_ptr()[col];
    let rows = &symbolic.row_idx()[start..symbolic.col_ptr()[col + 1]];
    start
        + rows
            .binary_search(&row)
            .expect("pattern contains every element coupling")
}

/// Elements whose forces and tangents are computed together, in parallel, before they are
/// added to the global arrays.
const BLOCK: usize = 256;

/// Fewer elements than this are assembled on the calling thread alone: rayon's hand-offs
/// would cost more than they save, and its job queue allocates now and then, which the
/// small systems' step loops must not (`models/tests/dynamics/no_alloc.rs`).
const PARALLEL_ELEMENTS: usize = 4 * BLOCK;

thread_local! {
    /// The element results of two blocks, kept between calls (grown, never shrunk).
    static BLOCKS: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Adds the internal forces of `elements` at `u` (all dofs, node-major with D / N dofs per
/// node) to `f` and their tangent to `k` (values on `asm`'s pattern, where they are the
/// elements from `first` on), without zeroing either. `kernel(e, u_e, f_e, k_e)` adds element
/// e's force and, when given, its tangent; an inverted element is reported with its index.
///
/// The elements go in blocks of [`BLOCK`]: from [`PARALLEL_ELEMENTS`] elements on, a
/// block's kernels run on rayon's threads while the block before is added in element order,
/// so the sums, and the results, are the same bit for bit on any number of threads; an
/// inverted element is named as the first of its block, whichever thread met one. The
/// block results live in a per-thread buffer kept between calls (a call made while it is in
/// use, e.g. from a task rayon runs while this one waits, uses a buffer of its own). Each
/// kernel starts with a clean vector-register state ([`crate::linalg::vector_state`]):
/// rayon's threads also run faer's factorizations.
pub fn add_internal<const N: usize, const D: usize>(
    elements: &[[usize; N]],
    first: usize,
    asm: &Assembler,
    u: &[f64],
    f: &mut [f64],
    mut k: Option<&mut [f64]>,
    kernel: impl Fn(
            usize,
            &SVector<f64, D>,
            &mut SVector<f64, D>,
            Option<&mut SMatrix<f64, D, D>>,
        ) -> Result<(), crate::element::total_lagrangian::Inverted>
        + Sync,
) -> Result<(), crate::error::ModelError> {
    let tangent = k.is_some();
    let stride = D + if tangent { D * D } else { 0 };
    // Room for the tangents even when only forces are asked: the buffer grows once.
    let need = 2 * BLOCK.min(elements.len()) * (D + D * D);
    let parallel = elements.len() >= PARALLEL_ELEMENTS;
    // Element e's force and tangent into `out`.
    let element = |e: usize, out: &mut [f64]| {
        // This thread may have run faer's wide kernels (its factorizations).
        crate::linalg::vector_state::clear();
        let el = &elements[e];
        let dpn = D / N;
        let ue = SVector::<f64, D>::from_fn(|row, _| u[dpn * el[row / dpn] + row % dpn]);
        let mut fe = SVector::<f64, D>::zeros();
        let mut m = tangent.then(SMatrix::<f64, D, D>::zeros);
        kernel(e, &ue, &mut fe, m.as_mut()).map_err(|inv| crate::error::ModelError::Inverted {
            element: e,
            j: inv.j,
        })?;
        out[..D].copy_from_slice(fe.as_slice());
        if let Some(m) = m {
            out[D..].copy_from_slice(m.as_slice());
        }
        Ok(())
    };
    let compute = |start: usize, out: &mut [f64]| {
        let end = (start + BLOCK).min(elements.len());
        let out = &mut out[..(end - start) * stride];
        let found = out
            .par_chunks_mut(stride)
            .with_min_len(if parallel { 1 } else { usize::MAX })
            .enumerate()
            .try_for_each(|(i, out)| element(start + i, out));
        match found {
            Ok(()) => Ok(()),
            // Whichever thread met an inverted element first: name the block's first one.
            Err(met) => Err(out
                .chunks_mut(stride)
                .enumerate()
                .try_for_each(|(i, out)| element(start + i, out))
                .err()
                .unwrap_or(met)),
        }
    };
    let add = |start: usize, out: &[f64], f: &mut [f64], k: Option<&mut [f64]>| {
        let end = (start + BLOCK).min(elements.len());
        let dpn = D / N;
        let mut k = k;
        for (e, out) in (start..end).zip(out.chunks(stride)) {
            for (a, &n) in elements[e].iter().enumerate() {
                for i in 0..dpn {
                    f[dpn * n + i] += out[dpn * a + i];
                }
            }
            if let Some(k) = k.as_deref_mut() {
                asm.add(
                    k,
                    first + e,
                    &SMatrixView::<f64, D, D>::from_slice(&out[D..]),
                );
            }
        }
    };
    let mut run = |buffer: &mut Vec<f64>| {
        if buffer.len() < need {
            buffer.resize(need, 0.0);
        }
        let (mut this, mut next) = buffer[..need].split_at_mut(need / 2);
        compute(0, this)?;
        for start in (0..elements.len()).step_by(BLOCK) {
            let after = start + BLOCK;
            let mut added = || add(start, this, f, k.as_deref_mut());
            let mut computed = || match after < elements.len() {
                true => compute(after, next),
                false => Ok(()),
            };
            if parallel {
                rayon::join(added, computed).1?;
            } else {
                added();
                computed()?;
            }
            std::mem::swap(&mut this, &mut next);
        }
        Ok(())
    };
    BLOCKS.with(move |b| match b.try_borrow_mut() {
        Ok(mut buffer) => run(&mut buffer),
        Err(_) => run(&mut Vec::new()),
    })
}

/// y ← y + α A x for a matrix on an assembler's pattern (no allocation).
pub fn mul_add(a: SparseColMatRef<'_, usize, f64>, x: &[f64], alpha: f64, y: &mut [f64]) {
    use faer::{Accum, ColMut, ColRef, Par};
    let x = ColRef::from_slice(x).as_mat();
    let y = ColMut::from_slice_mut(y).as_mat_mut();
    faer::sparse::linalg::matmul::sparse_dense_matmul(y, Accum::Add, a, x, alpha, Par::Seq);
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    /// The parallel assembly (a neo-Hookean block of 6,720 tetrahedra, beyond
    /// `PARALLEL_ELEMENTS`) gives the same forces and tangent, bit for bit, on rayon pools of
    /// one and two threads; an inverted element is named alike on both (the block's first).
    #[test]
    fn parallel_assembly_is_bit_identical_on_any_number_of_threads() {
        use crate::assembly::tetrahedra::Solid;
        use crate::element::{Elastic, Law, Material};
        let mesh = crate::mesh::generate::block([100.0, 80.0, 17.0], [6, 16, 14]).unwrap();
        assert!(mesh.tets().len() >= PARALLEL_ELEMENTS);
        let material = Material::new(Law::NeoHookean, Elastic::new("m", 0.0385, 0.43).unwrap());
        let solid = Solid::linear(&mesh, material);
        let asm = Assembler::new(solid.nodes().len(), 3, &solid.connectivity());
        let mut u: Vec<f64> = solid
            .nodes()
            .iter()
            .flat_map(|p| [0.01 * p[1].sin(), p[1] / 80.0, 0.02 * (p[0] * p[2]).cos()])
            .collect();
        let run = |threads: usize, u: &[f64]| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let (mut f, mut k) = (vec![0.0; u.len()], asm.zeros());
            let result = pool.install(|| solid.add_internal(&asm, u, &mut f, Some(&mut k)));
            (result.map_err(|e| e.to_string()), f, k)
        };
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let (one, two) = (run(1, &u), run(2, &u));
        assert!(one.0.is_ok());
        assert_eq!(bits(&one.1), bits(&two.1));
        assert_eq!(bits(&one.2), bits(&two.2));
        // Fold the nodes of the last quarter of the elements through themselves.
        for n in mesh.tets()[mesh.tets().len() * 3 / 4..].iter().flatten() {
            u[3 * n + 1] = -2.0 * solid.nodes()[*n][1];
        }
        let (one, two) = (run(1, &u), run(2, &u));
        assert!(one.0.is_err(), "{:?}", one.0);
        assert_eq!(one.0, two.0);
    }

    #[test]
    fn two_dof_nodes_scatter_to_the_right_slots() {
        // Two 2-node elements sharing node 1, 2 dofs per node: entry (a, b) of element e
        // must land at global (dof(a), dof(b)).
        let elements = [[0usize, 1], [1, 2]];
        let asm = Assembler::new(3, 2, &elements);
        for (e, nodes) in elements.iter().enumerate() {
            let dofs: Vec<usize> = nodes.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect();
            let mut v = asm.zeros();
            let ke = nalgebra::SMatrix::<f64, 4, 4>::from_fn(|r, c| (10 * r + c) as f64 + 1.0);
            asm.add(&mut v, e, &ke);
            let dense = asm.matrix(&v).to_dense();
            for r in 0..4 {
                for c in 0..4 {
                    assert_eq!(dense[(dofs[r], dofs[c])], ke[(r, c)]);
                }
            }
        }
        assert_eq!(asm.nnz(), 2 * 2 * 7);
    }

    #[test]
    fn two_springs_in_series() {
        // dofs 0-1-2 joined by springs k1 = 2, k2 = 3.
        let asm = Assembler::new(3, 1, &[[0, 1], [1, 2]]);
        let mut v = asm.zeros();
        asm.add(&mut v, 0, &(Matrix2::new(1.0, -1.0, -1.0, 1.0) * 2.0));
        asm.add(&mut v, 1, &(Matrix2::new(1.0, -1.0, -1.0, 1.0) * 3.0));
        let dense = asm.matrix(&v).to_dense();
        let expect = [[2.0, -2.0, 0.0], [-2.0, 5.0, -3.0], [0.0, -3.0, 3.0]];
        for (r, row) in expect.iter().enumerate() {
            for (c, &e) in row.iter().enumerate() {
                assert_eq!(dense[(r, c)], e);
            }
        }
        assert_eq!(asm.nnz(), 7);
        let mut y = vec![1.0; 3];
        mul_add(asm.matrix(&v), &[1.0, 2.0, 4.0], 1.0, &mut y);
        // K x = (2 - 4, -2 + 10 - 12, -6 + 12)
        assert_eq!(y, vec![-1.0, -3.0, 7.0]);
    }
}
