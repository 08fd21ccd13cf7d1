//! Fill-reducing ordering by nested dissection (METIS `METIS_NodeND`, vendored by the
//! `metis-sys` crate) for the supernodal Cholesky factorization (3D meshes and the 2D systems
//! of [`super::Factorization::plane`]). Measured on
//! the cut block (6 × 16 × 14 cubes, one noisy run each): tet4 factor 0.73 M entries and
//! 9.5 ms against 0.78 M and 14.8 ms with faer's AMD; tet10 14.1 M entries and 0.42–0.53 s
//! against 15.4 M and 0.65 s.
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

/// The nested-dissection permutation of a symmetric pattern (both triangles stored):
/// `perm[k]` is the original index of the k-th pivot.
pub fn nested_dissection(
    pattern: SymbolicSparseColMatRef<'_, usize>,
) -> Result<Vec<usize>, ModelError> {
    let n = pattern.ncols();
    if n < 2 {
        return Ok((0..n).collect());
    }
    let too_large =
        |what: &str| ModelError::LinearAlgebra(format!("{what} exceeds METIS's 32-bit indices"));
    let mut xadj: Vec<i32> = Vec::with_capacity(n + 1);
    let mut adjncy: Vec<i32> = Vec::with_capacity(pattern.row_idx().len());
    xadj.push(0);
    for j in 0..n {
        let rows = &pattern.row_idx()[pattern.col_ptr()[j]..pattern.col_ptr()[j + 1]];
        for &i in rows.iter().filter(|&&i| i != j) {
            adjncy.push(i32::try_from(i).map_err(|_| too_large("a row index"))?);
        }
        xadj.push(i32::try_from(adjncy.len()).map_err(|_| too_large("the number of entries"))?);
    }
    let mut nvtxs = i32::try_from(n).map_err(|_| too_large("the number of equations"))?;
    let mut options = [0; metis_sys::METIS_NOPTIONS as usize];
    let (mut perm, mut iperm) = (vec![0i32; n], vec![0i32; n]);
    static METIS: Mutex<()> = Mutex::new(());
    let _one_at_a_time = METIS
        .lock()
        .unwrap_or_else(|poisoned| poisoned.into_inner());
    // SAFETY: the arrays have the sizes METIS_NodeND documents (xadj n + 1, adjncy the
    // entries, perm and iperm n, options METIS_NOPTIONS) and live through the call.
    let status = unsafe {
        metis_sys::METIS_SetDefaultOptions(options.as_mut_ptr());
        metis_sys::METIS_NodeND(
            &mut nvtxs,
            xadj.as_mut_ptr(),
            adjncy.as_mut_ptr(),
            std::ptr::null_mut(),
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
    Ok(perm.into_iter().map(|p| p as usize).collect())
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
}
