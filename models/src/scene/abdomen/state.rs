//! The abdomen's state as a checkpoint holds it (see [`crate::scene::SceneState`]): the
//! values, the time and the warnings given, and for a built model the values its matrices
//! were assembled with (a stiffness change may be pending for the next step) and the
//! integrator's checkpoint — of the full system or of the reduced one in modal order. The
//! mesh, the matrices, the factorizations and the modal basis are built again from those
//! values: they come out the same, bit for bit.

use serde::{Deserialize, Serialize};

use crate::scene::ValuesState;
use crate::solve::Checkpoint;

/// The abdomen's state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct State {
    pub(super) values: ValuesState,
    pub(super) time: f64,
    pub(super) stiffness_changed: bool,
    pub(super) warnings: Vec<String>,
    pub(super) warned_validity: bool,
    pub(super) model: Option<ModelState>,
}

/// A built model's state.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub(super) struct ModelState {
    /// The values of the last build or stiffness update: what the matrices are of.
    pub(super) applied: ValuesState,
    pub(super) integrator: Checkpoint,
    /// The diaphragm's active tension of the last step and of the kept tangent (finite
    /// strain; N/mm).
    pub(super) tension: [f64; 2],
}
