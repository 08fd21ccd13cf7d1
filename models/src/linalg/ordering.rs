//! Fill-reducing ordering by nested dissection (METIS `METIS_NodeND`, vendored by the
//! `metis-sys` crate) for the supernodal Cholesky factorization that asks for it
//! ([`crate::linalg::Ordering`]: the 2D systems of [`crate::linalg::Factorization::plane`], the
//! quadratic tetrahedra of the cut block; measured against AMD: BENCHMARKS.md,
//! "Orderings").
//!
//! METIS is given one vertex per node ([`groups`]). It would find the same graph itself
//! (its `compress` option, on by default for `METIS_NodeND`, merges vertices with equal
//! adjacency and then computes two separators per level): giving it the node graph saves
//! that pass (BENCHMARKS.md, "Orderings").
//!
//! METIS seeds its random generator at each call, so calls from two threads at once would
//! race and give orderings that differ from run to run; the calls are therefore serialized.
//! The generator is GKlib's own (`USE_GKRAND`, set for the METIS build in
//! `.cargo/config.toml`), whose state belongs to this copy of the library rather than libc's
//! process-wide `rand()`: every ordering is the same whatever other threads, other copies of
//! the library (the FMI 2 and FMI 3 FMUs, an FMU beside the scene linked into the host) or
//! the host do (`tests/tests/fmi_import.rs` runs them all at once, 20 times). A build
//! without that flag would import `rand` from libc; the FMU tests check that it does not.

use std::sync::Mutex;

use faer::sparse::SymbolicSparseColMatRef;

use crate::error::ModelError;

/// Separators METIS computes at each level, keeping the smallest. METIS takes 2 itself
/// when it compresses a graph by more than 1.5 (`ometis.c`); the graph given to it here is
/// compressed already ([`groups`]). Two gave the smallest factor (BENCHMARKS.md,
/// "Orderings").
const SEPARATORS: i32 = 2;

/// The nested-dissection permutation of a symmetric pattern (both triangles stored):
/// `perm[k]` is the original index of the k-th pivot.
///
/// Runs of consecutive equations with the same column pattern (the free dofs of one node)
/// are ordered as one vertex weighted by their number, and kept together in the result
/// ([`groups`]).
pub fn nested_dissection(
    pattern: SymbolicSparseColMatRef<'_, usize>,
) -> Result<Vec<usize>, ModelError> {
    let n = pattern.ncols();
    if n < 2 {
        return Ok((0..n).collect());
    }
    let too_large =
        |what: &str| ModelError::LinearAlgebra(format!("{what} exceeds METIS's 32-bit indices"));
    let first = groups(pattern, usize::MAX);
    let m = first.len() - 1;
    let mut group_of = vec![0i32; n];
    for g in 0..m {
        let id = i32::try_from(g).map_err(|_| too_large("the number of equations"))?;
        group_of[first[g]..first[g + 1]].fill(id);
    }
    let mut xadj: Vec<i32> = Vec::with_capacity(m + 1);
    let mut adjncy: Vec<i32> = Vec::new();
    let mut vwgt: Vec<i32> = Vec::with_capacity(m);
    xadj.push(0);
    for g in 0..m {
        let j = first[g];
        let rows = &pattern.row_idx()[pattern.col_ptr()[j]..pattern.col_ptr()[j + 1]];
        let mut last = -1;
        for &i in rows {
            let h = group_of[i];
            if h != g as i32 && h != last {
                adjncy.push(h);
                last = h;
            }
        }
        xadj.push(i32::try_from(adjncy.len()).map_err(|_| too_large("the number of entries"))?);
        vwgt.push((first[g + 1] - j) as i32);
    }
    let mut nvtxs = m as i32;
    let mut options = [0; metis_sys::METIS_NOPTIONS as usize];
    let (mut perm, mut iperm) = (vec![0i32; m], vec![0i32; m]);
    static METIS: Mutex<()> = Mutex::new(());
    let _one_at_a_time = METIS
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    // SAFETY: the arrays have the sizes METIS_NodeND documents (xadj nvtxs + 1, adjncy the
    // entries, vwgt, perm and iperm nvtxs, options METIS_NOPTIONS) and live through the call.
    #[allow(unsafe_code)]
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        options[metis_sys::moptions_et_METIS_OPTION_NSEPS as usize] = SEPARATORS;
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            vwgt.as_mut_ptr(),
            options.as_mut_ptr(),
            perm.as_mut_ptr(),
            iperm.as_mut_ptr(),
        )
    };
    if status != metis_sys::rstatus_et_METIS_OK {
        return Err(ModelError::LinearAlgebra(format!(
            "METIS_NodeND returned {status}"
        )));
    }
    Ok(perm
        .into_iter()
        .flat_map(|g| first[g as usize]..first[g as usize + 1])
        .collect())
}

/// The starts of the runs of consecutive columns with equal row patterns, each at most
/// `longest` columns (a longer run is split), ending with n: such equations are
/// indistinguishable to the elimination, and ordering them as one vertex gives METIS a graph
/// a third the size for 3 dofs per node; [`crate::linalg::product`] gathers pairs of them together.
pub(crate) fn groups(pattern: SymbolicSparseColMatRef<'_, usize>, longest: usize) -> Vec<usize> {
    let col = |j: usize| &pattern.row_idx()[pattern.col_ptr()[j]..pattern.col_ptr()[j + 1]];
    let n = pattern.ncols();
    let mut first = vec![0];
    for j in 1..n {
        if col(j) != col(j - 1) || j - first[first.len() - 1] == longest {
            first.push(j);
        }
    }
    if n > 0 {
        first.push(n);
    }
    first
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::Assembler;

    #[test]
    fn the_ordering_is_a_permutation_and_separates_a_chain_in_the_middle() {
        let n = 63;
        let elems: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
        let asm = Assembler::new(n, 1, &elems);
        let perm = nested_dissection(asm.symbolic().as_ref()).unwrap();
        let mut sorted = perm.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        // Nested dissection eliminates a separator last: for a chain, an interior node.
        let last = perm[n - 1];
        assert!(last > 0 && last < n - 1, "{last}");
    }

    /// Three dofs per node: METIS sees one vertex per node, and each node's dofs stay
    /// together (in their order) in the permutation.
    #[test]
    fn the_dofs_of_a_node_are_ordered_together() {
        let n = 40;
        let elems: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
        let asm = Assembler::new(n, 3, &elems);
        let first = groups(asm.symbolic().as_ref(), usize::MAX);
        assert_eq!(first, (0..=n).map(|k| 3 * k).collect::<Vec<_>>());
        let perm = nested_dissection(asm.symbolic().as_ref()).unwrap();
        let mut sorted = perm.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..3 * n).collect::<Vec<_>>());
        for triple in perm.chunks(3) {
            assert_eq!(triple[0] % 3, 0, "{perm:?}");
            assert_eq!((triple[1], triple[2]), (triple[0] + 1, triple[0] + 2));
        }
        let last = perm[3 * n - 1] / 3;
        assert!(last > 0 && last < n - 1, "{last}");
    }
}
