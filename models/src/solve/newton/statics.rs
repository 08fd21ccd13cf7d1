//! Nonlinear statics, r(u) = f_int(u) − f_ext = 0 on the free dofs, under prescribed
//! displacements (by elimination, as [`crate::solve::Statics`]) and external forces.
//!
//! A call of [`Newton::solve`] goes from the last equilibrium to a new load in the
//! increments of [`Increments`]: the prescribed displacements and the external forces move
//! linearly from the old load to the new one, by at most `max_increment` (mm) of any
//! prescribed displacement per increment. Each increment starts from the linearized
//! predictor, Δu_f = K_ff⁻¹ (Δf_f − K_fc Δu_c), with the kept factorization of the tangent
//! (made at the converged state if there is none), then iterates by Newton's method
//! ([`Iteration::run`]) on the free dofs. An increment that does not converge in
//! `max_iterations`, whose line search fails, or that inverts an element (or whose tangent
//! is not positive definite), is cut back to half its size and retried from the last
//! converged state; a converged one lets the next grow back, up to the first size. An
//! increment smaller than the first one halved `max_cutbacks` times fails the solve with
//! [`ModelError::NotConverged`], naming the fraction of the load change reached; `u` is
//! left at the start of the call. A solve at an unchanged load (a new start, or new
//! equations; no forces that follow the load, [`InternalForces::follow_the_load`]) has
//! nothing to cut back: its halves would repeat the same problem, so it is retried once,
//! from a fresh factorization, only if it started on a kept one.
//!
//! With a single-precision factorization ([`Factorization::SupernodalSingle`]) the
//! corrections are those of an approximate tangent, as on a kept factorization; a fresh one
//! that gives no descent or a correction that is not finite has the rest of the increment
//! factorized in double (and only a double one's failed search counts as round-off). The
//! symbolic analysis is made once, in [`Newton::new`]; nothing is allocated per iteration.

use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::{max_abs, norm_of, Failure, Increments, Iteration, Settings, System};
use crate::assembly::{Assembler, Dirichlet, InternalForces};
use crate::error::ModelError;
use crate::linalg::{conjugate_gradient, Cholesky, Factorization};

/// What a solve did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// Iterations (corrections Δu) of each converged increment.
    pub iterations: Vec<usize>,
    /// Numeric factorizations, failed increments included.
    pub factorizations: usize,
    /// Iterations of the increments that did not converge (cut back, or failing the solve or
    /// its start), summed.
    pub failed_iterations: usize,
    /// Increments that were cut back.
    pub cutbacks: usize,
    /// ‖r_f‖ / scale at each iterate of the last increment (the convergence history).
    pub residuals: Vec<f64>,
    /// Time spent assembling, factorizing and solving in this solve.
    pub assembly: Duration,
    /// Time spent factorizing the tangent.
    pub factorization: Duration,
    /// Time spent solving with the factorization.
    pub solve: Duration,
}

impl Report {
    /// Counters and times zeroed, the lists' storage kept.
    fn clear(&mut self) {
        self.iterations.clear();
        self.residuals.clear();
        *self = Report {
            iterations: std::mem::take(&mut self.iterations),
            residuals: std::mem::take(&mut self.residuals),
            ..Report::default()
        };
    }
}

/// What a solve depends on besides the equations and the displacement: the load of the last
/// equilibrium and where the kept tangent was factorized (see [`Newton::checkpoint`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// The prescribed displacements of the last equilibrium (all dofs, mm).
    pub prescribed: Vec<f64>,
    /// The external forces of the last equilibrium (all dofs, N).
    pub external: Vec<f64>,
    /// The state (all dofs) at which the kept tangent was factorized; `None` without one.
    pub tangent_at: Option<Vec<f64>>,
    /// Whether the kept tangent's factor is in single precision
    /// ([`Factorization::SupernodalSingle`]; absent in states saved before it: double).
    #[serde(default)]
    pub single_precision: bool,
}

/// A sensitivity's solve stops at ‖K x − b‖ ≤ this · ‖b‖: the derivatives to about five
/// digits (1.5e-5 relative on the default tet10 block against a solve to 1e-10, which takes
/// half as many iterations again), where a fit's steps and intervals need two or three.
pub const SENSITIVITY_TOLERANCE: f64 = 1e-6;

/// Conjugate-gradient iterations a sensitivity's solve may take (on a kept factorization
/// of a nearby tangent it takes a few tens at most).
const SENSITIVITY_ITERATIONS: usize = 500;

/// Multiples σ of the tangent at rest added to a tangent that is not positive definite,
/// tried in turn ([`Bound::shifted`]).
const SHIFTS: [f64; 5] = [1e-2, 1e-1, 1.0, 10.0, 100.0];

/// A Newton–Raphson solver of nonlinear statics for one pattern and one set of constrained
/// dofs.
pub struct Newton {
    core: Core,
    iteration: Iteration,
}

/// The solver's state apart from the iteration's work vectors.
struct Core {
    bc: Dirichlet,
    chol: Cholesky,
    settings: Settings,
    /// Whether `chol` holds a factorization of the present equations' tangent (made at
    /// the state `factored_at`; `k` holds that tangent on the full pattern).
    factorized: bool,
    factored_at: Vec<f64>,
    /// Full tangent and its free–free part.
    k: Vec<f64>,
    reduced: Vec<f64>,
    /// The tangent at rest (u = 0, no load; full pattern), assembled the first time a
    /// tangent is not positive definite ([`SHIFTS`]); empty until then.
    at_rest: Vec<f64>,
    /// Internal forces at the last evaluation, and the state evaluated (all dofs).
    f: Vec<f64>,
    at: Vec<f64>,
    /// The last converged state (all dofs), the predictor's prescribed change (all dofs)
    /// and its correction (free dofs).
    converged: Vec<f64>,
    change: Vec<f64>,
    du: Vec<f64>,
    /// The load of the last equilibrium and of the current target (all dofs).
    prescribed: Vec<f64>,
    external: Vec<f64>,
    target_prescribed: Vec<f64>,
    target_external: Vec<f64>,
    /// The load fraction of the evaluations.
    s: f64,
    /// The largest force norm seen in this solve (the residual's scale).
    scale: f64,
    report: Report,
    /// The buffers of [`Newton::sensitivity`], made at its first call.
    exact: Option<Box<Exact>>,
}

/// The exact tangent at an equilibrium (full pattern and free–free part) and the vectors of
/// a sensitivity's solve (free dofs).
struct Exact {
    k: Vec<f64>,
    reduced: Vec<f64>,
    f: Vec<f64>,
    b: Vec<f64>,
    x: Vec<f64>,
}

impl std::fmt::Debug for Newton {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Newton")
            .field("free", &self.core.bc.n_free())
            .field("settings", &self.core.settings)
            .finish()
    }
}

impl Newton {
    /// Symbolic analysis of the free–free pattern; the last equilibrium is u = 0 under no
    /// load.
    pub fn new(
        asm: &Assembler,
        constrained: &[usize],
        factorization: Factorization,
        settings: Settings,
    ) -> Result<Self, ModelError> {
        settings.check()?;
        let bc = Dirichlet::new(asm, constrained)?;
        let chol = Cholesky::analyze(bc.symbolic().as_ref(), factorization)?;
        Ok(Self::with(bc, chol, asm.n_dofs(), asm.nnz(), settings))
    }

    /// A solver for other equations of the same pattern and constrained dofs (a mesh of
    /// the same connectivity with its nodes moved): the symbolic analysis shared, the last
    /// equilibrium u = 0 under no load.
    pub fn same_pattern(&self, settings: Settings) -> Result<Self, ModelError> {
        settings.check()?;
        let chol = self.core.chol.same_pattern()?;
        let (n, nnz) = (self.core.f.len(), self.core.k.len());
        Ok(Self::with(self.core.bc.clone(), chol, n, nnz, settings))
    }

    /// Back to the state [`Self::same_pattern`] makes (u = 0 under no load, no kept
    /// factorization), keeping the storage: a solver done with for the next equations of
    /// its pattern, which then need no fresh memory (a tet10 factor is mapped from the
    /// operating system page by page when new).
    pub fn recycle(&mut self, settings: Settings) -> Result<(), ModelError> {
        settings.check()?;
        let c = &mut self.core;
        c.factorized = false;
        c.chol.invalidate();
        c.at_rest.clear();
        for v in [
            &mut c.factored_at,
            &mut c.k,
            &mut c.reduced,
            &mut c.f,
            &mut c.at,
            &mut c.converged,
            &mut c.change,
            &mut c.du,
            &mut c.prescribed,
            &mut c.external,
            &mut c.target_prescribed,
            &mut c.target_external,
        ] {
            v.fill(0.0);
        }
        c.s = 0.0;
        c.scale = 0.0;
        self.iteration.reset();
        c.report.clear();
        c.settings = settings;
        Ok(())
    }

    /// Whether `other` solves with this one's symbolic analysis.
    pub fn shares_analysis(&self, other: &Newton) -> bool {
        self.core.chol.shares_analysis(&other.core.chol)
    }

    fn with(bc: Dirichlet, chol: Cholesky, n: usize, nnz: usize, settings: Settings) -> Self {
        let free = bc.n_free();
        let full = || vec![0.0; n];
        Self {
            iteration: Iteration::new(free, settings.max_iterations),
            core: Core {
                factorized: false,
                factored_at: full(),
                k: vec![0.0; nnz],
                reduced: vec![0.0; bc.nnz()],
                at_rest: Vec::new(),
                f: full(),
                at: full(),
                converged: full(),
                change: full(),
                du: vec![0.0; free],
                prescribed: full(),
                external: full(),
                target_prescribed: full(),
                target_external: full(),
                s: 0.0,
                scale: 0.0,
                report: Report {
                    residuals: Vec::with_capacity(settings.max_iterations + 1),
                    ..Report::default()
                },
                exact: None,
                bc,
                chol,
                settings,
            },
        }
    }

    /// The settings of later solves.
    pub fn settings(&self) -> Settings {
        self.core.settings
    }

    /// Changes the settings (e.g. `max_increment`) for later solves.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), ModelError> {
        settings.check()?;
        self.core.settings = settings;
        Ok(())
    }

    /// The dof split.
    pub fn dirichlet(&self) -> &Dirichlet {
        &self.core.bc
    }

    /// The internal forces (all dofs) at the last equilibrium: at the constrained dofs,
    /// the reactions plus the external forces there.
    pub fn internal_forces(&self) -> &[f64] {
        &self.core.f
    }

    /// Declares the kept factorization stale: the equations changed (material, contact
    /// springs), so the next increment starts from a new tangent.
    pub fn invalidate(&mut self) {
        self.core.factorized = false;
    }

    /// What the next solve depends on besides the equations and the caller's displacement.
    pub fn checkpoint(&self) -> Checkpoint {
        let c = &self.core;
        Checkpoint {
            prescribed: c.prescribed.clone(),
            external: c.external.clone(),
            tangent_at: c.factorized.then(|| c.factored_at.clone()),
            single_precision: c.factorized && c.chol.in_single(),
        }
    }

    /// Puts a checkpoint back for the same equations: the load of the last equilibrium and
    /// the kept tangent, factorized again where it was, so that the next solve goes as it
    /// would have from where the checkpoint was taken.
    pub fn resume(
        &mut self,
        eq: &(impl InternalForces + ?Sized),
        checkpoint: &Checkpoint,
    ) -> Result<(), ModelError> {
        let n = self.core.prescribed.len();
        if checkpoint.prescribed.len() != n || checkpoint.external.len() != n {
            return Err(ModelError::SizeMismatch {
                name: "Newton checkpoint",
                expected: n,
                got: checkpoint.prescribed.len(),
            });
        }
        self.restart(&checkpoint.prescribed, &checkpoint.external);
        if let Some(x) = &checkpoint.tangent_at {
            let c = &mut self.core;
            c.s = 0.0;
            c.at.copy_from_slice(x);
            Bound { core: c, eq }.tangent(!checkpoint.single_precision)?;
        }
        Ok(())
    }

    /// Declares the caller's displacement an equilibrium under this load (after it restored
    /// an earlier state): the next solve starts its increments from here.
    pub fn restart(&mut self, prescribed: &[f64], external: &[f64]) {
        let c = &mut self.core;
        for &d in c.bc.constrained() {
            c.prescribed[d] = prescribed[d];
        }
        c.external.copy_from_slice(external);
        c.factorized = false;
    }

    /// Direct differentiation of the last equilibrium `u` in a parameter p of the
    /// equations (a material constant), the prescribed displacements and the external
    /// forces not depending on p: from r(u(p), p) = 0, du_f/dp = −K_ff⁻¹ (∂f_int/∂p)_f with
    /// K the exact tangent at `u` and du_c/dp = 0. `partial` is ∂f_int/∂p at fixed `u` (all
    /// dofs); du/dp goes into `du` (all dofs) and the total derivative of the internal
    /// forces along the equilibria, ∂f_int/∂p + K du, into `total` (all dofs): at the held
    /// dofs the reactions' derivatives, at the free ones the solve's residual. K is
    /// assembled once; the system is solved by conjugate gradients preconditioned with the
    /// kept factorization (a tangent of an earlier iterate, in single precision; made at `u`
    /// if none is kept), to [`SENSITIVITY_TOLERANCE`], so the kept factorization and the
    /// next solve are untouched. Returns the iterations taken.
    pub fn sensitivity(
        &mut self,
        eq: &(impl InternalForces + ?Sized),
        u: &[f64],
        partial: &[f64],
        du: &mut [f64],
        total: &mut [f64],
    ) -> Result<usize, ModelError> {
        let c = &mut self.core;
        let x = c.exact.get_or_insert_with(|| {
            Box::new(Exact {
                k: vec![0.0; c.k.len()],
                reduced: vec![0.0; c.reduced.len()],
                f: vec![0.0; c.f.len()],
                b: vec![0.0; c.bc.n_free()],
                x: vec![0.0; c.bc.n_free()],
            })
        });
        eq.at_load_fraction(1.0);
        eq.internal(u, &mut x.f, Some(&mut x.k))?;
        c.bc.combine(&[(1.0, &x.k)], &mut x.reduced);
        c.bc.reduce(partial, &mut x.b);
        x.b.iter_mut().for_each(|b| *b = -*b);
        x.x.fill(0.0);
        if !c.factorized {
            c.at.copy_from_slice(u);
            c.s = 1.0;
            Bound { core: c, eq }.tangent(false)?;
        }
        let x = c.exact.as_mut().expect("made above");
        let iterations = conjugate_gradient::solve(
            c.bc.matrix(&x.reduced),
            &mut c.chol,
            &x.b,
            &mut x.x,
            SENSITIVITY_TOLERANCE,
            SENSITIVITY_ITERATIONS,
        )?;
        du.fill(0.0);
        c.bc.expand(&x.x, du);
        total.copy_from_slice(partial);
        c.bc.add_coupled(&x.k, &x.x, total);
        // The free rows: ∂f/∂p + K_ff x = −(b − K_ff x), the solve's residual.
        x.b.iter_mut().for_each(|b| *b = -*b);
        crate::assembly::mul_add(c.bc.matrix(&x.reduced), &x.x, 1.0, &mut x.b);
        c.bc.expand(&x.b, total);
        Ok(iterations)
    }

    /// As [`Self::solve`], but iterating first from `start` (all dofs; its held dofs taken
    /// at the prescribed values) at the new load: a start near the answer — the equilibrium
    /// of nearby equations moved along its derivative, a continuation in a material
    /// constant ([`Self::sensitivity`]) — converges in a few iterations on the kept
    /// factorization, where the path from the last equilibrium takes its increments. A
    /// start that does not converge is dropped and the path from the last equilibrium
    /// taken (the report counts both); on failure of both `u` keeps the last equilibrium.
    pub fn solve_from(
        &mut self,
        eq: &(impl InternalForces + ?Sized),
        u: &mut [f64],
        start: &[f64],
        prescribed: &[f64],
        external: &[f64],
    ) -> Result<&Report, ModelError> {
        self.core.report.clear();
        let c = &mut self.core;
        let last = (c.prescribed.clone(), c.external.clone());
        for &d in c.bc.constrained() {
            c.prescribed[d] = prescribed[d];
        }
        c.external.copy_from_slice(external);
        let mut x = start.to_vec();
        for &d in c.bc.constrained() {
            x[d] = prescribed[d];
        }
        if self.reach(eq, &mut x, prescribed, external).is_ok() {
            u.copy_from_slice(&x);
            return Ok(&self.core.report);
        }
        let c = &mut self.core;
        (c.prescribed, c.external) = last;
        self.reach(eq, u, prescribed, external)?;
        Ok(&self.core.report)
    }

    /// Moves `u` from the last equilibrium to equilibrium under the prescribed values
    /// `prescribed` (read at the constrained dofs) and the external forces `external` (all
    /// dofs). On failure `u` keeps the last equilibrium ([`Self::report`] says what the
    /// attempt did).
    pub fn solve(
        &mut self,
        eq: &(impl InternalForces + ?Sized),
        u: &mut [f64],
        prescribed: &[f64],
        external: &[f64],
    ) -> Result<&Report, ModelError> {
        self.core.report.clear();
        self.reach(eq, u, prescribed, external)?;
        Ok(&self.core.report)
    }

    /// What the last solve did, whether it converged or not.
    pub fn report(&self) -> &Report {
        &self.core.report
    }

    /// [`Self::solve`] adding to the report.
    fn reach(
        &mut self,
        eq: &(impl InternalForces + ?Sized),
        u: &mut [f64],
        prescribed: &[f64],
        external: &[f64],
    ) -> Result<(), ModelError> {
        let c = &mut self.core;
        for &d in c.bc.constrained() {
            c.target_prescribed[d] = prescribed[d];
        }
        c.target_external.copy_from_slice(external);
        c.scale = norm_of(external).max(norm_of(&c.external));
        c.converged.copy_from_slice(u);
        let change =
            c.bc.constrained()
                .iter()
                .map(|&d| (prescribed[d] - c.prescribed[d]).abs())
                .fold(0.0, f64::max);
        let base = 1.0 / (change / c.settings.max_increment).ceil().max(1.0);
        let unchanged = change == 0.0 && c.target_external == c.external && !eq.follow_the_load();
        let cutbacks = if unchanged {
            usize::from(c.factorized).min(c.settings.max_cutbacks)
        } else {
            c.settings.max_cutbacks
        };
        let mut increments = Increments::new(base, cutbacks);
        while let Some((from, to)) = increments.next() {
            match self.increment(eq, from, to) {
                Ok(iterations) => {
                    let c = &mut self.core;
                    c.report.iterations.push(iterations);
                    increments.succeeded();
                }
                Err(why) => {
                    let c = &mut self.core;
                    // The factorization may come from a diverged iterate: start afresh.
                    c.factorized = false;
                    if increments.failed() {
                        c.report.cutbacks += 1;
                        continue;
                    }
                    // The load change reached before the failure; `u` stays as it came.
                    return Err(ModelError::NotConverged {
                        reached: increments.reached(),
                        reason: format!(
                            "{}, with the increment cut back to {:.3e} of the load change",
                            why.reason(c.settings.max_iterations),
                            increments.size()
                        ),
                    });
                }
            }
        }
        // `f` holds the internal forces of the last accepted iterate: the equilibrium.
        let c = &mut self.core;
        u.copy_from_slice(&c.converged);
        c.prescribed.copy_from_slice(&c.target_prescribed);
        c.external.copy_from_slice(&c.target_external);
        Ok(())
    }

    /// One increment from the converged state at fraction `from` to `to`; on success the
    /// equilibrium is in `converged`.
    fn increment(
        &mut self,
        eq: &(impl InternalForces + ?Sized),
        from: f64,
        to: f64,
    ) -> Result<usize, Failure> {
        let c = &mut self.core;
        c.at.copy_from_slice(&c.converged);
        let step = Bound { core: c, eq }.predict(from, to)?;
        // The free unknowns, iterated in the predictor's buffer.
        let mut x = std::mem::take(&mut c.du);
        for (k, &d) in c.bc.free().iter().enumerate() {
            x[k] = c.at[d];
        }
        c.s = to;
        let settings = c.settings;
        let result = self
            .iteration
            .run(&mut Bound { core: c, eq }, &mut x, &settings, step);
        c.report.residuals.clear();
        c.report
            .residuals
            .extend_from_slice(&self.iteration.residuals);
        match result {
            Ok(_) => {
                c.set_at(&x);
                c.converged.copy_from_slice(&c.at);
            }
            Err(_) => c.report.failed_iterations += self.iteration.taken,
        }
        c.du = x;
        result
    }
}

impl Core {
    /// The state at the free unknowns `x` with the prescribed values at the load fraction
    /// of the evaluations, into `at`.
    fn set_at(&mut self, x: &[f64]) {
        let s = self.s;
        for &d in self.bc.constrained() {
            self.at[d] = self.prescribed[d] + s * (self.target_prescribed[d] - self.prescribed[d]);
        }
        for (k, &d) in self.bc.free().iter().enumerate() {
            self.at[d] = x[k];
        }
    }

    /// The external force at dof `d` for load fraction `s`.
    fn external_at(&self, d: usize, s: f64) -> f64 {
        self.external[d] + s * (self.target_external[d] - self.external[d])
    }
}

/// The solver's state with the equations it solves: the system Newton's method iterates on.
struct Bound<'a, E: ?Sized> {
    core: &'a mut Core,
    eq: &'a E,
}

impl<E: InternalForces + ?Sized> Bound<'_, E> {
    /// Assembles and factorizes the tangent at `at` for the evaluations' load fraction (in
    /// double precision if `exact`, else as the analysis asks); returns whether the factor
    /// is in double precision.
    fn tangent(&mut self, exact: bool) -> Result<bool, ModelError> {
        let c = &mut *self.core;
        c.factorized = false;
        let start = Instant::now();
        self.eq.at_load_fraction(c.s);
        let result = self.eq.internal(&c.at, &mut c.f, Some(&mut c.k));
        c.report.assembly += start.elapsed();
        result?;
        let start = Instant::now();
        c.bc.combine(&[(1.0, &c.k)], &mut c.reduced);
        let matrix = c.bc.matrix(&c.reduced);
        let mut factorized = if exact {
            c.chol.factorize_exact(matrix)
        } else {
            c.chol.factorize(matrix)
        };
        if let Err(ModelError::Singular { .. }) = factorized {
            factorized = factorized.or_else(|e| self.shifted(e));
        }
        let c = &mut *self.core;
        c.report.factorization += start.elapsed();
        c.report.factorizations += 1;
        c.factorized = factorized.is_ok();
        c.factored_at.copy_from_slice(&c.at);
        factorized.map(|()| !c.chol.in_single())
    }

    /// Factorizes K_T + σ K₀ for the first σ of [`SHIFTS`] whose factorization succeeds
    /// (K₀ the tangent at rest, positive definite where the supports hold the body), after
    /// `failed`, the factorization of K_T alone: Newton's iterations go on from an
    /// indefinite tangent (slack membranes' negative geometric stiffness outweighing the
    /// contents' on a fine graded mesh) towards the same equilibrium, the residual being
    /// exact. A floating body stays singular with every shift: `failed` is returned.
    fn shifted(&mut self, failed: ModelError) -> Result<(), ModelError> {
        let c = &mut *self.core;
        if c.at_rest.is_empty() {
            let (rest, mut f) = (vec![0.0; c.at.len()], vec![0.0; c.f.len()]);
            c.at_rest = vec![0.0; c.k.len()];
            self.eq.at_load_fraction(0.0);
            let assembled = self.eq.internal(&rest, &mut f, Some(&mut c.at_rest));
            self.eq.at_load_fraction(c.s);
            assembled?;
        }
        for sigma in SHIFTS {
            c.bc.combine(&[(1.0, &c.k), (sigma, &c.at_rest)], &mut c.reduced);
            if c.chol.factorize_exact(c.bc.matrix(&c.reduced)).is_ok() {
                return Ok(());
            }
        }
        Err(failed)
    }

    /// The linearized predictor: `at` (the converged state on entry) moves by
    /// Δu_f = K_ff⁻¹ (Δf_f − K_fc Δu_c) for the load change from `from` to `to`, with the
    /// prescribed values at their targets (into `at`; its correction in `du`). Factorizes
    /// the tangent at the converged state if no factorization is kept. Without a load
    /// change `at` stays. Returns the ∞-norm of the correction.
    fn predict(&mut self, from: f64, to: f64) -> Result<f64, Failure> {
        let c = &mut *self.core;
        let unchanged =
            c.bc.constrained()
                .iter()
                .all(|&d| c.target_prescribed[d] == c.prescribed[d])
                && c.target_external == c.external;
        if unchanged {
            return Ok(0.0);
        }
        if !c.factorized {
            c.s = from;
            self.tangent(false).map_err(Failure::Model)?;
        }
        let c = &mut *self.core;
        let start = Instant::now();
        c.change.fill(0.0);
        for &d in c.bc.constrained() {
            c.change[d] = (to - from) * (c.target_prescribed[d] - c.prescribed[d]);
            c.at[d] = c.prescribed[d] + to * (c.target_prescribed[d] - c.prescribed[d]);
        }
        for (k, &d) in c.bc.free().iter().enumerate() {
            c.du[k] = c.external_at(d, to) - c.external_at(d, from);
        }
        c.bc.subtract_prescribed(&c.k, &c.change, &mut c.du);
        c.chol.solve_in_place(&mut c.du);
        for (k, &d) in c.bc.free().iter().enumerate() {
            c.at[d] += c.du[k];
        }
        c.report.solve += start.elapsed();
        Ok(max_abs(&c.du))
    }
}

impl<E: InternalForces + ?Sized> System for Bound<'_, E> {
    /// r_f = f_int − f_ext on the free dofs at `x` for the evaluations' load fraction; the
    /// scale is the largest force norm of the solve (internal forces, reactions included,
    /// and external forces).
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(f64, f64), ModelError> {
        let c = &mut *self.core;
        c.set_at(x);
        let start = Instant::now();
        self.eq.at_load_fraction(c.s);
        let result = self.eq.internal(&c.at, &mut c.f, None);
        c.report.assembly += start.elapsed();
        result?;
        let mut sq = 0.0;
        for (k, &d) in c.bc.free().iter().enumerate() {
            r[k] = c.f[d] - c.external_at(d, c.s);
            sq += r[k] * r[k];
        }
        c.scale = c.scale.max(norm_of(&c.f)).max(1e-300);
        Ok((sq.sqrt(), c.scale))
    }

    fn factorize(&mut self, x: &[f64], exact: bool) -> Result<bool, ModelError> {
        self.core.set_at(x);
        self.tangent(exact)
    }

    fn factorized(&self) -> bool {
        self.core.factorized
    }

    fn solve(&mut self, d: &mut [f64]) {
        let c = &mut *self.core;
        let start = Instant::now();
        c.chol.solve_in_place(d);
        c.report.solve += start.elapsed();
    }
}
