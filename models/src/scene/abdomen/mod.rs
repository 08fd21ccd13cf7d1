//! The abdomen scene (seed 003 §5.4): a 2D plane-strain model of the midsagittal section of
//! the abdominal cavity. Triangles fill the cavity; line elements model the diaphragm, the
//! abdominal wall and the pelvic floor on the boundary nodes; spine and pelvic bone are fixed,
//! the abdominal wall optionally too. A pressing force acts on the diaphragm:
//!
//! F(t) = press_force(t) + press_amplitude · sin(2π · press_frequency · t)   (N per mm depth),
//!
//! spread as a uniform pressure F / L_diaphragm normal to the diaphragm, pointing into the
//! cavity (caudally at the dome), with consistent nodal loads. Inputs may change between any
//! two steps. Time integration: Houbolt by default (seed 003 App. B.2.2), selectable.
//!
//! Tissue properties (mm–N–s–t): four per tissue as in the seed (E, ν or cross-section,
//! density, damping). Damping is mass-proportional per tissue, C = Σ_t α_t M_t. Defaults:
//! abdominal wall E = 22.5 kPa, the in-vivo sagittal-plane value of Song et al., Surg Endosc
//! 20 (2006) 987–990; densities 1e-9 t/mm³ (water). The other stiffnesses, cross-sections
//! and damping values are assumed orders of magnitude, not taken from a source: cavity
//! 5 kPa, ν = 0.45; diaphragm 0.2 MPa, 4 mm²/mm; pelvic floor 0.1 MPa, 8 mm²/mm; wall
//! 20 mm²/mm; α = 5 1/s. The default pressing amplitude 0.8 N/mm corresponds to about 4 kPa
//! on a 200 mm diaphragm, the bear-down pressure used by Noakes et al., J Biomech 41 (2008).

pub mod anatomy;
pub mod config;
pub mod geometry;
pub mod mesher;
mod outputs;

use std::path::PathBuf;

use config::PelvisConfig;
use mesher::Meshed;
use outputs::OutputPlan;

use super::{Scene, SceneError, Values, Variability, Variable};
use crate::assembly::plane::{self, Continuum, PlaneProperties, Truss};
use crate::assembly::{loads, Assembler, Dirichlet};
use crate::element::Elastic;
use crate::mesh::Mesh2d;
use crate::solve::{Damping, Integrator, IntegratorKind, Layout, Statics, Structure};
use crate::stress::TriangleStresses;

/// Tissue names as used in variable names: the cavity (triangles) and the three membranes
/// (line regions 0, 1, 2).
const TISSUES: [&str; 4] = ["cavity", "diaphragm", "wall", "floor"];

const CONFIGURATION: u32 = 0;
const TARGET_TRIANGLES: u32 = 1;
const WALL_SUPPORT: u32 = 2;
const INTEGRATOR: u32 = 3;
const MAX_STEP: u32 = 4;
/// First of the 4 × 4 tissue parameters: E, ν or area, density, damping per tissue.
const TISSUE_BASE: u32 = 5;
const PRESS_AMPLITUDE: u32 = 21;
const PRESS_FREQUENCY: u32 = 22;
const PRESS_FORCE: u32 = 23;
const FIRST_OUTPUT: u32 = 24;

fn tissue_vr(tissue: usize, field: u32) -> u32 {
    TISSUE_BASE + 4 * tissue as u32 + field
}

fn table() -> Vec<Variable> {
    use Variability::{Fixed, Tunable};
    let mut t = vec![
        Variable::string("configuration", "", "pelvis/spine configuration: empty = built-in default, a shipped name (normal, narrow, wide, lordotic, tilted) or a TOML file path"),
        Variable::parameter("target_triangles", Fixed, "1", 6000.0, (50.0, 500_000.0), "mesh resolution: approximate number of triangles"),
        Variable::string("abdominal_wall", "free", "`free` or `fixed` (seed 003: the wall can additionally be fixed)"),
        Variable::string("integrator", "houbolt", "houbolt, newmark, central_difference or rk4"),
        Variable::parameter("max_step", Fixed, "s", 1e-3, (1e-8, 10.0), "largest internal time step; a communication step is split into equal substeps"),
    ];
    let defaults = [(0.005, 0.45), (0.2, 4.0), (0.0225, 20.0), (0.1, 8.0)];
    for (i, name) in TISSUES.iter().enumerate() {
        let (e, second) = defaults[i];
        t.push(Variable::parameter(
            &format!("{name}_E"),
            Tunable,
            "MPa",
            e,
            (1e-9, 1e6),
            &format!("Young's modulus of the {name}"),
        ));
        t.push(if i == 0 {
            Variable::parameter(
                "cavity_nu",
                Tunable,
                "1",
                second,
                (-0.99, 0.499_999),
                "Poisson's ratio of the cavity contents",
            )
        } else {
            Variable::parameter(
                &format!("{name}_area"),
                Fixed,
                "mm2",
                second,
                (1e-6, 1e4),
                &format!("cross-section of the {name} line elements per mm of depth"),
            )
        });
        t.push(Variable::parameter(
            &format!("{name}_density"),
            Fixed,
            "t/mm3",
            1e-9,
            (1e-15, 1e-6),
            &format!("density of the {name}"),
        ));
        t.push(Variable::parameter(
            &format!("{name}_damping"),
            Fixed,
            "1/s",
            5.0,
            (0.0, 1e6),
            &format!("mass-proportional damping coefficient of the {name}"),
        ));
    }
    t.extend([
        Variable::input(
            "press_amplitude",
            "N/mm",
            0.8,
            (-1e3, 1e3),
            "amplitude of the sinusoidal pressing force on the diaphragm, per mm depth",
        ),
        Variable::input(
            "press_frequency",
            "Hz",
            0.5,
            (0.0, 1e3),
            "frequency of the sinusoidal pressing force",
        ),
        Variable::input(
            "press_force",
            "N/mm",
            0.0,
            (-1e3, 1e3),
            "pressing force added to the sinusoid, supplied each step by the importer",
        ),
        Variable::output(
            "floor_stress_mean",
            "MPa",
            1,
            "length-weighted mean axial stress of the pelvic-floor line elements (tension > 0)",
        ),
        Variable::output(
            "floor_stress_max",
            "MPa",
            1,
            "largest axial stress of the pelvic-floor line elements",
        ),
        Variable::output(
            "floor_triangles_vm_mean",
            "MPa",
            1,
            "area-weighted mean von Mises stress of the triangles along the pelvic floor",
        ),
        Variable::output(
            "floor_triangles_vm_max",
            "MPa",
            1,
            "largest von Mises stress of the triangles along the pelvic floor",
        ),
        Variable::output(
            "cavity_vm_mean",
            "MPa",
            1,
            "area-weighted mean von Mises stress of all triangles",
        ),
        Variable::output(
            "cavity_vm_max",
            "MPa",
            1,
            "largest von Mises stress of all triangles",
        ),
        Variable::output(
            "apex_ux",
            "mm",
            1,
            "x-displacement of the diaphragm apex (highest diaphragm node)",
        ),
        Variable::output("apex_uy", "mm", 1, "y-displacement of the diaphragm apex"),
        Variable::output(
            "floor_mid_ux",
            "mm",
            1,
            "x-displacement of the pelvic-floor midpoint",
        ),
        Variable::output(
            "floor_mid_uy",
            "mm",
            1,
            "y-displacement of the pelvic-floor midpoint",
        ),
        Variable::output(
            "wall_mid_ux",
            "mm",
            1,
            "x-displacement of the abdominal-wall midpoint",
        ),
        Variable::output(
            "wall_mid_uy",
            "mm",
            1,
            "y-displacement of the abdominal-wall midpoint",
        ),
        Variable::output(
            "press_total",
            "N/mm",
            1,
            "pressing force applied at the current time",
        ),
    ]);
    t
}

/// Everything built at initialization.
struct Model {
    meshed: Meshed,
    props: PlaneProperties,
    asm: Assembler,
    k: Vec<f64>,
    structure: Structure,
    integrator: Box<dyn Integrator + Send>,
    /// Reduced load vector of a unit pressing force, and the work vector for the load.
    unit_load: Vec<f64>,
    fixed: Vec<usize>,
    u_full: Vec<f64>,
    /// Stress operators of the triangles for the current properties.
    stresses: TriangleStresses,
    outputs: OutputPlan,
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model")
            .field("triangles", &self.meshed.mesh.triangles().len())
            .finish()
    }
}

/// The scene. Build with [`Abdomen::new`], set parameters, `initialize`, then step.
#[derive(Debug)]
pub struct Abdomen {
    values: Values,
    resources: PathBuf,
    model: Option<Model>,
    /// The outputs after the last step, once requested.
    outputs: Option<[f64; outputs::COUNT]>,
    stiffness_changed: bool,
    time: f64,
}

impl Default for Abdomen {
    fn default() -> Self {
        Self::new()
    }
}

impl Abdomen {
    /// A scene with the built-in defaults. Shipped configurations are looked up in the
    /// repository's `experiments/pelvis` until `Scene::set_resource_dir` points to a resources
    /// folder (then `<resources>/pelvis`).
    pub fn new() -> Self {
        Self {
            values: Values::new(table()),
            resources: PathBuf::from(concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../experiments/pelvis"
            )),
            model: None,
            outputs: None,
            stiffness_changed: false,
            time: 0.0,
        }
    }

    /// Sets a real variable by name.
    pub fn set(&mut self, name: &str, value: f64) -> Result<(), SceneError> {
        let vr = self.lookup(name)?;
        self.set_real(vr, &[value])
    }

    /// Sets a string variable by name.
    pub fn set_str(&mut self, name: &str, value: &str) -> Result<(), SceneError> {
        let vr = self.lookup(name)?;
        self.set_string(vr, value)
    }

    /// Reads a scalar real variable by name.
    pub fn get(&mut self, name: &str) -> Result<f64, SceneError> {
        let vr = self.lookup(name)?;
        let mut x = [0.0];
        self.get_real(vr, &mut x)?;
        Ok(x[0])
    }

    /// The mesh with its quality figures, after initialization.
    pub fn meshed(&self) -> Option<&Meshed> {
        self.model.as_ref().map(|m| &m.meshed)
    }

    /// The mesh, the properties and the current nodal displacements (all dofs).
    pub fn field(&self) -> Option<(&Mesh2d, &PlaneProperties, &[f64])> {
        self.model
            .as_ref()
            .map(|m| (&m.meshed.mesh, &m.props, m.u_full.as_slice()))
    }

    /// Current simulation time (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The static displacement (all dofs) under a constant pressing force `force` (N/mm).
    pub fn static_displacement(&self, force: f64) -> Result<Vec<f64>, SceneError> {
        let m = self.model.as_ref().ok_or_else(not_initialized)?;
        let mut statics = Statics::new(&m.asm, &m.fixed, Layout::Simplicial)?;
        statics.factorize(&m.k)?;
        let mut f = vec![0.0; m.meshed.mesh.n_dofs()];
        m.structure.dirichlet().expand(&m.unit_load, &mut f);
        f.iter_mut().for_each(|x| *x *= force);
        let mut u = vec![0.0; f.len()];
        statics.solve(m.asm.matrix(&m.k), &f, &mut u);
        Ok(u)
    }

    /// The outputs (table order, from `floor_stress_mean` on) for a displacement field of all
    /// dofs, e.g. one from [`Abdomen::static_displacement`].
    pub fn evaluate(&self, u_full: &[f64], press: f64) -> Result<Vec<f64>, SceneError> {
        let m = self.model.as_ref().ok_or_else(not_initialized)?;
        let outputs = m
            .outputs
            .compute(&m.meshed.mesh, &m.props, &m.stresses, u_full, press);
        Ok(outputs.to_vec())
    }

    fn properties(&self) -> Result<PlaneProperties, SceneError> {
        let v = |tissue: usize, field: u32| self.values.real(tissue_vr(tissue, field));
        let continuum = Continuum {
            elastic: Elastic::new("cavity", v(0, 0), v(0, 1))?,
            density: v(0, 2),
        };
        let trusses = (1..4)
            .map(|t| Truss::new(TISSUES[t], v(t, 0), v(t, 1), v(t, 2)))
            .collect::<Result<_, _>>()?;
        Ok(PlaneProperties {
            continua: vec![continuum],
            trusses,
        })
    }

    /// Properties whose "density" is α_t ρ_t: their mass matrix is the damping matrix.
    fn damping_properties(&self, props: &PlaneProperties) -> PlaneProperties {
        let alpha = |t: usize| self.values.real(tissue_vr(t, 3));
        let mut d = props.clone();
        d.continua[0].density *= alpha(0);
        for (i, truss) in d.trusses.iter_mut().enumerate() {
            truss.density *= alpha(i + 1);
        }
        d
    }

    fn build(&self) -> Result<Model, SceneError> {
        let config = PelvisConfig::resolve(self.values.string(CONFIGURATION)?, &self.resources)?;
        let target = self.values.real(TARGET_TRIANGLES) as usize;
        let meshed = mesher::mesh(&config.control_points()?, target)?;
        let mesh = &meshed.mesh;
        let props = self.properties()?;
        let asm = plane::assembler(mesh);
        let (mut k, mut m, mut c) = (asm.zeros(), asm.zeros(), asm.zeros());
        plane::stiffness(mesh, &asm, &props, &mut k);
        plane::mass(mesh, &asm, &props, &mut m);
        plane::mass(mesh, &asm, &self.damping_properties(&props), &mut c);
        let lumped = plane::lumped_mass(mesh, &props);
        let mut supported = vec!["spine", "pelvic_bone"];
        match self.values.string(WALL_SUPPORT)? {
            "free" => {}
            "fixed" => supported.push("abdominal_wall"),
            other => {
                return Err(SceneError::Config(format!(
                    "abdominal_wall `{other}`: use `free` or `fixed`"
                )))
            }
        }
        let mut fixed = Vec::new();
        for set in supported {
            fixed.extend(
                mesh.node_sets()
                    .get(set)?
                    .iter()
                    .flat_map(|n| [2 * n, 2 * n + 1]),
            );
        }
        let bc = Dirichlet::new(&asm, &fixed)?;
        let mut structure = Structure::new(bc, &k, &m, &lumped, Damping::NONE, Layout::Simplicial)?;
        structure.set_damping_matrix(&c);
        let unit_load = diaphragm_unit_load(mesh, structure.dirichlet())?;
        let kind = IntegratorKind::parse(self.values.string(INTEGRATOR)?)?;
        Ok(Model {
            stresses: TriangleStresses::new(mesh, &props),
            outputs: OutputPlan::new(mesh)?,
            u_full: vec![0.0; mesh.n_dofs()],
            meshed,
            props,
            asm,
            k,
            structure,
            integrator: kind.create(),
            unit_load,
            fixed,
        })
    }

    /// The pressing force (N/mm) at time t.
    fn press(&self, t: f64) -> f64 {
        let (a, f) = (
            self.values.real(PRESS_AMPLITUDE),
            self.values.real(PRESS_FREQUENCY),
        );
        self.values.real(PRESS_FORCE) + a * (2.0 * std::f64::consts::PI * f * t).sin()
    }

    fn update_stiffness(&mut self) -> Result<(), SceneError> {
        let props = self.properties()?;
        let m = self.model.as_mut().ok_or_else(not_initialized)?;
        plane::stiffness(&m.meshed.mesh, &m.asm, &props, &mut m.k);
        m.structure.set_stiffness(&m.k);
        m.stresses = TriangleStresses::new(&m.meshed.mesh, &props);
        m.props = props;
        let dt = m.integrator.dt();
        m.integrator.prepare(&m.structure, dt)?;
        self.stiffness_changed = false;
        Ok(())
    }
}

fn not_initialized() -> SceneError {
    SceneError::NotSettable {
        name: "abdomen".into(),
        reason: "the scene is not initialized",
    }
}

/// Consistent nodal loads (free dofs) of a unit total force spread as a uniform pressure over
/// the diaphragm, normal to it and into the cavity.
fn diaphragm_unit_load(mesh: &Mesh2d, bc: &Dirichlet) -> Result<Vec<f64>, SceneError> {
    let lines: Vec<[usize; 2]> = mesh
        .lines()
        .iter()
        .zip(mesh.line_regions())
        .filter(|(_, &r)| r == 0)
        .map(|(l, _)| *l)
        .collect();
    let length: f64 = lines
        .iter()
        .map(|l| {
            let (a, b) = (mesh.nodes()[l[0]], mesh.nodes()[l[1]]);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum();
    let mut f = vec![0.0; mesh.n_dofs()];
    for l in &lines {
        // Line elements run in boundary order (counter-clockwise): the cavity lies to the left.
        loads::edge_pressure(mesh.nodes(), *l, 1.0 / length, &mut f);
    }
    let mut reduced = vec![0.0; bc.n_free()];
    bc.reduce(&f, &mut reduced);
    Ok(reduced)
}

impl Scene for Abdomen {
    fn variables(&self) -> &[Variable] {
        self.values.table()
    }

    fn set_resource_dir(&mut self, dir: &std::path::Path) {
        self.resources = dir.join("pelvis");
    }

    fn set_real(&mut self, vr: u32, values: &[f64]) -> Result<(), SceneError> {
        self.values.set_real(vr, values)?;
        if (TISSUE_BASE..PRESS_AMPLITUDE).contains(&vr) {
            self.properties()?;
            self.stiffness_changed = self.model.is_some();
        }
        Ok(())
    }

    fn get_real(&mut self, vr: u32, out: &mut [f64]) -> Result<(), SceneError> {
        if self.values.read(vr, out)? {
            return Ok(());
        }
        let press = self.press(self.time);
        let m = self.model.as_ref().ok_or_else(not_initialized)?;
        let outputs = self.outputs.get_or_insert_with(|| {
            m.outputs
                .compute(&m.meshed.mesh, &m.props, &m.stresses, &m.u_full, press)
        });
        out[0] = outputs[(vr - FIRST_OUTPUT) as usize];
        Ok(())
    }

    fn set_string(&mut self, vr: u32, value: &str) -> Result<(), SceneError> {
        if vr == INTEGRATOR {
            IntegratorKind::parse(value)?;
        }
        if vr == WALL_SUPPORT && !matches!(value, "free" | "fixed") {
            return Err(SceneError::Config(format!(
                "abdominal_wall `{value}`: use `free` or `fixed`"
            )));
        }
        self.values.set_string(vr, value)
    }

    fn get_string(&self, vr: u32) -> Result<String, SceneError> {
        self.values.string(vr).map(str::to_string)
    }

    fn initialize(&mut self) -> Result<(), SceneError> {
        let mut model = self.build()?;
        let dt = self.values.real(MAX_STEP);
        model.integrator.prepare(&model.structure, dt)?;
        let n = model.structure.n();
        let f0 = self.press(0.0);
        let unit = &model.unit_load;
        let mut load = |_: f64, f: &mut [f64]| {
            f.iter_mut().zip(unit).for_each(|(x, u)| *x = f0 * u);
        };
        model.integrator.start(
            &model.structure,
            0.0,
            &vec![0.0; n],
            &vec![0.0; n],
            &mut load,
        )?;
        self.model = Some(model);
        self.time = 0.0;
        self.outputs = None;
        self.values.freeze();
        Ok(())
    }

    fn do_step(&mut self, t: f64, h: f64) -> Result<(), SceneError> {
        if !(h.is_finite() && h > 0.0) {
            return Err(SceneError::Config(format!(
                "step size h = {h} must be finite and > 0"
            )));
        }
        if self.stiffness_changed {
            self.update_stiffness()?;
        }
        let substeps = (h / self.values.real(MAX_STEP) - 1e-9).ceil().max(1.0);
        let mut dt = h / substeps;
        let (a, freq, bias) = (
            self.values.real(PRESS_AMPLITUDE),
            self.values.real(PRESS_FREQUENCY),
            self.values.real(PRESS_FORCE),
        );
        let m = self.model.as_mut().ok_or_else(not_initialized)?;
        // Importers compute h as a difference of communication points, which jitters in the
        // last bits; such a step reuses the factorization (the step still ends at t + h).
        if (dt - m.integrator.dt()).abs() <= 1e-9 * dt {
            dt = m.integrator.dt();
        } else {
            m.integrator.prepare(&m.structure, dt)?;
        }
        if let Some(limit) = m.integrator.critical_time_step() {
            if dt > limit {
                return Err(SceneError::Config(format!(
                    "{} is unstable at dt = {dt:e} s: its stability limit here is {limit:e} s; \
                     lower max_step or use houbolt/newmark",
                    m.integrator.kind().name()
                )));
            }
        }
        let unit = &m.unit_load;
        let mut load = |tau: f64, f: &mut [f64]| {
            let force = bias + a * (2.0 * std::f64::consts::PI * freq * tau).sin();
            f.iter_mut().zip(unit).for_each(|(x, u)| *x = force * u);
        };
        for _ in 0..substeps as u64 {
            m.integrator.step(&m.structure, &mut load)?;
        }
        m.structure
            .dirichlet()
            .expand(&m.integrator.state().u, &mut m.u_full);
        self.time = t + h;
        self.outputs = None;
        Ok(())
    }
}
