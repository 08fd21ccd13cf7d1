//! Houbolt's implicit three-step method (seed 003 App. B.2.2, after Bathe 1996 §9.2.3).
//!
//! With backward differences of third order (seed 003 eq. B.15, B.16)
//!
//! ü_{n+1} = (2u_{n+1} − 5u_n + 4u_{n−1} − u_{n−2}) / Δt²,
//! u̇_{n+1} = (11u_{n+1} − 18u_n + 9u_{n−1} − 2u_{n−2}) / (6Δt),
//!
//! the equation of motion at t_{n+1} becomes
//!
//! (2/Δt² M + 11/(6Δt) C + K) u_{n+1} = f_{n+1} + M (5u_n − 4u_{n−1} + u_{n−2})/Δt²
//!                                       + C (3u_n − 3/2 u_{n−1} + 1/3 u_{n−2})/Δt.
//!
//! The effective matrix is constant for a given (M, C, K, Δt): factor once, then each step is
//! two sparse products and one triangular solve.
//!
//! **Starting procedure.** The scheme needs two displacements before the current one. The
//! first two steps after a start are taken with Newmark's average-acceleration method
//! ([`super::Newmark`]), which is second order (local error O(Δt³), so the global error stays
//! O(Δt²)), unconditionally stable and exact for motions quadratic in time (tested: a free
//! mass under constant force); from the third step on Houbolt uses u₀, u₁, u₂. The same
//! procedure restarts the history when Δt changes mid-run, from the current (u, u̇, ü).
//! A Taylor expansion backwards in time (u₋ₖ = u₀ − kΔt v₀ + (kΔt)²/2 a₀) was tried first and
//! rejected: at large Δt the a₀ term puts fictitious energy into the high modes (the energy of
//! a cantilever released from a static deflection rose 156-fold at Δt = 1000 × the explicit
//! limit before Houbolt damped it out).

use super::integrator::{
    check_dt, check_finite, consistent_acceleration, initial_state, Integrator, IntegratorKind,
    Load, State,
};
use super::newmark::Newmark;
use super::structure::{Effective, Structure};
use crate::error::ModelError;

/// Houbolt integrator. See the module documentation.
#[derive(Debug, Default)]
pub struct Houbolt {
    state: State,
    dt: f64,
    effective: Effective,
    /// u_{n−1} and u_{n−2}.
    back: [Vec<f64>; 2],
    /// Steps left to take with the starter, and the starter itself.
    start_steps: u8,
    starter: Newmark,
    rhs: Vec<f64>,
    mass_part: Vec<f64>,
    damping_part: Vec<f64>,
}

impl Houbolt {
    /// One step of the starting procedure: Newmark from the current state, then the old
    /// current displacement joins the history.
    fn starter_step(&mut self, s: &Structure, load: &mut Load<'_>) -> Result<(), ModelError> {
        if self.start_steps == 2 {
            self.starter.restart_from(&self.state);
        }
        self.starter.step(s, load)?;
        let [b1, b2] = &mut self.back;
        std::mem::swap(b1, b2);
        b1.copy_from_slice(&self.state.u);
        let steps = self.state.steps + 1;
        self.state.copy_from(self.starter.state());
        self.state.steps = steps;
        self.start_steps -= 1;
        Ok(())
    }
}

impl Integrator for Houbolt {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Houbolt
    }

    fn prepare(&mut self, s: &Structure, dt: f64) -> Result<(), ModelError> {
        let started = !self.state.u.is_empty();
        if check_dt(dt)? != self.dt && started {
            self.start_steps = 2;
        }
        self.dt = dt;
        if self.start_steps > 0 {
            // A restart is pending: the starter needs the new dt or matrices too.
            self.starter.prepare(s, dt)?;
        }
        for x in [&mut self.rhs, &mut self.mass_part, &mut self.damping_part] {
            x.resize(s.n(), 0.0);
        }
        self.effective
            .factorize(s, 2.0 / (dt * dt), 11.0 / (6.0 * dt))
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
        consistent_acceleration(s, &mut self.state, load)?;
        self.back = [vec![0.0; s.n()], vec![0.0; s.n()]];
        self.starter.prepare(s, self.dt)?;
        // Sizes the starter's state now, so that restarts in `step` do not allocate.
        self.starter.restart_from(&self.state);
        self.start_steps = 2;
        Ok(())
    }

    fn step(&mut self, s: &Structure, load: &mut Load<'_>) -> Result<(), ModelError> {
        if self.start_steps > 0 {
            return self.starter_step(s, load);
        }
        let dt = self.dt;
        let t1 = self.state.t + dt;
        load(t1, &mut self.rhs);
        let (u, [u1, u2]) = (&self.state.u, &self.back);
        for i in 0..u.len() {
            self.mass_part[i] = (5.0 * u[i] - 4.0 * u1[i] + u2[i]) / (dt * dt);
            self.damping_part[i] = (3.0 * u[i] - 1.5 * u1[i] + u2[i] / 3.0) / dt;
        }
        s.add_mass_damping(&mut self.mass_part, &self.damping_part, &mut self.rhs);
        self.effective.solve(&mut self.rhs);
        // Rotate history: u_{n−2} ← u_{n−1} ← u_n ← u_{n+1}; rhs now holds u_{n+1}.
        let [b1, b2] = &mut self.back;
        std::mem::swap(b1, b2);
        std::mem::swap(b1, &mut self.state.u);
        std::mem::swap(&mut self.state.u, &mut self.rhs);
        let (u, [u1, u2], u3) = (&self.state.u, &self.back, &self.rhs);
        // Now u = u_{n+1}, u1 = u_n, u2 = u_{n−1}, u3 (old u_{n−2}, stale rhs) = u_{n−2}.
        for i in 0..u.len() {
            self.state.a[i] = (2.0 * u[i] - 5.0 * u1[i] + 4.0 * u2[i] - u3[i]) / (dt * dt);
            self.state.v[i] = (11.0 * u[i] - 18.0 * u1[i] + 9.0 * u2[i] - 2.0 * u3[i]) / (6.0 * dt);
        }
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
}
