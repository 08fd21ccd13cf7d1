//! Central-difference method, explicit, with the lumped mass (Bathe 1996 §9.2.1), written in
//! the equivalent half-step ("leapfrog") form:
//!
//! u_{n+1} = u_n + Δt u̇_{n+½},  ü_{n+1} = M_L⁻¹ (f_{n+1} − K u_{n+1} − C u̇_{n+½}),
//! u̇_{n+3/2} = u̇_{n+½} + Δt ü_{n+1},  reported u̇_{n+1} = u̇_{n+½} + Δt/2 ü_{n+1}.
//!
//! Without damping this is exactly the classical central difference. Damping forces use the
//! lagging half-step velocity (first order in the damping term; Belytschko, Liu & Moran 2000
//! §6.2.1). Stable for Δt ≤ Δt_crit = 2/ω_max (undamped), with ω_max from
//! [`super::spectrum`]; the limit is reported by [`Integrator::critical_time_step`]. Above it
//! the scheme runs as asked and grows without bound; the scenes refuse such steps.

use super::integrator::{
    check_dt, check_finite, initial_state, Checkpoint, Integrator, IntegratorKind, Load, State,
};
use super::spectrum::max_omega_squared;
use super::structure::Structure;
use crate::error::ModelError;

/// Central-difference integrator. See the module documentation.
#[derive(Debug, Default)]
pub struct CentralDifference {
    state: State,
    dt: f64,
    critical: f64,
    v_half: Vec<f64>,
    f: Vec<f64>,
}

/// The initial state of an explicit scheme: (t₀, u₀, v₀) with ü₀ = M_L⁻¹ (f(t₀) − K u₀ − C v₀);
/// `f` is the scheme's load work vector.
pub(crate) fn explicit_start(
    s: &Structure,
    t0: f64,
    u0: &[f64],
    v0: &[f64],
    load: &mut Load<'_>,
    f: &mut [f64],
) -> Result<State, ModelError> {
    let mut state = initial_state(s, t0, u0, v0)?;
    load(t0, f);
    lumped_acceleration(s, f, &state.u, &state.v, &mut state.a);
    Ok(state)
}

/// ü = M_L⁻¹ (f − K u − C v).
pub(crate) fn lumped_acceleration(s: &Structure, f: &[f64], u: &[f64], v: &[f64], a: &mut [f64]) {
    s.residual(f, u, v, a);
    a.iter_mut().zip(s.lumped_mass()).for_each(|(x, m)| *x /= m);
}

impl Integrator for CentralDifference {
    fn kind(&self) -> IntegratorKind {
        IntegratorKind::CentralDifference
    }

    fn prepare(&mut self, s: &Structure, dt: f64) -> Result<(), ModelError> {
        s.require_linear("central_difference")?;
        self.dt = check_dt(dt)?;
        self.critical = 2.0 / max_omega_squared(s).sqrt();
        self.f.resize(s.n(), 0.0);
        Ok(())
    }

    fn checkpoint(&self) -> Checkpoint {
        Checkpoint {
            history: vec![self.v_half.clone()],
            ..Checkpoint::new(self.kind(), self.dt, &self.state)
        }
    }

    fn resume(&mut self, s: &Structure, c: &Checkpoint) -> Result<(), ModelError> {
        c.check(self.kind(), self.dt, s.n())?;
        let [v_half] = c.history.as_slice() else {
            return Err(ModelError::LinearAlgebra(
                "a central-difference checkpoint holds v_{n+½}".into(),
            ));
        };
        self.state = c.state.clone();
        self.v_half = v_half.clone();
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
        let State { v, a, .. } = &self.state;
        self.v_half = v
            .iter()
            .zip(a.iter())
            .map(|(v, a)| v + 0.5 * self.dt * a)
            .collect();
        Ok(())
    }

    fn step(&mut self, s: &Structure, load: &mut Load<'_>) -> Result<(), ModelError> {
        crate::linalg::vector_state::clear();
        let dt = self.dt;
        let t1 = self.state.t + dt;
        let State { u, v, a, .. } = &mut self.state;
        u.iter_mut()
            .zip(&self.v_half)
            .for_each(|(u, vh)| *u += dt * vh);
        load(t1, &mut self.f);
        lumped_acceleration(s, &self.f, u, &self.v_half, a);
        for i in 0..u.len() {
            v[i] = self.v_half[i] + 0.5 * dt * a[i];
            self.v_half[i] += dt * a[i];
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

    fn critical_time_step(&self) -> Option<f64> {
        Some(self.critical)
    }
}
