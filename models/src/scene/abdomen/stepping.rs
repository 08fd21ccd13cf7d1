//! How the abdomen is loaded and stepped: the load of the pressing force (an active tension
//! of the diaphragm at finite strain), the step that halves where Newton's method fails, and
//! the full-order runs the training and the static outputs need — static equilibria under a
//! constant press (one solve, or Newton's load increments at finite strain) and presses
//! stepped from rest.

use std::sync::Arc;

use super::build::FullOrder;
use crate::assembly::quadratic_plane::{PlaneBody, SharedTension};
use crate::assembly::InternalForces;
use crate::error::ModelError;
use crate::linalg::Factorization;
use crate::scene::SceneError;
use crate::solve::newton::{Increments, Newton, Settings};
use crate::solve::{Integrator, Statics, Structure};

/// Times a finite-strain step may be halved ([`step_halving`]).
pub(super) const HALVINGS: usize = 4;

/// One step of `dt`; at finite strain a step whose Newton iterations do not converge is
/// taken again from where it started in the increments of [`Increments`] — halved, and
/// halved again if need be, up to `halvings` times, the steps after a success growing back
/// to `dt` — the integrator prepared for each step size it takes and for `dt` after
/// (Houbolt restarts its history with its starter). Where the membranes go slack at the end
/// of a press of a free, soft abdominal wall, 10 ms steps fail and 5 ms ones do not.
pub(super) fn step_halving(
    integrator: &mut (dyn Integrator + Send + Sync),
    structure: &Structure,
    load: &mut dyn FnMut(f64, &mut [f64]),
    dt: f64,
    halvings: usize,
) -> Result<(), ModelError> {
    if !structure.is_nonlinear() {
        return integrator.step(structure, load);
    }
    let mut increments = Increments::new(1.0, halvings);
    let mut prepared = 1.0;
    while let Some((from, to)) = increments.next() {
        let share = to - from;
        if share != prepared {
            integrator.prepare(structure, share * dt)?;
            prepared = share;
        }
        match integrator.step(structure, load) {
            Ok(()) => increments.succeeded(),
            Err(ModelError::NotConverged { .. } | ModelError::Inverted { .. })
                if increments.failed() => {}
            Err(e) => return Err(e),
        }
    }
    if prepared != 1.0 {
        integrator.prepare(structure, dt)?;
    }
    Ok(())
}

/// The load of the pressing force F(t) = `force(t)` with its pattern `unit`: f(t) =
/// F(t) · unit — or at finite strain, `contracting` given ([`FullOrder::contracting`]), the
/// contracting muscles' active tension T = F/Θ₀ for F > 0 (set where the internal forces read it; a
/// muscle pulls, it does not push) and the load F · unit for F < 0 (drawn out: the suction
/// of the chest, a dead load).
pub(super) fn pressing<'a>(
    force: impl Fn(f64) -> f64 + 'a,
    unit: &'a [f64],
    contracting: Option<(&'a SharedTension, f64)>,
) -> impl FnMut(f64, &mut [f64]) + 'a {
    move |t, f| {
        let mut x = force(t);
        if let Some((tension, theta)) = contracting {
            tension.set(x.max(0.0) / theta);
            x = x.min(0.0);
        }
        f.iter_mut().zip(unit).for_each(|(f, u)| *f = x * u);
    }
}

/// The static displacement (all dofs) under a constant pressing force `force` (N/mm): one
/// solve with K, or at finite strain Newton's method (load increments cut back where it
/// does not converge), the diaphragm contracting (force > 0) or drawn out.
pub fn static_displacement(full: &FullOrder, force: f64) -> Result<Vec<f64>, SceneError> {
    let asm = &full.disc.asm;
    if full.body.is_some() {
        let mut states = static_ramp(full, &[force])?;
        return Ok(states.pop().expect("one state per force"));
    }
    let structure = &full.structure;
    let mut f = vec![0.0; full.disc.n_dofs()];
    structure.dirichlet().expand(full.unit_load(), &mut f);
    f.iter_mut().for_each(|x| *x *= force);
    let mut u = vec![0.0; f.len()];
    let once = Factorization::plane(structure.n(), false);
    let mut statics = Statics::new(asm, full.fixed(), once)?;
    statics.factorize(full.stiffness())?;
    statics.solve(asm.matrix(full.stiffness()), &f, &mut u);
    Ok(u)
}

/// At finite strain, the static displacements (all dofs) under the pressing forces
/// `forces` (N/mm) in turn ([`Equilibria`]: a rising ramp solves each from the last).
pub fn static_ramp(full: &FullOrder, forces: &[f64]) -> Result<Vec<Vec<f64>>, SceneError> {
    let mut equilibria = Equilibria::new(full)?;
    forces
        .iter()
        .map(|&force| equilibria.at(force).map(<[f64]>::to_vec))
        .collect()
}

/// Static equilibria at finite strain under pressing forces asked for in any order, each
/// solved by Newton's method (its load increments cut back where it does not converge) from
/// the equilibrium already found nearest below it on the same side of zero (rest at
/// first): a continuation in the force, so that a search whose trials come close to each
/// other (the pressure-driven start) solves each from close by.
pub struct Equilibria<'a> {
    full: &'a FullOrder,
    newton: Newton,
    contracting: Contracting,
    unit: Vec<f64>,
    found: Vec<(f64, Vec<f64>)>,
}

impl<'a> Equilibria<'a> {
    /// None found yet; an error where the model is not at finite kinematics.
    pub fn new(full: &'a FullOrder) -> Result<Self, SceneError> {
        let tension = Arc::new(SharedTension::default());
        let Some(body) = full.disc.body(&full.props, &tension) else {
            return Err(SceneError::Config(
                "a static ramp needs finite kinematics".into(),
            ));
        };
        let structure = &full.structure;
        let mut unit = vec![0.0; full.disc.n_dofs()];
        structure.dirichlet().expand(full.unit_load(), &mut unit);
        let newton = Newton::new(
            &full.disc.asm,
            full.fixed(),
            Factorization::plane(structure.n(), false),
            Settings::default(),
        )?;
        let contracting = Contracting {
            body,
            tension,
            from: 0.0,
            to: 0.0,
        };
        Ok(Self {
            full,
            newton,
            contracting,
            unit,
            found: Vec::new(),
        })
    }

    /// The static displacement (all dofs) under `force` (N/mm): the diaphragm contracting
    /// (force > 0, an active tension F/Θ₀) or drawn out (a dead load).
    pub fn at(&mut self, force: f64) -> Result<&[f64], SceneError> {
        let start = self
            .found
            .iter()
            .filter(|(f, _)| f * force >= 0.0 && f.abs() <= force.abs())
            .max_by(|a, b| a.0.abs().total_cmp(&b.0.abs()));
        let (from, mut u) =
            start.map_or((0.0, vec![0.0; self.unit.len()]), |(f, u)| (*f, u.clone()));
        let theta = self.full.theta();
        self.contracting.from = from.max(0.0) / theta;
        self.contracting.to = force.max(0.0) / theta;
        let f: Vec<f64> = self.unit.iter().map(|x| x * force.min(0.0)).collect();
        let zero = vec![0.0; f.len()];
        self.newton.solve(&self.contracting, &mut u, &zero, &f)?;
        self.found.push((force, u));
        Ok(&self.found[self.found.len() - 1].1)
    }
}

/// The full model's states (all dofs) after each step of a press
/// F(t) = `amplitude` (1 − cos 2π `frequency` t)/2 from rest over the share `span` of its
/// period (1: the whole press; ½: up to its peak), stepped at `dt` by an integrator of the
/// model's kind, with F at each (finite-strain training). The press runs on a
/// [`detached`](FullOrder::detached) structure: presses may run side by side.
pub fn press_run(
    full: &FullOrder,
    [amplitude, frequency, dt, span]: [f64; 4],
) -> Result<(Vec<Vec<f64>>, Vec<f64>), SceneError> {
    let own = full.detached()?;
    let (free, presses) = press_states(
        full,
        &own.structure,
        &own.tension,
        full.unit_load(),
        [amplitude, frequency, dt, span],
    )?;
    let bc = full.structure.dirichlet();
    let states = free
        .iter()
        .map(|u| {
            let mut all = vec![0.0; full.disc.n_dofs()];
            bc.expand(u, &mut all);
            all
        })
        .collect();
    Ok((states, presses))
}

/// The states (its own unknowns) of structure `s` — the full one or a reduced one, with
/// the unit load `unit` on its unknowns, its forces reading the diaphragm's tension from
/// `tension` — after each step of a press of `amplitude` (N/mm) at `frequency` (Hz) over
/// the share `span` of its period, stepped at `dt` (s) by an integrator of `full`'s kind,
/// as [`press_run`]'s, with F at each.
pub(super) fn press_states(
    full: &FullOrder,
    s: &Structure,
    tension: &SharedTension,
    unit: &[f64],
    [amplitude, frequency, dt, span]: [f64; 4],
) -> Result<(Vec<Vec<f64>>, Vec<f64>), SceneError> {
    let force =
        |t: f64| amplitude * 0.5 * (1.0 - (2.0 * std::f64::consts::PI * frequency * t).cos());
    let mut integrator = full.kind().create();
    integrator.prepare(s, dt)?;
    let mut load = pressing(force, unit, Some((tension, full.theta())));
    let rest = vec![0.0; s.n()];
    integrator.start(s, 0.0, &rest, &rest, &mut load)?;
    let steps = (span / (frequency * dt)).ceil() as usize;
    let (mut states, mut presses) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
    for _ in 0..steps {
        step_halving(integrator.as_mut(), s, &mut load, dt, HALVINGS)?;
        let state = integrator.state();
        states.push(state.u.clone());
        presses.push(force(state.t));
    }
    Ok((states, presses))
}

/// The body at finite strain with the diaphragm's active tension (which its forces read
/// from `tension`) going from `from` to `to` along Newton's load increments.
struct Contracting {
    body: PlaneBody,
    tension: Arc<SharedTension>,
    from: f64,
    to: f64,
}

impl InternalForces for Contracting {
    fn at_load_fraction(&self, s: f64) {
        self.tension.set(self.from + s * (self.to - self.from));
    }

    fn follow_the_load(&self) -> bool {
        self.from != self.to
    }

    fn internal(&self, u: &[f64], f: &mut [f64], k: Option<&mut [f64]>) -> Result<(), ModelError> {
        self.body.internal(u, f, k)
    }
}

#[cfg(test)]
mod tests {
    use super::super::variables::{table, TARGET_TRIANGLES};
    use super::*;
    use crate::scene::Values;

    /// Forces asked for out of order, each after the first on its side of zero continued
    /// from the nearest equilibrium below (0.6 and 0.4 from 0.2, 1.0 from 0.6, −0.3 from
    /// −0.1), give the equilibria a solve from rest gives (to 1e-6 of the largest
    /// displacement), drawn-out ones included.
    #[test]
    fn equilibria_continued_in_any_order_are_those_from_rest() {
        let mut values = Values::new(table());
        values.set_real(TARGET_TRIANGLES, &[150.0]).unwrap();
        let full = FullOrder::build(&values).unwrap_or_else(|e| panic!("{e}"));
        let mut equilibria = Equilibria::new(&full).unwrap();
        for force in [0.2, 0.6, 0.4, 1.0, -0.1, -0.3] {
            let continued = equilibria.at(force).unwrap().to_vec();
            let from_rest = static_ramp(&full, &[force]).unwrap().pop().unwrap();
            let scale = from_rest.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
            let gap = continued
                .iter()
                .zip(&from_rest)
                .fold(0.0, |m: f64, (a, b)| m.max((a - b).abs()));
            assert!(gap <= 1e-6 * scale, "{force} N/mm: {gap:e} of {scale}");
        }
    }
}
