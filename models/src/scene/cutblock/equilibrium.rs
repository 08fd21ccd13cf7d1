//! The cut block's equilibrium solver for one topology: the linear law keeps one
//! factorization of K (with the active contact springs) per material, topology and contact
//! set, so a new load costs one solve; a finite-strain law goes from the last equilibrium
//! to the new load with Newton's method ([`crate::solve::newton`]) in increments of at most
//! `max_increment` of pull. It holds the last equilibrium, the copies a failed solve goes
//! back to, and the work done; what it solves on (the solid, the pattern, the flank contact
//! and where the loads act) it is handed by its topology ([`On`]).

use super::contact::FlankContact;
use super::geometry::Geometry;
use super::profiles::TopSurface;
use super::work::{Timing, Work};
use crate::assembly::forces::{self, InternalForces};
use crate::assembly::tetrahedra::{Solid, Tetrahedron};
use crate::assembly::{mul_add, Assembler, Dirichlet};
use crate::error::ModelError;
use crate::linalg::{Factorization, Ordering};
use crate::scene::SceneError;
use crate::solve::newton::{self, Newton, Settings};
use crate::solve::Statics;

/// Newton keeps its factorization while each iteration reduces the residual at least 4
/// times (the solver's default asks for 10): on the default tet10 block a factorization
/// costs about 430 ms and an iteration on a kept one about 30 ms, and after a blade advance
/// the iterations on the first tangent contract by 0.02–0.16, so that with 10 most
/// advances were refactorized once more (BENCHMARKS.md, "Newton's kept factorization").
const REUSE_CONTRACTION: f64 = 0.25;

/// For tet10 the factorization costs more iterations (about 15 against about 5 for tet4),
/// and the Anderson-accelerated iterations on a kept one contract faster than the plain
/// ones the 0.25 above was chosen for: a tet10 factorization is kept while each iteration
/// halves the residual (fewer factorizations for more, cheaper iterations; for tet4 0.5
/// would be slower: BENCHMARKS.md, "Newton's kept factorization").
const REUSE_CONTRACTION_TET10: f64 = 0.5;

/// Newton's settings for the block's tetrahedron `kind` with pull increments of at most
/// `max_increment` (mm).
pub fn settings(kind: Tetrahedron, max_increment: f64) -> Settings {
    Settings {
        max_increment,
        reuse_contraction: match kind {
            Tetrahedron::Tet4 => REUSE_CONTRACTION,
            Tetrahedron::Tet10 => REUSE_CONTRACTION_TET10,
        },
        ..Settings::default()
    }
}

/// How the equilibrium is found.
#[derive(Debug)]
enum Solver {
    /// The linear law: K (with the active springs) factorized, K without them kept for
    /// the internal forces.
    Linear {
        statics: Box<Statics>,
        k_base: Vec<f64>,
        k: Vec<f64>,
    },
    /// A finite-strain law.
    Newton(Box<Newton>),
}

impl Solver {
    /// A solver for the pattern `asm` with the dofs `fixed` held, for a finite-strain law
    /// if `finite`: factorized after the ordering measured fastest for `kind`.
    fn new(
        asm: &Assembler,
        fixed: &[usize],
        finite: bool,
        kind: Tetrahedron,
        settings: Settings,
    ) -> Result<Self, SceneError> {
        let ordering = match kind {
            Tetrahedron::Tet4 => Ordering::MinimumDegree,
            Tetrahedron::Tet10 => Ordering::NestedDissection,
        };
        Ok(if finite {
            Self::Newton(Box::new(Newton::new(
                asm,
                fixed,
                Factorization::SupernodalSingle(ordering),
                settings,
            )?))
        } else {
            Self::Linear {
                statics: Box::new(Statics::new(
                    asm,
                    fixed,
                    Factorization::Supernodal(ordering),
                )?),
                k_base: asm.zeros(),
                k: asm.zeros(),
            }
        })
    }

    fn dirichlet(&self) -> &Dirichlet {
        match self {
            Self::Linear { statics, .. } => statics.dirichlet(),
            Self::Newton(n) => n.dirichlet(),
        }
    }

    /// A solver of the same kind for equations of the same pattern, sharing the analysis:
    /// the `spare` if it shares it too (its storage reused), else a new one.
    fn same_pattern(
        &self,
        asm: &Assembler,
        settings: Settings,
        spare: Option<Spare>,
    ) -> Result<Self, SceneError> {
        if let Some(Spare(mut spare)) = spare.filter(|s| s.0.shares_analysis(self)) {
            match &mut spare {
                Self::Newton(n) => n.recycle(settings)?,
                Self::Linear { statics, .. } => statics.invalidate(),
            }
            return Ok(spare);
        }
        Ok(match self {
            Self::Linear { statics, .. } => Self::Linear {
                statics: Box::new(statics.same_pattern()?),
                k_base: asm.zeros(),
                k: asm.zeros(),
            },
            Self::Newton(n) => Self::Newton(Box::new(n.same_pattern(settings)?)),
        })
    }

    /// Whether both are of one kind and share the symbolic analysis.
    fn shares_analysis(&self, other: &Solver) -> bool {
        match (self, other) {
            (Self::Linear { statics: a, .. }, Self::Linear { statics: b, .. }) => {
                a.shares_analysis(b)
            }
            (Self::Newton(a), Self::Newton(b)) => a.shares_analysis(b),
            _ => false,
        }
    }
}

/// The solver of a replaced topology, kept to lend its storage to the next topology of the
/// same pattern (a blade advance within a cell): the factor's storage and the vectors are
/// then reused instead of mapped afresh from the operating system page by page, as
/// allocations of tens of megabytes are (a tet10 factor).
#[derive(Debug)]
pub struct Spare(Solver);

/// A copy of an equilibrium to go back to (its buffers made once, with the solver).
#[derive(Debug)]
struct Snapshot {
    u: Vec<f64>,
    internal: Vec<f64>,
}

impl Snapshot {
    fn new(n_dofs: usize) -> Self {
        Self {
            u: vec![0.0; n_dofs],
            internal: vec![0.0; n_dofs],
        }
    }
}

/// Which copy [`Equilibrium::go_back`] restores.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Saved {
    /// The start of the solve: the solve is undone.
    Solve,
    /// A settle's first settled set: its re-linearization is given up (the fallback).
    Settled,
}

/// What an equilibrium of a topology is solved on: its solid and pattern, its flank
/// contact with the springs' penalty stiffness, its top surface (where the press acts) and
/// the nodes of its pulled face.
pub struct On<'a> {
    pub solid: &'a Solid,
    pub asm: &'a Assembler,
    pub contact: Option<&'a FlankContact>,
    pub penalty: f64,
    pub top: &'a TopSurface,
    pub pulled: &'a [usize],
}

impl InternalForces for On<'_> {
    /// The solid's internal forces and the contact springs'.
    fn internal(
        &self,
        u: &[f64],
        f: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        forces::clear(f, k.as_deref_mut());
        self.solid.add_internal(self.asm, u, f, k.as_deref_mut())?;
        if let Some(c) = self.contact {
            c.add_forces(self.penalty, u, f);
            if let Some(k) = k {
                c.add_stiffness(self.asm, self.penalty, k);
            }
        }
        Ok(())
    }
}

/// The solver of one topology and its last equilibrium.
#[derive(Debug)]
pub struct Equilibrium {
    solver: Solver,
    /// The last equilibrium: displacements, external and internal forces (all dofs).
    pub u: Vec<f64>,
    pub f: Vec<f64>,
    pub internal: Vec<f64>,
    /// The prescribed displacements of the pulled face and the press force of `u`.
    pub load: (f64, f64),
    /// The prescribed values (all dofs).
    pub prescribed: Vec<f64>,
    /// Scratch: the linear law's loads with the springs' share, and the equilibrium at the
    /// start of a solve (restored on failure) and after a settle's first settled contact
    /// set (restored when its springs cannot be linearized again).
    loads: Vec<f64>,
    saved: Snapshot,
    settled: Snapshot,
    /// Factorizations, Newton increments and iterations since the topology was built, and
    /// where their time went.
    pub work: Work,
    pub timing: Timing,
    /// Whether a solve since the scene last looked kept the springs linearized where their
    /// nodes were caught (the settle's fallback).
    pub fell_back: bool,
    /// Where the next finite-strain solve starts its iterations, if not from the last
    /// equilibrium ([`Newton::solve_from`]; taken by that solve).
    pub start: Option<Vec<f64>>,
}

impl Equilibrium {
    /// The solver for the pattern `asm` (with `n_dofs` dofs) and the held dofs `fixed`,
    /// for a finite-strain law if `finite`; `same` the previous topology's solver when it
    /// has this pattern, whose symbolic analysis it shares (and the `spare` solver's
    /// storage, if that shares it too). The unloaded block is its equilibrium.
    pub fn new(
        asm: &Assembler,
        fixed: &[usize],
        (finite, kind): (bool, Tetrahedron),
        settings: Settings,
        same: Option<&Equilibrium>,
        spare: Option<Spare>,
    ) -> Result<Self, SceneError> {
        let solver = match same {
            Some(p) => p.solver.same_pattern(asm, settings, spare)?,
            None => {
                drop(spare);
                Solver::new(asm, fixed, finite, kind, settings)?
            }
        };
        let n_dofs = asm.n_dofs();
        Ok(Self {
            solver,
            u: vec![0.0; n_dofs],
            f: vec![0.0; n_dofs],
            internal: vec![0.0; n_dofs],
            load: (0.0, 0.0),
            prescribed: vec![0.0; n_dofs],
            loads: vec![0.0; n_dofs],
            saved: Snapshot::new(n_dofs),
            settled: Snapshot::new(n_dofs),
            work: Work {
                analyses: u64::from(same.is_none()),
                ..Work::default()
            },
            timing: Timing::default(),
            fell_back: false,
            start: None,
        })
    }

    /// Whether a topology with the held dofs `fixed` and a law of kind `finite` can share
    /// this solver's pattern (given the same elements).
    pub fn fits(&self, fixed: &[usize], finite: bool) -> bool {
        matches!(self.solver, Solver::Newton(_)) == finite
            && self.solver.dirichlet().constrained() == fixed
    }

    /// Whether this is a finite-strain law's Newton solver.
    pub fn is_newton(&self) -> bool {
        matches!(self.solver, Solver::Newton(_))
    }

    /// The held dofs.
    pub fn constrained(&self) -> &[usize] {
        self.solver.dirichlet().constrained()
    }

    /// The solver, for the next topology of `next`'s pattern ([`Spare`]); `None` if it has
    /// another pattern, so that no storage is held that cannot be reused.
    pub fn into_spare(self, next: &Equilibrium) -> Option<Spare> {
        self.solver
            .shares_analysis(&next.solver)
            .then_some(Spare(self.solver))
    }

    /// The Newton solver's checkpoint (finite-strain laws).
    pub fn newton_checkpoint(&self) -> Option<newton::Checkpoint> {
        match &self.solver {
            Solver::Newton(n) => Some(n.checkpoint()),
            Solver::Linear { .. } => None,
        }
    }

    /// Puts a Newton checkpoint back (finite-strain laws; the linear law has none).
    pub fn resume_newton(
        &mut self,
        on: &On<'_>,
        checkpoint: &newton::Checkpoint,
    ) -> Result<(), SceneError> {
        if let Solver::Newton(n) = &mut self.solver {
            n.resume(on, checkpoint)?;
        }
        Ok(())
    }

    /// The largest pull increment of a finite-strain law's Newton solver.
    pub fn max_increment(&self) -> Option<f64> {
        match &self.solver {
            Solver::Newton(n) => Some(n.settings().max_increment),
            Solver::Linear { .. } => None,
        }
    }

    /// Changes `max_increment` for the next finite-strain solves.
    pub fn set_max_increment(&mut self, max_increment: f64) -> Result<(), SceneError> {
        if let Solver::Newton(n) = &mut self.solver {
            let settings = Settings {
                max_increment,
                ..n.settings()
            };
            n.set_settings(settings)?;
        }
        Ok(())
    }

    /// The linear law's stiffness K (in closed form, [`Solid::add_stiffness`]) and its
    /// factorization; a finite-strain law's next solve starts from a new tangent.
    pub fn assemble_linear(&mut self, on: &On<'_>) -> Result<(), SceneError> {
        let k_base = match &mut self.solver {
            Solver::Linear { k_base, .. } => k_base,
            Solver::Newton(n) => {
                n.invalidate();
                return Ok(());
            }
        };
        k_base.fill(0.0);
        on.solid.add_stiffness(on.asm, k_base)?;
        self.factorize(on)
    }

    /// After a change of the equations (material, contact springs): factorizes the linear
    /// law's K plus the active springs; a finite-strain law's next solve starts from a new
    /// tangent.
    pub fn factorize(&mut self, on: &On<'_>) -> Result<(), SceneError> {
        let (statics, k_base, k) = match &mut self.solver {
            Solver::Linear { statics, k_base, k } => (statics, k_base, k),
            Solver::Newton(n) => {
                n.invalidate();
                return Ok(());
            }
        };
        k.copy_from_slice(k_base);
        if let Some(c) = on.contact {
            c.add_stiffness(on.asm, on.penalty, k);
        }
        statics.factorize(k)?;
        self.work.factorizations += 1;
        Ok(())
    }

    /// The external forces `f` of the press and the prescribed values of the pull.
    pub fn set_loads(&mut self, on: &On<'_>, g: &Geometry, pull: f64, press: f64, scalpel_x: f64) {
        self.f.fill(0.0);
        if press > 0.0 {
            on.top
                .press_load(on.solid.nodes(), g, press, scalpel_x, &mut self.f);
        }
        for &n in on.pulled {
            self.prescribed[3 * n + 1] = pull;
        }
    }

    /// After a failed solve or a restored equilibrium: the loads and the solver's state
    /// back to `u` under `load` (pull, press), with the springs `on` holds.
    pub fn restart(
        &mut self,
        on: &On<'_>,
        g: &Geometry,
        load: (f64, f64),
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        self.load = load;
        self.set_loads(on, g, load.0, load.1, scalpel_x);
        match &mut self.solver {
            Solver::Newton(n) => n.restart(&self.prescribed, &self.f),
            Solver::Linear { .. } => self.factorize(on)?,
        }
        Ok(())
    }

    /// Back to the unloaded block (after a start from the previous topology's equilibria that
    /// did not converge).
    pub fn unload(&mut self, on: &On<'_>, g: &Geometry, scalpel_x: f64) -> Result<(), SceneError> {
        self.u.fill(0.0);
        self.internal.fill(0.0);
        self.restart(on, g, (0.0, 0.0), scalpel_x)
    }

    /// Keeps the present equilibrium as the copy `saved` to go back to.
    pub fn keep(&mut self, saved: Saved) {
        let to = match saved {
            Saved::Solve => &mut self.saved,
            Saved::Settled => &mut self.settled,
        };
        to.u.copy_from_slice(&self.u);
        to.internal.copy_from_slice(&self.internal);
    }

    /// Back to the copy `saved` (its displacements and internal forces; the caller puts
    /// its springs back and [`restart`](Self::restart)s): undoing a solve also undoes what
    /// its settles fell back to; going back to a settled set is the fallback.
    pub fn go_back(&mut self, saved: Saved) {
        let from = match saved {
            Saved::Solve => &self.saved,
            Saved::Settled => &self.settled,
        };
        self.u.copy_from_slice(&from.u);
        self.internal.copy_from_slice(&from.internal);
        self.fell_back = saved == Saved::Settled;
    }

    /// Direct differentiation of the last equilibrium in ν at fixed E and loads: du/dν into
    /// `du` and the derivative of the internal forces along the equilibria into `total`
    /// (all dofs; at the pulled face the reaction's). A finite-strain law solves with the
    /// exact tangent preconditioned by Newton's kept factorization
    /// ([`Newton::sensitivity`]); the linear law, whose K is factorized as it is, with
    /// one solve. The contact springs' penalty scales with E alone, so they add to K but
    /// nothing to ∂f_int/∂ν. Returns the solve's iterations (1 for the linear law).
    pub fn poisson_sensitivity(
        &mut self,
        on: &On<'_>,
        du: &mut [f64],
        total: &mut [f64],
    ) -> Result<usize, SceneError> {
        let mut partial = vec![0.0; self.u.len()];
        on.solid
            .add_poisson_derivative(on.asm, &self.u, &mut partial)?;
        Ok(match &mut self.solver {
            Solver::Linear { statics, k, k_base } => {
                for (l, p) in self.loads.iter_mut().zip(&partial) {
                    *l = -p;
                }
                du.fill(0.0);
                statics.solve(on.asm.matrix(k), &self.loads, du);
                total.copy_from_slice(&partial);
                mul_add(on.asm.matrix(k_base), du, 1.0, total);
                1
            }
            Solver::Newton(n) => n.sensitivity(on, &self.u, &partial, du, total)?,
        })
    }

    /// The equilibrium for the prescribed values and `f` with the springs `on` holds; a
    /// finite-strain law iterates first from the `start`, if one was given (taken either way).
    pub fn solve(&mut self, on: &On<'_>) -> Result<(), SceneError> {
        let start = self.start.take();
        match &mut self.solver {
            Solver::Linear { statics, k, k_base } => {
                self.loads.copy_from_slice(&self.f);
                if let Some(c) = on.contact {
                    c.add_loads(on.penalty, &mut self.loads);
                }
                self.u.copy_from_slice(&self.prescribed);
                statics.solve(on.asm.matrix(k), &self.loads, &mut self.u);
                self.internal.fill(0.0);
                mul_add(on.asm.matrix(k_base), &self.u, 1.0, &mut self.internal);
            }
            Solver::Newton(n) => {
                let solved = match start {
                    Some(start) => n
                        .solve_from(on, &mut self.u, &start, &self.prescribed, &self.f)
                        .map(drop),
                    None => n
                        .solve(on, &mut self.u, &self.prescribed, &self.f)
                        .map(drop),
                };
                // Counted whether it converged or not.
                let report = n.report();
                let w = &mut self.work;
                w.factorizations += report.factorizations as u64;
                w.increments += report.iterations.len() as u64;
                w.iterations += report.iterations.iter().sum::<usize>() as u64;
                w.failed_iterations += report.failed_iterations as u64;
                let t = &mut self.timing;
                t.assembly += report.assembly;
                t.factorization += report.factorization;
                t.solve += report.solve;
                solved?;
                self.internal.copy_from_slice(n.internal_forces());
            }
        }
        Ok(())
    }
}
