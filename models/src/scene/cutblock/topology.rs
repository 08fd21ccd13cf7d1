//! The current topology of the cut block: the cut mesh, its solid (linear or quadratic
//! tetrahedra of one material law), the pattern, the solver, the contact of the flanks and
//! the last equilibrium.
//!
//! Two solvers: the linear law keeps one factorization of K (with the active contact
//! springs) per material, topology and contact set, so a new load costs one solve; a
//! finite-strain law goes from the last equilibrium to the new load with Newton's method
//! ([`crate::solve::newton`]) in increments of at most `max_increment` of pull.
//!
//! The work of one step is bounded for every value in the declared ranges: at most
//! [`MAX_INCREMENTS`] load increments of the pull change (a larger count is refused before
//! any work, naming `max_increment` and the change), each cut back at most 8 times and of at
//! most 25 Newton iterations ([`Settings`]); with contact, at most [`CONTACT_ITERATIONS`]
//! solves until the contact set repeats and [`RELINEARIZATION_SOLVES`] more while its
//! springs are linearized again (75 per settle), and the change split into at most 2 + 4 +
//! [`CONTACT_PARTS`] parts (15 settles).

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::contact::{FlankContact, Held, Spring, PENALTY_FACTOR, SLIDING_LIMIT};
use super::geometry::{Geometry, Strategy, Support};
use super::profiles::TopSurface;
use super::transfer::{extrapolate, transfer};
use super::Work;
use crate::assembly::solid::{Body, Solid, Tetrahedron};
use crate::assembly::{mul_add, Assembler};
use crate::element::{Elastic, Law, Material};
use crate::error::ModelError;
use crate::mesh::cut::{self, CutMesh};
use crate::mesh::{Mesh3d, QuadraticMesh};
use crate::scene::SceneError;
use crate::solve::newton::{self, Equations, Newton, Settings};
use crate::solve::{Factorization, Ordering, Statics};

/// The most Newton load increments one step may take.
pub const MAX_INCREMENTS: f64 = 1000.0;

/// Largest number of solves of one settle while the contact set changes.
const CONTACT_ITERATIONS: usize = 25;

/// Largest number of solves one settle spends re-linearizing its springs
/// ([`Topology::relinearize`]).
const RELINEARIZATION_SOLVES: usize = 50;

/// The most equal parts a load change is split into when its flanks end through each other.
const CONTACT_PARTS: usize = 8;

/// How the equilibrium is found.
#[derive(Debug)]
enum Solver {
    /// The linear law: K (with the active springs) factorized, K without them kept for
    /// the internal forces.
    Linear {
        statics: Box<Statics>,
        k_base: Vec<f64>,
        k: Vec<f64>,
    },
    /// A finite-strain law.
    Newton(Box<Newton>),
}

impl Solver {
    fn dirichlet(&self) -> &crate::assembly::Dirichlet {
        match self {
            Self::Linear { statics, .. } => statics.dirichlet(),
            Self::Newton(n) => n.dirichlet(),
        }
    }

    /// A solver of the same kind for equations of the same pattern, sharing the analysis:
    /// the `spare` if it shares it too (its storage reused), else a new one.
    fn same_pattern(
        &self,
        asm: &Assembler,
        settings: Settings,
        spare: Option<Spare>,
    ) -> Result<Self, SceneError> {
        if let Some(Spare(mut spare)) = spare.filter(|s| s.0.shares_analysis(self)) {
            match &mut spare {
                Self::Newton(n) => n.recycle(settings)?,
                Self::Linear { statics, .. } => statics.invalidate(),
            }
            return Ok(spare);
        }
        Ok(match self {
            Self::Linear { statics, .. } => Self::Linear {
                statics: Box::new(statics.same_pattern()?),
                k_base: asm.zeros(),
                k: asm.zeros(),
            },
            Self::Newton(n) => Self::Newton(Box::new(n.same_pattern(settings)?)),
        })
    }

    /// Whether both are of one kind and share the symbolic analysis.
    fn shares_analysis(&self, other: &Solver) -> bool {
        match (self, other) {
            (Self::Linear { statics: a, .. }, Self::Linear { statics: b, .. }) => {
                a.shares_analysis(b)
            }
            (Self::Newton(a), Self::Newton(b)) => a.shares_analysis(b),
            _ => false,
        }
    }
}

/// The solver of a replaced topology, kept to lend its storage to the next topology of the
/// same pattern (a blade advance within a cell): the factor's storage and the vectors are
/// then reused instead of mapped afresh from the operating system page by page, as
/// allocations of tens of megabytes are (a tet10 factor).
#[derive(Debug)]
pub struct Spare(Solver);

/// Everything that depends on the current cut.
#[derive(Debug)]
pub struct Topology {
    /// Where the incision ends (x, mm; 0 uncut).
    pub front: f64,
    pub solid: Solid,
    /// Node pairs facing each other across the cut (front flank, back flank), mid-edge
    /// nodes included.
    pub flank_pairs: Vec<(usize, usize)>,
    /// The pattern, shared with the topologies of the same connectivity.
    pub asm: Arc<Assembler>,
    solver: Solver,
    /// Flank contact, if the scene has a cut and contact is on.
    pub contact: Option<FlankContact>,
    /// The y size of the cell in front of the cut (sets penalty and search tolerance).
    layer: f64,
    /// The top surface (undeformed z = size_z).
    pub top: TopSurface,
    /// Nodes of the pulled face.
    pub pulled: Vec<usize>,
    /// The last equilibrium: displacements, external and internal forces (all dofs).
    pub u: Vec<f64>,
    pub f: Vec<f64>,
    pub internal: Vec<f64>,
    /// The prescribed displacements of the pulled face and the press force of `u`.
    load: (f64, f64),
    /// Scratch: the equilibrium at the start of a solve (restored on failure) and after a
    /// settle's first settled contact set (restored when its springs cannot be linearized
    /// again), the prescribed values (all dofs), and the linear law's loads with the
    /// springs' share.
    saved: Snapshot,
    settled: Snapshot,
    prescribed: Vec<f64>,
    loads: Vec<f64>,
    /// Factorizations, Newton increments and iterations since this topology was built.
    pub work: Work,
    /// Whether a solve since the scene last looked kept the springs linearized where their
    /// nodes were caught ([`Self::settle`]'s fallback).
    pub fell_back: bool,
    /// The finite-strain laws: equilibria of this pattern at earlier blade positions, the
    /// latest last (at most `PATH_POINTS` − 1; [`Self::start_from`]).
    path: Vec<Station>,
    /// The cut mesh and its quadratic one (tet10): moved, not made anew, for the next
    /// front within the cell ([`Geometry::moved_cut`]).
    cut: CutMesh,
    quadratic: Option<QuadraticMesh>,
}

/// A copy of an equilibrium to go back to (its buffers made once, with the topology).
#[derive(Debug)]
struct Snapshot {
    u: Vec<f64>,
    internal: Vec<f64>,
}

impl Snapshot {
    fn new(n_dofs: usize) -> Self {
        Self {
            u: vec![0.0; n_dofs],
            internal: vec![0.0; n_dofs],
        }
    }

    fn save(&mut self, u: &[f64], internal: &[f64]) {
        self.u.copy_from_slice(u);
        self.internal.copy_from_slice(internal);
    }
}

/// An equilibrium of a topology of the same pattern (the same connectivity and numbering:
/// the front within one cell, [`Geometry::x_planes`]) at an earlier blade position, under
/// its load: a point of the path a blade advance's start is extrapolated along
/// ([`Topology::start_from`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Station {
    front: f64,
    load: (f64, f64),
    u: Vec<f64>,
}

/// The most equilibria a start is extrapolated from: a quadratic in the blade position.
const PATH_POINTS: usize = 3;

/// Which copy [`Topology::back`] restores.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Saved {
    /// The start of the solve: the solve is undone.
    Solve,
    /// A settle's first settled set: its re-linearization is given up (the fallback).
    Settled,
}

/// What a later solve of a topology depends on besides what its build makes (see
/// [`crate::scene::SceneState`]): the cut, the material of its matrices, the last
/// equilibrium, the contact springs and the Newton solver's kept tangent.
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

/// The solid and the contact springs as the Newton solver's equations.
struct Equilibrium<'a> {
    solid: &'a Solid,
    asm: &'a Assembler,
    contact: Option<&'a FlankContact>,
    penalty: f64,
}

impl Equations for Equilibrium<'_> {
    fn add_internal(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        let mut body = Body {
            solid: self.solid,
            asm: self.asm,
        };
        body.add_internal(u, f, k.as_deref_mut())?;
        if let Some(c) = self.contact {
            c.add_forces(self.penalty, u, f);
            if let Some(k) = k {
                c.add_stiffness(self.asm, self.penalty, k);
            }
        }
        Ok(())
    }
}

/// The solid's node sets: the mesh's, with mid-edge nodes for quadratic tetrahedra.
struct Sets<'a> {
    mesh: &'a Mesh3d,
    quadratic: Option<&'a QuadraticMesh>,
}

impl Sets<'_> {
    fn get(&self, name: &str) -> Result<Vec<usize>, SceneError> {
        let corners = self.mesh.node_sets().get(name)?;
        Ok(match self.quadratic {
            Some(q) => q.extend(corners),
            None => corners.to_vec(),
        })
    }
}

/// The constrained dofs of the supports (see [`Support`]).
fn supports(
    g: &Geometry,
    sets: &Sets,
    solid: &Solid,
) -> Result<(Vec<usize>, Vec<usize>), SceneError> {
    let clamped = sets.get("y0")?;
    let pulled = sets.get("y1")?;
    let mut fixed: Vec<usize> = pulled.iter().map(|n| 3 * n + 1).collect();
    let all = |n: &usize| [3 * n, 3 * n + 1, 3 * n + 2];
    match g.options.support {
        Support::Clamped => fixed.extend(clamped.iter().flat_map(all)),
        Support::Gripped => {
            fixed.extend(clamped.iter().flat_map(all));
            fixed.extend(pulled.iter().flat_map(|n| [3 * n, 3 * n + 2]));
        }
        Support::Sliding => {
            fixed.extend(clamped.iter().map(|n| 3 * n + 1));
            let origin = find_node(solid.nodes(), [0.0, 0.0, 0.0])?;
            let corner = find_node(solid.nodes(), [g.size[0], 0.0, 0.0])?;
            fixed.extend([3 * origin, 3 * origin + 2, 3 * corner + 2]);
        }
    }
    Ok((fixed, pulled))
}

/// The flank facets for contact: boundary faces of the cut mesh with every corner on a
/// flank, split into their four sub-triangles for quadratic tetrahedra.
fn flank_facets(
    mesh: &Mesh3d,
    corner_pairs: &[(usize, usize)],
    quadratic: Option<&QuadraticMesh>,
) -> Vec<[usize; 3]> {
    let mut on_flank = vec![false; mesh.nodes().len()];
    for &(f, b) in corner_pairs {
        on_flank[f] = true;
        on_flank[b] = true;
    }
    let faces = mesh
        .boundary()
        .iter()
        .map(|f| f.nodes)
        .filter(|f| f.iter().all(|&n| on_flank[n]));
    match quadratic {
        None => faces.collect(),
        Some(q) => faces
            .flat_map(|f| {
                let [a, b, c, ab, bc, ca] = q.face(f);
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect(),
    }
}

impl Topology {
    /// Meshes the block cut up to `front`, checks that every body is supported, builds the
    /// solid, the pattern and the solver, and factorizes the linear law's stiffness. A
    /// `previous` topology whose mesh has the same connectivity and supports (the front
    /// moved within a cell, [`Geometry::x_planes`]) lends its pattern and symbolic analysis,
    /// and a `spare` solver of that analysis its storage.
    pub fn build(
        g: &Geometry,
        front: f64,
        material: Material,
        kind: Tetrahedron,
        settings: Settings,
        previous: Option<&Topology>,
        spare: Option<Spare>,
    ) -> Result<Self, SceneError> {
        let derive = |mesh: &Mesh3d| (kind == Tetrahedron::Tet10).then(|| QuadraticMesh::new(mesh));
        let moved = previous.and_then(|p| Some((p, g.moved_cut(&p.cut, p.front, front)?)));
        let (cut, quadratic) = match moved {
            // `previous`'s connectivity, supported as it was.
            Some((p, cut)) => {
                let cut = cut?;
                let quadratic = match &p.quadratic {
                    Some(q) if kind == Tetrahedron::Tet10 => Some(q.moved(&cut.mesh)),
                    _ => derive(&cut.mesh),
                };
                (cut, quadratic)
            }
            None => {
                let cut = g.cut(front)?;
                check_supported(&cut.mesh, cut.mesh.node_sets().get("y0")?)?;
                let quadratic = derive(&cut.mesh);
                (cut, quadratic)
            }
        };
        let (mesh, flank_pairs) = (&cut.mesh, &cut.flank_pairs);
        let solid = match &quadratic {
            Some(q) => Solid::quadratic(q, material),
            None => Solid::linear(mesh, material),
        };
        let sets = Sets {
            mesh,
            quadratic: quadratic.as_ref(),
        };
        let (fixed, pulled) = supports(g, &sets, &solid)?;
        let facets = flank_facets(mesh, flank_pairs, quadratic.as_ref());
        let facing = match (&quadratic, g.options.strategy) {
            (Some(q), Strategy::Duplicate) => {
                q.facing_pairs(flank_pairs, &shared_on_cut(mesh, g.y_cut, flank_pairs))
            }
            (Some(q), Strategy::Delete) => q.facing_pairs(flank_pairs, &[]),
            (None, _) => flank_pairs.clone(),
        };
        let contact = if g.options.contact {
            FlankContact::new(solid.nodes(), facets, &facing, solid.len(), g.layer)
        } else {
            None
        };
        let elements = elements_of(&solid, contact.as_ref());
        let fixed = {
            let mut f = fixed;
            f.sort_unstable();
            f.dedup();
            f
        };
        let finite = material.law.finite();
        let same = previous.filter(|p| {
            matches!(p.solver, Solver::Newton(_)) == finite
                && p.solver.dirichlet().constrained() == fixed
                && p.elements() == elements
        });
        let analysed = u64::from(same.is_none());
        let (asm, solver) = match same {
            Some(p) => (
                Arc::clone(&p.asm),
                p.solver.same_pattern(&p.asm, settings, spare)?,
            ),
            None => {
                drop(spare);
                let asm = Arc::new(Assembler::new(solid.nodes().len(), 3, &elements));
                // Measured fastest for each ([`Ordering`]).
                let ordering = match kind {
                    Tetrahedron::Tet4 => Ordering::MinimumDegree,
                    Tetrahedron::Tet10 => Ordering::NestedDissection,
                };
                let solver = if finite {
                    Solver::Newton(Box::new(Newton::new(
                        &asm,
                        &fixed,
                        Factorization::SupernodalSingle(ordering),
                        settings,
                    )?))
                } else {
                    Solver::Linear {
                        statics: Box::new(Statics::new(
                            &asm,
                            &fixed,
                            Factorization::Supernodal(ordering),
                        )?),
                        k_base: asm.zeros(),
                        k: asm.zeros(),
                    }
                };
                (asm, solver)
            }
        };
        let top = TopSurface::new(mesh, g, quadratic.as_ref());
        let n_dofs = solid.n_dofs();
        let mut t = Self {
            front,
            solid,
            flank_pairs: facing,
            asm,
            solver,
            contact,
            layer: g.layer,
            top,
            pulled,
            u: vec![0.0; n_dofs],
            f: vec![0.0; n_dofs],
            internal: vec![0.0; n_dofs],
            load: (0.0, 0.0),
            saved: Snapshot::new(n_dofs),
            settled: Snapshot::new(n_dofs),
            prescribed: vec![0.0; n_dofs],
            loads: vec![0.0; n_dofs],
            work: Work {
                analyses: analysed,
                ..Work::default()
            },
            fell_back: false,
            path: Vec::new(),
            cut,
            quadratic,
        };
        t.assemble_linear()?;
        Ok(t)
    }

    /// The solver, for the next topology of `next`'s pattern ([`Spare`]); `None` if it has
    /// another pattern, so that no storage is held that cannot be reused.
    pub fn into_spare(self, next: &Topology) -> Option<Spare> {
        self.solver
            .shares_analysis(&next.solver)
            .then_some(Spare(self.solver))
    }

    /// The node lists of the solid's elements and the contact's.
    fn elements(&self) -> Vec<&[usize]> {
        elements_of(&self.solid, self.contact.as_ref())
    }

    /// The topology's state (see [`TopologyState`]).
    pub fn checkpoint(&self) -> TopologyState {
        let m = self.solid.material;
        TopologyState {
            front: self.front,
            law: m.law.name().into(),
            young: m.elastic.young(),
            poisson: m.elastic.poisson(),
            u: self.u.clone(),
            f: self.f.clone(),
            internal: self.internal.clone(),
            load: self.load,
            prescribed: self.prescribed.clone(),
            contact: self.contact.as_ref().map(|c| ContactState::from(&c.held())),
            newton: match &self.solver {
                Solver::Newton(n) => Some(n.checkpoint()),
                Solver::Linear { .. } => None,
            },
            work: self.work,
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
        let n = t.u.len();
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
        t.u.clone_from(&state.u);
        t.f.clone_from(&state.f);
        t.internal.clone_from(&state.internal);
        t.load = state.load;
        t.prescribed.clone_from(&state.prescribed);
        if let (Some(c), Some(saved)) = (&mut t.contact, &state.contact) {
            c.hold(&Held::from(saved));
        }
        t.factorize()?;
        if let (Solver::Newton(n), Some(checkpoint)) = (&mut t.solver, &state.newton) {
            let mut eq = Equilibrium {
                solid: &t.solid,
                asm: &t.asm,
                contact: t.contact.as_ref(),
                penalty: PENALTY_FACTOR * t.solid.material.elastic.young() * t.layer,
            };
            n.resume(&mut eq, checkpoint)?;
        }
        t.work = state.work;
        t.path.clone_from(&state.path);
        Ok(t)
    }

    /// Starts the next solve, for the finite-strain laws (the linear law solves directly and
    /// needs no start), under `from`'s load: from the equilibria of `from`'s pattern at
    /// earlier blade positions under that load, `from`'s own the latest, extrapolated to
    /// this front ([`extrapolate`]), where this topology has that pattern and there are two
    /// or three of them; else from `from`'s equilibrium carried onto this mesh
    /// ([`transfer`]). Returns whether it started from either.
    pub fn start_from(
        &mut self,
        g: &Geometry,
        from: &Topology,
        scalpel_x: f64,
    ) -> Result<bool, SceneError> {
        let Solver::Newton(n) = &self.solver else {
            return Ok(false);
        };
        let constrained = n.dirichlet().constrained().to_vec();
        let mut extrapolated = false;
        if Arc::ptr_eq(&self.asm, &from.asm) {
            let mut path: Vec<Station> = from
                .path
                .iter()
                .filter(|s| s.load == from.load)
                .cloned()
                .collect();
            path.push(Station {
                front: from.front,
                load: from.load,
                u: from.u.clone(),
            });
            path.drain(..path.len().saturating_sub(PATH_POINTS));
            let points: Vec<(f64, &[f64])> =
                path.iter().map(|s| (s.front, s.u.as_slice())).collect();
            if let Some(u) = extrapolate(&points, self.front) {
                self.u = u;
                extrapolated = true;
            }
            path.drain(..path.len().saturating_sub(PATH_POINTS - 1));
            self.path = path;
        }
        if !extrapolated {
            let Some(u) = transfer(&from.solid, &from.u, &self.solid, g.y_cut) else {
                return Ok(false);
            };
            self.u = u;
        }
        self.set_loads(g, from.load.0, from.load.1, scalpel_x);
        for d in constrained {
            self.u[d] = self.prescribed[d];
        }
        self.restart(g, from.load, scalpel_x)?;
        Ok(true)
    }

    /// Back to the unloaded block (after a start from another mesh that did not converge).
    pub fn unload(&mut self, g: &Geometry, scalpel_x: f64) -> Result<(), SceneError> {
        self.u.fill(0.0);
        self.internal.fill(0.0);
        self.restart(g, (0.0, 0.0), scalpel_x)
    }

    /// The linear law's stiffness K (in closed form, [`Solid::add_stiffness`]) and its
    /// factorization.
    fn assemble_linear(&mut self) -> Result<(), SceneError> {
        let k_base = match &mut self.solver {
            Solver::Linear { k_base, .. } => k_base,
            Solver::Newton(n) => {
                n.invalidate();
                return Ok(());
            }
        };
        k_base.fill(0.0);
        self.solid.add_stiffness(&self.asm, k_base)?;
        self.factorize()
    }

    /// After a change of the equations (material, contact springs): factorizes the linear
    /// law's K plus the active springs; a finite-strain law's next solve starts from a new
    /// tangent.
    fn factorize(&mut self) -> Result<(), SceneError> {
        let penalty = self.penalty();
        let (statics, k_base, k) = match &mut self.solver {
            Solver::Linear { statics, k_base, k } => (statics, k_base, k),
            Solver::Newton(n) => {
                n.invalidate();
                return Ok(());
            }
        };
        k.copy_from_slice(k_base);
        if let Some(c) = &self.contact {
            c.add_stiffness(&self.asm, penalty, k);
        }
        statics.factorize(k)?;
        self.work.factorizations += 1;
        Ok(())
    }

    /// Penalty stiffness k_p = PENALTY_FACTOR · E · h (N/mm).
    fn penalty(&self) -> f64 {
        PENALTY_FACTOR * self.solid.material.elastic.young() * self.layer
    }

    /// The material law and its parameters.
    pub fn material(&self) -> Material {
        self.solid.material
    }

    /// Takes new material parameters (the law stays): the linear law reassembles and
    /// refactorizes; a finite-strain law solves the next step with them. With displacement
    /// loading the equilibrium does not depend on E, but on ν it does.
    pub fn set_material(&mut self, material: Material) -> Result<(), SceneError> {
        if material != self.solid.material {
            self.solid.material = material;
            self.assemble_linear()?;
        }
        Ok(())
    }

    /// Changes `max_increment` for the next finite-strain solves.
    pub fn set_max_increment(&mut self, max_increment: f64) -> Result<(), SceneError> {
        if let Solver::Newton(n) = &mut self.solver {
            let settings = Settings {
                max_increment,
                ..n.settings()
            };
            n.set_settings(settings)?;
        }
        Ok(())
    }

    /// Solves for the pull (mm) and the press force (N) at the scalpel position. With flank
    /// contact: solve, search the flanks, and while the set of held nodes changes, solve
    /// again with the new springs (at most `CONTACT_ITERATIONS` solves; a set that comes
    /// back is a cycle and an error), then linearize the springs again where they hold
    /// ([`Self::settle`]; where that fails, the set's first answer stays). A load change
    /// that leaves the flanks through each other (beyond the contact's small-sliding range)
    /// or whose set of held nodes cycles or does not settle is retried from the last
    /// equilibrium in 2, 4, … up to `CONTACT_PARTS` equal parts, the springs updated after
    /// each. On error the last equilibrium stays.
    pub fn solve(
        &mut self,
        g: &Geometry,
        pull: f64,
        press: f64,
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        if let Solver::Newton(n) = &self.solver {
            let (change, max_increment) = ((pull - self.load.0).abs(), n.settings().max_increment);
            let increments = (change / max_increment).ceil();
            if increments > MAX_INCREMENTS {
                return Err(SceneError::TooManyIncrements {
                    input: "pull",
                    change,
                    max_increment,
                    increments,
                    limit: MAX_INCREMENTS,
                });
            }
        }
        self.saved.save(&self.u, &self.internal);
        let (load, held) = (self.load, self.contact.as_ref().map(FlankContact::held));
        let mut result = self.settle(g, pull, press, scalpel_x);
        let mut parts = 2;
        while matches!(
            result,
            Err(SceneError::Slid { .. } | SceneError::NotConverged { .. })
        ) && parts <= CONTACT_PARTS
        {
            self.back(Saved::Solve, g, load, &held, scalpel_x)?;
            result = (1..=parts).try_for_each(|k| {
                let s = k as f64 / parts as f64;
                let at = |from: f64, to: f64| from + s * (to - from);
                self.settle(g, at(load.0, pull), at(load.1, press), scalpel_x)
            });
            parts *= 2;
        }
        if result.is_err() {
            self.back(Saved::Solve, g, load, &held, scalpel_x)?;
        }
        result
    }

    /// Back to a saved equilibrium with its springs `held` under `load`: displacements,
    /// internal forces, contact, loads and the solver. Undoing a solve also undoes what its
    /// settles fell back to; going back to a settled set is the fallback.
    fn back(
        &mut self,
        saved: Saved,
        g: &Geometry,
        load: (f64, f64),
        held: &Option<Held>,
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        let from = match saved {
            Saved::Solve => &self.saved,
            Saved::Settled => &self.settled,
        };
        self.u.copy_from_slice(&from.u);
        self.internal.copy_from_slice(&from.internal);
        if let (Some(c), Some(held)) = (&mut self.contact, held) {
            c.hold(held);
        }
        self.fell_back = saved == Saved::Settled;
        self.restart(g, load, scalpel_x)
    }

    /// After a failed solve: the loads, the springs and the solver's state back to `u`
    /// under `load` (pull, press).
    fn restart(
        &mut self,
        g: &Geometry,
        load: (f64, f64),
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        self.load = load;
        self.set_loads(g, load.0, load.1, scalpel_x);
        match &mut self.solver {
            Solver::Newton(n) => n.restart(&self.prescribed, &self.f),
            Solver::Linear { .. } => self.factorize()?,
        }
        Ok(())
    }

    /// The external forces `f` of the press and the prescribed values of the pull.
    fn set_loads(&mut self, g: &Geometry, pull: f64, press: f64, scalpel_x: f64) {
        self.f.fill(0.0);
        if press > 0.0 {
            self.top
                .press_load(self.solid.nodes(), g, press, scalpel_x, &mut self.f);
        }
        for &n in &self.pulled {
            self.prescribed[3 * n + 1] = pull;
        }
    }

    /// Equilibrium under (pull, press) with the contact set settled ([`Self::settle_set`])
    /// and its springs linearized where they hold ([`Self::relinearize`]); where that does
    /// not converge, the settled set's answer with the springs linearized where their nodes
    /// were caught stays. A node left deeper than the small-sliding limit is an error.
    fn settle(
        &mut self,
        g: &Geometry,
        pull: f64,
        press: f64,
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        self.set_loads(g, pull, press, scalpel_x);
        let mut solves = CONTACT_ITERATIONS;
        self.settle_set(&mut solves)?;
        self.load = (pull, press);
        let Some(c) = &self.contact else {
            return Ok(());
        };
        if !c.active.is_empty() {
            let held = Some(c.held());
            self.settled.save(&self.u, &self.internal);
            if self.relinearize().is_err() {
                self.back(Saved::Settled, g, (pull, press), &held, scalpel_x)?;
            }
        }
        self.within_sliding()
    }

    /// A node left behind a flank facet deeper than the small-sliding limit is an error.
    fn within_sliding(&self) -> Result<(), SceneError> {
        let Some(c) = &self.contact else {
            return Ok(());
        };
        let limit = SLIDING_LIMIT * self.layer;
        match c.deepest {
            Some(node) if c.penetration > limit => Err(SceneError::Slid {
                node,
                depth: c.penetration,
                limit,
            }),
            _ => Ok(()),
        }
    }

    /// Solves, searches the flanks and re-solves with the springs found until the set of
    /// held nodes repeats, at most `solves` solves (counted down; a set that comes back is
    /// a cycle and an error).
    fn settle_set(&mut self, solves: &mut usize) -> Result<(), SceneError> {
        let mut seen: Vec<Vec<usize>> = Vec::new();
        loop {
            if *solves == 0 {
                return Err(SceneError::NotConverged {
                    what: "the flank contact's active set",
                    iterations: seen.len(),
                });
            }
            *solves -= 1;
            self.equilibrium()?;
            let Some(c) = &mut self.contact else {
                return Ok(());
            };
            let springs = c.detect(self.solid.nodes(), &self.u);
            if c.same_as_active(&springs) {
                return Ok(());
            }
            let held: Vec<usize> = springs.iter().map(|s| s.node).collect();
            if seen.contains(&held) {
                return Err(SceneError::NotConverged {
                    what: "the flank contact's active set (it cycles)",
                    iterations: seen.len(),
                });
            }
            seen.push(held);
            c.active = springs;
            self.factorize()?;
        }
    }

    /// Linearizes the held springs again at the present state and settles the set anew,
    /// until the springs are linearized where they hold ([`FlankContact::linearized_alike`]):
    /// the answer is then the same whatever state the springs were first linearized at.
    /// At most [`RELINEARIZATION_SOLVES`] solves in all; a spring on a degenerate facet, or
    /// a node left deeper than the small-sliding limit, is an error too.
    fn relinearize(&mut self) -> Result<(), SceneError> {
        let mut solves = RELINEARIZATION_SOLVES;
        loop {
            let Some(c) = &mut self.contact else {
                return Ok(());
            };
            let springs =
                c.relinearized(self.solid.nodes(), &self.u)
                    .ok_or(SceneError::NotConverged {
                        what: "the flank springs' linearization (a degenerate facet)",
                        iterations: 0,
                    })?;
            if c.linearized_alike(&springs, &self.u) {
                return self.within_sliding();
            }
            c.active = springs;
            self.factorize()?;
            self.settle_set(&mut solves)
                .map_err(|_| SceneError::NotConverged {
                    what: "the flank springs' linearization",
                    iterations: RELINEARIZATION_SOLVES,
                })?;
        }
    }

    /// The equilibrium for the prescribed values and `f` with the current springs.
    fn equilibrium(&mut self) -> Result<(), SceneError> {
        let penalty = self.penalty();
        match &mut self.solver {
            Solver::Linear { statics, k, k_base } => {
                self.loads.copy_from_slice(&self.f);
                if let Some(c) = &self.contact {
                    c.add_loads(penalty, &mut self.loads);
                }
                self.u.copy_from_slice(&self.prescribed);
                statics.solve(self.asm.matrix(k), &self.loads, &mut self.u);
                self.internal.fill(0.0);
                mul_add(self.asm.matrix(k_base), &self.u, 1.0, &mut self.internal);
            }
            Solver::Newton(n) => {
                let mut eq = Equilibrium {
                    solid: &self.solid,
                    asm: &self.asm,
                    contact: self.contact.as_ref(),
                    penalty,
                };
                let report = n.solve(&mut eq, &mut self.u, &self.prescribed, &self.f)?;
                let w = &mut self.work;
                w.factorizations += report.factorizations as u64;
                w.increments += report.iterations.len() as u64;
                w.iterations += report.iterations.iter().sum::<usize>() as u64;
                w.assembly += report.assembly;
                w.factorization += report.factorization;
                w.solve += report.solve;
                self.internal.copy_from_slice(n.internal_forces());
            }
        }
        Ok(())
    }
}

/// The node lists of the solid's elements, then the contact's (the assembler's elements).
fn elements_of<'a>(solid: &'a Solid, contact: Option<&'a FlankContact>) -> Vec<&'a [usize]> {
    let mut elements = solid.connectivity();
    if let Some(c) = contact {
        elements.extend(c.elements.iter().map(|e| e.as_slice()));
    }
    elements
}

/// The nodes on the cut plane that the cut left shared (crack front and uncut part).
fn shared_on_cut(mesh: &Mesh3d, y_cut: f64, flank_pairs: &[(usize, usize)]) -> Vec<usize> {
    let on_flank: std::collections::HashSet<usize> =
        flank_pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    (0..mesh.nodes().len())
        .filter(|n| mesh.nodes()[*n][1] == y_cut && !on_flank.contains(n))
        .collect()
}

fn find_node(nodes: &[[f64; 3]], at: [f64; 3]) -> Result<usize, SceneError> {
    nodes
        .iter()
        .position(|p| (0..3).all(|d| (p[d] - at[d]).abs() <= 1e-9 * (1.0 + at[d].abs())))
        .ok_or_else(|| SceneError::Config(format!("no node at {at:?}")))
}

/// Every connected body must touch the clamped face, else it would float.
fn check_supported(mesh: &Mesh3d, clamped: &[usize]) -> Result<(), SceneError> {
    let comp = cut::node_components(mesh);
    let supported: std::collections::HashSet<usize> = clamped.iter().map(|&n| comp[n]).collect();
    let mut bodies: Vec<usize> = comp.clone();
    bodies.sort_unstable();
    bodies.dedup();
    if let Some(node) = comp.iter().position(|c| !supported.contains(c)) {
        return Err(SceneError::Separated {
            bodies: bodies.len(),
            node,
            at: mesh.nodes()[node],
        });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::cutblock::CutBlock;
    use crate::scene::Scene;

    /// ‖f_int(u) − f‖ on the free dofs at the topology's displacements.
    fn residual(t: &Topology) -> f64 {
        let mut r = vec![0.0; t.u.len()];
        t.solid.add_internal(&t.asm, &t.u, &mut r, None).unwrap();
        for (r, f) in r.iter_mut().zip(&t.f) {
            *r -= f;
        }
        for &d in t.solver.dirichlet().constrained() {
            r[d] = 0.0;
        }
        newton::norm_of(&r)
    }

    /// The residuals at the start of an advance of the blade to 38 mm at a 10 mm pull
    /// (neo-Hookean tet4) after equilibria at 38 − 3δ, 38 − 2δ and 38 − δ mm (one cell):
    /// extrapolated from them, and the last carried onto the new mesh.
    fn starts(step: f64) -> (f64, f64) {
        let mut s = CutBlock::new();
        s.initialize(0.0).unwrap();
        s.set("pull", 10.0).unwrap();
        for k in [3.0, 2.0, 1.0] {
            s.set("scalpel_x", 38.0 - k * step).unwrap();
            s.do_step(0.0, 1.0).unwrap();
        }
        let settings = s.settings(Tetrahedron::Tet4);
        let (g, old) = (s.geometry.as_ref().unwrap(), s.topology.as_mut().unwrap());
        assert_eq!(old.path.len(), 2);
        let start = |old: &Topology| {
            let (m, kind) = (old.material(), Tetrahedron::Tet4);
            let mut t = Topology::build(g, 38.0, m, kind, settings, Some(old), None).unwrap();
            assert!(Arc::ptr_eq(&t.asm, &old.asm), "the same pattern");
            assert!(t.start_from(g, old, 38.0).unwrap());
            residual(&t)
        };
        let extrapolated = start(old);
        old.path.clear();
        (extrapolated, start(old))
    }

    /// The quadratic through three equilibria follows the path to third order in the step
    /// (the mesh moves affinely with the blade, so each node's displacement is a smooth
    /// function of it), the last equilibrium carried onto the new mesh to first order (it
    /// lags a step behind around the tip): halving δ from 0.5 to 0.25 mm divides the
    /// extrapolated start's residual by about 2³ and the carried one's by about 2 (measured
    /// 2026-12-01: orders 3.29 and 0.99; at δ = 1 mm 8.8e-3 against 0.135 N).
    #[test]
    fn an_advance_within_a_cell_starts_from_its_path_extrapolated() {
        let (coarse, fine) = (starts(0.5), starts(0.25));
        let order = |a: f64, b: f64| (a / b).log2();
        let (extrapolated, carried) = (order(coarse.0, fine.0), order(coarse.1, fine.1));
        assert!((extrapolated - 3.0).abs() <= 0.5, "order {extrapolated:.2}");
        assert!((carried - 1.0).abs() <= 0.25, "order {carried:.2}");
        let (e, c) = starts(1.0);
        assert!(
            e < 0.1 * c,
            "at 1 mm: extrapolated {e:.3e}, carried {c:.3e}"
        );
    }
}
