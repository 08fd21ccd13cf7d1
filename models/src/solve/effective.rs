//! The factorized effective matrix c_m M + c_c C + K of an implicit scheme, and for a
//! finite-strain structure the Newton iteration of a step: R(u) = c_m M u + c_c C u +
//! f_int(u) − rhs = 0, solved by [`crate::solve::newton`]'s executor. The symbolic analysis
//! is done on first use and kept; later calls refactorize numerically only.
//!
//! A step's iterations start from the last displacement on the kept factorization (the
//! prepared matrix, or the last step's tangent); a fresh one is c_m M + c_c C + K_T(u),
//! shifted towards the mass where it is not positive definite ([`Effective::solve`]).

use super::newton::{norm_of, Iteration, Settings, System};
use super::structure::Structure;
use crate::assembly::InternalForces;
use crate::error::ModelError;
use crate::linalg::Cholesky;

/// Newton iterations a finite-strain step may take. Most steps take 2–7; the steps in
/// which the abdomen's membranes go slack at the end of a press took up to 93 on the mixed
/// element (default scene, ν = 0.4999, 10 ms steps, with the membranes' earlier
/// tension-field tangent).
const MAX_NEWTON_ITERATIONS: usize = 100;
/// A fresh tangent's correction that does not reduce a residual below this fraction of the
/// force scale has met the round-off of the stresses (the neo-Hookean stress at strains of
/// 10⁻⁷ carries a round-off of 10⁻⁹ of itself).
const ROUND_OFF: f64 = 1e-6;
/// The factorization is kept while every iteration reduces ‖R‖ at least by this factor; a
/// slower iteration refactorizes the tangent at the current iterate (modified Newton).
const KEEP_FACTOR_CONTRACTION: f64 = 0.25;
/// Shifts towards the mass tried when a tangent is not positive definite
/// ([`Tangent::factorize_tangent`]).
const SHIFTS: usize = 12;

/// The settings of a step's Newton iterations to the residual tolerance `tolerance`.
fn settings(tolerance: f64) -> Settings {
    Settings {
        residual_tolerance: tolerance,
        displacement_tolerance: f64::INFINITY,
        max_iterations: MAX_NEWTON_ITERATIONS,
        reuse_contraction: KEEP_FACTOR_CONTRACTION,
        round_off: ROUND_OFF,
        accelerate: false,
        ..Settings::default()
    }
}

/// The factorized effective matrix and, for a finite-strain structure, what a step's
/// Newton iteration keeps.
#[derive(Debug, Default)]
pub(crate) struct Effective {
    tangent: Tangent,
    iteration: Option<Iteration>,
    /// Iterations and tangent factorizations of the last step (0 for a linear structure).
    iterations: usize,
}

/// The factorization and what it was made of.
#[derive(Debug, Default)]
struct Tangent {
    chol: Option<Cholesky>,
    values: Vec<f64>,
    coefficients: (f64, f64),
    /// Finite strain: the displacement at which the kept tangent was factorized, when it is
    /// not the prepared matrix (a checkpoint refactorizes there to continue bit for bit).
    tangent_at: Vec<f64>,
    has_tangent: bool,
    /// The mass coefficient added to the kept tangent to make it positive definite (0
    /// unless the tangent at `tangent_at` was not).
    shift: f64,
    /// The step's right-hand side, and work vectors: (c_m M + c_c C) u, and the internal
    /// forces' all-dof vectors.
    target: Vec<f64>,
    inertia: Vec<f64>,
    u_full: Vec<f64>,
    f_full: Vec<f64>,
    k_full: Vec<f64>,
    k_reduced: Vec<f64>,
    factorizations: usize,
}

impl Effective {
    /// Forms and factorizes c_m M + c_c C + K.
    pub(crate) fn factorize(
        &mut self,
        s: &Structure,
        c_m: f64,
        c_c: f64,
    ) -> Result<(), ModelError> {
        let t = &mut self.tangent;
        let chol = match &mut t.chol {
            Some(c) if c.n() == s.n() => c,
            slot => {
                t.values = vec![0.0; s.dirichlet().nnz()];
                slot.insert(s.analyze()?)
            }
        };
        if s.is_nonlinear() && t.target.len() != s.n() {
            let bc = s.dirichlet();
            t.target = vec![0.0; s.n()];
            t.inertia = vec![0.0; s.n()];
            t.u_full = vec![0.0; bc.n_dofs()];
            t.f_full = vec![0.0; bc.n_dofs()];
            t.k_full = vec![0.0; bc.full_nnz()];
            t.k_reduced = vec![0.0; bc.nnz()];
            self.iteration = Some(Iteration::new(s.n(), MAX_NEWTON_ITERATIONS));
        }
        t.coefficients = (c_m, c_c);
        t.has_tangent = false;
        t.tangent_at.resize(s.n(), 0.0);
        s.effective(c_m, c_c, &mut t.values);
        chol.factorize(s.dirichlet().matrix(&t.values))
    }

    /// Where the kept factor's tangent was taken and its shift, if it is not the prepared
    /// matrix.
    pub(crate) fn kept_tangent(&self) -> Option<(Vec<f64>, f64)> {
        let t = &self.tangent;
        t.has_tangent.then(|| (t.tangent_at.clone(), t.shift))
    }

    /// Refactorizes (c_m + `shift`) M + c_c C + K_T(x) with the prepared coefficients, as a
    /// step's Newton iteration at `x` did (to resume from a checkpoint).
    pub(crate) fn refactorize_at(
        &mut self,
        s: &Structure,
        x: &[f64],
        shift: f64,
    ) -> Result<(), ModelError> {
        let (Some(forces), Some(_)) = (s.internal_forces(), self.tangent.chol.as_ref()) else {
            return Err(ModelError::LinearAlgebra(
                "a kept tangent needs a prepared finite-strain structure".into(),
            ));
        };
        let t = &mut self.tangent;
        let (c_m, c_c) = t.coefficients;
        t.internal(s, forces, x, true)?;
        t.combine(s, c_m + shift, c_c);
        t.chol
            .as_mut()
            .expect("prepared")
            .factorize(s.dirichlet().matrix(&t.values))?;
        t.tangent_at.copy_from_slice(x);
        t.has_tangent = true;
        t.shift = shift;
        Ok(())
    }

    /// Solves a step: on entry `x` holds the right-hand side (load and history terms), on
    /// return the new displacement. Linear: one solve with the factor. Finite strain:
    /// Newton's method on R(u) = c_m M u + c_c C u + f_int(u) − rhs from `guess` (the last
    /// displacement), to the structure's Newton tolerance
    /// ([`super::structure::NEWTON_TOLERANCE`] unless it sets its own). Allocates nothing (but the error).
    pub(crate) fn solve(
        &mut self,
        s: &Structure,
        x: &mut [f64],
        guess: &[f64],
    ) -> Result<(), ModelError> {
        let (Some(forces), Some(iteration)) = (s.internal_forces(), self.iteration.as_mut()) else {
            self.tangent
                .chol
                .as_mut()
                .expect("an integrator is prepared before it steps")
                .solve_in_place(x);
            return Ok(());
        };
        let t = &mut self.tangent;
        t.target.copy_from_slice(x);
        t.factorizations = 0;
        x.copy_from_slice(guess);
        let mut step = Step {
            tangent: t,
            structure: s,
            forces,
        };
        let done = iteration.run(&mut step, x, &settings(s.newton_tolerance()), 0.0);
        self.iterations = match done {
            Ok(iterations) => iterations,
            Err(why) => {
                return Err(ModelError::NotConverged {
                    reached: 0.0,
                    reason: format!("{} in one time step", why.reason(MAX_NEWTON_ITERATIONS)),
                })
            }
        };
        Ok(())
    }

    /// Newton iterations of the last step (0 for a linear structure).
    pub(crate) fn iterations(&self) -> usize {
        self.iterations
    }

    /// Tangent factorizations of the last step (0 for a linear structure).
    pub(crate) fn factorizations(&self) -> usize {
        self.tangent.factorizations
    }
}

impl Tangent {
    /// f_int(x) (reduced, into `inertia`'s companion `f_full`) and, if `tangent`, K_T(x)
    /// reduced into `k_reduced`.
    fn internal(
        &mut self,
        s: &Structure,
        forces: &dyn InternalForces,
        x: &[f64],
        tangent: bool,
    ) -> Result<(), ModelError> {
        let bc = s.dirichlet();
        bc.expand(x, &mut self.u_full);
        let k = tangent.then_some(&mut self.k_full[..]);
        forces.internal(&self.u_full, &mut self.f_full, k)?;
        if tangent {
            bc.combine(&[(1.0, &self.k_full)], &mut self.k_reduced);
        }
        Ok(())
    }

    /// c_m M + c_c C + K_T (the last tangent) into `values`.
    fn combine(&mut self, s: &Structure, c_m: f64, c_c: f64) {
        let (m, c) = s.mass_and_damping_values();
        for (((v, m), c), k) in self.values.iter_mut().zip(m).zip(c).zip(&self.k_reduced) {
            *v = c_m * m + c_c * c + k;
        }
    }

    /// Factorizes (c_m + σ) M + c_c C + K_T at `x`: σ = 0, or where that is not positive
    /// definite (the contents near an instability, an iterate beyond the solution, or slack
    /// membranes, whose exact tangent is negative across them) the smallest of 10⁻⁴, 10⁻³,
    /// … times trace K_T / trace M that makes it so — a shift towards the mass that keeps
    /// Newton's corrections descent directions (pseudo-transient continuation). Returns
    /// whether it is unshifted (the exact tangent).
    fn factorize_tangent(
        &mut self,
        s: &Structure,
        forces: &dyn InternalForces,
        x: &[f64],
    ) -> Result<bool, ModelError> {
        self.internal(s, forces, x, true)?;
        self.factorizations += 1;
        let (c_m, c_c) = self.coefficients;
        let ratio =
            diagonal_sum(s, &self.k_reduced).abs() / diagonal_sum(s, s.mass_and_damping_values().0);
        let mut shift = 0.0;
        let mut attempt = 0;
        loop {
            self.combine(s, c_m + shift, c_c);
            let chol = self.chol.as_mut().expect("prepared");
            match chol.factorize(s.dirichlet().matrix(&self.values)) {
                Err(ModelError::Singular { .. }) if attempt < SHIFTS => {
                    shift = ratio * 10f64.powi(attempt as i32 - 4);
                    attempt += 1;
                }
                result => {
                    result?;
                    self.tangent_at.copy_from_slice(x);
                    self.has_tangent = true;
                    self.shift = shift;
                    return Ok(shift == 0.0);
                }
            }
        }
    }
}

/// A step's Newton iteration: the residual R(u) = (c_m M + c_c C) u + f_int(u) − rhs and
/// the factorized tangent.
struct Step<'a> {
    tangent: &'a mut Tangent,
    structure: &'a Structure,
    forces: &'a dyn InternalForces,
}

impl System for Step<'_> {
    /// R(u) into `r`; the scale is the largest norm of the terms that balance.
    fn residual(&mut self, x: &[f64], r: &mut [f64]) -> Result<(f64, f64), ModelError> {
        let (t, s) = (&mut *self.tangent, self.structure);
        t.internal(s, self.forces, x, false)?;
        s.dirichlet().reduce(&t.f_full, r);
        t.inertia.fill(0.0);
        let (c_m, c_c) = t.coefficients;
        s.add_mass_and_damping(x, c_m, c_c, &mut t.inertia);
        let scale = [&*t.target, &*r, &*t.inertia]
            .map(norm_of)
            .into_iter()
            .fold(0.0, f64::max);
        for ((r, i), target) in r.iter_mut().zip(&t.inertia).zip(&t.target) {
            *r += i - target;
        }
        Ok((norm_of(r), scale))
    }

    fn factorize(&mut self, x: &[f64], _exact: bool) -> Result<bool, ModelError> {
        self.tangent
            .factorize_tangent(self.structure, self.forces, x)
    }

    /// The prepared matrix, or the last tangent, is always kept.
    fn factorized(&self) -> bool {
        true
    }

    fn solve(&mut self, d: &mut [f64]) {
        self.tangent
            .chol
            .as_mut()
            .expect("prepared")
            .solve_in_place(d);
    }
}

/// The sum of the diagonal of a matrix on the structure's reduced pattern.
fn diagonal_sum(s: &Structure, values: &[f64]) -> f64 {
    let p = s.dirichlet().symbolic();
    let a = faer::sparse::SparseColMatRef::new(p.as_ref(), values);
    (0..p.ncols())
        .map(|j| crate::linalg::cholesky::diagonal(a, j))
        .sum()
}
