//! Sparse Cholesky factorization (faer, 32-bit indices) with a fill-reducing ordering: faer's
//! AMD for the simplicial storage (2D systems whose factor serves many solves); for the
//! supernodal one (3D meshes, and 2D systems refactorized often or large:
//! [`Factorization::plane`]) nested dissection (METIS, [`super::ordering`]) or AMD, as the
//! caller asks ([`Ordering`]). The simplicial factor is solved by the project's own sweeps ([`super::sweeps`]), the supernodal one by faer. The symbolic analysis is done once
//! per pattern; numeric refactorization and solves reuse it and the preallocated workspace,
//! so a solve allocates nothing.
//!
//! [`Factorization::SupernodalSingle`] keeps the numeric factor in single precision (f32):
//! half the memory traffic of the factorization and the solves, for a factor that only
//! preconditions an iteration on a double-precision residual (Newton's: its corrections need
//! not be exact, Newton's method in `solve`). A single-precision factorization whose pivots fail the
//! check below is made again in double precision, which then decides.
//!
//! A singular or nearly singular matrix (a floating body, a missing support, a mechanism)
//! is reported as [`ModelError::Singular`]: faer refuses non-positive pivots, and we also
//! refuse pivots that fell below [`PIVOT_RATIO_TOL`] times their diagonal entry, which is
//! where round-off hides a zero pivot.

use faer::dyn_stack::{MemBuffer, MemStack, StackReq};
use faer::linalg::cholesky::llt::factor::{LltError, LltParams, LltRegularization};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, supernodal::SupernodalLltRef, CholeskySymbolicParams, LltRef,
    SymbolicCholesky, SymbolicCholeskyRaw, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side, Spec};
use std::sync::Arc;

use super::ordering;
use super::sweeps::Sweeps;
use crate::budget;
use crate::error::ModelError;

/// Smallest admissible ratio of a Cholesky pivot L_jj² to its diagonal entry A_jj.
///
/// For a rigid-body mode the exact pivot is zero and round-off leaves ~1e-16…1e-13 of the
/// diagonal; a physical stiffness contrast of 1e6 gives ratios near 1e-6.
pub const PIVOT_RATIO_TOL: f64 = 1e-10;

/// Smallest ratio L_jj² / A_jj a single-precision factor is trusted with; below it the
/// factorization is made again in double precision, whose check ([`PIVOT_RATIO_TOL`])
/// decides. A zero pivot computed in f32 is left at round-off: ε = 6e-8 times the updates
/// summed into it (BENCHMARKS.md, "Single-precision pivots").
const SINGLE_PIVOT_RATIO_TOL: f64 = 1e-4;

/// Factors with more stored values than this are factorized on all of rayon's threads
/// (the dense supernode updates parallelize; smaller factors would only pay the overhead).
const PARALLEL_VALUES: usize = 1 << 20;

/// How faer stores the Cholesky factor: simplicial, ordered by AMD, is faster per solve for
/// 2D meshes; supernodal, with the [`Ordering`] it carries, is much faster to factorize for
/// 3D meshes and for large 2D ones (measured; see BENCHMARKS.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Factorization {
    /// Simplicial, ordered by faer's AMD, solved by the project's own sweeps.
    #[default]
    Simplicial,
    /// Supernodal in double precision, with the fill-reducing ordering it carries.
    Supernodal(Ordering),
    /// Supernodal, the numeric factor in single precision where its pivots pass the check
    /// (solves then carry errors of order 1e-7 relative times the conditioning): for the
    /// factors Newton's iterations reuse.
    SupernodalSingle(Ordering),
}

/// The fill-reducing ordering of a supernodal factorization. Which is faster depends on the
/// mesh: on the cut block (cubes of 6 tetrahedra) the linear tetrahedra factorize faster
/// after AMD, the quadratic ones after nested dissection (BENCHMARKS.md, "Orderings").
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ordering {
    /// Nested dissection (METIS, [`super::ordering`]).
    NestedDissection,
    /// faer's approximate minimum degree.
    MinimumDegree,
}

/// 2D systems of more equations than this are factorized supernodally even where one factor
/// serves many solves ([`Factorization::plane`]).
pub const PLANE_SIMPLICIAL_LIMIT: usize = 100_000;

impl Factorization {
    /// The storage for a 2D system of `equations` unknowns whose factor is `reused` for many
    /// solves (a linear time integration) or not (Newton's iterations and static solves
    /// refactorize for about every solve): simplicial for a reused factor of up to
    /// [`PLANE_SIMPLICIAL_LIMIT`] equations, supernodal otherwise (BENCHMARKS.md,
    /// "Simplicial or supernodal in 2D").
    pub fn plane(equations: usize, reused: bool) -> Self {
        if reused && equations <= PLANE_SIMPLICIAL_LIMIT {
            Self::Simplicial
        } else {
            Self::Supernodal(Ordering::NestedDissection)
        }
    }
}

/// A symbolic + numeric Cholesky factorization with its workspace. Indices are 32-bit
/// (less memory traffic in the solves); a pattern too large for them is refused.
pub struct Cholesky {
    analysis: Arc<Analysis>,
    l_values: Vec<f64>,
    /// The right-hand side in the factor's numbering during a simplicial solve.
    permuted: Vec<f64>,
    /// A simplicial factor laid out for the sweeps (empty for a supernodal one).
    sweeps: Sweeps,
    mem: MemBuffer,
    factorized: bool,
    /// The single-precision factor and its scratch ([`Factorization::SupernodalSingle`]).
    single: Option<Single>,
    /// Whether the present factorization is the single-precision one.
    in_single: bool,
}

/// A single-precision factor, the matrix's values and a right-hand side in f32.
struct Single {
    l: Vec<f32>,
    a: Vec<f32>,
    x: Vec<f32>,
}

/// What the symbolic analysis of one pattern gives: shared by every factorization of a
/// matrix with that pattern ([`Cholesky::same_pattern`]).
struct Analysis {
    symbolic: SymbolicCholesky<u32>,
    /// The analysed pattern in 32-bit indices: faer factorizes a matrix of the factor's
    /// index type.
    pattern: SymbolicSparseColMat<u32>,
    /// Equation of each pivot in the original numbering (new → old).
    perm_fwd: Vec<usize>,
    /// Parallelism of the numeric factorization (see [`PARALLEL_VALUES`]).
    par: Par,
    /// Whether the factorizations try single precision first.
    single: bool,
}

impl std::fmt::Debug for Cholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Cholesky")
            .field("n", &self.analysis.symbolic.nrows())
            .field("l_nnz", &self.factor_nnz())
            .finish()
    }
}

impl Cholesky {
    /// Symbolic analysis (ordering — AMD or nested dissection by `factorization` —,
    /// elimination tree, factor pattern) of a symmetric
    /// pattern stored with both triangles.
    pub fn analyze(
        pattern: SymbolicSparseColMatRef<'_, usize>,
        factorization: Factorization,
    ) -> Result<Self, ModelError> {
        let narrow = narrow(pattern)?;
        let (threshold, ordering) = match factorization {
            Factorization::Simplicial => (SupernodalThreshold::FORCE_SIMPLICIAL, None),
            Factorization::Supernodal(o) | Factorization::SupernodalSingle(o) => {
                (SupernodalThreshold::FORCE_SUPERNODAL, Some(o))
            }
        };
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: threshold,
            ..Default::default()
        };
        let (fwd, inv);
        let ordering = match ordering {
            None | Some(Ordering::MinimumDegree) => SymmetricOrdering::Amd,
            Some(Ordering::NestedDissection) => {
                let nd = ordering::nested_dissection(pattern)?;
                let mut i = vec![0; nd.len()];
                for (k, &p) in nd.iter().enumerate() {
                    i[p] = k as u32;
                }
                fwd = nd.into_iter().map(|p| p as u32).collect::<Vec<_>>();
                inv = i;
                SymmetricOrdering::Custom(PermRef::new_checked(&fwd, &inv, fwd.len()))
            }
        };
        let symbolic = factorize_symbolic_cholesky(narrow.as_ref(), Side::Lower, ordering, params)
            .map_err(|e| ModelError::LinearAlgebra(format!("symbolic Cholesky: {e:?}")))?;
        let par = if symbolic.len_val() > PARALLEL_VALUES {
            Par::rayon(0)
        } else {
            Par::Seq
        };
        let perm_fwd = match symbolic.perm() {
            Some(p) => p.arrays().0.iter().map(|&i| i as usize).collect(),
            None => (0..symbolic.nrows()).collect(),
        };
        Self::numeric(Arc::new(Analysis {
            symbolic,
            pattern: narrow,
            perm_fwd,
            par,
            single: matches!(factorization, Factorization::SupernodalSingle(_)),
        }))
    }

    /// A factorization of another matrix with the pattern this one was analysed for: the
    /// analysis shared, the factor and workspace its own.
    pub fn same_pattern(&self) -> Result<Self, ModelError> {
        Self::numeric(Arc::clone(&self.analysis))
    }

    /// Whether `other` factorizes with this one's symbolic analysis (made by
    /// [`Self::same_pattern`] of one another).
    pub fn shares_analysis(&self, other: &Cholesky) -> bool {
        Arc::ptr_eq(&self.analysis, &other.analysis)
    }

    /// Forgets the factorization (its storage kept): a solve before the next
    /// [`factorize`](Self::factorize) panics, as on a new one.
    pub fn invalidate(&mut self) {
        self.factorized = false;
        self.in_single = false;
    }

    /// The factor's storage and workspace for an analysis, claimed against the budget. With
    /// single precision: the f32 factor and copies, and the f64 factor a fallback needs —
    /// claimed here, so that a fallback stays within the budget, but made only on the first
    /// fallback.
    fn numeric(analysis: Arc<Analysis>) -> Result<Self, ModelError> {
        if analysis.single {
            let symbolic = &analysis.symbolic;
            let req = StackReq::any_of(&[scratch::<f32>(&analysis), scratch::<f64>(&analysis)]);
            let (values, entries, n) = (
                symbolic.len_val(),
                analysis.pattern.row_idx().len(),
                symbolic.nrows(),
            );
            budget::claim(
                "the single-precision Cholesky factor",
                budget::bytes_of::<f32>(values + entries + n)
                    .saturating_add(budget::bytes_of::<f64>(values))
                    .saturating_add(req.size_bytes()),
            )?;
            return Ok(Self {
                sweeps: Sweeps::default(),
                l_values: Vec::new(),
                permuted: Vec::new(),
                mem: MemBuffer::new(req),
                factorized: false,
                single: Some(Single {
                    l: vec![0.0; values],
                    a: vec![0.0; entries],
                    x: vec![0.0; n],
                }),
                in_single: false,
                analysis,
            });
        }
        let symbolic = &analysis.symbolic;
        let req = scratch::<f64>(&analysis);
        // The factor, and for the simplicial layout its copy for the sweeps (values, their
        // positions, row indices: at most one of each per stored value).
        let (copies, sweeps) = match symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(s) => (
                2 * budget::bytes_of::<f64>(1),
                Sweeps::new(s.col_ptr(), s.row_idx()),
            ),
            SymbolicCholeskyRaw::Supernodal(_) => (0, Sweeps::default()),
        };
        let per_value = budget::bytes_of::<f64>(1) + copies;
        budget::claim(
            "the Cholesky factor",
            symbolic
                .len_val()
                .saturating_mul(per_value)
                .saturating_add(req.size_bytes()),
        )?;
        Ok(Self {
            sweeps,
            l_values: vec![0.0; symbolic.len_val()],
            permuted: vec![0.0; symbolic.nrows()],
            mem: MemBuffer::new(req),
            factorized: false,
            single: None,
            in_single: false,
            analysis,
        })
    }

    /// Whether the present factorization is in single precision.
    pub fn in_single(&self) -> bool {
        self.factorized && self.in_single
    }

    /// Number of equations.
    pub fn n(&self) -> usize {
        self.analysis.symbolic.nrows()
    }

    /// Number of stored values of the factor L.
    pub fn factor_nnz(&self) -> usize {
        self.analysis.symbolic.len_val()
    }

    /// Numeric factorization of `a` (same pattern as analysed): in single precision first
    /// where the analysis asks for it ([`Factorization::SupernodalSingle`]) and its pivots
    /// pass, else in double. On error the previous factorization is invalidated, so a later
    /// solve cannot silently use stale values.
    pub fn factorize(&mut self, a: SparseColMatRef<'_, usize, f64>) -> Result<(), ModelError> {
        self.factorized = false;
        assert_eq!(
            a.val().len(),
            self.analysis.pattern.row_idx().len(),
            "Cholesky::factorize with a matrix of another pattern than the analysed one"
        );
        self.in_single = self.single.is_some() && self.factorize_single(a);
        if self.in_single {
            self.factorized = true;
            return Ok(());
        }
        self.factorize_double(a)
    }

    /// Numeric factorization of `a` in double precision, whatever the analysis asks for.
    pub fn factorize_exact(
        &mut self,
        a: SparseColMatRef<'_, usize, f64>,
    ) -> Result<(), ModelError> {
        self.factorized = false;
        self.in_single = false;
        self.factorize_double(a)
    }

    /// The single-precision factorization of `a`; false where it fails or a pivot fails
    /// the check.
    fn factorize_single(&mut self, a: SparseColMatRef<'_, usize, f64>) -> bool {
        let Some(single) = &mut self.single else {
            return false;
        };
        for (x, &v) in single.a.iter_mut().zip(a.val()) {
            *x = v as f32;
        }
        let result = self.analysis.symbolic.factorize_numeric_llt::<f32>(
            &mut single.l,
            SparseColMatRef::new(self.analysis.pattern.as_ref(), &single.a),
            Side::Lower,
            LltRegularization::default(),
            self.analysis.par,
            MemStack::new(&mut self.mem),
            Spec::default(),
        );
        let factorized = result.is_ok();
        super::vector_state::clear();
        factorized && weakest_pivot(&self.analysis, &single.l, a).0 >= SINGLE_PIVOT_RATIO_TOL
    }

    /// The double-precision factorization of `a` (its storage, claimed by [`Self::numeric`],
    /// made on first use when the analysis is single-precision).
    fn factorize_double(&mut self, a: SparseColMatRef<'_, usize, f64>) -> Result<(), ModelError> {
        if self.l_values.is_empty() {
            self.l_values = vec![0.0; self.analysis.symbolic.len_val()];
        }
        let stack = MemStack::new(&mut self.mem);
        let result = self.analysis.symbolic.factorize_numeric_llt(
            &mut self.l_values,
            SparseColMatRef::new(self.analysis.pattern.as_ref(), a.val()),
            Side::Lower,
            LltRegularization::default(),
            self.analysis.par,
            stack,
            Spec::default(),
        );
        super::vector_state::clear();
        if let Err(LltError::NonPositivePivot { index }) = result {
            let equation = self.analysis.perm_fwd.get(index).copied().unwrap_or(index);
            return Err(ModelError::Singular {
                equation,
                dof: equation,
                ratio: 0.0,
            });
        }
        self.check_pivots(a)?;
        if let SymbolicCholeskyRaw::Simplicial(_) = self.analysis.symbolic.raw() {
            self.sweeps.load(&self.l_values);
        }
        self.factorized = true;
        Ok(())
    }

    /// Refuses pivots below `PIVOT_RATIO_TOL` times their diagonal entry.
    fn check_pivots(&self, a: SparseColMatRef<'_, usize, f64>) -> Result<(), ModelError> {
        let worst = weakest_pivot(&self.analysis, &self.l_values, a);
        if worst.0 < PIVOT_RATIO_TOL || worst.0.is_nan() {
            return Err(ModelError::Singular {
                equation: worst.1,
                dof: worst.1,
                ratio: worst.0,
            });
        }
        Ok(())
    }

    /// Solves A x = b in place (`rhs` holds b on entry, x on return). Allocates nothing.
    /// A simplicial factor is swept by [`super::sweeps`], a supernodal one by faer.
    ///
    /// # Panics
    /// If called before a successful [`factorize`](Self::factorize) — a programming error,
    /// since every caller factorizes in its constructor or refuses to proceed on error.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) {
        assert!(
            self.factorized,
            "Cholesky::solve_in_place before a successful factorize"
        );
        match self.analysis.symbolic.raw() {
            SymbolicCholeskyRaw::Simplicial(_) => {
                let x = &mut self.permuted;
                for (x, &p) in x.iter_mut().zip(&self.analysis.perm_fwd) {
                    *x = rhs[p];
                }
                self.sweeps.solve(x);
                for (&x, &p) in x.iter().zip(&self.analysis.perm_fwd) {
                    rhs[p] = x;
                }
            }
            SymbolicCholeskyRaw::Supernodal(_) if self.in_single => {
                let single = self.single.as_mut().expect("a single-precision factor");
                for (x, &b) in single.x.iter_mut().zip(rhs.iter()) {
                    *x = b as f32;
                }
                let n = rhs.len();
                LltRef::new(&self.analysis.symbolic, &single.l).solve_in_place_with_conj(
                    Conj::No,
                    MatMut::from_column_major_slice_mut(&mut single.x, n, 1),
                    Par::Seq,
                    MemStack::new(&mut self.mem),
                );
                super::vector_state::clear();
                for (b, &x) in rhs.iter_mut().zip(&single.x) {
                    *b = x.into();
                }
            }
            SymbolicCholeskyRaw::Supernodal(_) => {
                let n = rhs.len();
                let stack = MemStack::new(&mut self.mem);
                let rhs = MatMut::from_column_major_slice_mut(rhs, n, 1);
                LltRef::new(&self.analysis.symbolic, &self.l_values).solve_in_place_with_conj(
                    Conj::No,
                    rhs,
                    Par::Seq,
                    stack,
                );
                super::vector_state::clear();
            }
        }
    }
}

/// The smallest ratio L_jj² / A_jj of the factor `l` of `a` (NaN first) and its
/// equation.
fn weakest_pivot<T: faer::traits::RealField + Copy + Into<f64>>(
    analysis: &Analysis,
    l: &[T],
    a: SparseColMatRef<'_, usize, f64>,
) -> (f64, usize) {
    let mut worst = (f64::INFINITY, 0);
    let mut visit = |j: usize, l_jj: T| {
        let eq = analysis.perm_fwd[j];
        let l_jj: f64 = l_jj.into();
        let ratio = l_jj * l_jj / diagonal(a, eq);
        if ratio.is_nan() || ratio < worst.0 {
            worst = (ratio, eq);
        }
    };
    match analysis.symbolic.raw() {
        SymbolicCholeskyRaw::Simplicial(s) => {
            // faer stores the diagonal first in each column of L.
            for (j, &start) in s.col_ptr()[..s.nrows()].iter().enumerate() {
                visit(j, l[start as usize]);
            }
        }
        SymbolicCholeskyRaw::Supernodal(s) => {
            let l = SupernodalLltRef::new(s, l);
            for sn in 0..s.n_supernodes() {
                let node = l.supernode(sn);
                let val = node.val();
                for c in 0..val.ncols() {
                    visit(node.start() + c, val[(c, c)]);
                }
            }
        }
    }
    worst
}

/// The workspace of a numeric factorization and of a solve in precision `T`.
fn scratch<T: faer::traits::ComplexField>(analysis: &Analysis) -> StackReq {
    let symbolic = &analysis.symbolic;
    StackReq::any_of(&[
        symbolic.factorize_numeric_llt_scratch::<T>(analysis.par, Spec::<LltParams, T>::default()),
        symbolic.solve_in_place_scratch::<T>(1, Par::Seq),
    ])
}

/// Diagonal entry A_jj of a matrix with sorted row indices.
pub(crate) fn diagonal(a: SparseColMatRef<'_, usize, f64>, j: usize) -> f64 {
    let s = a.symbolic();
    let (start, end) = (s.col_ptr()[j], s.col_ptr()[j + 1]);
    s.row_idx()[start..end]
        .binary_search(&j)
        .map_or(0.0, |k| a.val()[start + k])
}

/// The pattern with 32-bit indices (the factorization's and the products' index type), or an
/// error naming what does not fit.
pub(super) fn narrow(
    pattern: SymbolicSparseColMatRef<'_, usize>,
) -> Result<SymbolicSparseColMat<u32>, ModelError> {
    let too_large = || {
        ModelError::LinearAlgebra(format!(
            "{} stored entries exceed the solvers' 32-bit indices",
            pattern.row_idx().len()
        ))
    };
    let to_u32 = |x: &[usize]| -> Result<Vec<u32>, ModelError> {
        x.iter()
            .map(|&i| u32::try_from(i).map_err(|_| too_large()))
            .collect()
    };
    Ok(SymbolicSparseColMat::new_checked(
        pattern.nrows(),
        pattern.ncols(),
        to_u32(pattern.col_ptr())?,
        None,
        to_u32(pattern.row_idx())?,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::Assembler;
    use nalgebra::{Matrix2, SMatrix, SVector};

    fn chain(n: usize, k: f64) -> (Assembler, Vec<f64>) {
        let elems: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
        let asm = Assembler::new(n, 1, &elems);
        let mut v = asm.zeros();
        for e in 0..n - 1 {
            asm.add(&mut v, e, &(Matrix2::new(1.0, -1.0, -1.0, 1.0) * k));
        }
        (asm, v)
    }

    #[test]
    fn solves_a_grounded_chain_in_both_layouts_and_orderings() {
        for factorization in [
            Factorization::Simplicial,
            Factorization::Supernodal(Ordering::NestedDissection),
            Factorization::Supernodal(Ordering::MinimumDegree),
        ] {
            let (asm, mut v) = chain(50, 3.0);
            // Ground node 0 with a spring of the same stiffness.
            let d0 = crate::assembly::slot(asm.symbolic(), 0, 0);
            v[d0] += 3.0;
            let mut chol = Cholesky::analyze(asm.symbolic().as_ref(), factorization).unwrap();
            chol.factorize(asm.matrix(&v)).unwrap();
            // Most of a chain's columns share no rows below them: panels of one column.
            if factorization == Factorization::Simplicial {
                assert!(chol.sweeps.widths().contains(&1));
            }
            // Unit load at the free end: u_i = (i + 1)/k.
            let mut x = vec![0.0; 50];
            x[49] = 1.0;
            chol.solve_in_place(&mut x);
            for (i, xi) in x.iter().enumerate() {
                assert!(
                    (xi - (i + 1) as f64 / 3.0).abs() < 1e-11,
                    "{factorization:?} {i}"
                );
            }
        }
    }

    /// The supernodal factorization orders as asked: AMD as the simplicial one does (faer's),
    /// nested dissection otherwise; both solve a 3D block's stiffness alike.
    #[test]
    fn a_supernodal_factorization_orders_as_asked() {
        use crate::element::{Elastic, Law, Material};
        let planes = [4, 3, 3].map(|n| (0..=n).map(f64::from).collect::<Vec<_>>());
        let mesh = crate::mesh::generate::block_on_planes(
            &planes,
            crate::mesh::generate::Split::ExtrudedX { mirrored: false },
        )
        .unwrap();
        let material = Material::new(Law::Linear, Elastic::new("block", 1.0, 0.3).unwrap());
        let solid = crate::assembly::tetrahedra::Solid::linear(&mesh, material);
        let asm = crate::assembly::tetrahedra::assembler(&mesh);
        let mut k = asm.zeros();
        let zero = vec![0.0; solid.n_dofs()];
        solid
            .add_internal(&asm, &zero, &mut zero.clone(), Some(&mut k))
            .unwrap();
        // A grounding spring on every diagonal entry: positive definite.
        for d in 0..solid.n_dofs() {
            k[crate::assembly::slot(asm.symbolic(), d, d)] += 1e-3;
        }
        let analyse = |f| Cholesky::analyze(asm.symbolic().as_ref(), f).unwrap();
        let amd = analyse(Factorization::Supernodal(Ordering::MinimumDegree));
        let nd = analyse(Factorization::Supernodal(Ordering::NestedDissection));
        assert_eq!(
            amd.analysis.perm_fwd,
            analyse(Factorization::Simplicial).analysis.perm_fwd
        );
        assert_ne!(amd.analysis.perm_fwd, nd.analysis.perm_fwd);
        let b: Vec<f64> = (0..solid.n_dofs()).map(|i| (i % 7) as f64 - 3.0).collect();
        let solve = |mut chol: Cholesky| {
            chol.factorize(asm.matrix(&k)).unwrap();
            let mut x = b.clone();
            chol.solve_in_place(&mut x);
            x
        };
        let (x_amd, x_nd) = (solve(amd), solve(nd));
        let mut r = b.clone();
        crate::assembly::mul_add(asm.matrix(&k), &x_amd, -1.0, &mut r);
        assert!(r.iter().all(|r| r.abs() < 1e-9), "{r:?}");
        assert!(x_amd
            .iter()
            .zip(&x_nd)
            .all(|(a, b)| (a - b).abs() < 1e-9 * a.abs().max(1.0)));
    }

    /// The single-precision factor solves to f32's accuracy times the chain's conditioning
    /// (~4n² = 1e4, so 6e-8 · 1e4 = 6e-4 at worst; measured 1.7e-5, asserted 1e-4); the
    /// double one, on request, to f64's.
    #[test]
    fn single_precision_solves_to_its_accuracy_and_double_on_request() {
        let (asm, mut v) = chain(50, 3.0);
        v[crate::assembly::slot(asm.symbolic(), 0, 0)] += 3.0;
        let mut chol = Cholesky::analyze(
            asm.symbolic().as_ref(),
            Factorization::SupernodalSingle(Ordering::MinimumDegree),
        )
        .unwrap();
        let error = |chol: &mut Cholesky| {
            let mut x = vec![0.0; 50];
            x[49] = 1.0;
            chol.solve_in_place(&mut x);
            x.iter()
                .enumerate()
                .map(|(i, xi)| (xi / ((i + 1) as f64 / 3.0) - 1.0).abs())
                .fold(0.0, f64::max)
        };
        chol.factorize(asm.matrix(&v)).unwrap();
        assert!(chol.in_single());
        let single = error(&mut chol);
        assert!(single < 1e-4 && single > 1e-12, "{single}");
        chol.factorize_exact(asm.matrix(&v)).unwrap();
        assert!(!chol.in_single());
        assert!(error(&mut chol) < 1e-12);
    }

    /// A factorization whose f32 pivots fail the single-precision check is made in double
    /// precision and solves to f64's accuracy: a grounded chain whose spring next to the
    /// ground is 1e6 stiffer than the others (pivot ratio ~1e-6), and one whose stiffness
    /// exceeds f32's range (1e40).
    #[test]
    fn single_precision_falls_back_to_double_where_its_pivots_fail() {
        for (stiff, k) in [(1e6, 1.0), (1.0, 1e40)] {
            let n = 30;
            let elems: Vec<[usize; 2]> = (0..n - 1).map(|i| [i, i + 1]).collect();
            let asm = Assembler::new(n, 1, &elems);
            let mut v = asm.zeros();
            let spring = Matrix2::new(1.0, -1.0, -1.0, 1.0);
            for e in 0..n - 1 {
                let ke = if e == 0 { stiff * k } else { k };
                asm.add(&mut v, e, &(spring * ke));
            }
            v[crate::assembly::slot(asm.symbolic(), 0, 0)] += k;
            let mut chol = Cholesky::analyze(
                asm.symbolic().as_ref(),
                Factorization::SupernodalSingle(Ordering::NestedDissection),
            )
            .unwrap();
            chol.factorize(asm.matrix(&v)).unwrap();
            assert!(!chol.in_single(), "stiff {stiff}, k {k}");
            // Unit load at the free end: the springs in series, 1/k + 1/(stiff k) + (n − 2)/k
            // at the end.
            let mut x = vec![0.0; n];
            x[n - 1] = 1.0;
            chol.solve_in_place(&mut x);
            let end = (1.0 + 1.0 / stiff + (n - 2) as f64) / k;
            // f64's round-off times the contrast (measured 3.5e-12 at 1e6); f32's would be
            // ~1e-7 times it.
            assert!((x[n - 1] / end - 1.0).abs() < 1e-10, "{} {end}", x[n - 1]);
        }
    }

    #[test]
    fn floating_chain_is_singular_in_every_layout() {
        for factorization in [
            Factorization::Simplicial,
            Factorization::Supernodal(Ordering::NestedDissection),
            Factorization::SupernodalSingle(Ordering::NestedDissection),
            Factorization::Supernodal(Ordering::MinimumDegree),
            Factorization::SupernodalSingle(Ordering::MinimumDegree),
        ] {
            let (asm, v) = chain(40, 7.0);
            let mut chol = Cholesky::analyze(asm.symbolic().as_ref(), factorization).unwrap();
            let err = chol.factorize(asm.matrix(&v)).unwrap_err();
            assert!(
                matches!(err, ModelError::Singular { .. }),
                "{factorization:?}: {err}"
            );
        }
    }

    /// A dense SPD matrix of 7 equations (one element over all of them): every column joins
    /// a panel, so the sweeps run panels of width 4 and 3 (the plane and chain tests in
    /// `cholesky` and tests/dynamics/full_order_step.rs cover widths 1, 2 and 4).
    #[test]
    fn a_dense_matrix_is_solved_like_nalgebra_solves_it() {
        let b = SMatrix::<f64, 7, 7>::from_fn(|i, j| ((3 * i + 5 * j) % 11) as f64 - 5.0);
        let a = b * b.transpose() + SMatrix::<f64, 7, 7>::identity() * 7.0;
        let asm = Assembler::new(7, 1, &[[0, 1, 2, 3, 4, 5, 6]]);
        let mut values = asm.zeros();
        asm.add(&mut values, 0, &a);
        let mut chol =
            Cholesky::analyze(asm.symbolic().as_ref(), Factorization::Simplicial).unwrap();
        chol.factorize(asm.matrix(&values)).unwrap();
        let widths: Vec<u32> = chol.sweeps.widths();
        assert_eq!(widths, [4, 3]);
        let rhs = SVector::<f64, 7>::from_fn(|i, _| i as f64 - 2.5);
        let mut x: Vec<f64> = rhs.iter().copied().collect();
        chol.solve_in_place(&mut x);
        let expected = a.cholesky().unwrap().solve(&rhs);
        for (x, e) in x.iter().zip(expected.iter()) {
            assert!((x - e).abs() < 1e-13 * expected.amax(), "{x} {e}");
        }
    }
}
