//! Newmark's method with the average-acceleration parameters β = 1/4, γ = 1/2 (seed 003
//! App. B.2.1: α = 1/4, δ = 1/2 in its notation; Bathe 1996 §9.2.4). Unconditionally stable,
//! second order, no numerical dissipation.
//!
//! (K + 4/Δt² M + 2/Δt C) u_{n+1} = f_{n+1} + M (4/Δt² u_n + 4/Δt u̇_n + ü_n) + C (2/Δt u_n + u̇_n),
//! ü_{n+1} = 4/Δt² (u_{n+1} − u_n) − 4/Δt u̇_n − ü_n,  u̇_{n+1} = u̇_n + Δt/2 (ü_n + ü_{n+1}).

use super::effective::Effective;
use super::integrator::{
    check_dt, check_finite, consistent_acceleration, initial_state, Checkpoint, Integrator,
    IntegratorKind, Load, State,
};
use super::structure::{History, Structure};
use crate::error::ModelError;

/// Newmark average-acceleration integrator. See the module documentation.
#[derive(Debug, Default)]
pub struct Newmark {
    state: State,
    dt: f64,
    effective: Effective,
    rhs: Vec<f64>,
    mass_part: Vec<f64>,
    damping_part: Vec<f64>,
}

impl Newmark {
    /// Continues from `state` (as Houbolt's starting procedure does) without recomputing
    /// the acceleration; requires a prior `prepare` for the same structure.
    pub(crate) fn restart_from(&mut self, state: &State) {
        self.state.copy_from(state);
    }
}

impl Integrator for Newmark {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Newmark
    }

    fn prepare(&mut self, s: &Structure, dt: f64) -> Result<(), ModelError> {
        self.dt = check_dt(dt)?;
        for x in [&mut self.rhs, &mut self.mass_part, &mut self.damping_part] {
            x.resize(s.n(), 0.0);
        }
        self.effective.factorize(s, 4.0 / (dt * dt), 2.0 / dt)
    }

    fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            tangent_at: self.effective.kept_tangent(),
            ..Checkpoint::new(self.kind(), self.dt, &self.state)
        }
    }

    fn resume(&mut self, s: &Structure, c: &Checkpoint) -> Result<(), ModelError> {
        c.check(self.kind(), self.dt, s.n())?;
        self.state = c.state.clone();
        if let Some((x, shift)) = &c.tangent_at {
            self.effective.refactorize_at(s, x, *shift)?;
        }
        Ok(())
    }

    fn start(
        &mut self,
        s: &Structure,
        t0: f64,
        u0: &[f64],
        v0: &[f64],
        load: &mut Load<'_>,
    ) -> Result<(), ModelError> {
        self.state = initial_state(s, t0, u0, v0)?;
        consistent_acceleration(s, &mut self.state, load)
    }

    fn step(&mut self, s: &Structure, load: &mut Load<'_>) -> Result<(), ModelError> {
        crate::linalg::vector_state::clear();
        let dt = self.dt;
        let t1 = self.state.t + dt;
        load(t1, &mut self.rhs);
        let State { u, v, a, .. } = &mut self.state;
        let history = History {
            vectors: [u, v, a],
            mass: [4.0 / (dt * dt), 4.0 / dt, 1.0],
            damping: [2.0 / dt, 1.0, 0.0],
        };
        s.add_history(
            history,
            &mut self.mass_part,
            &mut self.damping_part,
            &mut self.rhs,
        );
        self.effective.solve(s, &mut self.rhs, u)?;
        for i in 0..u.len() {
            let a1 = 4.0 / (dt * dt) * (self.rhs[i] - u[i]) - 4.0 / dt * v[i] - a[i];
            v[i] += 0.5 * dt * (a[i] + a1);
            a[i] = a1;
        }
        std::mem::swap(u, &mut self.rhs);
        self.state.t = t1;
        self.state.steps += 1;
        check_finite(self.kind(), &self.state)
    }

    fn state(&self) -> &State {
        &self.state
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn newton_iterations(&self) -> usize {
        self.effective.iterations()
    }

    fn newton_factorizations(&self) -> usize {
        self.effective.factorizations()
    }
}
