//! Where the abdomen stops being valid, and what it says when a run gets there
//! ([`crate::scene::Scene::take_warnings`], once per run each):
//!
//! - **locking**: the element at the contents' ν — `tri3` beyond 0.45 (at 0.49 the apex of
//!   the scene moves 3 % less than on the mixed element), the displacement `tri6` beyond
//!   0.499 (`tests/locking.rs`, `abdomen_elements.rs`); the mixed element does not lock;
//! - **linear kinematics**: a principal strain beyond [`SMALL_STRAIN_LIMIT`] (5 %);
//! - **the reduced model** (`model_order = "reduced"`): a press outside the range it is
//!   trained for ([`super::training::TrainingRange`]).
//!
//! Finite kinematics has no limit of its own here: the membranes go slack in compression
//! as thin sheets do ([`crate::element::membrane`]), and an element turned inside out or a
//! step without equilibrium is an error, not a warning.

use super::discretization::Element;
use super::simulation::Simulation;
use crate::element::mixed::Formulation;
use crate::error::seconds;
use crate::scene::SMALL_STRAIN_LIMIT;

/// The locking warning for contents of Poisson's ratio `nu` on `sim`'s element, if it
/// locks there; `names` are the `element` and `formulation` values, for the message.
pub fn locking(sim: &Simulation, nu: f64, names: (&str, &str)) -> Option<String> {
    let choice = sim.full.disc.choice;
    let limit = match (choice.element, choice.formulation) {
        (Element::Tri3, _) => 0.45,
        (Element::Tri6, Formulation::Displacement) => 0.499,
        (Element::Tri6, Formulation::Mixed) => return None,
    };
    (nu > limit).then(|| {
        format!(
            "cavity_nu = {nu} is beyond the {limit} up to which element = \"{}\" with \
             formulation = \"{}\" is free of locking: displacements come out too small and \
             stresses oscillate; use element = \"tri6\", formulation = \"mixed\"",
            names.0, names.1
        )
    })
}

/// The kinematics' warning at time `time`, if the state leaves their validity: at linear
/// kinematics the largest principal strain beyond the small-strain limit (a modal model
/// expands its field only when [`Simulation::strain_bound`] does not rule that out).
pub fn kinematics(sim: &mut Simulation, time: f64) -> Option<String> {
    if sim.full.disc.choice.finite {
        return None;
    }
    if sim.strain_bound().is_some_and(|b| b <= SMALL_STRAIN_LIMIT) {
        return None;
    }
    sim.expand();
    let strain = sim.full.view(sim.u_full()).largest_strain();
    (strain > SMALL_STRAIN_LIMIT).then(|| {
        format!(
            "at t = {} s the largest principal strain is {:.1} %, beyond the {:.0} % linear \
             (small-strain) kinematics are valid for: use kinematics = \"finite\" \
             (element = \"tri6\") or a smaller load",
            seconds(time),
            100.0 * strain,
            100.0 * SMALL_STRAIN_LIMIT
        )
    })
}

/// The reduced model's warning when the press, between `extremes` (N/mm) at `frequency`
/// (Hz; 0 for a constant press), leaves the range it is trained for.
pub fn training(sim: &Simulation, extremes: [f64; 2], frequency: f64) -> Option<String> {
    let hyper = sim.reduced.as_ref()?.hyper.as_ref()?;
    hyper.range.check(extremes, frequency)
}
