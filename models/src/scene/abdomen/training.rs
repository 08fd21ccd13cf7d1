//! The hyper-reduced finite-strain abdomen (`model_order = "reduced"`, issue 29): what it is
//! trained on, and the range that training covers.
//!
//! Training states, on the full finite-strain model: the static equilibria under presses
//! of (i/N)² times the training press A, i = 1 … N = [`STATIC_STATES`] (Newton, each from
//! the last; denser at low presses, where the membranes go from slack to taut; with the
//! abdominal wall free, states of a slow press instead: [`quasi_static`]), and
//! presses F(t) = a (1 − cos 2π f t)/2 at the training frequency f, a = A/8, 3A/8 and A
//! ([`DYNAMIC_SHARES`]), stepped by the model's integrator (the inertia a fast press
//! excites) at `max_step` or, if that is coarser, [`STEPS_PER_PERIOD`] steps per period of
//! the training frequency ([`step`]). Their POD in the energy inner product to [`POD_TOLERANCE`] is
//! the basis ([`pod::basis`]); ECSW weights fitted to the reduced internal forces at the
//! same states to [`ECSW_TOLERANCE`] sample the elements the online Newton iterations
//! evaluate ([`crate::solve::ecsw`]). Mass and damping are projected exactly (they are
//! linear); the pressing load is projected too.

use std::sync::Arc;
use std::time::Instant;

use super::build::FullOrder;
use super::stepping::{press_run, static_ramp};
use crate::assembly::quadratic_plane::PlaneBody;
use crate::budget;
use crate::scene::SceneError;
use crate::solve::ecsw::{Fit, HyperReduced};
use crate::solve::{pod, ModalBasis, Structure};
use rayon::prelude::*;

/// Static training states: presses of (i/N)² of the training press, i = 1 … N.
pub const STATIC_STATES: usize = 10;

/// The dynamic training presses' amplitudes as shares of the training press: a fast press
/// of a low amplitude excites other shapes than one of a high amplitude (trained at the
/// full amplitude only, low presses came out tens of per cent off: BENCHMARKS.md, "The
/// hyper-reduced abdomen's training").
pub const DYNAMIC_SHARES: [f64; 3] = [0.125, 0.375, 1.0];

/// The POD keeps the vectors that leave at most this share of the training states out
/// (energy norm, [`pod`]): 48 vectors on the default abdomen. The error of the floor's peak
/// stress does not fall steadily with the tolerance; at 3e-4 the slower presses of the
/// shipped configurations are within 0.65 % (BENCHMARKS.md, "The hyper-reduced abdomen's
/// training").
pub const POD_TOLERANCE: f64 = 3e-4;

/// The ECSW weights reproduce the reduced training forces to this share (root mean square
/// over the states of each state's relative error): 210 of 1,129 elements on the default
/// abdomen. The basis, not the sampling, sets the outputs' error (BENCHMARKS.md, "The
/// hyper-reduced abdomen's training").
pub const ECSW_TOLERANCE: f64 = 5e-2;

/// The reduced model's Newton iterations stop at a residual of this share of its scale:
/// a hundred times the full model's tolerance, still a thousand times below the reduction's
/// own error (10⁻³ of the peaks and more): fewer iterations per step (BENCHMARKS.md, "The
/// hyper-reduced abdomen's training").
pub const REDUCED_NEWTON_TOLERANCE: f64 = 1e-6;

/// The training presses take at least this many steps per period of the training
/// frequency: 10 ms at the default 5 Hz, the default `max_step`. `max_step` bounds the
/// online model's steps; it must not coarsen the training states (trained at four states
/// per period the reduced model came out several times further from full order:
/// BENCHMARKS.md, "The hyper-reduced abdomen's training").
pub const STEPS_PER_PERIOD: f64 = 20.0;

/// The step of the training presses for a model of largest step `max_step`.
pub fn step(range: TrainingRange, max_step: f64) -> f64 {
    max_step.min(1.0 / (STEPS_PER_PERIOD * range.frequency))
}

/// What the reduced model is trained for: presses from 0 to `press` (N/mm) of frequencies
/// up to `frequency` (Hz).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrainingRange {
    /// The training press A (N/mm): the largest press the reduced model is trained for.
    pub press: f64,
    /// The training frequency f (Hz): the highest press frequency it is trained for.
    pub frequency: f64,
}

impl TrainingRange {
    /// The warning for a press between `low` and `peak` (N/mm) of frequency `frequency`
    /// (Hz; 0 for a constant press) that leaves the range (beyond its round-off: 1.5 × 0.8
    /// is 1.2000000000000002).
    pub fn check(&self, [low, peak]: [f64; 2], frequency: f64) -> Option<String> {
        let slack = 1.0 + 1e-12;
        let outside = low < 0.0 || peak > self.press * slack || frequency > self.frequency * slack;
        outside.then(|| {
            format!(
                "the press ({low} to {peak} N/mm at {frequency} Hz) leaves the range the \
                 reduced model is trained for (0 to {} N/mm, up to {} Hz): its error is not \
                 known there; raise training_press / training_frequency or use \
                 model_order = \"full\"",
                self.press, self.frequency
            )
        })
    }
}

/// The trained hyper-reduction: the forces, the fit, the range and the time the training
/// took (s, basis included).
#[derive(Debug)]
pub struct HyperReduction {
    /// The hyper-reduced internal forces: the ECSW-weighted sampled elements on the basis.
    pub forces: Arc<HyperReduced>,
    /// What the ECSW fit found: states fitted on, elements sampled, residual reached.
    pub fit: Fit,
    /// The press and frequency range the training covers.
    pub range: TrainingRange,
    /// The wall-clock time the training took, training states and basis included (s).
    pub seconds: f64,
}

/// Trains the reduced model of `model` (finite strain, its body `body`, largest step
/// `max_step`) over `range`, the training presses stepped at [`step`], with at most `max`
/// basis vectors: the basis and the hyper-reduction.
pub fn train(
    model: &FullOrder,
    body: &Arc<PlaneBody>,
    range: TrainingRange,
    max_step: f64,
    max: usize,
) -> Result<(ModalBasis, HyperReduction), SceneError> {
    let clock = Instant::now();
    let (states, presses) = states(model, range, step(range, max_step))?;
    let full = &model.structure;
    let bc = full.dirichlet();
    let snapshots: Vec<Vec<f64>> = states
        .iter()
        .map(|u| {
            let mut free = vec![0.0; full.n()];
            bc.reduce(u, &mut free);
            free
        })
        .collect();
    let basis = pod::basis(full, &snapshots, POD_TOLERANCE, max)?;
    let (forces, fit) = HyperReduced::train(
        body.clone(),
        &basis,
        full,
        &states,
        |i| model.set_press(presses[i]),
        ECSW_TOLERANCE,
    )?;
    let hyper = HyperReduction {
        forces: Arc::new(forces),
        fit,
        range,
        seconds: clock.elapsed().as_secs_f64(),
    };
    Ok((basis, hyper))
}

/// The training states (all dofs) of `model` over `range` with the press at each: the
/// quasi-static ones ([`quasi_static`]), then the dynamic presses stepped at `dt` — the
/// four runs side by side on rayon's threads, each within a quarter of the memory budget
/// left ([`budget::part`]; each run is deterministic, so the states are the same on any
/// number of threads) — and the states claimed against the budget.
fn states(
    model: &FullOrder,
    range: TrainingRange,
    dt: f64,
) -> Result<(Vec<Vec<f64>>, Vec<f64>), SceneError> {
    let share = budget::shares(1 + DYNAMIC_SHARES.len());
    let (slow, dynamic) = rayon::join(
        || budget::part(share, || quasi_static(model, range, dt)),
        || {
            DYNAMIC_SHARES
                .par_iter()
                .map(|a| {
                    let press = [a * range.press, range.frequency, dt, 1.0];
                    budget::part(share, || press_run(model, press))
                })
                .collect::<Result<Vec<_>, _>>()
        },
    );
    let (mut states, mut presses) = slow?;
    for (run, at) in dynamic? {
        states.extend(run);
        presses.extend(at);
    }
    let n = states.first().map_or(0, Vec::len);
    budget::claim(
        "the reduced model's training states",
        budget::bytes_of::<f64>(n.saturating_mul(states.len())),
    )?;
    Ok((states, presses))
}

/// The quasi-static training states with the press at each. With the wall braced, the
/// static equilibria under presses of (i/N)² of the training press, i = 1 … N =
/// [`STATIC_STATES`]. A free wall is a membrane slack at rest, from which Newton's method
/// finds the first static equilibrium only slowly (BENCHMARKS.md, "The hyper-reduced
/// abdomen's training"); with
/// inertia a slow press gets there in steps: the rise of a press to the training press at a
/// tenth of the training frequency ([`SLOW_PRESS`]), every [`SLOW_STRIDE`]-th state.
fn quasi_static(
    model: &FullOrder,
    range: TrainingRange,
    dt: f64,
) -> Result<(Vec<Vec<f64>>, Vec<f64>), SceneError> {
    if model.fixed_wall() {
        let levels: Vec<f64> = (1..=STATIC_STATES)
            .map(|i| range.press * (i as f64 / STATIC_STATES as f64).powi(2))
            .collect();
        return Ok((static_ramp(model, &levels)?, levels));
    }
    let (states, presses) = press_run(model, [range.press, range.frequency / SLOW_PRESS, dt, 0.5])?;
    // Every SLOW_STRIDE-th state, and the last (the peak) in any case.
    let last = states.len().saturating_sub(1);
    let kept = |i: usize| (i + 1).is_multiple_of(SLOW_STRIDE) || i == last;
    Ok(states
        .into_iter()
        .zip(presses)
        .enumerate()
        .filter_map(|(i, state)| kept(i).then_some(state))
        .unzip())
}

/// The free wall's quasi-static press runs at the training frequency divided by this.
pub const SLOW_PRESS: f64 = 10.0;

/// Of the free wall's slow press every this many states train the model (ten of the 100
/// steps of its rise at the default 5 Hz and 10 ms).
pub const SLOW_STRIDE: usize = 10;

/// The reduced structure: mass, damping and the stiffness at rest projected exactly, on a
/// pattern of every r × r entry (the reduced tangent is dense), with the hyper-reduced
/// internal forces.
pub fn structure(
    full: &Structure,
    phi: &ModalBasis,
    forces: &Arc<HyperReduced>,
) -> Result<Structure, SceneError> {
    let (k, m, c) = (
        phi.galerkin(full.stiffness()),
        phi.galerkin(full.mass()),
        phi.galerkin(full.damping_matrix()),
    );
    let reduced = Structure::dense_full(k.as_ref(), m.as_ref(), c.as_ref())?;
    // Internal forces write on the full pattern; with no dof held it is the reduced one.
    debug_assert_eq!(reduced.dirichlet().full_nnz(), reduced.dirichlet().nnz());
    let forces = forces
        .clone()
        .internal_forces(reduced.dirichlet().symbolic());
    Ok(reduced
        .with_internal_forces(forces)
        .with_newton_tolerance(REDUCED_NEWTON_TOLERANCE))
}

#[cfg(test)]
mod tests {
    use super::super::variables::{table, TARGET_TRIANGLES};
    use super::*;
    use crate::scene::Values;

    /// The training step is `max_step` where that is finer than a twentieth of the
    /// training period, that twentieth where `max_step` is coarser.
    #[test]
    fn the_training_step_is_max_step_or_a_twentieth_of_the_period() {
        let at = |frequency| TrainingRange {
            press: 1.0,
            frequency,
        };
        assert_eq!(step(at(5.0), 0.05), 0.01);
        assert_eq!(step(at(5.0), 0.002), 0.002);
        assert_eq!(step(at(0.5), 0.05), 0.05);
        assert_eq!(step(at(50.0), 0.01), 0.001);
    }

    /// The default abdomen on a coarse mesh (to keep a full basis small).
    fn coarse() -> FullOrder {
        let mut values = Values::new(table());
        values.set_real(TARGET_TRIANGLES, &[60.0]).unwrap();
        FullOrder::build(&values).unwrap_or_else(|e| panic!("{e}"))
    }

    /// The defaults' training range.
    const RANGE: TrainingRange = TrainingRange {
        press: 1.2,
        frequency: 5.0,
    };

    /// A Newton tolerance far below the models' own (their iterations then end on the
    /// round-off of their corrections), for comparisons of two paths to 1e-9.
    const TIGHT: f64 = 1e-12;

    /// The basis and hyper-reduction of `model` trained over [`RANGE`] at 10 ms.
    fn trained(model: &FullOrder) -> (ModalBasis, HyperReduction) {
        let body = model.body.clone().expect("finite strain");
        train(model, &body, RANGE, 0.01, 80).unwrap_or_else(|e| panic!("{e}"))
    }

    /// With a complete basis (the POD of the unit vectors) and every element at weight
    /// one, the reduced model is the full one in other coordinates; Newton's corrections
    /// are invariant under that change of coordinates (only its stopping tests, on norms,
    /// are not), so both runs agree to the steps' Newton tolerance: 1e-9 with both run to
    /// [`TIGHT`].
    #[test]
    fn the_complete_basis_at_unit_weights_is_the_full_model() {
        let model = coarse();
        let full = &model.structure;
        let n = full.n();
        let unit_vectors: Vec<Vec<f64>> = (0..n)
            .map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect())
            .collect();
        let basis = pod::basis(full, &unit_vectors, 0.0, n).unwrap();
        assert_eq!(basis.dim(), n);
        let own = model.detached().unwrap();
        let body = model.body_reading(&own.tension).unwrap();
        let forces = Arc::new(HyperReduced::galerkin(body, &basis, full));
        let reduced = structure(full, &basis, &forces)
            .unwrap()
            .with_newton_tolerance(TIGHT);
        let mut unit = vec![0.0; n];
        basis.project(model.unit_load(), &mut unit);
        let press = |s: &Structure, unit: &[f64]| {
            super::super::stepping::press_states(
                &model,
                s,
                &own.tension,
                unit,
                [0.8, 5.0, 0.01, 1.0],
            )
            .unwrap_or_else(|e| panic!("{e}"))
            .0
        };
        let expected = press(
            &own.structure.clone().with_newton_tolerance(TIGHT),
            model.unit_load(),
        );
        let got = press(&reduced, &unit);
        assert_eq!(got.len(), 20);
        let peak = expected
            .iter()
            .flatten()
            .fold(0.0_f64, |m, x| m.max(x.abs()));
        let mut u = vec![0.0; n];
        let mut largest = 0.0_f64;
        for (step, (a, q)) in expected.iter().zip(&got).enumerate() {
            basis.expand(q, &mut u);
            let diff = a
                .iter()
                .zip(&u)
                .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()));
            largest = largest.max(diff / peak);
            assert!(diff <= 1e-9 * peak, "step {step}: {diff:e} of {peak:e}");
        }
        println!("largest difference over the 20 steps: {largest:e} of the peak");
    }

    /// The sampled elements' weighted forces reproduce the reduced forces of all elements
    /// at every training state to the stated tolerance (root mean square of the relative
    /// errors), evaluated anew through both force paths.
    #[test]
    fn the_sampled_elements_reproduce_the_training_forces_to_the_tolerance() {
        let model = coarse();
        let full = &model.structure;
        let (basis, hyper) = trained(&model);
        let body = model.body.clone().expect("finite strain");
        let all = HyperReduced::galerkin(body, &basis, full);
        let (states, presses) = states(&model, RANGE, 0.01).unwrap();
        let r = basis.dim();
        let (mut free, mut q) = (vec![0.0; full.n()], vec![0.0; r]);
        let (mut sampled, mut exact) = (vec![0.0; r], vec![0.0; r]);
        let mut squares = 0.0;
        for (u, &press) in states.iter().zip(&presses) {
            full.dirichlet().reduce(u, &mut free);
            basis.coordinates(full.mass(), &free, &mut q);
            model.set_press(press);
            hyper.forces.evaluate(&q, &mut sampled, None).unwrap();
            all.evaluate(&q, &mut exact, None).unwrap();
            let norm = |x: &[f64]| x.iter().map(|x| x * x).sum::<f64>().sqrt();
            let diff: Vec<f64> = sampled.iter().zip(&exact).map(|(a, b)| a - b).collect();
            squares += (norm(&diff) / norm(&exact)).powi(2);
        }
        let rms = (squares / states.len() as f64).sqrt();
        assert!(rms <= ECSW_TOLERANCE, "{rms:e}");
        assert!(
            (rms - hyper.fit.residual).abs() <= 1e-9,
            "{rms} vs {:?}",
            hyper.fit
        );
    }

    /// The hyper-reduced tangent (the sampled elements' tangents, weighted and projected) is
    /// the derivative of the hyper-reduced force: central differences at the static state
    /// under the default press agree with it, every entry to 1e-6 of the largest.
    #[test]
    fn the_hyper_reduced_tangent_is_the_derivative_of_its_force() {
        let model = coarse();
        let full = &model.structure;
        let (basis, hyper) = trained(&model);
        assert!(hyper.fit.sampled < hyper.fit.elements, "{:?}", hyper.fit);
        let u = static_ramp(&model, &[0.8]).unwrap().pop().unwrap();
        model.set_press(0.8);
        let (r, n) = (basis.dim(), full.n());
        let (mut free, mut q) = (vec![0.0; n], vec![0.0; r]);
        full.dirichlet().reduce(&u, &mut free);
        basis.coordinates(full.mass(), &free, &mut q);
        let (mut f, mut k) = (vec![0.0; r], vec![0.0; r * r]);
        hyper.forces.evaluate(&q, &mut f, Some(&mut k)).unwrap();
        let scale = k.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        // Small: the stiffest coordinates are far from linear over a step of 1e-6 (measured:
        // 1e-4 of the largest entry off at 1e-6, 1e-8 at 1e-8).
        let h = 1e-8 * q.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let (mut plus, mut minus) = (vec![0.0; r], vec![0.0; r]);
        let mut worst = (0.0_f64, 0, 0);
        for j in 0..r {
            let mut qj = q.clone();
            qj[j] += h;
            hyper.forces.evaluate(&qj, &mut plus, None).unwrap();
            qj[j] -= 2.0 * h;
            hyper.forces.evaluate(&qj, &mut minus, None).unwrap();
            for i in 0..r {
                let difference = (plus[i] - minus[i]) / (2.0 * h);
                let error = (difference - k[i + r * j]).abs() / scale;
                if error > worst.0 {
                    worst = (error, i, j);
                }
            }
        }
        assert!(worst.0 <= 1e-6, "{worst:?} of the largest entry");
    }
}
