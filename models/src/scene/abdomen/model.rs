//! What the abdomen builds at initialization: the configuration resolved to an outline, the
//! mesh, per-tissue properties, the assembled stiffness, mass and damping, the supports, the
//! dynamic system with its integrator, the load pattern of the pressing force and the output
//! plan.

use std::path::Path;

use super::config::PelvisConfig;
use super::mesher::{self, Meshed};
use super::outputs::OutputPlan;
use super::variables::{
    tissue_vr, CONFIGURATION, INTEGRATOR, TARGET_TRIANGLES, TISSUES, WALL_SUPPORT,
};
use crate::assembly::plane::{self, Continuum, PlaneProperties, Truss};
use crate::assembly::{loads, Assembler, Dirichlet};
use crate::element::Elastic;
use crate::mesh::Mesh2d;
use crate::scene::{SceneError, Values};
use crate::solve::{Damping, Factorization, Integrator, IntegratorKind, Statics, Structure};
use crate::stress::TriangleStresses;

/// Everything built at initialization.
pub struct Model {
    pub meshed: Meshed,
    pub props: PlaneProperties,
    asm: Assembler,
    k: Vec<f64>,
    pub structure: Structure,
    pub integrator: Box<dyn Integrator + Send>,
    /// Reduced load vector of a unit pressing force.
    pub unit_load: Vec<f64>,
    fixed: Vec<usize>,
    /// The displacement of all dofs after the last step.
    pub u_full: Vec<f64>,
    /// Stress operators of the triangles for the current properties.
    pub stresses: TriangleStresses,
    pub outputs: OutputPlan,
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model")
            .field("triangles", &self.meshed.mesh.triangles().len())
            .finish()
    }
}

/// Per-tissue properties from the current parameter values.
pub fn properties(values: &Values) -> Result<PlaneProperties, SceneError> {
    let v = |tissue: usize, field: u32| values.real(tissue_vr(tissue, field));
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
fn damping_properties(values: &Values, props: &PlaneProperties) -> PlaneProperties {
    let alpha = |t: usize| values.real(tissue_vr(t, 3));
    let mut d = props.clone();
    d.continua[0].density *= alpha(0);
    for (i, truss) in d.trusses.iter_mut().enumerate() {
        truss.density *= alpha(i + 1);
    }
    d
}

/// The dofs held fixed: spine and pelvic bone, and the abdominal wall when `fixed`.
fn supports(mesh: &Mesh2d, wall: &str) -> Result<Vec<usize>, SceneError> {
    let mut supported = vec!["spine", "pelvic_bone"];
    match wall {
        "free" => {}
        "fixed" => supported.push("abdominal_wall"),
        other => return Err(wall_error(other)),
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
    Ok(fixed)
}

/// The error for an `abdominal_wall` value other than `free` or `fixed`.
pub fn wall_error(value: &str) -> SceneError {
    SceneError::Config(format!("abdominal_wall `{value}`: use `free` or `fixed`"))
}

impl Model {
    /// Builds the model for the current parameter values; shipped configurations are looked
    /// up in `resources`.
    pub fn build(values: &Values, resources: &Path) -> Result<Self, SceneError> {
        let config = PelvisConfig::resolve(values.string(CONFIGURATION)?, resources)?;
        let target = values.real(TARGET_TRIANGLES) as usize;
        let meshed = mesher::mesh(&config.control_points()?, target)?;
        let mesh = &meshed.mesh;
        let props = properties(values)?;
        let asm = plane::assembler(mesh);
        let (mut k, mut m, mut c) = (asm.zeros(), asm.zeros(), asm.zeros());
        plane::stiffness(mesh, &asm, &props, &mut k);
        plane::mass(mesh, &asm, &props, &mut m);
        plane::mass(mesh, &asm, &damping_properties(values, &props), &mut c);
        let lumped = plane::lumped_mass(mesh, &props);
        let fixed = supports(mesh, values.string(WALL_SUPPORT)?)?;
        let bc = Dirichlet::new(&asm, &fixed)?;
        let mut structure = Structure::new(
            bc,
            &k,
            &m,
            &lumped,
            Damping::NONE,
            Factorization::Simplicial,
        )?;
        structure.set_damping_matrix(&c);
        let unit_load = diaphragm_unit_load(mesh, structure.dirichlet())?;
        let kind = IntegratorKind::parse(values.string(INTEGRATOR)?)?;
        Ok(Self {
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

    /// Reassembles the stiffness for new properties and refactorizes the integrator's
    /// effective matrix at its current step.
    pub fn set_properties(&mut self, props: PlaneProperties) -> Result<(), SceneError> {
        plane::stiffness(&self.meshed.mesh, &self.asm, &props, &mut self.k);
        self.structure.set_stiffness(&self.k);
        self.stresses = TriangleStresses::new(&self.meshed.mesh, &props);
        self.props = props;
        let dt = self.integrator.dt();
        self.integrator.prepare(&self.structure, dt)?;
        Ok(())
    }

    /// The static displacement (all dofs) under a constant pressing force `force` (N/mm).
    pub fn static_displacement(&self, force: f64) -> Result<Vec<f64>, SceneError> {
        let mut statics = Statics::new(&self.asm, &self.fixed, Factorization::Simplicial)?;
        statics.factorize(&self.k)?;
        let mut f = vec![0.0; self.meshed.mesh.n_dofs()];
        self.structure.dirichlet().expand(&self.unit_load, &mut f);
        f.iter_mut().for_each(|x| *x *= force);
        let mut u = vec![0.0; f.len()];
        statics.solve(self.asm.matrix(&self.k), &f, &mut u);
        Ok(u)
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
