//! The abdomen as the scene steps it: the full-order system ([`FullOrder`]), the time
//! integrator on it — or on the reduced system of a reduced `model_order`
//! ([`ReducedSystem`]) — the displacement of all dofs expanded from it when read, the
//! outputs and the error indicator.

use super::build::FullOrder;
use super::config::PelvisConfig;
use super::discretization::Choice;
use super::outputs::{self, Field};
use super::parameters::{modes, order, order_allows, press, properties, subdivisions};
use super::pressure::{find_force, Found};
use super::reduced::{ReducedSystem, Training};
use super::stepping::{pressing, step_halving, HALVINGS};
use super::training::TrainingRange;
use super::variables::{
    CONFIGURATION, ELEMENT, FORMULATION, INTEGRATOR, KINEMATICS, MAX_STEP, MODEL_ORDER,
    TRAINING_FREQUENCY, TRAINING_PRESS,
};
use crate::assembly::plane::PlaneProperties;
use crate::error::ModelError;
use crate::scene::{SceneError, Values};
use crate::solve::{Checkpoint, Indicator, Integrator, IntegratorKind, Motion, Structure};

/// The built abdomen and its integrator.
pub struct Simulation {
    pub full: FullOrder,
    /// Steps the full system, or the reduced one when `reduced` is present.
    pub integrator: Box<dyn Integrator + Send + Sync>,
    /// What a hyper-reduced model is trained for.
    training: Training,
    /// The reduced system of a reduced `model_order`.
    pub reduced: Option<ReducedSystem>,
    /// The displacement of all dofs after the last step, valid when `expanded`.
    u_full: Vec<f64>,
    expanded: bool,
    /// Free-dof scratch for expanding reduced coordinates.
    u_free: Vec<f64>,
    /// The error indicator, its stiffness factorized on first request, and the state and
    /// load it reads (free dofs: u, v, a, f).
    indicator: Option<(Indicator, [Vec<f64>; 4])>,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("full", &self.full)
            .field("reduced", &self.reduced.is_some())
            .finish()
    }
}

/// The checks of [`Simulation::build`] that need no mesh ([`crate::scene::Scene::check`]):
/// the configuration resolves to valid boundary curves, the element, formulation,
/// kinematics, integrator and model order are known and go together, the counts are whole
/// and every tissue's properties are valid.
pub fn check(values: &Values) -> Result<(), SceneError> {
    PelvisConfig::resolve(values.string(CONFIGURATION)?)?.control_points()?;
    let choice = Choice::parse(
        values.string(ELEMENT)?,
        values.string(FORMULATION)?,
        values.string(KINEMATICS)?,
    )?;
    let kind = IntegratorKind::parse(values.string(INTEGRATOR)?)?;
    if choice.finite && !kind.steps_finite_strain() {
        return Err(ModelError::LinearOnly { what: kind.name() }.into());
    }
    let model_order = values.string(MODEL_ORDER)?;
    order_allows(model_order, order(model_order)?, choice.finite)?;
    subdivisions(values)?;
    modes(values)?;
    properties(values)?;
    press(values, choice, kind)?;
    Ok(())
}

impl Simulation {
    /// Builds the full-order system for the current parameter values, its integrator and
    /// the reduced system of a reduced `model_order`; what [`check`] refuses is refused
    /// before any work.
    pub fn build(values: &Values) -> Result<Self, SceneError> {
        check(values)?;
        let full = FullOrder::build(values)?;
        let training = Training {
            range: TrainingRange {
                press: values.real(TRAINING_PRESS),
                frequency: values.real(TRAINING_FREQUENCY),
            },
            max_step: values.real(MAX_STEP),
        };
        let reduced = match order(values.string(MODEL_ORDER)?)? {
            None => None,
            Some(reduced) => Some(ReducedSystem::new(
                &full,
                reduced,
                modes(values)?,
                training,
            )?),
        };
        Ok(Self {
            u_full: vec![0.0; full.disc.n_dofs()],
            expanded: true,
            u_free: vec![0.0; full.structure.n()],
            integrator: full.kind().create(),
            training,
            reduced,
            indicator: None,
            full,
        })
    }

    /// Prepares the integrator for steps of `dt` and starts it at rest at `t0` in equilibrium
    /// with the pressing force `force(t)` (N/mm) there: undeformed where the force is zero,
    /// else at the static displacement under it (a start in the middle of a press is not a
    /// step load).
    pub fn start(
        &mut self,
        t0: f64,
        dt: f64,
        force: impl Fn(f64) -> f64,
    ) -> Result<(), SceneError> {
        self.start_in(t0, dt, force, None)
    }

    /// [`start`](Self::start) in the equilibrium `at` (all dofs) where it is known.
    fn start_in(
        &mut self,
        t0: f64,
        dt: f64,
        force: impl Fn(f64) -> f64,
        at: Option<Vec<f64>>,
    ) -> Result<(), SceneError> {
        let initial = force(t0);
        let full = &self.full;
        let mut u0 = vec![0.0; full.structure.n()];
        if initial != 0.0 {
            let u = match at {
                Some(u) => u,
                None => super::stepping::static_displacement(full, initial)?,
            };
            full.structure.dirichlet().reduce(&u, &mut u0);
        }
        if let Some(r) = &self.reduced {
            let mut q = vec![0.0; r.basis.dim()];
            r.basis.coordinates(full.structure.mass(), &u0, &mut q);
            u0 = q;
        }
        let (structure, unit) = stepped(&self.reduced, &self.full);
        let integrator = &mut self.integrator;
        integrator.prepare(structure, dt)?;
        let mut load = pressing(force, unit, self.full.contracting());
        let at_rest = vec![0.0; u0.len()];
        integrator.start(structure, t0, &u0, &at_rest, &mut load)?;
        self.expanded = false;
        Ok(())
    }

    /// Puts an integrator checkpoint back (see [`Checkpoint`]) with the diaphragm's active
    /// tensions of its last step and of its kept tangent ([`FullOrder::tension`]): the
    /// integrator prepared for its step on the stepped system (full or reduced), then
    /// resumed (refactorizing a kept tangent at its own tension).
    pub fn resume(
        &mut self,
        checkpoint: &Checkpoint,
        [now, at_tangent]: [f64; 2],
        carried: &[Vec<f64>],
    ) -> Result<(), SceneError> {
        if let Some(r) = self.reduced.as_ref().filter(|_| !carried.is_empty()) {
            self.reduced = Some(r.carrying(&self.full, carried.to_vec())?);
        }
        self.full.set_tension(at_tangent);
        let (structure, _) = stepped(&self.reduced, &self.full);
        let integrator = &mut self.integrator;
        integrator.prepare(structure, checkpoint.dt)?;
        integrator.resume(structure, checkpoint)?;
        self.full.set_tension(now);
        self.expanded = false;
        Ok(())
    }

    /// Takes `steps` steps of `dt` under the pressing force `force(τ)` at integrator time τ.
    pub fn advance(
        &mut self,
        dt: f64,
        steps: u64,
        force: impl Fn(f64) -> f64,
    ) -> Result<(), SceneError> {
        let dt = self.prepared(dt)?;
        let (structure, unit) = stepped(&self.reduced, &self.full);
        let mut load = pressing(force, unit, self.full.contracting());
        for _ in 0..steps {
            step_halving(self.integrator.as_mut(), structure, &mut load, dt, HALVINGS)?;
        }
        self.expanded = false;
        Ok(())
    }

    /// Takes `steps` steps of `dt`, each under the pressing force that makes the contents'
    /// mean pressure at its end the target (MPa), which runs linearly from the one `last`
    /// met to `target` at the last step: the step taken again from where it started with
    /// each trial force of [`find_force`], from the last step's force and slope. Returns
    /// the last step's, and the contents' mean pressure its last trial (the one that stands)
    /// ended with.
    pub fn advance_at_pressure(
        &mut self,
        dt: f64,
        steps: u64,
        target: f64,
        mut last: Found,
    ) -> Result<(Found, f64), SceneError> {
        let from = last.target;
        let dt = self.prepared(dt)?;
        // Trials overwrite the expanded field; it is current again only after the last.
        self.expanded = false;
        let Self {
            full,
            integrator,
            reduced,
            u_full,
            u_free,
            expanded,
            ..
        } = self;
        let (structure, unit) = stepped(reduced, full);
        let mut reached = f64::NAN;
        for j in 1..=steps {
            let share = j as f64 / steps as f64;
            let goal = if j == steps {
                target
            } else {
                from + share * (target - from)
            };
            // Taken again on the factorization in use, not the ones the checkpoint kept.
            let start = integrator.checkpoint().without_tangents();
            let mut fresh = true;
            last = find_force(goal, last, |force| {
                if !std::mem::take(&mut fresh) {
                    integrator.resume(structure, &start)?;
                }
                let mut load = pressing(|_| force, unit, full.contracting());
                match step_halving(integrator.as_mut(), structure, &mut load, dt, HALVINGS) {
                    Ok(()) => {}
                    Err(
                        ModelError::NotConverged { .. }
                        | ModelError::Inverted { .. }
                        | ModelError::Singular { .. },
                    ) => {
                        // Halving left the integrator prepared for a shorter step.
                        integrator.prepare(structure, dt)?;
                        return Ok(None);
                    }
                    Err(e) => return Err(e.into()),
                }
                expand_into(full, reduced, &integrator.state().u, u_free, u_full);
                reached = full.plan.pressure(&full.field(u_full));
                Ok(Some(reached))
            })?;
        }
        // The last trial stands, and its field is expanded.
        *expanded = true;
        Ok((last, reached))
    }

    /// Prepares the integrator for steps of `dt` and returns the step it takes: a `dt`
    /// within 1e-9 relative of the prepared one reuses the factorization (importers compute
    /// h as a difference of communication points, which jitters in the last bits). An
    /// explicit scheme's step above its stability limit is refused.
    fn prepared(&mut self, dt: f64) -> Result<f64, SceneError> {
        let (structure, _) = stepped(&self.reduced, &self.full);
        let integrator = &mut self.integrator;
        let dt = if (dt - integrator.dt()).abs() <= 1e-9 * dt {
            integrator.dt()
        } else {
            integrator.prepare(structure, dt)?;
            dt
        };
        if let Some(limit) = integrator.critical_time_step() {
            if dt > limit {
                return Err(SceneError::Unstable {
                    integrator: integrator.kind().name(),
                    dt,
                    limit,
                });
            }
        }
        Ok(dt)
    }

    /// Starts at rest at `t0`, as [`start`](Self::start) does, in equilibrium with the
    /// pressing force that makes the contents' mean pressure `target` (MPa): found over
    /// static solves from `guess` (none for a target of 0), at finite strain each from the
    /// nearest equilibrium below ([`Equilibria`](super::stepping::Equilibria)). Returns the
    /// force and slope.
    pub fn start_at_pressure(
        &mut self,
        t0: f64,
        dt: f64,
        target: f64,
        guess: Found,
    ) -> Result<Found, SceneError> {
        // The equilibrium of the last trial, the one that stands.
        let mut last = None;
        let found = match target > 0.0 {
            true => {
                let full = &self.full;
                // At finite strain each trial continues from the nearest equilibrium below.
                let mut equilibria = match full.body.is_some() {
                    true => Some(super::stepping::Equilibria::new(full)?),
                    false => None,
                };
                let mut solve = |force| match &mut equilibria {
                    Some(e) => e.at(force).map(<[f64]>::to_vec),
                    None => super::stepping::static_displacement(full, force),
                };
                find_force(target, guess, |force| match solve(force) {
                    Ok(u) => {
                        let p = full.plan.pressure(&full.field(&u));
                        last = Some(u);
                        Ok(Some(p))
                    }
                    Err(SceneError::Model(
                        ModelError::NotConverged { .. } | ModelError::Inverted { .. },
                    )) => Ok(None),
                    Err(e) => Err(e),
                })?
            }
            false => Found {
                force: 0.0,
                target,
                ..guess
            },
        };
        self.start_in(t0, dt, |_| found.force, last)?;
        Ok(found)
    }

    /// Brings the displacement of all dofs up to date (expanding the reduced coordinates
    /// after steps); read it with [`u_full`](Self::u_full).
    pub fn expand(&mut self) {
        if !self.expanded {
            let u = &self.integrator.state().u;
            expand_into(
                &self.full,
                &self.reduced,
                u,
                &mut self.u_free,
                &mut self.u_full,
            );
            self.expanded = true;
        }
    }

    /// In modal order, a bound of the largest principal strain that needs no expansion:
    /// Σ_j |q_j| · (largest strain of basis vector j) — the per-triangle measure is a
    /// seminorm of the strain, so the triangle inequality holds triangle by triangle. None in
    /// full order and for the hyper-reduced finite-strain model.
    pub fn strain_bound(&self) -> Option<f64> {
        let r = self.reduced.as_ref().filter(|r| r.rows.is_some())?;
        let q = &self.integrator.state().u;
        Some(q.iter().zip(&r.strains).map(|(q, s)| q.abs() * s).sum())
    }

    /// The error indicator η of the state after the last step ([`Indicator`]): the full
    /// model's residual there under the pressing force `force(τ)` at integrator time τ — the
    /// reduced coordinates expanded in a reduced order — relative to the displacement, in
    /// the energy norm of the stiffness at rest; infinite where the expanded state inverts an
    /// element. The first request factorizes that stiffness; each costs one full-order
    /// evaluation of the internal forces and one solve.
    pub fn indicator(&mut self, force: impl Fn(f64) -> f64) -> Result<f64, SceneError> {
        let full = &self.full;
        let n = full.structure.n();
        let (indicator, [u, v, a, f]) = match &mut self.indicator {
            Some(i) => i,
            slot => slot.insert((
                Indicator::new(&full.structure)?,
                std::array::from_fn(|_| vec![0.0; n]),
            )),
        };
        let state = self.integrator.state();
        for (expanded, q) in [
            (&mut *u, &state.u),
            (&mut *v, &state.v),
            (&mut *a, &state.a),
        ] {
            match &self.reduced {
                Some(r) => r.basis.expand(q, expanded),
                None => expanded.copy_from_slice(q),
            }
        }
        pressing(force, full.unit_load(), full.contracting())(state.t, f);
        let motion = Motion { u, v, a };
        match indicator.estimate(&full.structure, f, motion) {
            // The expanded state turns an element inside out: as far from the full model's
            // states as can be.
            Err(ModelError::Inverted { .. }) => Ok(f64::INFINITY),
            other => Ok(other?),
        }
    }

    /// The displacement of all dofs as of the last [`expand`](Self::expand).
    pub fn u_full(&self) -> &[f64] {
        &self.u_full
    }

    /// The outputs after the last step (see [`outputs::OutputPlan::compute`]); the
    /// cavity-wide ones only if `cavity`.
    pub fn outputs(&mut self, press: f64, cavity: bool) -> [f64; outputs::COUNT] {
        let rows = self.reduced.as_mut().and_then(|r| r.rows.as_mut());
        match rows {
            Some(rows) => rows.evaluate(&self.integrator.state().u),
            None => self.expand(),
        }
        if cavity {
            self.expand();
        }
        let full = &self.full;
        let field: Field<'_> = full.field(&self.u_full);
        let cavity = cavity.then_some(&field);
        match self.reduced.as_ref().and_then(|r| r.rows.as_ref()) {
            Some(rows) => full.plan.compute(rows, cavity, press),
            None => full.plan.compute(&field, cavity, press),
        }
    }

    /// Reassembles the stiffness for new properties and refactorizes the integrator's
    /// effective matrix at its current step. A reduced model builds (or trains) its basis
    /// again and carries its integrator's state and history onto it, each vector projected
    /// (q = Φᵀ M u): the scheme goes on as the full one does, not from a restart.
    pub fn set_properties(&mut self, props: PlaneProperties) -> Result<(), SceneError> {
        self.full.set_properties(props);
        self.expanded = false;
        self.indicator = None;
        let dt = self.integrator.dt();
        let Some(old) = &self.reduced else {
            self.integrator.prepare(&self.full.structure, dt)?;
            return Ok(());
        };
        let checkpoint = self.integrator.checkpoint();
        let (new, moved) = old.rebuilt(&self.full, &checkpoint, self.training)?;
        self.integrator.prepare(&new.structure, dt)?;
        let resumed = self.integrator.resume(&new.structure, &moved);
        self.reduced = Some(new);
        resumed?;
        Ok(())
    }
}

/// The displacement of all dofs of the stepped system's unknowns `u` (a reduced model's
/// coordinates expanded through its free dofs, `u_free`) into `u_full`.
fn expand_into(
    full: &FullOrder,
    reduced: &Option<ReducedSystem>,
    u: &[f64],
    u_free: &mut [f64],
    u_full: &mut [f64],
) {
    let bc = full.structure.dirichlet();
    match reduced {
        Some(r) => {
            r.basis.expand(u, u_free);
            bc.expand(u_free, u_full);
        }
        None => bc.expand(u, u_full),
    }
}

/// The system the integrator steps and its unit load: the reduced one if any.
fn stepped<'a>(
    reduced: &'a Option<ReducedSystem>,
    full: &'a FullOrder,
) -> (&'a Structure, &'a [f64]) {
    match reduced {
        Some(r) => (&r.structure, &r.unit_load),
        None => (&full.structure, full.unit_load()),
    }
}
