//! The abdomen's state as a checkpoint holds it (see [`crate::scene::SceneState`]): the
//! values, the time and the warnings given, and for a built model the values its matrices
//! were assembled with (a stiffness change may be pending for the next step) and the
//! integrator's checkpoint — of the full system or of the reduced one in modal order — and
//! the state a modal basis was built to carry at the last stiffness change. The mesh, the
//! matrices, the factorizations and the modal basis are built again from those: they come
//! out the same, bit for bit.

use serde::{Deserialize, Serialize};

use super::pressure::Found;
use crate::scene::{Inert, ValuesState};
use crate::solve::Checkpoint;

/// The abdomen's state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State {
    pub(super) values: ValuesState,
    pub(super) time: f64,
    /// The time the state lags behind `time` after steps too short to integrate (s).
    #[serde(default)]
    pub(super) lag: f64,
    /// Where the press's phase was last set (time s, phase rad).
    #[serde(default)]
    pub(super) phase_origin: [f64; 2],
    /// In `press_mode = "pressure"`, the last step's pressing force, slope and target.
    pub(super) found: Found,
    pub(super) stiffness_changed: bool,
    pub(super) warnings: Vec<String>,
    pub(super) warned_validity: bool,
    /// Whether the run has warned of a target the relaxed muscles stayed above (absent in
    /// states saved before it: not warned).
    #[serde(default)]
    pub(super) warned_relaxed: bool,
    /// The parameters already warned of in this run for having no effect.
    #[serde(default)]
    pub(super) inert: Inert,
    pub(super) simulation: Option<SimulationState>,
}

/// A built simulation's state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct SimulationState {
    /// The values of the last build or stiffness update: what the matrices are of.
    pub(super) applied: ValuesState,
    pub(super) integrator: Checkpoint,
    /// The diaphragm's active tension of the last step and of the kept tangent (finite
    /// strain; N/mm).
    pub(super) tension: [f64; 2],
    /// The state a modal basis was built to carry at the last stiffness change (free
    /// dofs); empty before any.
    #[serde(default)]
    pub(super) carried: Vec<Vec<f64>>,
}
