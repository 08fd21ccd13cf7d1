//! The cut-block scene (seed 002): a silicone block of linear tetrahedra (mirrored cubes,
//! 5 tetrahedra each, §3.1), clamped at y = 0 and pulled in y at y = L (§2.1), pressed by a
//! force on the top surface at the scalpel tip, with a straight incision in the plane
//! y = y_cut from the top down to a depth, growing in x with the scalpel (§3.4).
//! Quasi-static: every step solves equilibrium for the current inputs (§3.3).
//!
//! What a step costs depends on what changed: loads only → one solve with the existing
//! factorization; E or ν → reassembly and numeric refactorization; the cut grew by a cell →
//! a new mesh, pattern, symbolic analysis and factorization.

mod contact;
mod outputs;
mod topology;

use outputs::Outputs;
use topology::{Geometry, Options, Strategy, Support, Topology};

use super::{
    check_step, megabytes, memory_limit, Scene, SceneError, Values, Variability, Variable,
};
use crate::budget;
use crate::element::Elastic;

/// Laser-profile stations: y = 0, 0.5, …, 90 mm in lab coordinates (the default block
/// pulled by up to 10 mm).
pub const PROFILE_STATIONS: usize = 181;
/// Spacing of the profile stations (mm).
pub const PROFILE_STEP: f64 = 0.5;
/// The scanner lines x = 25, 50, 75 mm (seed 002 §3.5, Fig. 4.7).
pub const PROFILE_LINES: [f64; 3] = [25.0, 50.0, 75.0];

// Value references (indices into the table built by `table`).
const SIZE: [u32; 3] = [0, 1, 2];
const CELLS: [u32; 3] = [3, 4, 5];
const Y_CUT: u32 = 6;
const DEPTH: u32 = 7;
const PRESS_RADIUS: u32 = 8;
const STRATEGY: u32 = 9;
const SUPPORT: u32 = 10;
const YOUNG: u32 = 11;
const POISSON: u32 = 12;
const PULL: u32 = 13;
const PRESS: u32 = 14;
const SCALPEL: u32 = 15;
const CONTACT: u32 = 16;
const MEMORY_LIMIT: u32 = 17;
const FIRST_OUTPUT: u32 = 18;

fn table() -> Vec<Variable> {
    use Variability::{Fixed, Tunable};
    let count = (1.0, 400.0);
    let length = (1e-3, 1e4);
    vec![
        Variable::parameter("size_x", Fixed, "mm", 100.0, length, "block length in x"),
        Variable::parameter("size_y", Fixed, "mm", 80.0, length, "block length in y (pull direction)"),
        Variable::parameter("size_z", Fixed, "mm", 17.0, length, "block height in z"),
        Variable::parameter("cells_x", Fixed, "1", 6.0, count, "cubes along x (whole number)"),
        Variable::parameter("cells_y", Fixed, "1", 16.0, count, "cubes along y (whole number)"),
        Variable::parameter("cells_z", Fixed, "1", 14.0, count, "cubes along z (whole number)"),
        Variable::parameter("y_cut", Fixed, "mm", 45.0, (0.0, 1e4), "plane of the incision (the nearest node plane is moved onto it)"),
        Variable::parameter("cut_depth", Fixed, "mm", 8.5, (0.0, 1e4), "incision depth from the top (0: no cut)"),
        Variable::parameter("press_radius", Fixed, "mm", 5.0, (0.0, 1e4), "top faces whose centroid lies within this distance of the scalpel tip carry the press force (at least the nearest face)"),
        Variable::string("cut_strategy", "duplicate", "`duplicate` (split nodes on the cut faces) or `delete` (remove the element layer in front of the cut)"),
        Variable::string("support", "clamped", "`clamped` (face y = 0 fixed, face y = L: u_y prescribed, u_x, u_z free), `gripped` (face y = L also held in x and z) or `sliding` (only u_y on both faces, rigid modes removed)"),
        Variable::parameter("E", Tunable, "MPa", 0.0385, (1e-12, 1e9), "Young's modulus (seed 002 ch. 4: 0.0385 MPa)"),
        Variable::parameter("nu", Tunable, "1", 0.43, (-0.999, 0.499_999), "Poisson's ratio (seed 002 ch. 4: 0.43)"),
        Variable::input("pull", "mm", 0.0, (-1e3, 1e3), "prescribed u_y of the face y = L"),
        Variable::input("press_force", "N", 0.0, (0.0, 1e6), "downward force on the top surface at the scalpel tip"),
        Variable::input("scalpel_x", "mm", 0.0, (0.0, 1e4), "scalpel position; the incision covers x from 0 to here, in whole cells"),
        Variable::string("contact", "penalty", "`penalty` (closing cut flanks are kept apart, node-to-facet penalty) or `none` (flanks may pass through each other)"),
        memory_limit(),
        Variable::output("reaction_force", "N", 1, "y-reaction force on the pulled face y = L"),
        Variable::output("cut_opening", "mm", 1, "largest gap between facing flank nodes on the top surface"),
        Variable::output("bottom_lift", "mm", 1, "largest upward displacement of the bottom surface under the cut plane"),
        Variable::output("x_contraction", "mm", 1, "largest inward x-displacement of the end faces x = 0 and x = size_x"),
        Variable::output("max_von_mises", "MPa", 1, "maximum of the volume-weighted nodal averages of element von Mises stress (seed 002 eq. 4.4)"),
        Variable::output("cut_length", "mm", 1, "current incision length in x (whole cells behind the scalpel)"),
        Variable::output("contact_points", "1", 1, "number of flank nodes held by contact springs"),
        Variable::output("penetration", "mm", 1, "deepest penetration of a flank node into the opposite flank"),
        Variable::output("profile_x25", "mm", PROFILE_STATIONS, "deformed top-surface height along x = 25 mm at y = 0, 0.5, …, 90 mm (NaN: no surface, e.g. in the open cut)"),
        Variable::output("profile_x50", "mm", PROFILE_STATIONS, "deformed top-surface height along x = 50 mm, stations as profile_x25"),
        Variable::output("profile_x75", "mm", PROFILE_STATIONS, "deformed top-surface height along x = 75 mm, stations as profile_x25"),
    ]
}

/// The scene. Build with [`CutBlock::new`], set parameters, `initialize`, then step.
#[derive(Debug)]
pub struct CutBlock {
    values: Values,
    geometry: Option<Geometry>,
    topology: Option<Topology>,
    outputs: Option<Outputs>,
    work: Work,
}

/// What the scene has done so far: how often it rebuilt the topology, refactorized and solved.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Work {
    pub topology_builds: u64,
    pub factorizations: u64,
    pub solves: u64,
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
            outputs: None,
            work: Work::default(),
        }
    }

    /// Counts of topology builds, numeric factorizations and solves so far.
    pub fn work(&self) -> Work {
        let current = self.topology.as_ref().map_or(0, |t| t.factorizations);
        Work {
            factorizations: self.work.factorizations + current,
            ..self.work
        }
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

    /// The current mesh and nodal displacements (all dofs), for plots and files.
    pub fn field(&self) -> Option<(&crate::mesh::Mesh3d, &[f64])> {
        self.topology.as_ref().map(|t| (&t.mesh, t.u.as_slice()))
    }

    fn material(&self) -> Result<Elastic, SceneError> {
        Ok(Elastic::new(
            "cutblock",
            self.values.real(YOUNG),
            self.values.real(POISSON),
        )?)
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
        let cells = geometry.cut_cells(self.values.real(SCALPEL));
        match &mut self.topology {
            Some(t) if t.cut_cells == cells => t.set_material(material)?,
            slot => {
                // Built aside first: on error the last good topology and state stay.
                let limit = megabytes(self.values.real(MEMORY_LIMIT));
                let built = budget::within(limit, || Topology::build(geometry, cells, material))?;
                let old = slot.replace(built).map_or(0, |t| t.factorizations);
                self.work.factorizations += old;
                self.work.topology_builds += 1;
            }
        }
        let topology = self.topology.as_mut().expect("built above");
        topology.solve(
            geometry,
            self.values.real(PULL),
            self.values.real(PRESS),
            self.values.real(SCALPEL),
        )?;
        self.work.solves += 1;
        self.outputs = None;
        Ok(())
    }
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
        let outputs = self
            .outputs
            .get_or_insert_with(|| Outputs::compute(geometry, topology));
        outputs.read(vr - FIRST_OUTPUT, out);
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
        self.geometry = Some(budget::within(limit, || self.geometry_from_values())?);
        self.topology = None;
        self.solve()?;
        self.values.freeze();
        Ok(())
    }

    fn do_step(&mut self, _t: f64, h: f64) -> Result<(), SceneError> {
        check_step(h)?;
        self.solve()
    }
}
