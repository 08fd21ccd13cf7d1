//! Where the abdomen stops being valid, and what it says when a run gets there
//! ([`crate::scene::Scene::take_warnings`], once per run each):
//!
//! - **locking**: the element at the contents' ν — `tri3` beyond 0.45 (at 0.49 the apex of
//!   the scene moves 3 % less than on the mixed element), the displacement `tri6` beyond
//!   0.499 (`tests/locking.rs`, `abdomen_elements.rs`); the mixed element does not lock;
//! - **linear kinematics**: a principal strain beyond [`SMALL_STRAIN_LIMIT`] (5 %);
//! - **the reduced model** (`model_order = "reduced"`): a press outside the range it is
//!   trained for ([`super::training::TrainingRange`]);
//! - **the membranes' law** (finite kinematics, full order): a line stretched beyond
//!   [`MEMBRANE_STRETCH_LIMIT`].
//!
//! The membranes go slack in compression as thin sheets do ([`crate::element::membrane`]),
//! and an element turned inside out or a step without equilibrium is an error, not a
//! warning.

use super::discretization::Element;
use super::simulation::Simulation;
use super::variables::TISSUES;
use crate::element::membrane::Law;
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

/// The stretch of a membrane beyond which its law stops being valid. Soft tissue stiffens
/// as it is stretched; both laws soften in tangent instead: Hencky's nominal stress P = E ln
/// λ / λ has lost three quarters of its stiffness at rest there (dP/dλ = E (1 − ln λ) / λ² =
/// 0.26 E at λ = 1.5) and rises to its maximum E/e at λ = e, where a pressed membrane necks
/// — measured: driven by the contents' pressure, the pelvic floor snaps through as its
/// largest stress reaches E/e (normal pelvis, 9.1 kPa, docs/theory/abdomen.md); the
/// neo-Hookean sheet's tangent (E/4)(1 + 3 λ⁻⁴) has lost 60 % of it (0.40 E).
pub const MEMBRANE_STRETCH_LIMIT: f64 = 1.5;

/// The membranes' warning at time `time`, if a line (in full order, at finite kinematics)
/// carries a passive mean stress beyond its law's at [`MEMBRANE_STRETCH_LIMIT`].
pub fn membranes(sim: &mut Simulation, time: f64) -> Option<String> {
    if !sim.full.disc.choice.finite || sim.reduced.is_some() {
        return None;
    }
    sim.expand();
    let full = &sim.full;
    let regions = full.disc.mesh().line_regions();
    let trusses = &full.props.trusses;
    let (line, excess) = (0..regions.len())
        .map(|i| {
            let truss = trusses[usize::from(regions[i])];
            let limit = truss.law.stress(truss.young, MEMBRANE_STRETCH_LIMIT);
            (i, full.recovery.line(i, sim.u_full()) / limit)
        })
        .filter(|(_, excess)| excess.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    let law = trusses[usize::from(regions[line])].law;
    let lost = match law {
        Law::Hencky => "its Hencky law has lost three quarters of its stiffness",
        Law::NeoHookean => "its neo-Hookean law has lost 60 % of its stiffness",
    };
    (excess > 1.0).then(|| {
        format!(
            "at t = {} s the {} is stretched beyond {MEMBRANE_STRETCH_LIMIT} (its stress {:.1} \
             times the law's there), where {lost} and soft tissue would stiffen instead: \
             membrane forces and displacements beyond it are not those of tissue (reduce the \
             press)",
            seconds(time),
            TISSUES[usize::from(regions[line]) + 1],
            excess
        )
    })
}
