//! The abdomen scene (seed 003 §5.4): a 2D plane-strain model of the midsagittal section of
//! the abdominal cavity, pressed by the contracting diaphragm, for comparing pelvis
//! configurations by the load on the pelvic floor. This module is the [`Scene`]
//! implementation. Below it, lowest first: the variables and their defaults (`variables`),
//! the outline ([`geometry`], [`anatomy`], [`config`]), the mesh ([`mesher`]), the elements
//! and stresses ([`discretization`], `outputs`), the parameters read for a build
//! (`parameters`), the full-order system (`build`), the load and the steps (`stepping`),
//! the hyper-reduced model's training ([`training`]) and the reduced orders (`reduced`),
//! the system the scene steps (`simulation`), and where it stops being valid (`validity`).
//! The defaults' sources and the theory are in the repository's docs/theory/abdomen.md.

pub mod anatomy;
mod build;
pub mod config;
pub mod discretization;
pub mod geometry;
pub mod mesher;
mod outputs;
mod parameters;
mod pressure;
mod reduced;
mod simulation;
mod state;
mod stepping;
pub mod training;
mod validity;
mod variables;

pub use state::State;

use config::{PelvisConfig, ANATOMY};
use discretization::FieldView;
use mesher::Meshed;
use parameters::properties;
use pressure::Found;
use simulation::Simulation;
use variables::{
    table, CAVITY_PRESSURE, COSTAL_MARGIN, ELEMENT, ERROR_INDICATOR, FIRST_OUTPUT, FORMULATION,
    INTEGRATOR, KINEMATICS, MAX_STEP, MEMBRANE_LAW, MEMORY_LIMIT, MODEL_ORDER, PRESS_AMPLITUDE,
    PRESS_FORCE, PRESS_FREQUENCY, PRESS_LOAD, PRESS_MODE, PRESS_MUSCLES, TARGET_PRESSURE,
    TISSUE_BASE, WALL_SUPPORT,
};

use super::{
    check_step, megabytes, GeneratedConfiguration, GeneratorParameter, Inert, Scene, SceneError,
    SceneState, Values, ValuesState, Variable,
};
use crate::budget;
use crate::solve::{IntegratorKind, ModalBasis, Structure};

/// What the scene is, in one line (the FMUs' `description`).
pub const DESCRIPTION: &str = "2D midsagittal finite-element model of the abdominal cavity \
(6- or 3-node triangles with line-element membranes; linear or finite strain; full, modal or \
hyper-reduced order): pelvis/spine configuration, per-tissue stiffness, a press driven by the \
muscles' force or by the contents' pressure (intra-abdominal pressure), pelvic-floor stress \
(seed 003 §5.4)";

/// Most substeps one communication step may take: a step that would need more is refused
/// (it names `max_step` and h) instead of running for hours.
pub const MAX_SUBSTEPS: f64 = 100_000.0;

/// Steps shorter than this share of `max_step` only move the time (the abdomen's
/// `do_step`): at the default 10 ms, steps below 10 ns.
pub const TINY_STEP: f64 = 1e-6;

/// The scene. Build with [`Abdomen::new`], set parameters, `initialize`, then step.
#[derive(Debug)]
pub struct Abdomen {
    values: Values,
    sim: Option<Simulation>,
    /// The outputs after the last step, once requested; the cavity-wide ones are NaN
    /// until one of them is requested.
    outputs: Option<[f64; outputs::COUNT]>,
    stiffness_changed: bool,
    /// The values of the model's last build or stiffness update (what its matrices are of).
    applied: Option<ValuesState>,
    time: f64,
    /// The time the state lags behind `time` after steps too short to integrate (s).
    lag: f64,
    /// Where the press's phase was last set: (time in s, phase in rad); see [`Press`].
    phase_origin: [f64; 2],
    /// In `press_mode = "pressure"`, the pressing force of the last step and the slope of
    /// the contents' pressure against it there ([`pressure`]).
    found: Found,
    /// Warnings not yet taken, and whether the strain warning was given in this run.
    warnings: Vec<String>,
    warned_validity: bool,
    /// Whether this run has warned of a target the relaxed muscles stayed above.
    warned_relaxed: bool,
    /// The parameters already warned of in this run for having no effect.
    inert: Inert,
}

impl Default for Abdomen {
    fn default() -> Self {
        Self::new()
    }
}

impl Abdomen {
    /// A scene with the built-in defaults.
    pub fn new() -> Self {
        Self {
            values: Values::new(table()),
            sim: None,
            outputs: None,
            stiffness_changed: false,
            applied: None,
            time: 0.0,
            lag: 0.0,
            phase_origin: [0.0; 2],
            found: pressure::AT_REST,
            warnings: Vec::new(),
            warned_validity: false,
            warned_relaxed: false,
            inert: Inert::default(),
        }
    }

    /// A scene with the string values `strings` and the real values `reals` set by name,
    /// initialized at t = 0.
    pub fn initialized(
        strings: &[(&str, &str)],
        reals: &[(&str, f64)],
    ) -> Result<Self, SceneError> {
        let mut s = Self::new();
        for (name, value) in strings {
            s.set_str(name, value)?;
        }
        for (name, value) in reals {
            s.set(name, *value)?;
        }
        s.initialize(0.0)?;
        Ok(s)
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

    /// The 3-node mesh (for `tri6`, the corners) with its quality figures, after
    /// initialization.
    pub fn meshed(&self) -> Option<&Meshed> {
        self.sim.as_ref().map(|m| &m.full.disc.meshed)
    }

    /// The current nodal displacements (all dofs; a modal model expands its coordinates
    /// here) with the meshes and stresses, after initialization.
    pub fn field(&mut self) -> Option<FieldView<'_>> {
        let m = self.sim.as_mut()?;
        m.expand();
        Some(m.full.view(m.u_full()))
    }

    /// A displacement of all dofs, e.g. one from [`Abdomen::static_displacement`], with the
    /// meshes and stresses.
    pub fn view<'a>(&'a self, u: &'a [f64]) -> Result<FieldView<'a>, SceneError> {
        let m = self.built("view")?;
        if u.len() != m.full.disc.n_dofs() {
            return Err(SceneError::InvalidArgument {
                name: "displacement length",
                value: u.len() as f64,
                reason: "must be the model's number of dofs",
            });
        }
        Ok(m.full.view(u))
    }

    /// The reduction basis of a reduced model order (its kind, Ritz values and
    /// construction time), after initialization.
    pub fn modal_basis(&self) -> Option<&ModalBasis> {
        self.sim.as_ref()?.reduced.as_ref().map(|r| &r.basis)
    }

    /// The hyper-reduction of `model_order = "reduced"` (its fit, range and training time),
    /// after initialization.
    pub fn hyper(&self) -> Option<&training::HyperReduction> {
        self.sim.as_ref()?.reduced.as_ref()?.hyper.as_ref()
    }

    /// Starts the built model again, at rest at `start_time` under the press the inputs
    /// now give (in equilibrium with it, as [`Scene::initialize`] does), without building
    /// the mesh, the matrices or a reduced model's training again: a sweep over the press
    /// reuses one build. A pending stiffness change is applied first; the warnings start
    /// afresh with the run.
    pub fn restart(&mut self, start_time: f64) -> Result<(), SceneError> {
        if self.stiffness_changed {
            self.update_stiffness()?;
        }
        self.warnings.clear();
        let inert = self.inert.check_all(&self.values, parameters::inert);
        self.warnings.extend(inert);
        let target = self.target();
        let press = self.run_press();
        let dt = self.values.real(MAX_STEP);
        let m = self
            .sim
            .as_mut()
            .ok_or_else(|| SceneError::NotInitialized {
                name: "restart".into(),
            })?;
        match target {
            Some(p) => self.found = m.start_at_pressure(start_time, dt, p, pressure::AT_REST)?,
            None => m.start(start_time, dt, |t| press.at(t))?,
        }
        self.time = start_time;
        self.lag = 0.0;
        self.phase_origin = [0.0; 2];
        self.outputs = None;
        self.warned_validity = false;
        self.warned_relaxed = false;
        self.check_validity();
        Ok(())
    }

    /// The full-order equation of motion on the free dofs and the load of a unit pressing
    /// force (N on each free dof per N/mm), after initialization — in every model order, for
    /// solving the same system elsewhere (the peer benchmark exports it).
    pub fn system(&self) -> Option<(&Structure, &[f64])> {
        let m = self.sim.as_ref()?;
        Some((&m.full.structure, m.full.unit_load()))
    }

    /// Newton iterations of the last time step (0 at linear kinematics), after
    /// initialization.
    pub fn newton_iterations(&self) -> Option<usize> {
        Some(self.sim.as_ref()?.integrator.newton_iterations())
    }

    /// Tangent factorizations in the last time step's Newton iterations (0 at linear
    /// kinematics), after initialization.
    pub fn newton_factorizations(&self) -> Option<usize> {
        Some(self.sim.as_ref()?.integrator.newton_factorizations())
    }

    /// Current simulation time (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The static displacement (all dofs) under a constant pressing force `force` (N/mm).
    pub fn static_displacement(&self, force: f64) -> Result<Vec<f64>, SceneError> {
        stepping::static_displacement(&self.built("static_displacement")?.full, force)
    }

    /// The outputs (table order from `floor_stress_mean` to `press_total`, then
    /// `cavity_pressure`) for a displacement field of all dofs, e.g. one from
    /// [`Abdomen::static_displacement`].
    pub fn evaluate(&self, u_full: &[f64], press: f64) -> Result<Vec<f64>, SceneError> {
        self.view(u_full)?;
        let m = self.built("evaluate")?;
        let field = m.full.field(u_full);
        Ok(m.full.plan.compute(&field, Some(&field), press).to_vec())
    }

    /// The pressing force as the inputs now give it.
    fn pressing(&self) -> Press {
        if self.target().is_some() {
            return Press {
                force: self.found.force,
                amplitude: 0.0,
                frequency: 0.0,
                origin: self.phase_origin,
            };
        }
        Press {
            force: self.values.real(PRESS_FORCE),
            amplitude: self.values.real(PRESS_AMPLITUDE),
            frequency: self.values.real(PRESS_FREQUENCY),
            origin: self.phase_origin,
        }
    }

    /// The contents' mean pressure the press holds (MPa), in `press_mode = "pressure"`.
    fn target(&self) -> Option<f64> {
        (self.values.string(PRESS_MODE) == Ok("pressure"))
            .then(|| self.values.real(TARGET_PRESSURE))
    }

    /// The press of a run from its start: the phase 2πft on the caller's time.
    fn run_press(&self) -> Press {
        Press {
            origin: [0.0; 2],
            ..self.pressing()
        }
    }

    /// A model built for the current values, at rest at `start_time` under the pressing
    /// force there.
    fn started(&self, start_time: f64) -> Result<(Simulation, Found), SceneError> {
        let mut sim = Simulation::build(&self.values)?;
        let press = self.run_press();
        let dt = self.values.real(MAX_STEP);
        let found = match self.target() {
            Some(p) => sim.start_at_pressure(start_time, dt, p, pressure::AT_REST)?,
            None => {
                sim.start(start_time, dt, |t| press.at(t))?;
                pressure::AT_REST
            }
        };
        Ok((sim, found))
    }

    /// The built model, or an error naming what needed it.
    fn built(&self, what: &str) -> Result<&Simulation, SceneError> {
        self.sim
            .as_ref()
            .ok_or_else(|| SceneError::NotInitialized { name: what.into() })
    }

    fn update_stiffness(&mut self) -> Result<(), SceneError> {
        let props = properties(&self.values)?;
        let m = self
            .sim
            .as_mut()
            .ok_or_else(|| SceneError::NotInitialized {
                name: "do_step".into(),
            })?;
        m.set_properties(props)?;
        self.applied = Some(self.values.save());
        self.stiffness_changed = false;
        self.check_locking();
        Ok(())
    }

    /// The locking warning at the contents' current ν ([`validity::locking`]).
    fn check_locking(&mut self) {
        let Some(m) = &self.sim else {
            return;
        };
        let nu = self.values.real(TISSUE_BASE + 1);
        let names = (
            self.values.string(ELEMENT).unwrap_or_default(),
            self.values.string(FORMULATION).unwrap_or_default(),
        );
        if let Some(w) = validity::locking(m, nu, names) {
            self.warnings.push(w);
        }
    }

    /// Once per run, the kinematics' validity warning ([`validity::kinematics`]).
    fn check_validity(&mut self) {
        let press = self.pressing();
        let Some(m) = &mut self.sim else {
            return;
        };
        if self.warned_validity {
            return;
        }
        let warning = validity::kinematics(m, self.time)
            .or_else(|| validity::training(m, press.extremes(), press.varying_frequency()))
            .or_else(|| validity::membranes(m, self.time));
        if let Some(w) = warning {
            self.warned_validity = true;
            self.warnings.push(w);
        }
    }
}

/// The pressing force on the diaphragm (N per mm of depth): F(t) = force + amplitude ·
/// (1 − cos φ(t)) / 2, presses from rest to `amplitude` and back (issue 26; seed 003's
/// sinusoid also pulled half of the time, which the contracting diaphragm of finite strain
/// cannot). The phase φ(t) = φ₀ + 2π · frequency · (t − t₀) runs from the `origin` (t₀, φ₀):
/// (0, 0) for a run, so that φ = 2πft on the caller's time, and moved to the time of each
/// change of `press_frequency`, so that the press goes on continuously at the new frequency
/// (seed 003 changes amplitude and frequency at run time; issue 53).
#[derive(Debug, Clone, Copy)]
struct Press {
    force: f64,
    amplitude: f64,
    frequency: f64,
    origin: [f64; 2],
}

impl Press {
    fn at(self, t: f64) -> f64 {
        self.force + self.amplitude * 0.5 * (1.0 - self.phase(t).cos())
    }

    /// The phase φ(t) (rad).
    fn phase(self, t: f64) -> f64 {
        let [t0, phi0] = self.origin;
        phi0 + 2.0 * std::f64::consts::PI * self.frequency * (t - t0)
    }

    /// The least and the largest force of the press.
    fn extremes(self) -> [f64; 2] {
        let other = self.force + self.amplitude;
        [self.force.min(other), self.force.max(other)]
    }

    /// The frequency, 0 when the press is constant.
    fn varying_frequency(self) -> f64 {
        if self.amplitude == 0.0 {
            0.0
        } else {
            self.frequency
        }
    }
}

impl Scene for Abdomen {
    fn variables(&self) -> &[Variable] {
        self.values.table()
    }

    fn generator_parameters(&self) -> Vec<GeneratorParameter> {
        anatomy::FIELDS
            .iter()
            .map(|&(field, unit, min, max, description)| GeneratorParameter {
                name: format!("{ANATOMY}{field}"),
                unit,
                min,
                max,
                description,
            })
            .collect()
    }

    fn generate_configuration(
        &self,
        name: &str,
        description: &str,
        values: &[(&str, f64)],
    ) -> Result<GeneratedConfiguration, SceneError> {
        Ok(GeneratedConfiguration {
            parameter: "configuration",
            text: PelvisConfig::generated(name, description, values)?,
        })
    }

    /// A tissue parameter that changes value marks the stiffness for reassembly at the next
    /// step; setting the value it already has costs nothing. A change after initialization
    /// of a parameter that cannot act there is warned of, once per run.
    fn set_real(&mut self, vr: u32, values: &[f64]) -> Result<(), SceneError> {
        let old = self.values.real(vr);
        let phase = self.pressing().phase(self.time);
        self.values.set_real(vr, values)?;
        if old == values[0] {
            return Ok(());
        }
        if vr == PRESS_FREQUENCY && self.sim.is_some() {
            self.phase_origin = [self.time, phase];
        }
        if (TISSUE_BASE..PRESS_AMPLITUDE).contains(&vr) {
            properties(&self.values)?;
            self.stiffness_changed |= self.sim.is_some();
        }
        if self.sim.is_some() {
            let reason = parameters::inert(&self.values, vr);
            self.warnings
                .extend(self.inert.check(&self.values, vr, reason));
        }
        Ok(())
    }

    fn get_real(&mut self, vr: u32, out: &mut [f64]) -> Result<(), SceneError> {
        if self.values.read(vr, out)? {
            return Ok(());
        }
        let pressing = self.pressing();
        let (press, press_at) = (pressing.at(self.time), |t| pressing.at(t));
        let Some(m) = &mut self.sim else {
            return Err(SceneError::NotInitialized {
                name: self.values.variable(vr)?.name.clone(),
            });
        };
        if vr == ERROR_INDICATOR {
            // The load at integrator time τ is the press at FMI time τ + (t − lag −
            // t_integrator): the state is that of t − lag.
            let offset = self.time - self.lag - m.integrator.state().t;
            out[0] = m.indicator(|tau| press_at(tau + offset))?;
            return Ok(());
        }
        let k = match vr {
            CAVITY_PRESSURE => outputs::CAVITY_PRESSURE,
            _ => (vr - FIRST_OUTPUT) as usize,
        };
        let cavity = outputs::CAVITY.contains(&k);
        let outputs = match &mut self.outputs {
            Some(o) if !(cavity && o[k].is_nan()) => o,
            slot => slot.insert(m.outputs(press, cavity)),
        };
        out[0] = outputs[k];
        Ok(())
    }

    fn set_string(&mut self, vr: u32, value: &str) -> Result<(), SceneError> {
        if vr == INTEGRATOR {
            IntegratorKind::parse(value)?;
        }
        if vr == WALL_SUPPORT && !matches!(value, "free" | "fixed") {
            return Err(parameters::wall_error(value));
        }
        if vr == COSTAL_MARGIN && !matches!(value, "free" | "fixed") {
            return Err(parameters::margin_error(value));
        }
        if vr == MODEL_ORDER {
            parameters::order(value)?;
        }
        if vr == PRESS_MODE {
            parameters::press_mode(value)?;
        }
        if vr == PRESS_MUSCLES {
            parameters::wall_contracts(value)?;
        }
        if vr == MEMBRANE_LAW {
            parameters::membrane_law(value)?;
        }
        if vr == PRESS_LOAD {
            parameters::press_load(value)?;
        }
        if vr == ELEMENT {
            discretization::element(value)?;
        }
        if vr == FORMULATION {
            discretization::formulation(value)?;
        }
        if vr == KINEMATICS {
            discretization::finite(value)?;
        }
        self.values.set_string(vr, value)
    }

    fn get_string(&self, vr: u32) -> Result<String, SceneError> {
        self.values.string(vr).map(str::to_string)
    }

    fn check(&self) -> Result<(), SceneError> {
        simulation::check(&self.values)
    }

    fn initialize(&mut self, start_time: f64) -> Result<(), SceneError> {
        if !start_time.is_finite() {
            return Err(SceneError::InvalidArgument {
                name: "start time",
                value: start_time,
                reason: "must be finite",
            });
        }
        let limit = megabytes(self.values.real(MEMORY_LIMIT));
        let (sim, found) = budget::within(limit, || self.started(start_time))?;
        self.sim = Some(sim);
        self.found = found;
        self.applied = Some(self.values.save());
        self.time = start_time;
        self.lag = 0.0;
        self.phase_origin = [0.0; 2];
        self.outputs = None;
        self.values.freeze();
        self.warned_validity = false;
        self.warned_relaxed = false;
        let inert = self.inert.check_all(&self.values, parameters::inert);
        self.warnings.extend(inert);
        self.check_locking();
        self.check_validity();
        Ok(())
    }

    /// Advances from `t` to `t + h`. A step (with the steps absorbed before it) shorter than
    /// [`TINY_STEP`] of `max_step` — what an importer's accumulated round-off leaves — only
    /// moves the time: the state lags it by at most that share of a step (a change of the
    /// displacement of |u̇| h, far below round-off of any output). A step that differs from
    /// a whole number of the integrator's steps by such a span takes that number of its
    /// steps and keeps the difference as the lag. Integrating the span instead would prepare
    /// the integrator for a new step size, restarting its difference formulas (Houbolt's
    /// starter steps), or for one at which they divide round-off by h².
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), SceneError> {
        check_step(t, h)?;
        let max_step = self.values.real(MAX_STEP);
        let span = self.lag + h;
        if span < TINY_STEP * max_step {
            if self.sim.is_none() {
                return Err(SceneError::NotInitialized {
                    name: "do_step".into(),
                });
            }
            self.lag = span;
            self.time = t + h;
            self.outputs = None;
            return Ok(());
        }
        if self.stiffness_changed {
            self.update_stiffness()?;
        }
        // The lag absorbed (below TINY_STEP of a step) adds no substep.
        let substeps = (span / max_step - TINY_STEP).ceil().max(1.0);
        if substeps > MAX_SUBSTEPS {
            return Err(SceneError::TooManySubsteps {
                h: span,
                max_step,
                substeps,
                limit: MAX_SUBSTEPS,
            });
        }
        let (press, target) = (self.pressing(), self.target());
        let Some(m) = &mut self.sim else {
            return Err(SceneError::NotInitialized {
                name: "do_step".into(),
            });
        };
        // The integrator counts its own time from the start; the load follows the caller's
        // (the FMI time): the state is that of t − lag, and τ + (t − lag − t_integrator) is
        // t − lag + j·dt in substep j.
        let offset = t - self.lag - m.integrator.state().t;
        // Substeps of the integrator's step where that leaves a tiny span over (kept as the
        // lag): a new step size would restart its difference formulas.
        let leftover = span - substeps * m.integrator.dt();
        let (dt, lag) = match leftover.abs() < TINY_STEP * max_step {
            true => (m.integrator.dt(), leftover),
            false => (span / substeps, 0.0),
        };
        match target {
            Some(p) => {
                let reached;
                (self.found, reached) =
                    m.advance_at_pressure(dt, substeps as u64, p, self.found)?;
                let unmet = pressure::relaxed_above(self.found.force, reached, p, t + h);
                if let Some(w) = unmet.filter(|_| !self.warned_relaxed) {
                    self.warned_relaxed = true;
                    self.warnings.push(w);
                }
            }
            None => m.advance(dt, substeps as u64, |tau| press.at(tau + offset))?,
        }
        self.lag = lag;
        self.time = t + h;
        self.outputs = None;
        self.check_validity();
        Ok(())
    }

    fn take_warnings(&mut self) -> Vec<String> {
        std::mem::take(&mut self.warnings)
    }

    fn save(&self) -> SceneState {
        let sim = self.sim.as_ref().zip(self.applied.as_ref());
        SceneState::Abdomen(Box::new(State {
            values: self.values.save(),
            time: self.time,
            lag: self.lag,
            phase_origin: self.phase_origin,
            found: self.found,
            stiffness_changed: self.stiffness_changed,
            warnings: self.warnings.clone(),
            warned_validity: self.warned_validity,
            warned_relaxed: self.warned_relaxed,
            inert: self.inert.clone(),
            simulation: sim.map(|(m, applied)| state::SimulationState {
                applied: applied.clone(),
                integrator: m.integrator.checkpoint(),
                tension: m.full.tension(),
                carried: m.reduced.as_ref().map_or(Vec::new(), |r| r.carried.clone()),
            }),
        }))
    }

    /// The model is built aside from the values its matrices were of, its integrator
    /// resumed, and swapped in only when that worked.
    fn restore(&mut self, state: &SceneState) -> Result<(), SceneError> {
        let SceneState::Abdomen(s) = state else {
            return Err(SceneError::Config(format!(
                "a state of the {} scene cannot be restored into the abdomen",
                state.scene()
            )));
        };
        let mut values = self.values.clone();
        values.restore(&s.values)?;
        let sim = match &s.simulation {
            Some(m) => {
                let mut applied = self.values.clone();
                applied.restore(&m.applied)?;
                let limit = megabytes(applied.real(MEMORY_LIMIT));
                let mut sim = budget::within(limit, || Simulation::build(&applied))?;
                sim.resume(&m.integrator, m.tension, &m.carried)?;
                Some(sim)
            }
            None => None,
        };
        *self = Self {
            values,
            applied: s.simulation.as_ref().map(|m| m.applied.clone()),
            sim,
            outputs: None,
            stiffness_changed: s.stiffness_changed,
            time: s.time,
            lag: s.lag,
            phase_origin: s.phase_origin,
            found: s.found,
            warnings: s.warnings.clone(),
            warned_validity: s.warned_validity,
            warned_relaxed: s.warned_relaxed,
            inert: s.inert.clone(),
        };
        Ok(())
    }
}
