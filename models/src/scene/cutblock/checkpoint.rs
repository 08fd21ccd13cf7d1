//! What a topology's later solves depend on besides what its build makes, as a checkpoint
//! holds it (see [`crate::scene::SceneState`]): the cut, the material of its matrices, the
//! last equilibrium, the contact springs, the Newton solver's kept tangent and the path of
//! equilibria. A topology is built again from the cut and the material, and the rest put
//! back: it then solves on bit for bit as the one the state was taken of.

use serde::{Deserialize, Serialize};

use super::contact::{Held, Spring};
use super::geometry::Geometry;
use super::path::Station;
use super::topology::Topology;
use super::work::Work;
use crate::assembly::tetrahedra::Tetrahedron;
use crate::element::{Elastic, Law, Material};
use crate::scene::SceneError;
use crate::solve::newton::{self, Settings};

/// A topology's state (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TopologyState {
    front: f64,
    law: String,
    young: f64,
    poisson: f64,
    u: Vec<f64>,
    f: Vec<f64>,
    internal: Vec<f64>,
    load: (f64, f64),
    prescribed: Vec<f64>,
    contact: Option<ContactState>,
    newton: Option<newton::Checkpoint>,
    work: Work,
    #[serde(default)]
    path: Vec<Station>,
}

/// The contact as a checkpoint holds it ([`Held`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct ContactState {
    springs: Vec<SpringState>,
    penetration: f64,
    deepest: Option<usize>,
}

impl From<&Held> for ContactState {
    fn from(h: &Held) -> Self {
        Self {
            springs: h.active.iter().map(SpringState::from).collect(),
            penetration: h.penetration,
            deepest: h.deepest,
        }
    }
}

impl From<&ContactState> for Held {
    fn from(c: &ContactState) -> Self {
        Self {
            active: c.springs.iter().map(Spring::from).collect(),
            penetration: c.penetration,
            deepest: c.deepest,
        }
    }
}

/// A contact spring as a checkpoint holds it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct SpringState {
    element: usize,
    node: usize,
    b: [f64; 12],
    g0: f64,
}

impl From<&Spring> for SpringState {
    fn from(s: &Spring) -> Self {
        Self {
            element: s.element,
            node: s.node,
            b: s.b.into(),
            g0: s.g0,
        }
    }
}

impl From<&SpringState> for Spring {
    fn from(s: &SpringState) -> Self {
        Self {
            element: s.element,
            node: s.node,
            b: s.b.into(),
            g0: s.g0,
        }
    }
}

impl Topology {
    /// The topology's state (see [`TopologyState`]).
    pub fn checkpoint(&self) -> TopologyState {
        let m = self.solid.material;
        let eq = &self.eq;
        TopologyState {
            front: self.front,
            law: m.law.name().into(),
            young: m.elastic.young(),
            poisson: m.elastic.poisson(),
            u: eq.u.clone(),
            f: eq.f.clone(),
            internal: eq.internal.clone(),
            load: eq.load,
            prescribed: eq.prescribed.clone(),
            contact: self.contact.as_ref().map(|c| ContactState::from(&c.held())),
            newton: eq.newton_checkpoint(),
            work: eq.work,
            path: self.path.clone(),
        }
    }

    /// The topology a state was taken of: built again for its cut and material, then the
    /// equilibrium, springs and solver put back.
    pub fn resume(
        g: &Geometry,
        state: &TopologyState,
        kind: Tetrahedron,
        settings: Settings,
    ) -> Result<Self, SceneError> {
        let elastic = Elastic::new("saved", state.young, state.poisson)?;
        let material = Material::new(Law::parse(&state.law)?, elastic);
        let mut t = Self::build(g, state.front, material, kind, settings, None, None)?;
        let n = t.eq.u.len();
        for (name, v) in [
            ("u", &state.u),
            ("f", &state.f),
            ("internal", &state.internal),
        ] {
            if v.len() != n {
                return Err(SceneError::Config(format!(
                    "the saved `{name}` has {} values, the rebuilt topology {n}",
                    v.len()
                )));
            }
        }
        let eq = &mut t.eq;
        eq.u.clone_from(&state.u);
        eq.f.clone_from(&state.f);
        eq.internal.clone_from(&state.internal);
        eq.load = state.load;
        eq.prescribed.clone_from(&state.prescribed);
        if let (Some(c), Some(saved)) = (&mut t.contact, &state.contact) {
            c.hold(&Held::from(saved));
        }
        let (on, eq) = t.parts();
        eq.factorize(&on)?;
        if let Some(checkpoint) = &state.newton {
            eq.resume_newton(&on, checkpoint)?;
        }
        t.eq.work = state.work;
        t.path.clone_from(&state.path);
        Ok(t)
    }
}
