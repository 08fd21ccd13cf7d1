//! The cut-block scene (seed 002): a silicone block of tetrahedra (cubes of 6 tetrahedra,
//! split along x so that the cells the sliding grid makes thin at the end faces do not
//! lock, where seed 002 §3.1 had 5 per cube; linear or quadratic), clamped at y = 0 and
//! pulled in y at y = L (§2.1), pressed by a force on the top surface at the scalpel tip,
//! with a straight incision in the plane y = y_cut from the top down to a depth, growing in
//! x with the scalpel (§3.4):
//! it ends where the blade is (a node plane is put there) and never heals — withdrawing the
//! blade leaves it as long as the furthest the blade has been.
//! Quasi-static: every step solves equilibrium for the current inputs (§3.3), with a linear
//! (small-strain) or a finite-strain material law (neo-Hookean, St. Venant–Kirchhoff).
//!
//! What a step costs depends on what changed. Linear law: loads only → one solve with the
//! existing factorization; E or ν → reassembly and numeric refactorization. Finite strain:
//! Newton's method from the last equilibrium in increments of at most `max_increment` of
//! pull. Either law: the cut grew → a new mesh, pattern, symbolic analysis; a finite-strain
//! law then starts Newton from the last equilibrium carried onto the new mesh.
//!
//! Where the model stops being valid, it says so once per run (see
//! [`Scene::take_warnings`]): the linear law beyond 5 % principal strain
//! ([`super::SMALL_STRAIN_LIMIT`]), a cut so close to a node plane's
//! neighbours that the graded layers beside it differ by more than a factor 4, and closed
//! flanks whose contact springs could not be linearized again where they hold or that a
//! press acts on (the answer then may depend on the loading history; see `contact.rs`).

mod contact;
mod geometry;
mod outputs;
mod profiles;
mod topology;
mod transfer;
mod variables;

pub use geometry::SNAP;
use geometry::{Geometry, Options, Strategy, Support};
use outputs::Outputs;
pub use topology::MAX_INCREMENTS;
use topology::{Spare, Topology, TopologyState};
use variables::*;

use super::{
    check_step, megabytes, Scene, SceneError, SceneState, Values, ValuesState, Variable,
    SMALL_STRAIN_LIMIT,
};
use crate::assembly::solid::{Solid, Tetrahedron};
use crate::budget;
use crate::element::{Elastic, Law, Material};
use crate::solve::newton::Settings;
use std::time::Duration;

/// What the scene is, in one line (the FMUs' `description`).
pub const DESCRIPTION: &str = "3D tetrahedral silicone block (tet4 or tet10; linear, \
neo-Hookean or St. Venant-Kirchhoff) with a scalpel incision, pulled and pressed, cut flanks \
in contact; reaction force, cut opening, bottom lift and laser profiles (seed 002)";

/// Laser-profile stations: y = 0, 0.5, …, 90 mm in lab coordinates (the default block
/// pulled by up to 10 mm).
pub const PROFILE_STATIONS: usize = 181;
/// Spacing of the profile stations (mm).
pub const PROFILE_STEP: f64 = 0.5;
/// The scanner lines x = 25, 50, 75 mm (seed 002 §3.5, Fig. 4.7).
pub const PROFILE_LINES: [f64; 3] = [25.0, 50.0, 75.0];

/// The scene. Build with [`CutBlock::new`], set parameters, `initialize`, then step.
#[derive(Debug)]
pub struct CutBlock {
    values: Values,
    geometry: Option<Geometry>,
    topology: Option<Topology>,
    /// The last replaced topology's solver, for the next of its pattern.
    spare: Option<Spare>,
    /// How far the incision reaches: the furthest the blade has been, clamped to the block
    /// (the mesh's front is this within [`SNAP`] h of an end face, taken as the face).
    reached: f64,
    outputs: Outputs,
    work: Work,
    /// Warnings not yet taken, and whether the strain, the contact and the press warnings
    /// were given in this run.
    warnings: Vec<String>,
    warned_strain: bool,
    warned_contact: bool,
    warned_press: bool,
}

/// The cut block's state (see [`SceneState`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State {
    values: ValuesState,
    initialized: bool,
    topology: Option<TopologyState>,
    /// Absent in states saved before it: the topology's front.
    #[serde(default)]
    reached: Option<f64>,
    work: Work,
    warnings: Vec<String>,
    warned_strain: bool,
    #[serde(default)]
    warned_contact: bool,
    #[serde(default)]
    warned_press: bool,
}

/// What the scene has done so far: how often it rebuilt the topology (and of those, made a
/// new pattern and symbolic analysis), refactorized and solved, and for the finite-strain
/// laws the Newton increments and iterations and where their time went.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Work {
    pub topology_builds: u64,
    pub analyses: u64,
    pub factorizations: u64,
    pub solves: u64,
    pub increments: u64,
    pub iterations: u64,
    pub assembly: Duration,
    pub factorization: Duration,
    pub solve: Duration,
}

impl Work {
    fn add(self, other: Work) -> Work {
        Work {
            topology_builds: self.topology_builds + other.topology_builds,
            analyses: self.analyses + other.analyses,
            factorizations: self.factorizations + other.factorizations,
            solves: self.solves + other.solves,
            increments: self.increments + other.increments,
            iterations: self.iterations + other.iterations,
            assembly: self.assembly + other.assembly,
            factorization: self.factorization + other.factorization,
            solve: self.solve + other.solve,
        }
    }
}

/// Newton keeps its factorization while each iteration reduces the residual at least 4
/// times (the solver's default asks for 10). On the default tet10 block a factorization
/// costs about 430 ms and an iteration on a kept one about 30 ms, and after a blade advance
/// the iterations on the first tangent contract by 0.02–0.16: with 10 most advances
/// refactorized once more. Measured (`cargo bench -p models --bench cutblock`, one run,
/// BENCHMARKS.md): a 1 mm tet10 advance 1.28 s → 0.95 s, the 0 → 10 mm tet10 pull
/// 5.94 s → 5.19 s.
const REUSE_CONTRACTION: f64 = 0.25;

/// For tet10 the factorization costs more iterations (about 15 against about 5 for tet4),
/// and the Anderson-accelerated iterations on a kept one contract faster than the plain
/// ones the 0.25 above was chosen for: a tet10 factorization is kept while each iteration
/// halves the residual. Measured (`cargo run --release -p models --example cutblock_pull --
/// neo-hookean ELEMENT REFINE`, the full cut pulled 0 → 10 mm in 4 increments, one run
/// each, 2026-11-27, both with the accelerated iterations): tet10 6 → 4 factorizations,
/// 31 → 45 iterations, 3.71 → 3.08 s; at 1.5× the cells 6 → 5, 34 → 48, 22.6 → 17.7 s;
/// tet4 with 0.5 instead of 0.25 would
/// go 112 → 133 ms (4 → 3 factorizations, 31 → 41 iterations).
const REUSE_CONTRACTION_TET10: f64 = 0.5;

impl Default for CutBlock {
    fn default() -> Self {
        Self::new()
    }
}

impl CutBlock {
    /// A scene with the default (seed 002) configuration, not yet initialized.
    pub fn new() -> Self {
        Self {
            values: Values::new(table()),
            geometry: None,
            topology: None,
            spare: None,
            reached: 0.0,
            outputs: Outputs::default(),
            work: Work::default(),
            warnings: Vec::new(),
            warned_strain: false,
            warned_contact: false,
            warned_press: false,
        }
    }

    /// What the scene has done so far (all topologies).
    pub fn work(&self) -> Work {
        let current = self.topology.as_ref().map(|t| t.work);
        self.work.add(current.unwrap_or_default())
    }

    /// Sets a real variable by name (convenience for tests and the harness).
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), SceneError> {
        let vr = self.lookup(name)?;
        self.set_real(vr, &[value])
    }

    /// Reads a scalar real variable by name.
    pub fn get(&mut self, name: &str) -> Result<f64, SceneError> {
        let vr = self.lookup(name)?;
        let mut x = [0.0];
        self.get_real(vr, &mut x)?;
        Ok(x[0])
    }

    /// The current solid (nodes, elements, material) and nodal displacements (all dofs),
    /// for plots and files.
    pub fn field(&self) -> Option<(&Solid, &[f64])> {
        self.topology.as_ref().map(|t| (&t.solid, t.u.as_slice()))
    }

    /// The top-surface heights (mm) along the scan line x = `line` at the lab-frame stations
    /// `ys` (NaN where there is no surface), read as the `profile_x*` outputs read theirs —
    /// for scanners at other lines than x = 25, 50, 75 mm.
    pub fn profile(&self, line: f64, ys: &[f64]) -> Result<Vec<f64>, SceneError> {
        let t = self
            .topology
            .as_ref()
            .ok_or_else(|| SceneError::NotInitialized {
                name: "profile".into(),
            })?;
        let mut heights = vec![0.0; ys.len()];
        let nodes = t.solid.nodes();
        let sections = &mut Default::default();
        t.top.profile(
            nodes,
            &t.u,
            line,
            ys.iter().copied(),
            &mut heights,
            sections,
        );
        Ok(heights)
    }

    fn material(&self) -> Result<Material, SceneError> {
        let elastic = Elastic::new(
            "cutblock",
            self.values.real(YOUNG),
            self.values.real(POISSON),
        )?;
        Ok(Material::new(
            Law::parse(self.values.string(MATERIAL)?)?,
            elastic,
        ))
    }

    fn settings(&self, kind: Tetrahedron) -> Settings {
        Settings {
            max_increment: self.values.real(MAX_INCREMENT),
            reuse_contraction: match kind {
                Tetrahedron::Tet4 => REUSE_CONTRACTION,
                Tetrahedron::Tet10 => REUSE_CONTRACTION_TET10,
            },
            ..Settings::default()
        }
    }

    /// Once per run: the linear law's largest principal strain beyond its limit.
    fn check_strain(&mut self) {
        let Some(t) = &self.topology else {
            return;
        };
        if self.warned_strain || t.material().law != Law::Linear {
            return;
        }
        if let Some(strain) = outputs::strain_beyond(t, SMALL_STRAIN_LIMIT) {
            self.warned_strain = true;
            self.warnings.push(format!(
                "the largest principal strain is {:.1} %, beyond the {:.0} % the linear \
                 (small-strain) material is valid for: use material = \"neo-hookean\"",
                100.0 * strain,
                100.0 * SMALL_STRAIN_LIMIT
            ));
        }
    }

    /// Once per run each: an answer of the flank contact that may depend on the loading
    /// history — a solve whose springs stayed linearized where their nodes were caught, or
    /// a press on closed flanks (one load step or two end apart there:
    /// docs/theory/cutblock.md).
    fn check_contact(&mut self, press: f64) {
        let Some(t) = &mut self.topology else {
            return;
        };
        let fell_back = std::mem::take(&mut t.fell_back);
        let pressed = press > 0.0 && t.contact.as_ref().is_some_and(|c| !c.active.is_empty());
        if fell_back && !self.warned_contact {
            self.warned_contact = true;
            self.warnings.push(
                "the flank contact's springs could not be linearized again where they hold \
                 (the re-linearization did not settle, or let a node slide beyond the \
                 small-sliding range): this answer may depend on the loading history (its \
                 springs are linearized where their nodes were caught; on the tested paths \
                 that left reactions up to 8e-8 apart)"
                    .into(),
            );
        }
        if pressed && !self.warned_press {
            self.warned_press = true;
            self.warnings.push(format!(
                "the press ({press} N) acts on closed flanks: this answer may depend on the \
                 loading history (on the default block, compressed and pressed in one step \
                 or in two, the openings ended up to 0.3 mm and the reactions up to 4 % \
                 apart)"
            ));
        }
    }

    fn geometry_from_values(&self) -> Result<Geometry, SceneError> {
        let whole = |vr: u32| -> Result<usize, SceneError> {
            let x = self.values.real(vr);
            if x.fract() != 0.0 {
                return Err(SceneError::Config(format!(
                    "`{}` must be a whole number, got {x}",
                    self.values.variable(vr)?.name
                )));
            }
            Ok(x as usize)
        };
        Geometry::new(
            SIZE.map(|vr| self.values.real(vr)),
            [whole(CELLS[0])?, whole(CELLS[1])?, whole(CELLS[2])?],
            self.values.real(Y_CUT),
            self.values.real(DEPTH),
            self.values.real(PRESS_RADIUS),
            self.values.real(MESH_GRADING),
            Options {
                strategy: Strategy::parse(self.values.string(STRATEGY)?)?,
                support: Support::parse(self.values.string(SUPPORT)?)?,
                contact: self.values.string(CONTACT)? == "penalty",
            },
        )
    }

    /// Brings the topology up to date with the scalpel position and the material, then
    /// solves for the current loads.
    fn solve(&mut self) -> Result<(), SceneError> {
        let geometry = self
            .geometry
            .as_ref()
            .ok_or_else(|| SceneError::NotInitialized {
                name: "do_step".into(),
            })?;
        let material = self.material()?;
        let kind = Tetrahedron::parse(self.values.string(ELEMENT)?)?;
        let settings = self.settings(kind);
        let (pull, press, scalpel) = (
            self.values.real(PULL),
            self.values.real(PRESS),
            self.values.real(SCALPEL),
        );
        // The incision never heals: it reaches as far as the blade has been.
        let reached = geometry.reach(scalpel).max(self.reached);
        let front = geometry.front(reached);
        match &mut self.topology {
            Some(t) if t.front == front => {
                t.set_material(material)?;
                t.set_max_increment(settings.max_increment)?;
                t.solve(geometry, pull, press, scalpel)?;
            }
            slot => {
                // Built and solved aside: on error the last good topology and state stay.
                let limit = megabytes(self.values.real(MEMORY_LIMIT));
                let spare = self.spare.take();
                let mut built = budget::within(limit, || {
                    Topology::build(
                        geometry,
                        front,
                        material,
                        kind,
                        settings,
                        slot.as_ref(),
                        spare,
                    )
                })?;
                // A finite-strain law starts from the last equilibrium carried onto the
                // new mesh, and from the unloaded block if that does not converge.
                let warm = match slot.as_ref() {
                    Some(old) => built.start_from(geometry, old, scalpel)?,
                    None => false,
                };
                if let Err(e) = built.solve(geometry, pull, press, scalpel) {
                    if !warm {
                        return Err(e);
                    }
                    built.unload(geometry, scalpel)?;
                    built.solve(geometry, pull, press, scalpel)?;
                }
                if let Some(old) = slot.replace(built) {
                    self.work = self.work.add(old.work);
                    self.spare = slot.as_ref().and_then(|new| old.into_spare(new));
                }
                self.work.topology_builds += 1;
            }
        }
        self.reached = reached;
        self.work.solves += 1;
        self.outputs.invalidate();
        self.check_strain();
        self.check_contact(press);
        Ok(())
    }
}

/// Runs `solve` on one of rayon's threads, the caller waiting asleep (on a thread of the
/// pool already: in place). After a parallel element assembly rayon's idle threads spin for
/// a while before they sleep; a solve on a thread of its own would do its factorizations and
/// solves sharing the cores with all of them, from inside the pool with one fewer (measured
/// on 2 cores: blade advances 8–13 % faster, BENCHMARKS.md). Solves of scenes stepped from
/// several threads share the one pool: a thread waiting inside one solve may run another
/// scene's solve before it goes on, so their steps' latencies are coupled (their total
/// work is not).
fn in_pool<R: Send>(solve: impl FnOnce() -> R + Send) -> R {
    rayon::join(solve, || ()).0
}

impl Scene for CutBlock {
    fn variables(&self) -> &[Variable] {
        self.values.table()
    }

    fn set_real(&mut self, vr: u32, values: &[f64]) -> Result<(), SceneError> {
        self.values.set_real(vr, values)?;
        if vr == YOUNG || vr == POISSON {
            // Checked here so that a bad combination is refused at once, not at the step.
            self.material()?;
        }
        Ok(())
    }

    fn get_real(&mut self, vr: u32, out: &mut [f64]) -> Result<(), SceneError> {
        if self.values.read(vr, out)? {
            return Ok(());
        }
        let (Some(geometry), Some(topology)) = (&self.geometry, &self.topology) else {
            return Err(SceneError::NotInitialized {
                name: self.values.variable(vr)?.name.clone(),
            });
        };
        self.outputs
            .read(geometry, topology, self.reached, vr - FIRST_OUTPUT, out);
        Ok(())
    }

    fn set_string(&mut self, vr: u32, value: &str) -> Result<(), SceneError> {
        match vr {
            STRATEGY => Strategy::parse(value).map(drop)?,
            SUPPORT => Support::parse(value).map(drop)?,
            CONTACT if !matches!(value, "penalty" | "none") => {
                return Err(SceneError::Config(format!(
                    "contact `{value}`: use `penalty` or `none`"
                )));
            }
            MATERIAL => Law::parse(value).map(drop)?,
            ELEMENT => Tetrahedron::parse(value).map(drop)?,
            _ => {}
        }
        self.values.set_string(vr, value)
    }

    fn get_string(&self, vr: u32) -> Result<String, SceneError> {
        self.values.string(vr).map(str::to_string)
    }

    /// Quasi-static: the start time does not matter.
    fn initialize(&mut self, _start_time: f64) -> Result<(), SceneError> {
        let limit = megabytes(self.values.real(MEMORY_LIMIT));
        let geometry = budget::within(limit, || self.geometry_from_values())?;
        self.warnings.extend(geometry.warnings.iter().cloned());
        self.geometry = Some(geometry);
        (self.topology, self.spare, self.reached) = (None, None, 0.0);
        self.warned_strain = false;
        self.warned_contact = false;
        self.warned_press = false;
        in_pool(|| self.solve())?;
        self.values.freeze();
        Ok(())
    }

    fn take_warnings(&mut self) -> Vec<String> {
        std::mem::take(&mut self.warnings)
    }

    fn save(&self) -> SceneState {
        SceneState::CutBlock(Box::new(State {
            values: self.values.save(),
            initialized: self.geometry.is_some(),
            topology: self.topology.as_ref().map(Topology::checkpoint),
            reached: Some(self.reached),
            work: self.work,
            warnings: self.warnings.clone(),
            warned_strain: self.warned_strain,
            warned_contact: self.warned_contact,
            warned_press: self.warned_press,
        }))
    }

    /// Built aside from the saved values (geometry, then the topology with its saved
    /// state) and swapped in only when everything is built.
    fn restore(&mut self, state: &SceneState) -> Result<(), SceneError> {
        let SceneState::CutBlock(s) = state else {
            return Err(SceneError::Config(format!(
                "a state of the {} scene cannot be restored into the cut block",
                state.scene()
            )));
        };
        let mut values = self.values.clone();
        values.restore(&s.values)?;
        let scene = Self {
            values,
            ..Self::new()
        };
        let limit = megabytes(scene.values.real(MEMORY_LIMIT));
        let (geometry, topology) = if s.initialized {
            let geometry = budget::within(limit, || scene.geometry_from_values())?;
            let topology = match &s.topology {
                Some(t) => {
                    let kind = Tetrahedron::parse(scene.values.string(ELEMENT)?)?;
                    let settings = scene.settings(kind);
                    Some(budget::within(limit, || {
                        Topology::resume(&geometry, t, kind, settings)
                    })?)
                }
                None => None,
            };
            (Some(geometry), topology)
        } else {
            (None, None)
        };
        let reached = s
            .reached
            .unwrap_or_else(|| topology.as_ref().map_or(0.0, |t| t.front));
        *self = Self {
            geometry,
            topology,
            reached,
            work: s.work,
            warnings: s.warnings.clone(),
            warned_strain: s.warned_strain,
            warned_contact: s.warned_contact,
            warned_press: s.warned_press,
            ..scene
        };
        Ok(())
    }

    fn do_step(&mut self, _t: f64, h: f64) -> Result<(), SceneError> {
        check_step(h)?;
        in_pool(|| self.solve())
    }
}
