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

mod checkpoint;
mod contact;
mod equilibrium;
mod geometry;
mod outputs;
mod path;
mod profiles;
mod settle;
mod topology;
mod transfer;
mod variables;
mod work;

use checkpoint::TopologyState;
use equilibrium::{settings, Spare};
pub use geometry::SNAP;
use geometry::{Geometry, Options, Strategy, Support};
use outputs::Outputs;
pub use profiles::{PROFILE_LINES, PROFILE_STATIONS, PROFILE_STEP};
pub use settle::MAX_INCREMENTS;
use topology::Topology;
use variables::*;
pub use work::{Timing, Work};

use super::{
    check_step, megabytes, Inert, Scene, SceneError, SceneState, Values, ValuesState, Variable,
    SMALL_STRAIN_LIMIT,
};
use crate::assembly::tetrahedra::{Solid, Tetrahedron};
use crate::budget;
use crate::element::{Elastic, Law, Material};
use crate::error::ModelError;

/// What the scene is, in one line (the FMUs' `description`).
pub const DESCRIPTION: &str = "3D tetrahedral silicone block (tet4 or tet10; linear, \
neo-Hookean or St. Venant-Kirchhoff) with a scalpel incision, pulled and pressed, cut flanks \
in contact; reaction force, cut opening, bottom lift and laser profiles (seed 002)";

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
    /// Where the Newton solves of the replaced topologies spent their time.
    timing: Timing,
    /// Warnings not yet taken, and whether the strain, the contact and the press warnings
    /// were given in this run.
    warnings: Vec<String>,
    warned_strain: bool,
    warned_contact: bool,
    warned_press: bool,
    /// The parameters already warned of in this run for having no effect.
    inert: Inert,
}

/// A setting of the block's model: law, element, cubes along x, y and z and the mesh
/// grading β (the parameters `material`, `element`, `cells_*` and `mesh_grading`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    /// The material law (`material`).
    pub law: Law,
    /// The tetrahedron (`element`).
    pub element: Tetrahedron,
    /// Cubes along x, y and z (`cells_x`, `cells_y`, `cells_z`).
    pub cells: [f64; 3],
    /// β of the grading (`mesh_grading`; 1: uniform).
    pub grading: f64,
}

/// The accurate setting: neo-Hookean tet10 on 7 × 18 × 10 cubes graded with β = 2.25,
/// within 1 % (reaction), 3 % (bottom lift) and 0.1 mm (profile along x = 50 mm) of the
/// converged references at the seed's full cut and with the incision ending at 25, 49 and
/// 82 mm (the harness's `cut_speed_error::accurate`, whose test checks each figure;
/// docs/verification.md).
pub const ACCURATE: Setting = Setting {
    law: Law::NeoHookean,
    element: Tetrahedron::Tet10,
    cells: [7.0, 18.0, 10.0],
    grading: 2.25,
};

impl Setting {
    /// The setting the examples and benches name: `accurate` ([`ACCURATE`]), or a
    /// `material` (`linear`, `neo-hookean`, `stvk`) with an `element` on the scene's default
    /// cells and grading; an unknown name is an error naming it.
    pub fn named(material: &str, element: &str) -> Result<Self, SceneError> {
        if material == "accurate" {
            return Ok(ACCURATE);
        }
        let mut defaults = CutBlock::new();
        let [x, y, z, grading] =
            ["cells_x", "cells_y", "cells_z", "mesh_grading"].map(|n| defaults.get(n));
        Ok(Self {
            law: Law::parse(material)?,
            element: Tetrahedron::parse(element)?,
            cells: [x?, y?, z?],
            grading: grading?,
        })
    }

    /// The setting with its cells along each axis times `factor`.
    pub fn refined(self, factor: f64) -> Self {
        Self {
            cells: self.cells.map(|c| c * factor),
            ..self
        }
    }

    /// Sets the setting's parameters on `scene` (before `initialize`).
    pub fn apply(&self, scene: &mut CutBlock) -> Result<(), SceneError> {
        for (name, value) in [
            ("material", self.law.name()),
            ("element", self.element.name()),
        ] {
            let vr = scene.lookup(name)?;
            scene.set_string(vr, value)?;
        }
        for (name, cells) in ["cells_x", "cells_y", "cells_z"]
            .into_iter()
            .zip(self.cells)
        {
            scene.set(name, cells)?;
        }
        scene.set("mesh_grading", self.grading)
    }
}

/// The displacement (mm) of the largest nodal change along du/dν over which
/// [`CutBlock::poisson_sensitivity`] differences the heights: far above their round-off
/// (10⁻¹⁴ mm), far below the curvature of the surface.
pub const HEIGHT_STEP: f64 = 1e-5;

/// Derivatives in Poisson's ratio of the cut block's equilibrium
/// ([`CutBlock::poisson_sensitivity`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Sensitivity {
    /// ∂F/∂ν of the reaction force (N).
    pub reaction_force: f64,
    /// ∂h/∂ν of the heights along each scan line at the stations asked (mm; NaN where
    /// there is no surface).
    pub profiles: Vec<Vec<f64>>,
    /// du/dν (mm, all dofs of the present mesh).
    pub displacement: Vec<f64>,
    /// The iterations of the solve for du/dν (conjugate gradients; 1 for the linear law).
    pub iterations: usize,
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
    /// The parameters already warned of in this run for having no effect.
    #[serde(default)]
    inert: Inert,
}

/// The topology of an initialized scene; before initialization an error naming `what`.
fn built<'a>(topology: &'a Option<Topology>, what: &str) -> Result<&'a Topology, SceneError> {
    topology
        .as_ref()
        .ok_or_else(|| SceneError::NotInitialized { name: what.into() })
}

/// [`built`], to change.
fn built_mut<'a>(
    topology: &'a mut Option<Topology>,
    what: &str,
) -> Result<&'a mut Topology, SceneError> {
    topology
        .as_mut()
        .ok_or_else(|| SceneError::NotInitialized { name: what.into() })
}

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
            timing: Timing::default(),
            warnings: Vec::new(),
            warned_strain: false,
            warned_contact: false,
            warned_press: false,
            inert: Inert::default(),
        }
    }

    /// What the scene has done so far (all topologies).
    pub fn work(&self) -> Work {
        let current = self.topology.as_ref().map(|t| t.eq.work);
        self.work + current.unwrap_or_default()
    }

    /// Where the Newton solves' time went so far (all topologies; since the scene was made
    /// or restored: timings are not part of its state).
    pub fn timing(&self) -> Timing {
        let current = self.topology.as_ref().map(|t| t.eq.timing);
        self.timing + current.unwrap_or_default()
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
        self.topology
            .as_ref()
            .map(|t| (&t.solid, t.eq.u.as_slice()))
    }

    /// The top-surface heights (mm) along the scan line x = `line` at the lab-frame stations
    /// `ys` (NaN where there is no surface), read as the `profile_x*` outputs read theirs —
    /// for scanners at other lines than x = 25, 50, 75 mm.
    pub fn profile(&self, line: f64, ys: &[f64]) -> Result<Vec<f64>, SceneError> {
        let t = built(&self.topology, "profile")?;
        let mut heights = vec![0.0; ys.len()];
        let nodes = t.solid.nodes();
        let sections = &mut Default::default();
        t.top.profile(
            nodes,
            &t.eq.u,
            line,
            ys.iter().copied(),
            &mut heights,
            sections,
        );
        Ok(heights)
    }

    /// Where the next step's solve starts its iterations (the displacements of all dofs of
    /// the present mesh, its held ones taken at their prescribed values), if not from the
    /// last equilibrium: an equilibrium at a nearby ν moved along its derivative
    /// ([`Sensitivity::displacement`]) is a continuation in ν that converges in a few
    /// iterations. Finite-strain laws; a start that does not converge is dropped for the
    /// path from the last equilibrium, and a step that rebuilds the mesh ignores it. The
    /// answer is the same equilibrium to the solver's tolerance; the start is no part of
    /// the scene's state.
    pub fn start_next_from(&mut self, u: &[f64]) -> Result<(), SceneError> {
        let t = built_mut(&mut self.topology, "start_next_from")?;
        if u.len() != t.eq.u.len() {
            return Err(ModelError::SizeMismatch {
                name: "start_next_from",
                expected: t.eq.u.len(),
                got: u.len(),
            }
            .into());
        }
        t.eq.start = Some(u.to_vec());
        Ok(())
    }

    /// The derivatives in Poisson's ratio ν, at fixed E and loads, of the present
    /// equilibrium's reaction force and of its heights along the scan lines x = `lines` at
    /// the lab-frame stations `ys` (read as [`Self::profile`] reads them; NaN where there is
    /// no surface). du/dν by direct differentiation ([`Newton::sensitivity`]: the exact
    /// tangent's solve, preconditioned by the kept factorization); the reaction's from the
    /// internal forces' derivative; the heights' as central differences of the height
    /// read-out along du/dν (a geometric function of the displacements, differenced over
    /// [`HEIGHT_STEP`]). In E no solve is needed: with the pull prescribed the
    /// displacements do not depend on E, so ∂F/∂E = F/E and ∂h/∂E = 0.
    ///
    /// [`Newton::sensitivity`]: crate::solve::newton::Newton::sensitivity
    pub fn poisson_sensitivity(
        &mut self,
        lines: &[f64],
        ys: &[f64],
    ) -> Result<Sensitivity, SceneError> {
        let t = built_mut(&mut self.topology, "poisson_sensitivity")?;
        let n = t.eq.u.len();
        let (mut du, mut total) = (vec![0.0; n], vec![0.0; n]);
        let (on, eq) = t.parts();
        let iterations = eq.poisson_sensitivity(&on, &mut du, &mut total)?;
        let reaction_force = t.pulled.iter().map(|n| total[3 * n + 1]).sum();
        let largest = du.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let epsilon = if largest > 0.0 {
            HEIGHT_STEP / largest
        } else {
            0.0
        };
        let along = |sign: f64| -> Vec<f64> {
            t.eq.u
                .iter()
                .zip(&du)
                .map(|(u, d)| u + sign * epsilon * d)
                .collect()
        };
        let (plus, minus) = (along(1.0), along(-1.0));
        let nodes = t.solid.nodes();
        let sections = &mut Default::default();
        let mut heights = |u: &[f64], line: f64| {
            let mut h = vec![0.0; ys.len()];
            t.top
                .profile(nodes, u, line, ys.iter().copied(), &mut h, sections);
            h
        };
        let profiles = lines
            .iter()
            .map(|&line| {
                let (hi, lo) = (heights(&plus, line), heights(&minus, line));
                hi.iter()
                    .zip(&lo)
                    .map(|(hi, lo)| {
                        if epsilon > 0.0 {
                            (hi - lo) / (2.0 * epsilon)
                        } else {
                            0.0 * hi
                        }
                    })
                    .collect()
            })
            .collect();
        Ok(Sensitivity {
            reaction_force,
            profiles,
            displacement: du,
            iterations,
        })
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
        let fell_back = std::mem::take(&mut t.eq.fell_back);
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
        let settings = settings(kind, self.values.real(MAX_INCREMENT));
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
                t.eq.set_max_increment(settings.max_increment)?;
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
                built.solve_after(geometry, slot.as_ref(), pull, press, scalpel)?;
                if let Some(old) = slot.replace(built) {
                    self.work = self.work + old.eq.work;
                    self.timing = self.timing + old.eq.timing;
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

/// Why the parameter `vr` cannot act under the present values, if it cannot: Newton's load
/// increment with the linear law (which solves each step at once), the cut's strategy on a
/// block without a cut.
fn inert(values: &Values, vr: u32) -> Option<&'static str> {
    if vr == MAX_INCREMENT && values.string(MATERIAL).is_ok_and(|m| m == "linear") {
        return Some(
            "the linear law solves each step at once; max_increment acts with the finite-strain \
             laws",
        );
    }
    if vr == STRATEGY && values.real(DEPTH) == 0.0 {
        return Some("cut_depth = 0: the block has no cut");
    }
    None
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

    /// A change after initialization of a parameter that cannot act there is warned of,
    /// once per run.
    fn set_real(&mut self, vr: u32, values: &[f64]) -> Result<(), SceneError> {
        let old = self.values.real(vr);
        self.values.set_real(vr, values)?;
        if vr == YOUNG || vr == POISSON {
            // Checked here so that a bad combination is refused at once, not at the step.
            self.material()?;
        }
        if self.geometry.is_some() && old != values[0] {
            let reason = inert(&self.values, vr);
            self.warnings
                .extend(self.inert.check(&self.values, vr, reason));
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
                return Err(ModelError::unknown("contact", value, "penalty or none").into());
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
    fn check(&self) -> Result<(), SceneError> {
        self.geometry_from_values()?;
        self.material()?;
        Tetrahedron::parse(self.values.string(ELEMENT)?)?;
        Ok(())
    }

    fn initialize(&mut self, _start_time: f64) -> Result<(), SceneError> {
        self.check()?;
        let limit = megabytes(self.values.real(MEMORY_LIMIT));
        let geometry = budget::within(limit, || self.geometry_from_values())?;
        self.warnings.extend(geometry.warnings.iter().cloned());
        self.geometry = Some(geometry);
        (self.topology, self.spare, self.reached) = (None, None, 0.0);
        self.warned_strain = false;
        self.warned_contact = false;
        self.warned_press = false;
        let inert = self.inert.check_all(&self.values, inert);
        self.warnings.extend(inert);
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
            inert: self.inert.clone(),
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
                    let settings = settings(kind, scene.values.real(MAX_INCREMENT));
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
            inert: s.inert.clone(),
            ..scene
        };
        Ok(())
    }

    fn do_step(&mut self, t: f64, h: f64) -> Result<(), SceneError> {
        check_step(t, h)?;
        in_pool(|| self.solve())
    }
}
