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

use super::effective::Effective;
use super::integrator::{
    check_dt, check_finite, consistent_acceleration, initial_state, Checkpoint, Integrator,
    IntegratorKind, Load, State,
};
use super::newmark::Newmark;
use super::structure::{History, Structure};
use crate::error::ModelError;

/// Houbolt integrator. See the module documentation.
#[derive(Debug, Default)]
pub struct Houbolt {
    state: State,
    dt: f64,
    effective: Effective,
    /// u_{n−1} and u_{n−2}.
    back: [Vec<f64>; 2],
    /// Steps left to take with the starter, and the starter itself (an unprepared default,
    /// holding no factor, once the start is over).
    start_steps: u8,
    starter: Newmark,
    rhs: Vec<f64>,
    mass_part: Vec<f64>,
    damping_part: Vec<f64>,
    /// The difference formulas for the prepared Δt.
    coefficients: Coefficients,
}

/// The Houbolt formulas for one Δt as coefficients of (u_{n+1}, u_n, u_{n−1}, u_{n−2}), so
/// that a step multiplies instead of dividing.
#[derive(Debug, Default, Clone, Copy)]
struct Coefficients {
    /// The history's mass and damping terms, on (u_n, u_{n−1}, u_{n−2}).
    mass: [f64; 3],
    damping: [f64; 3],
    /// ü_{n+1} and u̇_{n+1} (seed 003 eq. B.15, B.16).
    acceleration: [f64; 4],
    velocity: [f64; 4],
}

impl Coefficients {
    fn new(dt: f64) -> Self {
        let (a, v) = (1.0 / (dt * dt), 1.0 / (6.0 * dt));
        Self {
            mass: [5.0 * a, -4.0 * a, a],
            damping: [3.0 / dt, -1.5 / dt, 1.0 / (3.0 * dt)],
            acceleration: [2.0 * a, -5.0 * a, 4.0 * a, -a],
            velocity: [11.0 * v, -18.0 * v, 9.0 * v, -2.0 * v],
        }
    }
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
        if self.start_steps == 0 {
            // Not needed until a restart (which prepares a new one): free its factor.
            self.starter = Newmark::default();
        }
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
        self.coefficients = Coefficients::new(dt);
        if self.start_steps > 0 {
            // A restart is pending: the starter needs the new dt or matrices too, and its
            // state sized now, so that the restart in `step` does not allocate.
            self.starter.prepare(s, dt)?;
            self.starter.restart_from(&self.state);
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
        crate::linalg::vector_state::clear();
        if self.start_steps > 0 {
            return self.starter_step(s, load);
        }
        let c = self.coefficients;
        let t1 = self.state.t + self.dt;
        load(t1, &mut self.rhs);
        let history = History {
            vectors: [&self.state.u, &self.back[0], &self.back[1]],
            mass: c.mass,
            damping: c.damping,
        };
        s.add_history(
            history,
            &mut self.mass_part,
            &mut self.damping_part,
            &mut self.rhs,
        );
        self.effective.solve(s, &mut self.rhs, &self.state.u)?;
        // Rotate history: u_{n−2} ← u_{n−1} ← u_n ← u_{n+1}; rhs now holds u_{n+1}.
        let [b1, b2] = &mut self.back;
        std::mem::swap(b1, b2);
        std::mem::swap(b1, &mut self.state.u);
        std::mem::swap(&mut self.state.u, &mut self.rhs);
        let (u, [u1, u2], u3) = (&self.state.u, &self.back, &self.rhs);
        // Now u = u_{n+1}, u1 = u_n, u2 = u_{n−1}, u3 (old u_{n−2}, stale rhs) = u_{n−2}.
        let (ca, cv) = (c.acceleration, c.velocity);
        let rows = u.iter().zip(u1).zip(u2).zip(u3);
        for ((a, v), (((&x0, &x1), &x2), &x3)) in
            self.state.a.iter_mut().zip(&mut self.state.v).zip(rows)
        {
            *a = ca[0] * x0 + ca[1] * x1 + ca[2] * x2 + ca[3] * x3;
            *v = cv[0] * x0 + cv[1] * x1 + cv[2] * x2 + cv[3] * x3;
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

    fn newton_iterations(&self) -> usize {
        self.effective.iterations()
    }

    fn newton_factorizations(&self) -> usize {
        self.effective.factorizations()
    }

    fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            history: self.back.to_vec(),
            start_steps: self.start_steps,
            starter: (self.start_steps > 0).then(|| Box::new(self.starter.checkpoint())),
            tangent_at: self.effective.kept_tangent(),
            ..Checkpoint::new(self.kind(), self.dt, &self.state)
        }
    }

    fn resume(&mut self, s: &Structure, c: &Checkpoint) -> Result<(), ModelError> {
        c.check(self.kind(), self.dt, s.n())?;
        let [b1, b2] = c.history.as_slice() else {
            return Err(ModelError::LinearAlgebra(
                "a Houbolt checkpoint holds u_{n−1} and u_{n−2}".into(),
            ));
        };
        self.state = c.state.clone();
        self.back = [b1.clone(), b2.clone()];
        self.start_steps = c.start_steps;
        self.starter = Newmark::default();
        if let Some(starter) = c.starter.as_deref().filter(|_| self.start_steps > 0) {
            self.starter.prepare(s, self.dt)?;
            self.starter.resume(s, starter)?;
        }
        if let Some((x, shift)) = &c.tangent_at {
            self.effective.refactorize_at(s, x, *shift)?;
        }
        Ok(())
    }
}
