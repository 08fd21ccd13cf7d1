//! Nonlinear statics, r(u) = f_int(u) − f_ext = 0 on the free dofs, under prescribed
//! displacements (by elimination, as [`super::Statics`]) and external forces.
//!
//! A call of [`Newton::solve`] goes from the last equilibrium to a new load in increments:
//! the prescribed displacements and the external forces move linearly from the old load to
//! the new one, by at most `max_increment` (mm) of any prescribed displacement per increment.
//! Each increment starts from the linearized predictor, Δu_f = K_ff⁻¹ (Δf_f − K_fc Δu_c),
//! with the kept factorization of the tangent (made at the converged state if there is
//! none), then iterates: solve K_ff Δu = −r_f and step along Δu. The factorization is
//! reused while the residual falls fast (modified Newton: each iteration must reduce ‖r_f‖
//! at least by the factor `reuse_contraction`); otherwise the tangent is reassembled and
//! refactorized at the current iterate (Newton–Raphson; with `reuse_contraction = 0` every
//! iteration). After a fresh factorization the step is taken with a backtracking line
//! search on ‖r_f‖ (α halved while ‖r_f(u + αΔu)‖ > (1 − 10⁻⁴ α) ‖r_f(u)‖, or while an
//! element inverts); the steps with a reused factorization are Anderson-accelerated
//! ([`super::anderson`]: the last steps on the same factorization within the increment
//! combined; the history starts afresh at each increment and each factorization, so a
//! restored checkpoint iterates as the uninterrupted run). An accelerated step that does not
//! decrease ‖r_f‖ is undone and retried plain (the retry counts as an iteration), and a
//! plain one that does not is undone and the tangent refactorized. Measured (2026-11-27,
//! one run of a scratch program): after the default tet10 block's blade advance from 50 to
//! 51 mm at a 10 mm pull, 14 iterations on the kept factorization became 9. The symbolic
//! analysis is made once, in [`Newton::new`].
//!
//! With a single-precision factorization ([`Factorization::SupernodalSingle`]) the
//! corrections are those of an approximate tangent, as on a kept factorization; a fresh one
//! whose direction is not finite or gives no descent has the rest of the increment
//! factorized in double (and only a double one's failed search counts as round-off).
//!
//! An increment has converged when ‖r_f‖ ≤ `residual_tolerance` · (the largest force norm
//! of the solve: internal forces, reactions included, and external forces) and the last
//! correction ‖αΔu‖_∞ ≤ `displacement_tolerance` · ‖u‖_∞; or when the line search finds no
//! descent at a residual already within round-off (10⁻¹³ of that scale, or a full Newton
//! correction below 10⁻⁸ of the displacements). An increment that
//! does not converge in `max_iterations`, whose line search fails, or that inverts an
//! element (or whose tangent is not positive definite), is cut back to half its size and
//! retried from the last converged state; a converged one lets the next grow back, up to
//! the first size. An increment smaller than the first one halved `max_cutbacks` times
//! fails the solve with [`ModelError::NotConverged`], naming the fraction of the load
//! change reached; `u` is left at the start of the call.
//!
//! Nothing is allocated per iteration: the vectors and the factor's storage are made in
//! [`Newton::new`]; an iteration assembles into them, refactorizes numerically and solves.

use std::time::{Duration, Instant};

use serde::{Deserialize, Serialize};

use super::anderson::Anderson;
use super::cholesky::{Cholesky, Factorization};
use crate::assembly::{Assembler, Dirichlet};
use crate::error::ModelError;

/// A residual below this fraction of the force scale is round-off.
const ROUND_OFF: f64 = 1e-13;

/// A Newton correction below this fraction of the displacements that gives no descent is
/// round-off (systems with condition numbers up to about 10⁸ reach it).
const ROUND_OFF_CORRECTION: f64 = 1e-8;

/// The Euclidean norm.
pub(crate) fn norm_of(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// The largest magnitude (the ∞-norm).
pub(crate) fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// What the solver iterates on: the internal forces and their tangent.
pub trait Equations {
    /// Adds the internal forces at `u` (all dofs) to `f` and, when given, the tangent values
    /// (on the assembler's pattern) to `k`. An inverted element is an error
    /// ([`ModelError::Inverted`]); the solver cuts back.
    fn add_internal(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ModelError>;

    /// Declares the load fraction s ∈ [0, 1] of the solve's load change at which the next
    /// evaluations are made (0 the last equilibrium's load, 1 the target): for equations
    /// whose own forces follow the load, such as an active tension. Others ignore it.
    fn at_load_fraction(&mut self, _s: f64) {}

    /// Writes (rather than adds) the internal forces and the tangent.
    fn internal(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        f.fill(0.0);
        if let Some(k) = k.as_deref_mut() {
            k.fill(0.0);
        }
        self.add_internal(u, f, k)
    }
}

/// The solver's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Largest change of any prescribed displacement per increment (mm).
    pub max_increment: f64,
    pub residual_tolerance: f64,
    pub displacement_tolerance: f64,
    pub max_iterations: usize,
    pub max_cutbacks: usize,
    /// The factorization is reused while every iteration reduces ‖r_f‖ at least by this
    /// factor; 0 refactorizes at every iteration (Newton–Raphson).
    pub reuse_contraction: f64,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            max_increment: 1.0,
            residual_tolerance: 1e-10,
            displacement_tolerance: 1e-10,
            max_iterations: 25,
            max_cutbacks: 8,
            reuse_contraction: 0.1,
        }
    }
}

/// What a solve did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// Iterations (corrections Δu) of each converged increment.
    pub iterations: Vec<usize>,
    /// Numeric factorizations, failed increments included.
    pub factorizations: usize,
    /// Increments that were cut back.
    pub cutbacks: usize,
    /// ‖r_f‖ / scale at each iterate of the last increment (the convergence history).
    pub residuals: Vec<f64>,
    /// Time spent assembling, factorizing and solving in this solve.
    pub assembly: Duration,
    pub factorization: Duration,
    pub solve: Duration,
}

/// Why an increment failed.
#[derive(Debug)]
enum Failure {
    Iterations,
    LineSearch,
    /// An inverted element, or a singular tangent.
    Model(ModelError),
}

/// What a solve depends on besides the equations and the displacement: the load of the last
/// equilibrium and where the kept tangent was factorized (see [`Newton::checkpoint`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    pub prescribed: Vec<f64>,
    pub external: Vec<f64>,
    pub tangent_at: Option<Vec<f64>>,
    /// Whether the kept tangent's factor is in single precision
    /// ([`Factorization::SupernodalSingle`]; absent in states saved before it: double).
    #[serde(default)]
    pub single_precision: bool,
}

/// A Newton–Raphson solver for one pattern and one set of constrained dofs.
pub struct Newton {
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
    /// Internal forces (all dofs), free residual, correction.
    f: Vec<f64>,
    r: Vec<f64>,
    du: Vec<f64>,
    /// Accelerates the iterations on a kept factorization.
    anderson: Anderson,
    /// Trial state, last converged state, and the predictor's prescribed change (all dofs).
    trial: Vec<f64>,
    converged: Vec<f64>,
    change: Vec<f64>,
    /// The load of the last equilibrium and of the current target (all dofs).
    prescribed: Vec<f64>,
    external: Vec<f64>,
    target_prescribed: Vec<f64>,
    target_external: Vec<f64>,
    /// The largest force norm seen in this solve (the residual's scale).
    scale: f64,
    report: Report,
}

impl std::fmt::Debug for Newton {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Newton")
            .field("free", &self.bc.n_free())
            .field("settings", &self.settings)
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
        Self::check(&settings)?;
        let bc = Dirichlet::new(asm, constrained)?;
        let chol = Cholesky::analyze(bc.symbolic().as_ref(), factorization)?;
        Ok(Self::with(bc, chol, asm.n_dofs(), asm.nnz(), settings))
    }

    /// A solver for other equations of the same pattern and constrained dofs (a mesh of
    /// the same connectivity with its nodes moved): the symbolic analysis shared, the last
    /// equilibrium u = 0 under no load.
    pub fn same_pattern(&self, settings: Settings) -> Result<Self, ModelError> {
        Self::check(&settings)?;
        let chol = self.chol.same_pattern()?;
        let (n, nnz) = (self.f.len(), self.k.len());
        Ok(Self::with(self.bc.clone(), chol, n, nnz, settings))
    }

    /// Back to the state [`Self::same_pattern`] makes (u = 0 under no load, no kept
    /// factorization), keeping the storage: a solver done with for the next equations of
    /// its pattern, which then need no fresh memory (a tet10 factor is mapped from the
    /// operating system page by page when new).
    pub fn recycle(&mut self, settings: Settings) -> Result<(), ModelError> {
        Self::check(&settings)?;
        self.factorized = false;
        self.chol.invalidate();
        for v in [
            &mut self.factored_at,
            &mut self.k,
            &mut self.reduced,
            &mut self.f,
            &mut self.r,
            &mut self.du,
            &mut self.trial,
            &mut self.converged,
            &mut self.change,
            &mut self.prescribed,
            &mut self.external,
            &mut self.target_prescribed,
            &mut self.target_external,
        ] {
            v.fill(0.0);
        }
        self.anderson.reset();
        self.scale = 0.0;
        self.report.residuals.clear();
        self.report.iterations.clear();
        // The counters and times zeroed, the lists' storage kept.
        self.report = Report {
            residuals: std::mem::take(&mut self.report.residuals),
            iterations: std::mem::take(&mut self.report.iterations),
            ..Report::default()
        };
        self.settings = settings;
        Ok(())
    }

    /// Whether `other` solves with this one's symbolic analysis.
    pub fn shares_analysis(&self, other: &Newton) -> bool {
        self.chol.shares_analysis(&other.chol)
    }

    fn with(bc: Dirichlet, chol: Cholesky, n: usize, nnz: usize, settings: Settings) -> Self {
        let free = bc.n_free();
        let full = || vec![0.0; n];
        Self {
            factorized: false,
            factored_at: full(),
            k: vec![0.0; nnz],
            reduced: vec![0.0; bc.nnz()],
            f: full(),
            r: vec![0.0; free],
            du: vec![0.0; free],
            anderson: Anderson::new(free),
            trial: full(),
            converged: full(),
            change: full(),
            prescribed: full(),
            external: full(),
            target_prescribed: full(),
            target_external: full(),
            scale: 0.0,
            report: Report {
                residuals: Vec::with_capacity(settings.max_iterations + 1),
                ..Report::default()
            },
            bc,
            chol,
            settings,
        }
    }

    fn check(settings: &Settings) -> Result<(), ModelError> {
        crate::error::positive("max_increment", settings.max_increment)?;
        if !(0.0..1.0).contains(&settings.reuse_contraction) {
            return Err(ModelError::InvalidParameter {
                name: "reuse_contraction".into(),
                value: settings.reuse_contraction,
                reason: "must lie in [0, 1)",
            });
        }
        Ok(())
    }

    pub fn settings(&self) -> Settings {
        self.settings
    }

    /// Changes the settings (e.g. `max_increment`) for later solves.
    pub fn set_settings(&mut self, settings: Settings) -> Result<(), ModelError> {
        Self::check(&settings)?;
        self.settings = settings;
        Ok(())
    }

    /// The dof split.
    pub fn dirichlet(&self) -> &Dirichlet {
        &self.bc
    }

    /// The internal forces (all dofs) at the last equilibrium: at the constrained dofs,
    /// the reactions plus the external forces there.
    pub fn internal_forces(&self) -> &[f64] {
        &self.f
    }

    /// Declares the kept factorization stale: the equations changed (material, contact
    /// springs), so the next increment starts from a new tangent.
    pub fn invalidate(&mut self) {
        self.factorized = false;
    }

    /// What the next solve depends on besides the equations and the caller's displacement.
    pub fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            prescribed: self.prescribed.clone(),
            external: self.external.clone(),
            tangent_at: self.factorized.then(|| self.factored_at.clone()),
            single_precision: self.factorized && self.chol.in_single(),
        }
    }

    /// Puts a checkpoint back for the same equations: the load of the last equilibrium and
    /// the kept tangent, factorized again where it was, so that the next solve goes as it
    /// would have from where the checkpoint was taken.
    pub fn resume(
        &mut self,
        eq: &mut impl Equations,
        checkpoint: &Checkpoint,
    ) -> Result<(), ModelError> {
        let n = self.prescribed.len();
        if checkpoint.prescribed.len() != n || checkpoint.external.len() != n {
            return Err(ModelError::SizeMismatch {
                name: "Newton checkpoint",
                expected: n,
                got: checkpoint.prescribed.len(),
            });
        }
        self.restart(&checkpoint.prescribed, &checkpoint.external);
        if let Some(x) = &checkpoint.tangent_at {
            self.trial.copy_from_slice(x);
            self.tangent(eq, 0.0, !checkpoint.single_precision)
                .map_err(|why| match why {
                    Failure::Model(e) => e,
                    _ => ModelError::LinearAlgebra("the kept tangent could not be rebuilt".into()),
                })?;
        }
        Ok(())
    }

    /// Declares the caller's displacement an equilibrium under this load (after it restored
    /// an earlier state): the next solve starts its increments from here.
    pub fn restart(&mut self, prescribed: &[f64], external: &[f64]) {
        for &d in self.bc.constrained() {
            self.prescribed[d] = prescribed[d];
        }
        self.external.copy_from_slice(external);
        self.factorized = false;
    }

    /// Moves `u` from the last equilibrium to equilibrium under the prescribed values
    /// `prescribed` (read at the constrained dofs) and the external forces `external` (all
    /// dofs). On failure `u` keeps the last equilibrium.
    pub fn solve(
        &mut self,
        eq: &mut impl Equations,
        u: &mut [f64],
        prescribed: &[f64],
        external: &[f64],
    ) -> Result<&Report, ModelError> {
        for &d in self.bc.constrained() {
            self.target_prescribed[d] = prescribed[d];
        }
        self.target_external.copy_from_slice(external);
        self.scale = norm_of(external).max(norm_of(&self.external));
        self.converged.copy_from_slice(u);
        let change = self
            .bc
            .constrained()
            .iter()
            .map(|&d| (prescribed[d] - self.prescribed[d]).abs())
            .fold(0.0, f64::max);
        let base = 1.0 / (change / self.settings.max_increment).ceil().max(1.0);
        self.report.iterations.clear();
        self.report.factorizations = 0;
        self.report.cutbacks = 0;
        self.report.assembly = Duration::ZERO;
        self.report.factorization = Duration::ZERO;
        self.report.solve = Duration::ZERO;
        let smallest = base / f64::from(1u32 << self.settings.max_cutbacks.min(30));
        let (mut s, mut ds) = (0.0, base);
        while s < 1.0 {
            let next = (s + ds).min(1.0);
            match self.increment(eq, s, next) {
                Ok(iterations) => {
                    self.report.iterations.push(iterations);
                    self.converged.copy_from_slice(&self.trial);
                    s = next;
                    ds = (2.0 * ds).min(base);
                }
                Err(why) => {
                    // The factorization may come from a diverged iterate: start afresh.
                    self.factorized = false;
                    if 0.5 * ds >= smallest {
                        self.report.cutbacks += 1;
                        ds *= 0.5;
                        continue;
                    }
                    // The load change reached before the failure; `u` stays as it came.
                    let reason = match why {
                        Failure::Iterations => format!(
                            "Newton's method did not converge in {} iterations",
                            self.settings.max_iterations
                        ),
                        Failure::LineSearch => "the line search found no descent".into(),
                        Failure::Model(e) => e.to_string(),
                    };
                    return Err(ModelError::NotConverged {
                        reached: s,
                        reason: format!(
                            "{reason}, with the increment cut back to {ds:.3e} of the load change"
                        ),
                    });
                }
            }
        }
        // `f` holds the internal forces of the last accepted iterate: the equilibrium.
        u.copy_from_slice(&self.converged);
        self.prescribed.copy_from_slice(&self.target_prescribed);
        self.external.copy_from_slice(&self.target_external);
        Ok(&self.report)
    }

    /// The load at fraction `s` of the change, at the constrained dofs of `x`.
    fn set_prescribed(&self, s: f64, x: &mut [f64]) {
        for &d in self.bc.constrained() {
            x[d] = self.prescribed[d] + s * (self.target_prescribed[d] - self.prescribed[d]);
        }
    }

    /// The external force at dof `d` for load fraction `s`.
    fn external_at(&self, d: usize, s: f64) -> f64 {
        self.external[d] + s * (self.target_external[d] - self.external[d])
    }

    /// One increment from the converged state at fraction `from` to `to`; on success the
    /// equilibrium is in `trial`.
    fn increment(&mut self, eq: &mut impl Equations, from: f64, to: f64) -> Result<usize, Failure> {
        self.report.residuals.clear();
        // Another load is another map: the steps of earlier increments do not combine.
        self.anderson.reset();
        self.trial.copy_from_slice(&self.converged);
        self.predict(eq, from, to)?;
        let mut norm = self.residual(eq, to)?;
        if self.trial == self.converged && norm <= self.settings.residual_tolerance * self.scale {
            return Ok(0);
        }
        // The contraction of the last iteration; infinite forces a refactorization.
        let mut contraction = 0.0;
        // Whether the next factorizations are made in double precision whatever the
        // analysis asks for (after a single-precision one gave no descent).
        let mut exact = false;
        for iteration in 1..=self.settings.max_iterations {
            let fresh = !self.factorized || contraction > self.settings.reuse_contraction;
            if fresh {
                self.tangent(eq, to, exact)?;
            }
            if let Err(e) = self.direction() {
                // A single-precision factor whose correction is not finite: the increment
                // goes on in double precision.
                if !(fresh && self.chol.in_single()) {
                    return Err(e);
                }
                exact = true;
                contraction = f64::INFINITY;
                continue;
            }
            let mut accelerated = false;
            let outcome = if fresh {
                self.line_search(eq, to, norm)
            } else {
                accelerated = self.anderson.step(&mut self.du);
                self.reused_step(eq, to, norm)
            };
            let step = match outcome {
                Ok((next, step, alpha)) => {
                    if fresh {
                        self.anderson.start(&self.du, alpha);
                    }
                    contraction = next / norm.max(1e-300);
                    norm = next;
                    step
                }
                // An accelerated step that gave no descent: the plain one next.
                Err(Failure::LineSearch) if accelerated => {
                    self.anderson.reset();
                    continue;
                }
                // A reused factorization that gave no descent: refactorize here.
                Err(Failure::LineSearch) if !fresh => {
                    contraction = f64::INFINITY;
                    continue;
                }
                // A single-precision factor whose direction gave no descent: the rest of
                // the increment in double precision, from where the search stopped (round-off
                // is judged on an exact direction only).
                Err(Failure::LineSearch) if self.chol.in_single() => {
                    norm = self.residual(eq, to)?;
                    exact = true;
                    contraction = f64::INFINITY;
                    continue;
                }
                // No descent left at round-off: converged as far as arithmetic allows.
                Err(Failure::LineSearch) if self.at_round_off(norm) => return Ok(iteration),
                Err(e) => return Err(e),
            };
            let size = self
                .trial
                .iter()
                .fold(0.0f64, |a, x| a.max(x.abs()))
                .max(1e-300);
            if norm <= self.settings.residual_tolerance * self.scale
                && step <= self.settings.displacement_tolerance * size
            {
                return Ok(iteration);
            }
        }
        Err(Failure::Iterations)
    }

    /// The linearized predictor: `trial` (the converged state on entry) moves by
    /// Δu_f = K_ff⁻¹ (Δf_f − K_fc Δu_c) for the load change from `from` to `to`, with the
    /// prescribed values at their targets. Factorizes the tangent at the converged state if
    /// no factorization is kept. Without a load change `trial` stays.
    fn predict(&mut self, eq: &mut impl Equations, from: f64, to: f64) -> Result<(), Failure> {
        let unchanged = self
            .bc
            .constrained()
            .iter()
            .all(|&d| self.target_prescribed[d] == self.prescribed[d])
            && self.target_external == self.external;
        if unchanged {
            return Ok(());
        }
        if !self.factorized {
            self.tangent(eq, from, false)?;
        }
        let start = Instant::now();
        self.change.fill(0.0);
        for &d in self.bc.constrained() {
            self.change[d] = (to - from) * (self.target_prescribed[d] - self.prescribed[d]);
        }
        let mut trial = std::mem::take(&mut self.trial);
        self.set_prescribed(to, &mut trial);
        self.trial = trial;
        for (k, &d) in self.bc.free().iter().enumerate() {
            self.du[k] = self.external_at(d, to) - self.external_at(d, from);
        }
        self.bc
            .subtract_prescribed(&self.k, &self.change, &mut self.du);
        self.chol.solve_in_place(&mut self.du);
        for (k, &d) in self.bc.free().iter().enumerate() {
            self.trial[d] += self.du[k];
        }
        self.report.solve += start.elapsed();
        Ok(())
    }

    /// r_f = f_int − f_ext on the free dofs at `trial` for load fraction `s`; updates the
    /// force scale, records ‖r_f‖ relative to it and returns ‖r_f‖.
    fn residual(&mut self, eq: &mut impl Equations, s: f64) -> Result<f64, Failure> {
        let start = Instant::now();
        eq.at_load_fraction(s);
        let result = eq.internal(&self.trial, &mut self.f, None);
        self.report.assembly += start.elapsed();
        result.map_err(Failure::Model)?;
        let mut sq = 0.0;
        for (k, &d) in self.bc.free().iter().enumerate() {
            self.r[k] = self.f[d] - self.external_at(d, s);
            sq += self.r[k] * self.r[k];
        }
        let norm = sq.sqrt();
        self.scale = self.scale.max(norm_of(&self.f)).max(1e-300);
        self.report.residuals.push(norm / self.scale);
        Ok(norm)
    }

    /// Assembles and factorizes the tangent at `trial` for load fraction `s` (in double
    /// precision if `exact`, else as the analysis asks).
    fn tangent(&mut self, eq: &mut impl Equations, s: f64, exact: bool) -> Result<(), Failure> {
        self.factorized = false;
        let start = Instant::now();
        eq.at_load_fraction(s);
        let result = eq.internal(&self.trial, &mut self.f, Some(&mut self.k));
        self.report.assembly += start.elapsed();
        result.map_err(Failure::Model)?;
        let start = Instant::now();
        self.bc.combine(&[(1.0, &self.k)], &mut self.reduced);
        let matrix = self.bc.matrix(&self.reduced);
        let factorized = if exact {
            self.chol.factorize_exact(matrix)
        } else {
            self.chol.factorize(matrix)
        };
        self.report.factorization += start.elapsed();
        self.report.factorizations += 1;
        self.factorized = factorized.is_ok();
        self.factored_at.copy_from_slice(&self.trial);
        factorized.map_err(Failure::Model)
    }

    /// Δu = −K_ff⁻¹ r_f.
    fn direction(&mut self) -> Result<(), Failure> {
        let start = Instant::now();
        for (d, r) in self.du.iter_mut().zip(&self.r) {
            *d = -r;
        }
        self.chol.solve_in_place(&mut self.du);
        self.report.solve += start.elapsed();
        if self.du.iter().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(Failure::LineSearch)
        }
    }

    /// Whether the state is converged as far as arithmetic allows: ‖r_f‖ within round-off of
    /// the force scale, or a fresh Newton correction Δu = −K⁻¹ r_f (in `du`) that gives no
    /// descent and is below [`ROUND_OFF_CORRECTION`] of u. With the exact tangent Δu is a
    /// descent direction of ‖r_f‖ unless r_f is round-off; near-incompressible laws sum
    /// internal forces far larger than the net ones, so their floor lies above the first
    /// (measured: ‖r_f‖ ≈ 5e-9 of the scale, Δu ≈ 2e-10 of u at ν = 0.4999).
    fn at_round_off(&self, norm: f64) -> bool {
        norm <= ROUND_OFF * self.scale
            || max_abs(&self.du) <= ROUND_OFF_CORRECTION * max_abs(&self.trial)
    }

    /// Steps `trial` by Δu from a reused factorization; if ‖r_f‖ does not decrease, undoes
    /// the step (recomputing the residual there) and reports no descent. Returns the new
    /// ‖r_f‖, ‖Δu‖_∞ and the step length 1.
    fn reused_step(
        &mut self,
        eq: &mut impl Equations,
        s: f64,
        norm: f64,
    ) -> Result<(f64, f64, f64), Failure> {
        self.move_trial(1.0);
        match self.residual(eq, s) {
            Ok(next) if next < norm => {
                let size = self.du.iter().fold(0.0f64, |a, x| a.max(x.abs()));
                return Ok((next, size, 1.0));
            }
            Ok(_) => {
                self.report.residuals.pop();
            }
            Err(Failure::Model(_)) => {}
            Err(other) => return Err(other),
        }
        self.move_trial(-1.0);
        self.residual(eq, s)?;
        self.report.residuals.pop();
        Err(Failure::LineSearch)
    }

    /// trial_f += α Δu.
    fn move_trial(&mut self, alpha: f64) {
        for (k, &d) in self.bc.free().iter().enumerate() {
            self.trial[d] += alpha * self.du[k];
        }
    }

    /// Steps `trial` along Δu with a backtracking line search; returns the new ‖r_f‖, the
    /// size ‖αΔu‖_∞ of the step taken and α.
    fn line_search(
        &mut self,
        eq: &mut impl Equations,
        s: f64,
        norm: f64,
    ) -> Result<(f64, f64, f64), Failure> {
        let mut alpha = 1.0;
        let mut taken = 0.0;
        for _ in 0..8 {
            // Move from the step taken so far to α Δu.
            self.move_trial(alpha - taken);
            taken = alpha;
            let size = alpha * self.du.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            match self.residual(eq, s) {
                Ok(next) if next <= (1.0 - 1e-4 * alpha) * norm || next == 0.0 => {
                    return Ok((next, size, alpha));
                }
                Ok(_) => {
                    self.report.residuals.pop();
                }
                Err(Failure::Model(_)) => {}
                Err(other) => return Err(other),
            }
            alpha *= 0.5;
        }
        Err(Failure::LineSearch)
    }
}
