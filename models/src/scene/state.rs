//! A scene's state as a checkpoint holds it: the parameter and input values and everything
//! a later step depends on (time, integrator history, the cut, the contact set, the kept
//! Newton tangent, warnings already given). [`Scene::save`](super::Scene::save) takes it,
//! [`Scene::restore`](super::Scene::restore) puts it back into a scene of the same kind —
//! the same instance, another one, or one in another process after serialization — which
//! then continues bit for bit as the scene it was taken from. What can be rebuilt exactly
//! from the values (mesh, matrices, factorizations, modal bases) is rebuilt, not stored.

use serde::{Deserialize, Serialize};

/// The state of one of the scenes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum SceneState {
    /// The state of an `abdomen` scene.
    Abdomen(Box<super::abdomen::State>),
    /// The state of a `cutblock` scene.
    CutBlock(Box<super::cutblock::State>),
}

impl SceneState {
    /// The scene the state is of.
    pub fn scene(&self) -> &'static str {
        match self {
            Self::Abdomen(_) => "abdomen",
            Self::CutBlock(_) => "cutblock",
        }
    }
}
