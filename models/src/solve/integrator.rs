//! The common interface of the time integrators for M ü + C u̇ + K u = f(t) (seed 003 App. B).
//!
//! Life cycle: [`Integrator::prepare`] for a step size (implicit schemes factor their
//! effective matrix there, explicit ones find their critical step), [`Integrator::start`]
//! with the initial state, then [`Integrator::step`] as often as needed. After a change of
//! the structure's matrices or of `dt`, call `prepare` again: it refactorizes numerically on
//! the existing symbolic analysis and the run continues from the current state. A step
//! allocates nothing.

use serde::{Deserialize, Serialize};

use super::structure::Structure;
use crate::error::ModelError;

/// The external load: `load(t, f)` writes f(t) (free dofs, N) into `f`.
pub type Load<'a> = dyn FnMut(f64, &mut [f64]) + 'a;

/// Displacement, velocity and acceleration on the free dofs at time `t`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct State {
    /// Time (s).
    pub t: f64,
    /// Displacement (mm); in a reduced model, its coordinates q.
    pub u: Vec<f64>,
    /// Velocity (mm/s), likewise.
    pub v: Vec<f64>,
    /// Acceleration (mm/s²), likewise.
    pub a: Vec<f64>,
    /// Steps taken since `start`.
    pub steps: u64,
}

impl State {
    /// Copies `other` into `self` without allocating when the lengths agree.
    pub fn copy_from(&mut self, other: &State) {
        self.t = other.t;
        self.steps = other.steps;
        for (dst, src) in [
            (&mut self.u, &other.u),
            (&mut self.v, &other.v),
            (&mut self.a, &other.a),
        ] {
            dst.clear();
            dst.extend_from_slice(src);
        }
    }
}

/// What a later step of an integrator depends on, beyond the structure and the step size
/// it was prepared for: [`Integrator::checkpoint`] takes it, [`Integrator::resume`] puts it
/// back into an integrator of the same kind prepared for the same structure and `dt`, which
/// then continues bit for bit as the one it was taken from.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Checkpoint {
    /// The scheme it was taken from.
    pub kind: IntegratorKind,
    /// The step size the scheme was prepared for (s).
    pub dt: f64,
    /// The state when it was taken.
    pub state: State,
    /// The scheme's own vectors: Houbolt u_{n−1}, u_{n−2}; central difference v_{n+½}.
    pub history: Vec<Vec<f64>>,
    /// Houbolt: steps left to take with its starter, and the starter's checkpoint then.
    pub start_steps: u8,
    /// Houbolt: its Newmark starter's checkpoint while `start_steps` > 0.
    pub starter: Option<Box<Checkpoint>>,
    /// RK4: the acceleration is stale (matrices changed since it was computed).
    pub stale: bool,
    /// Finite strain: the displacement (free dofs) at which the kept effective tangent was
    /// factorized and the mass shift it took; `None` while the factor is the prepared one.
    pub tangent_at: Option<(Vec<f64>, f64)>,
}

impl Checkpoint {
    /// A checkpoint of `kind` with the common parts; the scheme adds its own.
    pub(crate) fn new(kind: IntegratorKind, dt: f64, state: &State) -> Self {
        Self {
            kind,
            dt,
            state: state.clone(),
            history: Vec::new(),
            start_steps: 0,
            starter: None,
            stale: false,
            tangent_at: None,
        }
    }

    /// Every vector of the state a later step depends on (the ones [`map`](Self::map)
    /// carries), u and v first: u, v, a, the scheme's history and its starter's.
    pub fn vectors(&self) -> Vec<&[f64]> {
        let s = &self.state;
        let mut out = vec![&s.u[..], &s.v[..], &s.a[..]];
        out.extend(self.history.iter().map(|h| &h[..]));
        if let Some(starter) = &self.starter {
            out.extend(starter.vectors());
        }
        out
    }

    /// The checkpoint with every vector of its state and history (and its starter's) mapped
    /// by `f` — a reduced model's state carried onto a new basis — the acceleration marked
    /// stale and a kept tangent dropped (the integrator resumes on the matrix it is
    /// prepared with).
    pub fn map(&self, f: &mut dyn FnMut(&[f64]) -> Vec<f64>) -> Self {
        let s = &self.state;
        Self {
            kind: self.kind,
            dt: self.dt,
            state: State {
                t: s.t,
                u: f(&s.u),
                v: f(&s.v),
                a: f(&s.a),
                steps: s.steps,
            },
            history: self.history.iter().map(|h| f(h)).collect(),
            start_steps: self.start_steps,
            starter: self.starter.as_ref().map(|c| Box::new(c.map(f))),
            stale: true,
            tangent_at: None,
        }
    }

    /// The checkpoint without its kept tangents (its starter's too): an integrator resumes
    /// it on the factorization it is prepared with — a step taken again under another load,
    /// whose tension the kept tangents were not taken at.
    pub fn without_tangents(mut self) -> Self {
        self.tangent_at = None;
        self.starter = self.starter.map(|s| Box::new(s.without_tangents()));
        self
    }

    /// Refuses a checkpoint of another scheme, step size or system size.
    pub(crate) fn check(&self, kind: IntegratorKind, dt: f64, n: usize) -> Result<(), ModelError> {
        let fits = self.kind == kind
            && self.dt.to_bits() == dt.to_bits()
            && self.state.u.len() == n
            && self.history.iter().all(|h| h.len() == n);
        if fits {
            Ok(())
        } else {
            Err(ModelError::LinearAlgebra(format!(
                "a {} checkpoint at dt = {} s of {} unknowns cannot resume a {} integrator \
                 prepared for dt = {dt} s and {n} unknowns",
                self.kind.name(),
                self.dt,
                self.state.u.len(),
                kind.name()
            )))
        }
    }
}

/// The selectable integrators.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum IntegratorKind {
    /// Houbolt's implicit three-step method, started by Newmark's.
    Houbolt,
    /// Newmark's implicit average-acceleration method (β = 1/4, γ = 1/2).
    Newmark,
    /// The explicit central-difference method, with the lumped mass.
    CentralDifference,
    /// The explicit classical fourth-order Runge–Kutta method, with the lumped mass.
    Rk4,
}

impl IntegratorKind {
    /// Every integrator ([`parse`](Self::parse) searches them).
    pub const ALL: [Self; 4] = [
        Self::Houbolt,
        Self::Newmark,
        Self::CentralDifference,
        Self::Rk4,
    ];

    /// Lower-case name used in configuration files and reports.
    pub fn name(self) -> &'static str {
        match self {
            Self::Houbolt => "houbolt",
            Self::Newmark => "newmark",
            Self::CentralDifference => "central_difference",
            Self::Rk4 => "rk4",
        }
    }

    /// Parses a name as given by [`name`](Self::name).
    pub fn parse(name: &str) -> Result<Self, ModelError> {
        Self::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| ModelError::UnknownChoice {
                what: "integrator",
                value: name.to_string(),
                choices: "houbolt, newmark, central_difference or rk4",
            })
    }

    /// Whether it steps the finite-strain equation of motion (Newton within each step):
    /// the implicit ones; the explicit ones need the linear one
    /// ([`ModelError::LinearOnly`]).
    pub fn steps_finite_strain(self) -> bool {
        matches!(self, Self::Houbolt | Self::Newmark)
    }

    /// A new, unprepared integrator of this kind.
    pub fn create(self) -> Box<dyn Integrator + Send + Sync> {
        match self {
            Self::Houbolt => Box::new(super::Houbolt::default()),
            Self::Newmark => Box::new(super::Newmark::default()),
            Self::CentralDifference => Box::new(super::CentralDifference::default()),
            Self::Rk4 => Box::new(super::Rk4::default()),
        }
    }
}

/// A time-stepping scheme.
pub trait Integrator {
    /// Which scheme this is.
    fn kind(&self) -> IntegratorKind;

    /// Makes the scheme ready for steps of size `dt` on the structure's current matrices.
    fn prepare(&mut self, s: &Structure, dt: f64) -> Result<(), ModelError>;

    /// Sets the initial state (t₀, u₀, v₀); the initial acceleration follows from the
    /// equation of motion at t₀. Requires a prior `prepare`.
    fn start(
        &mut self,
        s: &Structure,
        t0: f64,
        u0: &[f64],
        v0: &[f64],
        load: &mut Load<'_>,
    ) -> Result<(), ModelError>;

    /// Advances the state by one step. Allocates nothing.
    fn step(&mut self, s: &Structure, load: &mut Load<'_>) -> Result<(), ModelError>;

    /// The current state.
    fn state(&self) -> &State;

    /// The step size the scheme is prepared for.
    fn dt(&self) -> f64;

    /// What a later step depends on (see [`Checkpoint`]).
    fn checkpoint(&self) -> Checkpoint;

    /// Puts a checkpoint back: requires a prior `prepare` for the same structure and the
    /// checkpoint's `dt`; the integrator then continues as the one the checkpoint was taken
    /// from, bit for bit.
    fn resume(&mut self, s: &Structure, checkpoint: &Checkpoint) -> Result<(), ModelError>;

    /// Newton iterations of the last step on a finite-strain structure (0 when linear, and
    /// for the explicit schemes, which refuse such a structure).
    fn newton_iterations(&self) -> usize {
        0
    }

    /// Factorizations of the tangent in the last step's Newton iterations (0 when linear,
    /// and for the explicit schemes).
    fn newton_factorizations(&self) -> usize {
        0
    }

    /// Largest stable step for the prepared structure (undamped), or `None` if the scheme
    /// is unconditionally stable.
    fn critical_time_step(&self) -> Option<f64> {
        None
    }
}

/// Errors with `Diverged` if any displacement is not finite.
pub(crate) fn check_finite(kind: IntegratorKind, state: &State) -> Result<(), ModelError> {
    match state.u.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => Err(ModelError::Diverged {
            integrator: kind.name(),
            t: state.t,
            step: state.steps,
            reason: format!("displacement of equation {i} is {}", state.u[i]),
        }),
    }
}

/// Validates a step size.
pub(crate) fn check_dt(dt: f64) -> Result<f64, ModelError> {
    crate::error::positive("dt", dt)
}

/// The state (t₀, u₀, v₀) with zero acceleration, after checking the lengths.
pub(crate) fn initial_state(
    s: &Structure,
    t0: f64,
    u0: &[f64],
    v0: &[f64],
) -> Result<State, ModelError> {
    for (name, x) in [("u0", u0), ("v0", v0)] {
        if x.len() != s.n() {
            return Err(ModelError::SizeMismatch {
                name,
                expected: s.n(),
                got: x.len(),
            });
        }
    }
    Ok(State {
        t: t0,
        u: u0.to_vec(),
        v: v0.to_vec(),
        a: vec![0.0; s.n()],
        steps: 0,
    })
}

/// Initial acceleration from the consistent mass: M a₀ = f(t₀) − C v₀ − K u₀ (at finite
/// strain − f_int(u₀), [`Structure::unbalanced`]). One extra factorization of M at start-up
/// (not in the step loop).
pub(crate) fn consistent_acceleration(
    s: &Structure,
    state: &mut State,
    load: &mut Load<'_>,
) -> Result<(), ModelError> {
    let mut f = vec![0.0; s.n()];
    load(state.t, &mut f);
    s.unbalanced(&f, &state.u, &state.v, &mut state.a)?;
    if state.a.iter().all(|&x| x == 0.0) {
        return Ok(()); // at rest and unloaded: a₀ = 0 without a factorization of M
    }
    let mut chol = s.analyze()?;
    chol.factorize(s.mass())?;
    chol.solve_in_place(&mut state.a);
    Ok(())
}
