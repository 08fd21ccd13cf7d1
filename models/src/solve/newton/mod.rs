//! Newton's method: one executor for every nonlinear solve of the crate — the static
//! equilibria of the scenes ([`Newton`]) and the steps of the implicit time integrators at
//! finite strain (`crate::solve::effective`). A solve is a [`System`] — a residual r(x) on
//! its unknowns and the factorization of its Jacobian — iterated from a start by
//! [`Iteration::run`], with one reuse policy, one line search ([`line_search`]), one
//! convergence test ([`Iteration::run`]'s) and one set of constants; a change of load too
//! large for one solve is taken in the increments of one cut-back policy ([`Increments`]).
//!
//! **An iteration** from x with the residual r = r(x): the kept factorization of an earlier
//! Jacobian is reused while the last iteration reduced ‖r‖ at least by the factor
//! `reuse_contraction` (modified Newton; 0 refactorizes at every iteration, Newton–Raphson),
//! else the Jacobian is factorized at x; the correction d = J⁻¹ r is taken along x − α d by
//! the line search. Steps on a kept factorization may be Anderson-accelerated
//! ([`anderson`]: the last steps on one factorization combined). A step that finds no
//! descent on a kept factorization (or an accelerated one) is retried on a fresh one (or
//! plain); a fresh factorization that is not the exact tangent (single precision, or
//! shifted towards the mass) and finds none is made again exactly.
//!
//! **Converged** when ‖r‖ ≤ `residual_tolerance` · scale (the largest norm of the forces
//! that balance) and the step ‖αd‖∞ ≤ `displacement_tolerance` · max(‖x‖∞,
//! [`DISPLACEMENT_FLOOR`]); or when a step is within round-off of x ([`ROUND_OFF_STEP`]);
//! or, with the exact tangent, when no descent is left at a residual within round-off
//! (`round_off` · scale, or a correction below [`ROUND_OFF_CORRECTION`] of x), or a step
//! along a correction below [`ROUND_OFF_CORRECTION`] of x does not halve the residual (the
//! residual is then the stresses' round-off: stiff lines at strains of 10⁻⁹ leave
//! corrections of 10⁻¹² mm that wander without end). Nothing is allocated per iteration.

mod anderson;
mod increments;
mod line_search;
mod statics;

pub use increments::Increments;
pub use line_search::line_search;
pub use statics::{Checkpoint, Newton, Report};

use anderson::Anderson;

use crate::error::ModelError;

/// A step below this fraction of the displacements is within round-off: converged.
pub const ROUND_OFF_STEP: f64 = 1e-10;

/// A correction of the exact tangent (Newton's estimate of the error in x) below this
/// fraction of the displacements that gives no descent, or a step along which does not
/// halve the residual, is the round-off of the stresses (stiff membranes on soft contents,
/// a contrast of 10⁶, leave corrections of 10⁻⁹ to 10⁻⁸ of the displacement floor; systems
/// with condition numbers up to about 10⁸ reach it).
pub const ROUND_OFF_CORRECTION: f64 = 1e-8;

/// Displacements (mm) below which steps and corrections are measured against this instead:
/// at strains near zero the finite-strain stress P(I + ∇u) loses the digits of ∇u it
/// shares with the identity (10⁻¹⁶/|∇u| of itself), so a load that starts from zero gives
/// corrections no iteration can make relatively small; 10⁻¹³ mm is far below anything an
/// output resolves.
pub const DISPLACEMENT_FLOOR: f64 = 1e-3;

/// The Euclidean norm.
pub fn norm_of(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// The largest magnitude (the ∞-norm).
pub fn max_abs(x: &[f64]) -> f64 {
    x.iter().fold(0.0f64, |a, v| a.max(v.abs()))
}

/// What Newton's method iterates on: a residual r(x) on n unknowns and the factorization
/// of its Jacobian J = ∂r/∂x (symmetric positive definite where the system is stable).
pub trait System {
    /// r(x) into `r`; returns ‖r‖ and the scale it is measured against (the largest norm
    /// of the forces that balance). An inverted element is an error the line search
    /// shortens its step for.
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(f64, f64), ModelError>;

    /// Factorizes the Jacobian at `x`, where the last residual was taken; `exact` asks for
    /// the exact tangent in double precision. Returns whether the factor is the exact
    /// tangent's (a single-precision factor or one shifted to be positive definite is not).
    fn factorize(&mut self, x: &[f64], exact: bool) -> Result<bool, ModelError>;

    /// Whether a factorization is kept (from an earlier iteration, increment or step).
    fn factorized(&self) -> bool;

    /// d ← J⁻¹ d with the kept factorization.
    fn solve(&mut self, d: &mut [f64]);
}

/// How a solve iterates and when it has converged.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Largest change of any prescribed displacement per load increment (mm; statics).
    pub max_increment: f64,
    /// Converged at ‖r‖ ≤ this · scale …
    pub residual_tolerance: f64,
    /// … and a step ‖αd‖∞ ≤ this · max(‖x‖∞, [`DISPLACEMENT_FLOOR`]) (infinite: the
    /// residual alone).
    pub displacement_tolerance: f64,
    /// Iterations allowed per load increment (statics) or time step.
    pub max_iterations: usize,
    /// Times a load increment may be halved (at an unchanged load at most once:
    /// [`Newton`]'s solve).
    pub max_cutbacks: usize,
    /// The factorization is reused while every iteration reduces ‖r‖ at least by this
    /// factor; 0 refactorizes at every iteration (Newton–Raphson).
    pub reuse_contraction: f64,
    /// A fresh exact correction that finds no descent at ‖r‖ ≤ this · scale is round-off:
    /// the floor of the residual the system's arithmetic leaves (element forces that
    /// cancel; far higher where the stresses carry round-off of their own).
    pub round_off: f64,
    /// Whether the steps on a kept factorization are Anderson-accelerated.
    pub accelerate: bool,
}

impl Default for Settings {
    /// The static solves': 1 mm increments, residual and step to 10⁻¹⁰, 25 iterations,
    /// 8 cut-backs, the factorization kept while the residual falls tenfold, accelerated.
    fn default() -> Self {
        Self {
            max_increment: 1.0,
            residual_tolerance: 1e-10,
            displacement_tolerance: 1e-10,
            max_iterations: 25,
            max_cutbacks: 8,
            reuse_contraction: 0.1,
            round_off: 1e-13,
            accelerate: true,
        }
    }
}

impl Settings {
    /// Refuses settings no solve can use.
    pub fn check(&self) -> Result<(), ModelError> {
        crate::error::positive("max_increment", self.max_increment)?;
        if !(0.0..1.0).contains(&self.reuse_contraction) {
            return Err(ModelError::InvalidParameter {
                name: "reuse_contraction".into(),
                value: self.reuse_contraction,
                reason: "must lie in [0, 1)",
            });
        }
        Ok(())
    }
}

/// Why a solve stopped short.
#[derive(Debug)]
pub enum Failure {
    /// Not converged in `max_iterations`.
    Iterations,
    /// The line search found no descent (above round-off).
    LineSearch,
    /// An inverted element, or a Jacobian that could not be factorized.
    Model(ModelError),
}

impl Failure {
    /// The reason as a message.
    pub fn reason(self, max_iterations: usize) -> String {
        match self {
            Failure::Iterations => {
                format!("Newton's method did not converge in {max_iterations} iterations")
            }
            Failure::LineSearch => "the line search found no descent".into(),
            Failure::Model(e) => e.to_string(),
        }
    }
}

/// The executor's work vectors for systems of one size (made once; an iteration allocates
/// nothing), and the convergence history of the last run.
#[derive(Debug, Clone)]
pub struct Iteration {
    r: Vec<f64>,
    d: Vec<f64>,
    trial: Vec<f64>,
    anderson: Anderson,
    /// ‖r‖ / scale at each iterate of the last run.
    pub residuals: Vec<f64>,
    /// Iterations of the last run, converged or not.
    pub taken: usize,
}

impl Iteration {
    /// Work vectors for systems of `n` unknowns, a history of up to `max_iterations`.
    pub fn new(n: usize, max_iterations: usize) -> Self {
        Self {
            r: vec![0.0; n],
            d: vec![0.0; n],
            trial: vec![0.0; n],
            anderson: Anderson::new(n),
            residuals: Vec::with_capacity(max_iterations + 1),
            taken: 0,
        }
    }

    /// The number of unknowns.
    pub fn len(&self) -> usize {
        self.r.len()
    }

    /// Whether the systems have no unknowns.
    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }

    /// Forgets the acceleration's history (the map changed).
    pub fn reset(&mut self) {
        self.anderson.reset();
        self.residuals.clear();
    }

    /// Iterates `x` (on entry the start, moved there from the last solution by a step of
    /// ∞-norm `start_step`) to the solution of `system`; returns the iterations taken. On
    /// failure `x` is the last iterate.
    pub fn run<S: System>(
        &mut self,
        system: &mut S,
        x: &mut [f64],
        settings: &Settings,
        start_step: f64,
    ) -> Result<usize, Failure> {
        self.residuals.clear();
        self.taken = 0;
        // Another start is another map: the steps of earlier runs do not combine.
        self.anderson.reset();
        let (mut norm, mut scale) = system.residual(x, &mut self.r).map_err(Failure::Model)?;
        self.residuals.push(norm / scale.max(1e-300));
        if converged(settings, norm, scale, start_step, x) {
            return Ok(0);
        }
        // The contraction of the last iteration; infinite forces a factorization.
        let mut contraction = 0.0;
        // Whether the next factorizations are to be exact (after an inexact one gave no
        // descent).
        let mut exact = false;
        for iteration in 1..=settings.max_iterations {
            self.taken = iteration;
            let fresh = !system.factorized() || contraction > settings.reuse_contraction;
            let exact_factor = if fresh {
                system.factorize(x, exact).map_err(Failure::Model)?
            } else {
                false
            };
            self.d.copy_from_slice(&self.r);
            system.solve(&mut self.d);
            if !self.d.iter().all(|v| v.is_finite()) {
                if fresh && !exact_factor && !exact {
                    exact = true;
                    contraction = f64::INFINITY;
                    continue;
                }
                return Err(Failure::LineSearch);
            }
            let accelerated = !fresh && settings.accelerate && self.anderson.step(&mut self.d);
            let searched = line_search(system, x, &self.d, &mut self.r, &mut self.trial, fresh)
                .map_err(Failure::Model)?;
            let Some((alpha, next, next_scale)) = searched else {
                if accelerated {
                    // The plain step next, on the same factorization.
                    self.anderson.reset();
                } else if !fresh || (!exact_factor && !exact) {
                    // A fresh factorization (exact where this one was not) at x.
                    exact |= fresh;
                    contraction = f64::INFINITY;
                } else if norm <= settings.round_off * scale
                    || max_abs(&self.d) <= ROUND_OFF_CORRECTION * size(x)
                {
                    // No descent left at round-off: converged as far as arithmetic allows.
                    return Ok(iteration);
                } else {
                    return Err(Failure::LineSearch);
                }
                continue;
            };
            if fresh && settings.accelerate {
                self.anderson.start(&self.d, alpha);
            }
            x.copy_from_slice(&self.trial);
            let correction = max_abs(&self.d);
            let step = alpha * correction;
            let stalled = fresh
                && exact_factor
                && next > 0.5 * norm
                && correction <= ROUND_OFF_CORRECTION * size(x);
            contraction = next / norm.max(1e-300);
            (norm, scale) = (next, next_scale);
            self.residuals.push(norm / scale.max(1e-300));
            if converged(settings, norm, scale, step, x) || stalled {
                return Ok(iteration);
            }
        }
        Err(Failure::Iterations)
    }
}

/// The displacements' size steps and corrections are measured against.
fn size(x: &[f64]) -> f64 {
    max_abs(x).max(DISPLACEMENT_FLOOR)
}

/// The convergence test at ‖r‖ = `norm` of `scale` after a step of ∞-norm `step` to `x`.
fn converged(settings: &Settings, norm: f64, scale: f64, step: f64, x: &[f64]) -> bool {
    let size = size(x);
    (norm <= settings.residual_tolerance * scale && step <= settings.displacement_tolerance * size)
        || step <= ROUND_OFF_STEP * size && step > 0.0
}
