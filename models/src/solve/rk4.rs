//! Classical fourth-order Runge–Kutta (seed 003 App. B.1.4, eq. B.8–B.12) on the first-order
//! form y = (u, u̇), ẏ = (u̇, M_L⁻¹ (f(t) − C u̇ − K u)) with the lumped mass. Explicit; stable
//! for ω_max Δt ≤ 2√2 (undamped), reported by [`Integrator::critical_time_step`].

use super::central_difference::{explicit_start, lumped_acceleration};
use super::integrator::{
    check_dt, check_finite, Checkpoint, Integrator, IntegratorKind, Load, State,
};
use super::spectrum::max_omega_squared;
use super::structure::Structure;
use crate::error::ModelError;

/// RK4 integrator. See the module documentation.
#[derive(Debug, Default)]
pub struct Rk4 {
    state: State,
    dt: f64,
    critical: f64,
    /// Stage slopes (du, dv) for the four stages.
    du: [Vec<f64>; 4],
    dv: [Vec<f64>; 4],
    u_stage: Vec<f64>,
    v_stage: Vec<f64>,
    f: Vec<f64>,
    /// The state's acceleration no longer matches the matrices (after `prepare`).
    stale_acceleration: bool,
}

impl Integrator for Rk4 {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::Rk4
    }

    fn prepare(&mut self, s: &Structure, dt: f64) -> Result<(), ModelError> {
        s.require_linear("rk4")?;
        self.dt = check_dt(dt)?;
        self.critical = 2.0 * std::f64::consts::SQRT_2 / max_omega_squared(s).sqrt();
        for x in self.du.iter_mut().chain(self.dv.iter_mut()) {
            x.resize(s.n(), 0.0);
        }
        for x in [&mut self.u_stage, &mut self.v_stage, &mut self.f] {
            x.resize(s.n(), 0.0);
        }
        self.stale_acceleration = true;
        Ok(())
    }

    fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            stale: self.stale_acceleration,
            ..Checkpoint::new(self.kind(), self.dt, &self.state)
        }
    }

    fn resume(&mut self, s: &Structure, c: &Checkpoint) -> Result<(), ModelError> {
        c.check(self.kind(), self.dt, s.n())?;
        self.state = c.state.clone();
        self.stale_acceleration = c.stale;
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
        self.state = explicit_start(s, t0, u0, v0, load, &mut self.f)?;
        self.stale_acceleration = false;
        Ok(())
    }

    fn step(&mut self, s: &Structure, load: &mut Load<'_>) -> Result<(), ModelError> {
        crate::linalg::vector_state::clear();
        let (dt, t0) = (self.dt, self.state.t);
        if self.stale_acceleration {
            load(t0, &mut self.f);
            let State { u, v, a, .. } = &mut self.state;
            lumped_acceleration(s, &self.f, u, v, a);
            self.stale_acceleration = false;
        }
        // Stage 1 is the slope at y_n, which the state already holds (its acceleration is
        // evaluated at the end of every step). Stage k ≥ 2 evaluates the slope at
        // y_n + c_k Δt · slope_{k−1}, c = (½, ½, 1).
        self.du[0].copy_from_slice(&self.state.v);
        self.dv[0].copy_from_slice(&self.state.a);
        const C: [f64; 4] = [0.0, 0.5, 0.5, 1.0];
        for (k, &c) in C.iter().enumerate().skip(1) {
            let State { u, v, .. } = &self.state;
            for i in 0..u.len() {
                self.u_stage[i] = u[i] + c * dt * self.du[k - 1][i];
                self.v_stage[i] = v[i] + c * dt * self.dv[k - 1][i];
            }
            load(t0 + c * dt, &mut self.f);
            self.du[k].copy_from_slice(&self.v_stage);
            lumped_acceleration(s, &self.f, &self.u_stage, &self.v_stage, &mut self.dv[k]);
        }
        let State { u, v, a, .. } = &mut self.state;
        let [du, dv] = [&self.du, &self.dv];
        for i in 0..u.len() {
            u[i] += dt / 6.0 * (du[0][i] + 2.0 * du[1][i] + 2.0 * du[2][i] + du[3][i]);
            v[i] += dt / 6.0 * (dv[0][i] + 2.0 * dv[1][i] + 2.0 * dv[2][i] + dv[3][i]);
        }
        load(t0 + dt, &mut self.f);
        lumped_acceleration(s, &self.f, u, v, a);
        self.state.t = t0 + dt;
        self.state.steps += 1;
        check_finite(self.kind(), &self.state)
    }

    fn state(&self) -> &State {
        &self.state
    }

    fn dt(&self) -> f64 {
        self.dt
    }

    fn critical_time_step(&self) -> Option<f64> {
        Some(self.critical)
    }
}
