//! What the abdomen builds at initialization: the configuration resolved to an outline, the
//! mesh, per-tissue properties, the assembled stiffness, mass and damping, the supports, the
//! dynamic system with its integrator, the load pattern of the pressing force and the output
//! plan — and for `model_order = "modal"` the reduced system ([`Modal`]) the integrator
//! steps instead of the full one.

use super::config::PelvisConfig;
use super::discretization::{self, Choice, Discretization, FieldView, Recovery};
use super::mesher;
use super::outputs::{self, Field, OutputPlan, Rows};
use super::variables::{
    tissue_vr, CONFIGURATION, ELEMENT, FORMULATION, GRADING, INTEGRATOR, KINEMATICS, MODEL_ORDER,
    MODES, SUBDIVISIONS, TARGET_TRIANGLES, TISSUES, WALL_SUPPORT,
};
use crate::assembly::plane::{Continuum, PlaneProperties, Truss};
use crate::assembly::Dirichlet;
use crate::element::Elastic;
use crate::scene::{SceneError, Values};
use crate::solve::newton::{Newton, Settings};
use crate::solve::{
    Checkpoint, Damping, Factorization, Integrator, IntegratorKind, ModalBasis, Reduction, Statics,
    Structure,
};

/// Everything built at initialization.
pub struct Model {
    pub disc: Discretization,
    pub props: PlaneProperties,
    k: Vec<f64>,
    /// The full system on the free dofs.
    pub structure: Structure,
    /// Steps the full system, or the reduced one when `modal` is present.
    pub integrator: Box<dyn Integrator + Send>,
    /// Reduced load vector of a unit pressing force.
    pub unit_load: Vec<f64>,
    fixed: Vec<usize>,
    /// The displacement of all dofs after the last step, valid when `expanded`.
    u_full: Vec<f64>,
    expanded: bool,
    /// Free-dof scratch for expanding modal coordinates.
    u_free: Vec<f64>,
    /// Stress recovery for the current properties.
    pub recovery: Recovery,
    pub outputs: OutputPlan,
    /// The reduced system of `model_order = "modal"`.
    pub modal: Option<Modal>,
}

/// The reduced-order system: the basis, the projected matrices, the projected unit load
/// and the output rows.
#[derive(Debug)]
pub struct Modal {
    pub basis: ModalBasis,
    pub structure: Structure,
    pub unit_load: Vec<f64>,
    rows: Rows,
    /// The largest principal strain of each basis vector, for [`Model::strain_bound`].
    strains: Vec<f64>,
    /// The `modes` parameter the basis was built with.
    count: usize,
}

impl std::fmt::Debug for Model {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Model")
            .field("triangles", &self.disc.mesh().triangles().len())
            .field("choice", &self.disc.choice)
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
fn supports(disc: &Discretization, wall: &str) -> Result<Vec<usize>, SceneError> {
    let mut supported = vec!["spine", "pelvic_bone"];
    match wall {
        "free" => {}
        "fixed" => supported.push("abdominal_wall"),
        other => return Err(wall_error(other)),
    }
    let mut fixed = Vec::new();
    for set in supported {
        fixed.extend(disc.boundary_dofs(set)?);
    }
    Ok(fixed)
}

/// A whole-number parameter (`modes`, `mesh_subdivisions`); a fractional value is refused.
fn whole(values: &Values, vr: u32, name: &str, reason: &'static str) -> Result<usize, SceneError> {
    let x = values.real(vr);
    if x.fract() != 0.0 {
        return Err(SceneError::Model(
            crate::error::ModelError::InvalidParameter {
                name: name.into(),
                value: x,
                reason,
            },
        ));
    }
    Ok(x as usize)
}

/// The `modes` parameter as a count.
fn modes(values: &Values) -> Result<usize, SceneError> {
    whole(
        values,
        MODES,
        "modes",
        "must be a whole number of basis vectors",
    )
}

/// The reduction of a `model_order` value: `None` for `full`.
pub fn order(value: &str) -> Result<Option<Reduction>, SceneError> {
    match value {
        "full" => Ok(None),
        "modal" => Ok(Some(Reduction::Ritz)),
        "eigenmodes" => Ok(Some(Reduction::Eigenmodes)),
        "eigenmodes_truncated" => Ok(Some(Reduction::Truncated)),
        other => Err(SceneError::Config(format!(
            "model_order `{other}`: use `full`, `modal`, `eigenmodes` or `eigenmodes_truncated`"
        ))),
    }
}

/// The error for an `abdominal_wall` value other than `free` or `fixed`.
pub fn wall_error(value: &str) -> SceneError {
    SceneError::Config(format!("abdominal_wall `{value}`: use `free` or `fixed`"))
}

impl Model {
    /// Builds the model for the current parameter values.
    pub fn build(values: &Values) -> Result<Self, SceneError> {
        let config = PelvisConfig::resolve(values.string(CONFIGURATION)?)?;
        let choice = Choice::parse(
            values.string(ELEMENT)?,
            values.string(FORMULATION)?,
            values.string(KINEMATICS)?,
        )?;
        let target = values.real(TARGET_TRIANGLES) as usize;
        let subdivisions = whole(
            values,
            SUBDIVISIONS,
            "mesh_subdivisions",
            "must be a whole number of subdivisions",
        )?;
        let meshed = mesher::mesh(
            &config.control_points()?,
            target,
            choice.element,
            subdivisions as u32,
            values.real(GRADING),
        )?;
        let disc = Discretization::new(meshed, choice);
        let props = properties(values)?;
        let asm = &disc.asm;
        let (mut k, mut m, mut c) = (asm.zeros(), asm.zeros(), asm.zeros());
        disc.stiffness(&props, &mut k);
        disc.mass(&props, &mut m);
        disc.mass(&damping_properties(values, &props), &mut c);
        let lumped = disc.lumped_mass(&props);
        let fixed = supports(&disc, values.string(WALL_SUPPORT)?)?;
        let bc = Dirichlet::new(asm, &fixed)?;
        let mut structure = Structure::new(
            bc,
            &k,
            &m,
            &lumped,
            Damping::NONE,
            Factorization::Simplicial,
        )?;
        structure.set_damping_matrix(&c);
        if let Some(forces) = disc.internal_forces(&props) {
            structure = structure.with_internal_forces(forces);
        }
        let unit_load = diaphragm_unit_load(&disc, structure.dirichlet());
        let kind = IntegratorKind::parse(values.string(INTEGRATOR)?)?;
        let mut model = Self {
            recovery: disc.recovery(&props),
            outputs: OutputPlan::new(disc.mesh())?,
            u_full: vec![0.0; disc.n_dofs()],
            expanded: true,
            u_free: vec![0.0; structure.n()],
            disc,
            props,
            k,
            structure,
            integrator: kind.create(),
            unit_load,
            fixed,
            modal: None,
        };
        model.modal = match order(values.string(MODEL_ORDER)?)? {
            None => None,
            Some(reduction) => Some(model.reduced(reduction, modes(values)?)?),
        };
        Ok(model)
    }

    /// The reduced system with a basis of `count` vectors for the pressing load's pattern,
    /// for the current matrices.
    fn reduced(&self, reduction: Reduction, count: usize) -> Result<Modal, SceneError> {
        let basis = ModalBasis::new(&self.structure, reduction, count, &self.unit_load)?;
        let mut unit_load = vec![0.0; basis.dim()];
        basis.project(&self.unit_load, &mut unit_load);
        let mut u = vec![0.0; self.u_full.len()];
        let strains = (0..basis.dim())
            .map(|j| {
                self.structure.dirichlet().expand(basis.column(j), &mut u);
                self.view(&u).largest_strain()
            })
            .collect();
        Ok(Modal {
            rows: Rows::new(self.field(&self.u_full), &basis, self.structure.dirichlet()),
            strains,
            structure: basis.reduce(&self.structure)?,
            unit_load,
            basis,
            count,
        })
    }

    /// Prepares the integrator for steps of `dt` and starts it at rest at `t0`, under the
    /// pressing force `force(t)` (N/mm).
    pub fn start(
        &mut self,
        t0: f64,
        dt: f64,
        force: impl Fn(f64) -> f64,
    ) -> Result<(), SceneError> {
        let (structure, unit) = stepped(&self.modal, &self.structure, &self.unit_load);
        let n = structure.n();
        self.integrator.prepare(structure, dt)?;
        let mut load = scaled(force, unit);
        self.integrator
            .start(structure, t0, &vec![0.0; n], &vec![0.0; n], &mut load)?;
        Ok(())
    }

    /// Puts an integrator checkpoint back (see [`Checkpoint`]): the integrator prepared for
    /// its step on the stepped system (full or reduced), then resumed.
    pub fn resume(&mut self, checkpoint: &Checkpoint) -> Result<(), SceneError> {
        let (structure, _) = stepped(&self.modal, &self.structure, &self.unit_load);
        self.integrator.prepare(structure, checkpoint.dt)?;
        self.integrator.resume(structure, checkpoint)?;
        self.expanded = false;
        Ok(())
    }

    /// Takes `steps` steps of `dt` under the pressing force `force(τ)` at integrator time τ.
    /// A `dt` within 1e-9 relative of the prepared one reuses the factorization: importers
    /// compute h as a difference of communication points, which jitters in the last bits.
    pub fn advance(
        &mut self,
        mut dt: f64,
        steps: u64,
        force: impl Fn(f64) -> f64,
    ) -> Result<(), SceneError> {
        let (structure, unit) = stepped(&self.modal, &self.structure, &self.unit_load);
        let integrator = &mut self.integrator;
        if (dt - integrator.dt()).abs() <= 1e-9 * dt {
            dt = integrator.dt();
        } else {
            integrator.prepare(structure, dt)?;
        }
        if let Some(limit) = integrator.critical_time_step() {
            if dt > limit {
                return Err(SceneError::Unstable {
                    integrator: integrator.kind().name(),
                    dt,
                    limit,
                });
            }
        }
        let mut load = scaled(force, unit);
        for _ in 0..steps {
            integrator.step(structure, &mut load)?;
        }
        self.expanded = false;
        Ok(())
    }

    /// Brings the displacement of all dofs up to date (expanding the modal coordinates
    /// after steps); read it with [`u_full`](Self::u_full).
    pub fn expand(&mut self) {
        if !self.expanded {
            let u = &self.integrator.state().u;
            let bc = self.structure.dirichlet();
            match &self.modal {
                Some(r) => {
                    r.basis.expand(u, &mut self.u_free);
                    bc.expand(&self.u_free, &mut self.u_full);
                }
                None => bc.expand(u, &mut self.u_full),
            }
            self.expanded = true;
        }
    }

    /// In modal order, a bound of the largest principal strain that needs no expansion:
    /// Σ_j |q_j| · (largest strain of basis vector j) — the per-triangle measure is a
    /// seminorm of the strain, so the triangle inequality holds triangle by triangle. None in
    /// full order.
    pub fn strain_bound(&self) -> Option<f64> {
        let r = self.modal.as_ref()?;
        let q = &self.integrator.state().u;
        Some(q.iter().zip(&r.strains).map(|(q, s)| q.abs() * s).sum())
    }

    /// The displacement of all dofs as of the last [`expand`](Self::expand).
    pub fn u_full(&self) -> &[f64] {
        &self.u_full
    }

    /// The outputs after the last step (see [`OutputPlan::compute`]); the cavity-wide ones
    /// only if `cavity`.
    pub fn outputs(&mut self, press: f64, cavity: bool) -> [f64; outputs::COUNT] {
        if cavity || self.modal.is_none() {
            self.expand();
        }
        if let Some(r) = &mut self.modal {
            r.rows.evaluate(&self.integrator.state().u);
        }
        let field = self.field(&self.u_full);
        let cavity = cavity.then_some(&field);
        match &self.modal {
            Some(r) => self.outputs.compute(&r.rows, cavity, press),
            None => self.outputs.compute(&field, cavity, press),
        }
    }

    /// The displacement `u` (all dofs) with what the outputs need to read it.
    pub fn field<'a>(&'a self, u: &'a [f64]) -> Field<'a> {
        Field {
            plan: &self.outputs,
            recovery: &self.recovery,
            u,
        }
    }

    /// The displacement `u` (all dofs) with the meshes and stresses, for drawing.
    pub fn view<'a>(&'a self, u: &'a [f64]) -> FieldView<'a> {
        FieldView {
            mesh: self.disc.mesh(),
            quadratic: self.disc.quadratic(),
            u,
            recovery: &self.recovery,
        }
    }

    /// Reassembles the stiffness for new properties and refactorizes the integrator's
    /// effective matrix at its current step. A modal model rebuilds its basis and restarts
    /// its integrator from the current state projected onto the new basis (q = Φᵀ M u, and
    /// likewise the velocity), under the pressing force `press` acting now.
    pub fn set_properties(&mut self, props: PlaneProperties, press: f64) -> Result<(), SceneError> {
        self.disc.stiffness(&props, &mut self.k);
        self.structure.set_stiffness(&self.k);
        if let Some(forces) = self.disc.internal_forces(&props) {
            self.structure.set_internal_forces(forces);
        }
        self.recovery = self.disc.recovery(&props);
        self.props = props;
        self.expanded = false;
        let dt = self.integrator.dt();
        let Some(old) = &self.modal else {
            self.integrator.prepare(&self.structure, dt)?;
            return Ok(());
        };
        let state = self.integrator.state().clone();
        let n = self.structure.n();
        let (mut u, mut v) = (vec![0.0; n], vec![0.0; n]);
        old.basis.expand(&state.u, &mut u);
        old.basis.expand(&state.v, &mut v);
        let new = self.reduced(old.basis.reduction, old.count)?;
        let mass = self.structure.mass();
        let (mut q, mut qv) = (vec![0.0; new.basis.dim()], vec![0.0; new.basis.dim()]);
        new.basis.coordinates(mass, &u, &mut q);
        new.basis.coordinates(mass, &v, &mut qv);
        self.integrator.prepare(&new.structure, dt)?;
        let started = {
            let mut load = scaled(|_| press, &new.unit_load);
            self.integrator
                .start(&new.structure, state.t, &q, &qv, &mut load)
        };
        self.modal = Some(new);
        started?;
        Ok(())
    }

    /// The static displacement (all dofs) under a constant pressing force `force` (N/mm):
    /// one solve with K, or at finite strain Newton's method (load increments cut back
    /// where it does not converge).
    pub fn static_displacement(&self, force: f64) -> Result<Vec<f64>, SceneError> {
        let asm = &self.disc.asm;
        let mut f = vec![0.0; self.disc.n_dofs()];
        self.structure.dirichlet().expand(&self.unit_load, &mut f);
        f.iter_mut().for_each(|x| *x *= force);
        let mut u = vec![0.0; f.len()];
        let materials = discretization::materials(&self.props);
        if let Some(mut body) = self.disc.body(&materials, &self.props) {
            let mut newton = Newton::new(
                asm,
                &self.fixed,
                Factorization::Simplicial,
                Settings::default(),
            )?;
            newton.solve(&mut body, &mut u, &vec![0.0; f.len()], &f)?;
            return Ok(u);
        }
        let mut statics = Statics::new(asm, &self.fixed, Factorization::Simplicial)?;
        statics.factorize(&self.k)?;
        statics.solve(asm.matrix(&self.k), &f, &mut u);
        Ok(u)
    }
}

/// The system the integrator steps and its unit load: the reduced one if modal.
fn stepped<'a>(
    modal: &'a Option<Modal>,
    full: &'a Structure,
    unit_load: &'a [f64],
) -> (&'a Structure, &'a [f64]) {
    match modal {
        Some(r) => (&r.structure, &r.unit_load),
        None => (full, unit_load),
    }
}

/// The load f(t) = force(t) · unit.
fn scaled<'a>(
    force: impl Fn(f64) -> f64 + 'a,
    unit: &'a [f64],
) -> impl FnMut(f64, &mut [f64]) + 'a {
    move |t, f| {
        let x = force(t);
        f.iter_mut().zip(unit).for_each(|(f, u)| *f = x * u);
    }
}

/// Line region of the diaphragm.
const DIAPHRAGM: u16 = 0;

/// Consistent nodal loads (free dofs) of a unit total force spread as a uniform pressure over
/// the diaphragm, normal to it and into the cavity.
fn diaphragm_unit_load(disc: &Discretization, bc: &Dirichlet) -> Vec<f64> {
    let (mut f, length) = disc.line_pressure(DIAPHRAGM, 1.0);
    f.iter_mut().for_each(|x| *x /= length);
    let mut reduced = vec![0.0; bc.n_free()];
    bc.reduce(&f, &mut reduced);
    reduced
}
