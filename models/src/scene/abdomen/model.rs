//! What the abdomen builds at initialization: the configuration resolved to an outline, the
//! mesh, per-tissue properties, the assembled stiffness, mass and damping, the supports, the
//! dynamic system with its integrator, the load pattern of the pressing force and the output
//! plan — and for a reduced `model_order` the reduced system ([`Modal`]) the integrator
//! steps instead of the full one: a modal basis at linear kinematics, the hyper-reduced
//! model of [`super::training`] at finite strain.

use super::config::PelvisConfig;
use super::discretization::{self, Choice, Discretization, FieldView, Recovery};
use super::mesher;
use super::outputs::{self, Field, OutputPlan, Rows};
use super::training::{self, Hyper, Range};
use super::variables::{
    tissue_vr, CONFIGURATION, COSTAL_MARGIN, ELEMENT, FORMULATION, GRADING, INTEGRATOR, KINEMATICS,
    MAX_STEP, MODEL_ORDER, MODES, SUBDIVISIONS, TARGET_TRIANGLES, TISSUES, TRAINING_FREQUENCY,
    TRAINING_PRESS, WALL_SUPPORT,
};
use std::sync::Arc;

use crate::assembly::plane::{Continuum, PlaneProperties, Truss};
use crate::assembly::quadratic_plane::{self, Active, BodyForces, PlaneBody, SharedTension};
use crate::assembly::Dirichlet;
use crate::element::Elastic;
use crate::error::ModelError;
use crate::scene::{SceneError, Values};
use crate::solve::newton::{Equations, Newton, Settings};
use crate::solve::{
    Checkpoint, Damping, Factorization, Indicator, Integrator, IntegratorKind, ModalBasis, Motion,
    Reduction, Statics, Structure,
};

/// Everything built at initialization.
pub struct Model {
    pub disc: Discretization,
    pub props: PlaneProperties,
    k: Vec<f64>,
    /// The full system on the free dofs.
    pub structure: Structure,
    /// Steps the full system, or the reduced one when `modal` is present.
    pub integrator: Box<dyn Integrator + Send + Sync>,
    /// Load vector (free dofs) of a unit pressing force ([`press_pattern`]).
    pub unit_load: Vec<f64>,
    /// The pressing force per unit active tension of the diaphragm at rest, Θ₀ (N/mm per
    /// N/mm), and the active tension the finite-strain forces read.
    theta: f64,
    tension: Arc<SharedTension>,
    /// The finite-strain body (None at linear kinematics).
    pub(super) body: Option<Arc<BodyForces>>,
    /// What a hyper-reduced model is trained for, and the model's largest step (which
    /// bounds the training's, [`training::step`]).
    training: (Range, f64),
    /// Whether the abdominal wall is held (the hyper-reduced model trains otherwise then).
    fixed_wall: bool,
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
    /// The error indicator, its stiffness factorized on first request, and the state and
    /// load it reads (free dofs: u, v, a, f).
    indicator: Option<(Indicator, [Vec<f64>; 4])>,
}

/// The reduced-order system: the basis, the projected matrices, the projected unit load
/// and the output rows.
#[derive(Debug)]
pub struct Modal {
    pub basis: ModalBasis,
    pub structure: Structure,
    pub unit_load: Vec<f64>,
    /// The outputs as rows in the coordinates (linear kinematics; at finite strain the
    /// outputs are read from the expanded field).
    rows: Option<Rows>,
    /// The largest principal strain of each basis vector, for [`Model::strain_bound`]
    /// (linear kinematics).
    strains: Vec<f64>,
    /// The hyper-reduction of a finite-strain model.
    pub hyper: Option<Hyper>,
    /// The order and the `modes` parameter the basis was built with.
    order: Order,
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

/// The dofs held fixed: spine and pelvic bone, the abdominal wall when `wall` is `fixed`,
/// and the costal margin (the node where wall and diaphragm meet) when `margin` is.
fn supports(disc: &Discretization, wall: &str, margin: &str) -> Result<Vec<usize>, SceneError> {
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
    match margin {
        "free" => {}
        "fixed" => {
            let sets = disc.mesh().node_sets();
            let wall = sets.get("abdominal_wall")?;
            let diaphragm = sets.get("diaphragm")?;
            fixed.extend(
                diaphragm
                    .iter()
                    .filter(|n| wall.contains(n))
                    .flat_map(|n| [2 * n, 2 * n + 1]),
            );
        }
        other => return Err(margin_error(other)),
    }
    Ok(fixed)
}

/// The error for a `costal_margin` value other than `fixed` or `free`.
pub fn margin_error(value: &str) -> SceneError {
    SceneError::Config(format!("costal_margin `{value}`: use `fixed` or `free`"))
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

/// A reduced `model_order`: a modal basis of the linear model, or the hyper-reduced
/// finite-strain model trained at initialization ([`training`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Order {
    Modal(Reduction),
    Hyper,
}

/// The reduced order of a `model_order` value: `None` for `full`.
pub fn order(value: &str) -> Result<Option<Order>, SceneError> {
    match value {
        "full" => Ok(None),
        "modal" => Ok(Some(Order::Modal(Reduction::Ritz))),
        "eigenmodes" => Ok(Some(Order::Modal(Reduction::Eigenmodes))),
        "eigenmodes_truncated" => Ok(Some(Order::Modal(Reduction::Truncated))),
        "reduced" => Ok(Some(Order::Hyper)),
        other => Err(SceneError::Config(format!(
            "model_order `{other}`: use `full`, `modal`, `eigenmodes`, `eigenmodes_truncated` \
             or `reduced`"
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
            choice.element.bytes_per_triangle(),
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
        let fixed = supports(
            &disc,
            values.string(WALL_SUPPORT)?,
            values.string(COSTAL_MARGIN)?,
        )?;
        let bc = Dirichlet::new(asm, &fixed)?;
        let tension = Arc::new(SharedTension::default());
        let body = disc.body_forces(&props, DIAPHRAGM, &tension);
        let factorization = Factorization::plane(bc.n_free(), body.is_none());
        let mut structure = Structure::new(bc, &k, &m, &lumped, Damping::NONE, factorization)?;
        structure.set_damping_matrix(&c);
        if let Some(body) = &body {
            structure =
                structure.with_internal_forces(quadratic_plane::internal_forces(body.clone()));
        }
        let (unit_load, theta) = press_pattern(&disc, &props, structure.dirichlet())?;
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
            theta,
            tension,
            body,
            training: (
                Range {
                    press: values.real(TRAINING_PRESS),
                    frequency: values.real(TRAINING_FREQUENCY),
                },
                values.real(MAX_STEP),
            ),
            fixed_wall: values.string(WALL_SUPPORT)? == "fixed",
            fixed,
            modal: None,
            indicator: None,
        };
        model.modal = match order(values.string(MODEL_ORDER)?)? {
            None => None,
            Some(reduced) => Some(model.reduced(reduced, modes(values)?)?),
        };
        Ok(model)
    }

    /// The reduced system with a basis of (at most) `count` vectors for the current
    /// matrices: for the pressing load's pattern at linear kinematics, by training at
    /// finite strain ([`Order::Hyper`]).
    fn reduced(&self, order: Order, count: usize) -> Result<Modal, SceneError> {
        let reduction = match order {
            Order::Modal(reduction) => reduction,
            Order::Hyper => return self.hyper_reduced(count),
        };
        let basis = ModalBasis::new(&self.structure, reduction, count, &self.unit_load)?;
        let mut u = vec![0.0; self.u_full.len()];
        let strains = (0..basis.dim())
            .map(|j| {
                self.structure.dirichlet().expand(basis.column(j), &mut u);
                self.view(&u).largest_strain()
            })
            .collect();
        Ok(Modal {
            rows: Some(Rows::new(
                self.field(&self.u_full),
                &basis,
                self.structure.dirichlet(),
            )),
            strains,
            structure: basis.reduce(&self.structure)?,
            unit_load: self.projected_load(&basis),
            basis,
            order,
            count,
            hyper: None,
        })
    }

    /// The hyper-reduced finite-strain system ([`training`]).
    fn hyper_reduced(&self, count: usize) -> Result<Modal, SceneError> {
        let Some(body) = &self.body else {
            return Err(SceneError::Config(
                "model_order = \"reduced\" is the hyper-reduced finite-strain model: use \
                 kinematics = \"finite\" (at linear kinematics model_order = \"modal\" is \
                 the reduced model)"
                    .into(),
            ));
        };
        let (range, max_step) = self.training;
        let (basis, hyper) = training::train(self, body, range, max_step, count)?;
        Ok(Modal {
            rows: None,
            strains: Vec::new(),
            structure: training::structure(&self.structure, &basis, &hyper.forces)?,
            unit_load: self.projected_load(&basis),
            basis,
            order: Order::Hyper,
            count,
            hyper: Some(hyper),
        })
    }

    /// Φᵀ f of the unit pressing load.
    fn projected_load(&self, basis: &ModalBasis) -> Vec<f64> {
        let mut unit_load = vec![0.0; basis.dim()];
        basis.project(&self.unit_load, &mut unit_load);
        unit_load
    }

    /// Prepares the integrator for steps of `dt` and starts it at rest at `t0` in equilibrium
    /// with the pressing force `force(t)` (N/mm) there: undeformed where the force is zero,
    /// else at the static displacement under it (a start in the middle of a press is not a
    /// step load).
    pub fn start(
        &mut self,
        t0: f64,
        dt: f64,
        force: impl Fn(f64) -> f64,
    ) -> Result<(), SceneError> {
        let initial = force(t0);
        let n_free = self.structure.n();
        let mut u0 = vec![0.0; n_free];
        if initial != 0.0 {
            let u = self.static_displacement(initial)?;
            self.structure.dirichlet().reduce(&u, &mut u0);
        }
        if let Some(r) = &self.modal {
            let mut q = vec![0.0; r.basis.dim()];
            r.basis.coordinates(self.structure.mass(), &u0, &mut q);
            u0 = q;
        }
        let (structure, unit) = stepped(&self.modal, &self.structure, &self.unit_load);
        let contracting = self
            .disc
            .choice
            .finite
            .then_some((&*self.tension, self.theta));
        self.integrator.prepare(structure, dt)?;
        let mut load = pressing(force, unit, contracting);
        let at_rest = vec![0.0; u0.len()];
        self.integrator
            .start(structure, t0, &u0, &at_rest, &mut load)?;
        self.expanded = false;
        Ok(())
    }

    /// Puts an integrator checkpoint back (see [`Checkpoint`]) with the diaphragm's active
    /// tensions of its last step and of its kept tangent ([`tension`](Self::tension)): the
    /// integrator prepared for its step on the stepped system (full or reduced), then
    /// resumed (refactorizing a kept tangent at its own tension).
    pub fn resume(
        &mut self,
        checkpoint: &Checkpoint,
        [now, at_tangent]: [f64; 2],
    ) -> Result<(), SceneError> {
        self.tension.set(at_tangent);
        let (structure, _) = stepped(&self.modal, &self.structure, &self.unit_load);
        self.integrator.prepare(structure, checkpoint.dt)?;
        self.integrator.resume(structure, checkpoint)?;
        self.tension.set(now);
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
        let contracting = self
            .disc
            .choice
            .finite
            .then_some((&*self.tension, self.theta));
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
        let mut load = pressing(force, unit, contracting);
        for _ in 0..steps {
            step_halving(integrator.as_mut(), structure, &mut load, dt, HALVINGS)?;
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
    /// full order and for the hyper-reduced finite-strain model.
    pub fn strain_bound(&self) -> Option<f64> {
        let r = self.modal.as_ref().filter(|r| r.rows.is_some())?;
        let q = &self.integrator.state().u;
        Some(q.iter().zip(&r.strains).map(|(q, s)| q.abs() * s).sum())
    }

    /// The error indicator η of the state after the last step ([`Indicator`]): the full
    /// model's residual there under the pressing force `force(τ)` at integrator time τ — the
    /// modal coordinates expanded in a reduced order — relative to the displacement, in the
    /// energy norm of the stiffness at rest; infinite where the expanded state inverts an
    /// element. The first request factorizes that stiffness; each costs one full-order
    /// evaluation of the internal forces and one solve.
    pub fn indicator(&mut self, force: impl Fn(f64) -> f64) -> Result<f64, SceneError> {
        let n = self.structure.n();
        let (indicator, [u, v, a, f]) = match &mut self.indicator {
            Some(i) => i,
            slot => slot.insert((
                Indicator::new(&self.structure)?,
                std::array::from_fn(|_| vec![0.0; n]),
            )),
        };
        let state = self.integrator.state();
        for (full, q) in [
            (&mut *u, &state.u),
            (&mut *v, &state.v),
            (&mut *a, &state.a),
        ] {
            match &self.modal {
                Some(r) => r.basis.expand(q, full),
                None => full.copy_from_slice(q),
            }
        }
        let contracting = self
            .disc
            .choice
            .finite
            .then_some((&*self.tension, self.theta));
        pressing(force, &self.unit_load, contracting)(state.t, f);
        let motion = Motion { u, v, a };
        match indicator.estimate(&self.structure, f, motion) {
            // The expanded state turns an element inside out: as far from the full model's
            // states as can be.
            Err(ModelError::Inverted { .. }) => Ok(f64::INFINITY),
            other => Ok(other?),
        }
    }

    /// The displacement of all dofs as of the last [`expand`](Self::expand).
    pub fn u_full(&self) -> &[f64] {
        &self.u_full
    }

    /// The outputs after the last step (see [`OutputPlan::compute`]); the cavity-wide ones
    /// only if `cavity`.
    pub fn outputs(&mut self, press: f64, cavity: bool) -> [f64; outputs::COUNT] {
        let rows = self.modal.as_mut().and_then(|r| r.rows.as_mut());
        match rows {
            Some(rows) => rows.evaluate(&self.integrator.state().u),
            None => self.expand(),
        }
        if cavity {
            self.expand();
        }
        let field = self.field(&self.u_full);
        let cavity = cavity.then_some(&field);
        match self.modal.as_ref().and_then(|r| r.rows.as_ref()) {
            Some(rows) => self.outputs.compute(rows, cavity, press),
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
    /// effective matrix at its current step. A reduced model builds (or trains) its basis
    /// again and carries its integrator's state and history onto it, each vector projected
    /// (q = Φᵀ M u): the scheme goes on as the full one does, not from a restart.
    pub fn set_properties(&mut self, props: PlaneProperties) -> Result<(), SceneError> {
        self.disc.stiffness(&props, &mut self.k);
        self.structure.set_stiffness(&self.k);
        self.body = self.disc.body_forces(&props, DIAPHRAGM, &self.tension);
        if let Some(body) = &self.body {
            self.structure
                .set_internal_forces(quadratic_plane::internal_forces(body.clone()));
        }
        self.recovery = self.disc.recovery(&props);
        self.props = props;
        self.expanded = false;
        self.indicator = None;
        let dt = self.integrator.dt();
        let Some(old) = &self.modal else {
            self.integrator.prepare(&self.structure, dt)?;
            return Ok(());
        };
        let checkpoint = self.integrator.checkpoint();
        let new = self.reduced(old.order, old.count)?;
        let mass = self.structure.mass();
        let mut u = vec![0.0; self.structure.n()];
        let moved = checkpoint.map(&mut |q| {
            old.basis.expand(q, &mut u);
            let mut projected = vec![0.0; new.basis.dim()];
            new.basis.coordinates(mass, &u, &mut projected);
            projected
        });
        self.integrator.prepare(&new.structure, dt)?;
        let resumed = self.integrator.resume(&new.structure, &moved);
        self.modal = Some(new);
        resumed?;
        Ok(())
    }

    /// The load pattern of a unit pressing force (free dofs).
    pub fn unit_load(&self) -> &[f64] {
        &self.unit_load
    }

    /// The diaphragm's active tension of the last step and the one its kept tangent was
    /// taken at (N per mm of depth; 0 at linear kinematics).
    pub fn tension(&self) -> [f64; 2] {
        [self.tension.get(), self.tension.at_tangent()]
    }

    /// The static displacement (all dofs) under a constant pressing force `force` (N/mm):
    /// one solve with K, or at finite strain Newton's method (load increments cut back
    /// where it does not converge), the diaphragm contracting (force > 0) or drawn out.
    pub fn static_displacement(&self, force: f64) -> Result<Vec<f64>, SceneError> {
        let asm = &self.disc.asm;
        if self.body.is_some() {
            let mut states = self.static_ramp(&[force])?;
            return Ok(states.pop().expect("one state per force"));
        }
        let mut f = vec![0.0; self.disc.n_dofs()];
        self.structure.dirichlet().expand(&self.unit_load, &mut f);
        f.iter_mut().for_each(|x| *x *= force);
        let mut u = vec![0.0; f.len()];
        let once = Factorization::plane(self.structure.n(), false);
        let mut statics = Statics::new(asm, &self.fixed, once)?;
        statics.factorize(&self.k)?;
        statics.solve(asm.matrix(&self.k), &f, &mut u);
        Ok(u)
    }

    /// At finite strain, the static displacements (all dofs) under the pressing forces
    /// `forces` (N/mm) in turn, each solve by Newton's method from the last equilibrium.
    pub fn static_ramp(&self, forces: &[f64]) -> Result<Vec<Vec<f64>>, SceneError> {
        let materials = discretization::materials(&self.props);
        let Some(body) = self.disc.body(&materials, &self.props) else {
            return Err(SceneError::Config(
                "a static ramp needs finite kinematics".into(),
            ));
        };
        let asm = &self.disc.asm;
        let mut unit = vec![0.0; self.disc.n_dofs()];
        self.structure
            .dirichlet()
            .expand(&self.unit_load, &mut unit);
        let mut newton = Newton::new(
            asm,
            &self.fixed,
            Factorization::plane(self.structure.n(), false),
            Settings::default(),
        )?;
        let mut contracting = Contracting {
            body,
            from: 0.0,
            to: 0.0,
        };
        let (mut u, zero) = (vec![0.0; unit.len()], vec![0.0; unit.len()]);
        let mut states = Vec::with_capacity(forces.len());
        for &force in forces {
            let f: Vec<f64> = unit.iter().map(|x| x * force.min(0.0)).collect();
            contracting.to = force.max(0.0) / self.theta;
            newton.solve(&mut contracting, &mut u, &zero, &f)?;
            contracting.from = contracting.to;
            states.push(u.clone());
        }
        Ok(states)
    }

    /// The full model's states (all dofs) after each step of a press
    /// F(t) = `amplitude` (1 − cos 2π `frequency` t)/2 from rest over the share `span` of
    /// its period (1: the whole press; ½: up to its peak), stepped at `dt` by an integrator
    /// of the model's kind, with F at each (finite-strain training). The press runs on a
    /// [`detached`](Self::detached) structure: presses may run side by side.
    pub fn press_run(
        &self,
        [amplitude, frequency, dt, span]: [f64; 4],
    ) -> Result<(Vec<Vec<f64>>, Vec<f64>), SceneError> {
        let own = self.detached()?;
        let (free, presses) = self.press_states(
            &own.structure,
            &own.tension,
            &self.unit_load,
            [amplitude, frequency, dt, span],
        )?;
        let bc = self.structure.dirichlet();
        let states = free
            .iter()
            .map(|u| {
                let mut all = vec![0.0; self.u_full.len()];
                bc.expand(u, &mut all);
                all
            })
            .collect();
        Ok((states, presses))
    }

    /// Whether the abdominal wall is held.
    pub(super) fn fixed_wall(&self) -> bool {
        self.fixed_wall
    }

    /// The full finite-strain structure with a diaphragm tension of its own.
    pub(super) fn detached(&self) -> Result<Detached, SceneError> {
        let tension = Arc::new(SharedTension::default());
        let body = self.body_reading(&tension)?;
        let structure = self
            .structure
            .clone()
            .with_internal_forces(quadratic_plane::internal_forces(body));
        Ok(Detached { structure, tension })
    }

    /// The finite-strain body for the current properties, its diaphragm's active tension
    /// read from `tension`.
    pub(super) fn body_reading(
        &self,
        tension: &Arc<SharedTension>,
    ) -> Result<Arc<BodyForces>, SceneError> {
        self.disc
            .body_forces(&self.props, DIAPHRAGM, tension)
            .ok_or_else(|| SceneError::Config("a press run needs finite kinematics".into()))
    }

    /// The states (its own unknowns) of structure `s` — the full one or a reduced one, with
    /// the unit load `unit` on its unknowns, its forces reading the diaphragm's tension
    /// from `tension` — after each step of a press of `amplitude` (N/mm) at `frequency`
    /// (Hz) over the share `span` of its period, stepped at `dt` (s), as
    /// [`press_run`](Self::press_run)'s, with F at each.
    pub(super) fn press_states(
        &self,
        s: &Structure,
        tension: &SharedTension,
        unit: &[f64],
        [amplitude, frequency, dt, span]: [f64; 4],
    ) -> Result<(Vec<Vec<f64>>, Vec<f64>), SceneError> {
        let force =
            |t: f64| amplitude * 0.5 * (1.0 - (2.0 * std::f64::consts::PI * frequency * t).cos());
        let mut integrator = self.integrator.kind().create();
        integrator.prepare(s, dt)?;
        let mut load = pressing(force, unit, Some((tension, self.theta)));
        let rest = vec![0.0; s.n()];
        integrator.start(s, 0.0, &rest, &rest, &mut load)?;
        let steps = (span / (frequency * dt)).ceil() as usize;
        let (mut states, mut presses) = (Vec::with_capacity(steps), Vec::with_capacity(steps));
        for _ in 0..steps {
            step_halving(integrator.as_mut(), s, &mut load, dt, HALVINGS)?;
            let state = integrator.state();
            states.push(state.u.clone());
            presses.push(force(state.t));
        }
        Ok((states, presses))
    }

    /// Sets the diaphragm's active tension of a pressing force `force` (N/mm; none when
    /// drawn out), as the load of a step does.
    pub fn set_press(&self, force: f64) {
        self.tension.set(force.max(0.0) / self.theta);
    }
}

/// The full finite-strain structure with a diaphragm tension of its own ([`Model::detached`]).
pub(super) struct Detached {
    pub structure: Structure,
    pub tension: Arc<SharedTension>,
}

/// The body at finite strain with the diaphragm's active tension going from `from` to `to`
/// along Newton's load increments.
struct Contracting<'a> {
    body: PlaneBody<'a>,
    from: f64,
    to: f64,
}

impl Equations for Contracting<'_> {
    fn at_load_fraction(&mut self, s: f64) {
        self.body.active = Some(Active {
            region: DIAPHRAGM,
            tension: self.from + s * (self.to - self.from),
        });
    }

    fn add_internal(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        self.body.add_internal(u, f, k)
    }
}

/// Times a finite-strain step may be halved ([`step_halving`]).
const HALVINGS: u32 = 4;

/// One step of `dt`; at finite strain a step whose Newton iterations do not converge is
/// taken again from where it started as two steps of dt/2, each halved again if need be,
/// up to `depth` times (the integrator prepared for the shorter step and for `dt` after:
/// Houbolt restarts its history with its starter). Measured: where the membranes go slack
/// at the end of a press of a free, soft abdominal wall, 10 ms steps fail and 5 ms ones do
/// not.
fn step_halving(
    integrator: &mut (dyn Integrator + Send + Sync),
    structure: &Structure,
    load: &mut dyn FnMut(f64, &mut [f64]),
    dt: f64,
    depth: u32,
) -> Result<(), ModelError> {
    match integrator.step(structure, load) {
        Err(ModelError::NotConverged { .. } | ModelError::Inverted { .. })
            if depth > 0 && structure.is_nonlinear() =>
        {
            integrator.prepare(structure, 0.5 * dt)?;
            for _ in 0..2 {
                step_halving(integrator, structure, load, 0.5 * dt, depth - 1)?;
            }
            integrator.prepare(structure, dt)
        }
        other => other,
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

/// The load of the pressing force F(t) = `force(t)` with its pattern `unit`
/// ([`press_pattern`]): f(t) = F(t) · unit — or at finite strain, `contracting` given, the
/// diaphragm's active tension T = F/Θ₀ for F > 0 (set where the internal forces read it;
/// a muscle pulls, it does not push) and the load F · unit for F < 0 (drawn out: the
/// suction of the chest, a dead load).
fn pressing<'a>(
    force: impl Fn(f64) -> f64 + 'a,
    unit: &'a [f64],
    contracting: Option<(&'a SharedTension, f64)>,
) -> impl FnMut(f64, &mut [f64]) + 'a {
    move |t, f| {
        let mut x = force(t);
        if let Some((tension, theta)) = contracting {
            tension.set(x.max(0.0) / theta);
            x = x.min(0.0);
        }
        f.iter_mut().zip(unit).for_each(|(f, u)| *f = x * u);
    }
}

/// Line region of the diaphragm.
const DIAPHRAGM: u16 = 0;

/// The pressing force's load pattern: the forces a contracting diaphragm exerts at rest
/// ([`Discretization::contraction`]) per unit of their resultant on the free dofs — so that
/// a pressing force F is F times this pattern, a resultant F into the cavity — and that
/// resultant per unit tension, Θ₀ (the turning of the diaphragm between its supports:
/// sin θ₁ + sin θ₂ for a dome leaving its supports at θ₁, θ₂ from the horizontal).
fn press_pattern(
    disc: &Discretization,
    props: &PlaneProperties,
    bc: &Dirichlet,
) -> Result<(Vec<f64>, f64), SceneError> {
    let f = disc.contraction(DIAPHRAGM, props)?;
    let mut reduced = vec![0.0; bc.n_free()];
    bc.reduce(&f, &mut reduced);
    let resultant = bc
        .free()
        .iter()
        .zip(&reduced)
        .fold([0.0; 2], |mut r, (&d, x)| {
            r[d % 2] += x;
            r
        });
    let theta = resultant[0].hypot(resultant[1]);
    if theta.is_nan() || theta <= 0.0 {
        return Err(SceneError::Config(
            "the diaphragm is straight between fixed supports: its contraction presses on \
             nothing (give the dome a rise)"
                .into(),
        ));
    }
    reduced.iter_mut().for_each(|x| *x /= theta);
    Ok((reduced, theta))
}
