//! The single-degree-of-freedom oscillator m ü + c u̇ + k u = 0 as a one-equation
//! [`Structure`], and the spectral properties of the integrators on it: period elongation
//! and amplitude decay per cycle, from theory (Houbolt's characteristic equation) and as
//! measured from a simulated free vibration.

use nalgebra::{Complex, Matrix1, Matrix3};

use crate::assembly::{Assembler, Dirichlet};
use crate::error::ModelError;
use crate::linalg::Factorization;
use crate::solve::{Damping, IntegratorKind, Structure};

/// Period elongation T̄/T − 1 and amplitude decay per cycle 1 − A(t + T̄)/A(t).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spectral {
    /// T̄/T − 1: how much longer the numerical period is than the exact one.
    pub period_elongation: f64,
    /// 1 − A(t + T̄)/A(t): the share of the amplitude lost per cycle.
    pub amplitude_decay: f64,
}

/// A one-dof structure with mass `m`, stiffness `k` and Rayleigh damping.
pub fn sdof(m: f64, k: f64, damping: Damping) -> Result<Structure, ModelError> {
    let asm = Assembler::new(1, 1, &[[0]]);
    let (mut kv, mut mv) = (asm.zeros(), asm.zeros());
    asm.add(&mut kv, 0, &Matrix1::new(k));
    asm.add(&mut mv, 0, &Matrix1::new(m));
    let bc = Dirichlet::new(&asm, &[])?;
    Structure::new(bc, &kv, &mv, &[m], damping, Factorization::Simplicial)
}

/// Houbolt on the undamped oscillator with Ω = ω Δt satisfies
/// (2 + Ω²) λ³ − 5 λ² + 4 λ − 1 = 0. For the principal roots λ = ρ e^{±iφ} the numerical
/// period is 2πΔt/φ, so T̄/T − 1 = Ω/φ − 1 and the amplitude per numerical cycle shrinks by
/// ρ^{2π/φ}.
pub fn houbolt_theory(dt_over_period: f64) -> Spectral {
    let omega_dt = 2.0 * std::f64::consts::PI * dt_over_period;
    let c = 2.0 + omega_dt * omega_dt;
    // Companion matrix of λ³ − (5/c) λ² + (4/c) λ − 1/c.
    let companion = Matrix3::new(5.0 / c, -4.0 / c, 1.0 / c, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
    let principal: Complex<f64> = companion
        .complex_eigenvalues()
        .iter()
        .copied()
        .max_by(|a, b| a.im.abs().total_cmp(&b.im.abs()))
        .expect("three eigenvalues");
    let (rho, phi) = (principal.norm(), principal.arg().abs());
    Spectral {
        period_elongation: omega_dt / phi - 1.0,
        amplitude_decay: 1.0 - rho.powf(2.0 * std::f64::consts::PI / phi),
    }
}

/// Simulates the undamped oscillator (T = 1 s, u₀ = 1, v₀ = 0) with `kind` for `cycles`
/// periods and measures the period from up-going zero crossings (linear interpolation) and
/// the amplitude decay from successive maxima (parabolic interpolation through three
/// samples), skipping the first two cycles where Houbolt's spurious root still decays.
pub fn measure(
    kind: IntegratorKind,
    dt_over_period: f64,
    cycles: usize,
) -> Result<Spectral, ModelError> {
    let two_pi = 2.0 * std::f64::consts::PI;
    let s = sdof(1.0, two_pi * two_pi, Damping::NONE)?;
    let mut integ = kind.create();
    integ.prepare(&s, dt_over_period)?;
    let mut zero = |_: f64, f: &mut [f64]| f.fill(0.0);
    integ.start(&s, 0.0, &[1.0], &[0.0], &mut zero)?;
    let n = (cycles as f64 / dt_over_period).ceil() as usize;
    let mut u = vec![1.0];
    for _ in 0..n {
        integ.step(&s, &mut zero)?;
        u.push(integ.state().u[0]);
    }
    let skip = (2.0 / dt_over_period) as usize;
    let mut crossings = Vec::new();
    let mut peaks = Vec::new();
    for i in skip.max(1)..u.len() - 1 {
        if u[i] < 0.0 && u[i + 1] >= 0.0 {
            crossings.push(i as f64 + u[i] / (u[i] - u[i + 1]));
        }
        if u[i] > u[i - 1] && u[i] >= u[i + 1] {
            let (a, b, c) = (u[i - 1], u[i], u[i + 1]);
            let denom = a - 2.0 * b + c;
            peaks.push(if denom == 0.0 {
                b
            } else {
                b - (a - c).powi(2) / (8.0 * denom)
            });
        }
    }
    let period_steps =
        (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64;
    let ratio = (peaks[peaks.len() - 1] / peaks[0]).powf(1.0 / (peaks.len() - 1) as f64);
    Ok(Spectral {
        period_elongation: period_steps * dt_over_period - 1.0,
        amplitude_decay: 1.0 - ratio,
    })
}

/// Error |u_h(t_end) − u(t_end)| of a damped free vibration (m = 1, ω = 2π, damping ratio
/// from mass-proportional Rayleigh damping α = 2ζω), u₀ = 1, v₀ = 0, for step `dt`.
pub fn free_vibration_error(
    kind: IntegratorKind,
    zeta: f64,
    dt: f64,
    t_end: f64,
) -> Result<f64, ModelError> {
    let omega = 2.0 * std::f64::consts::PI;
    let damping = Damping {
        alpha: 2.0 * zeta * omega,
        beta: 0.0,
    };
    let s = sdof(1.0, omega * omega, damping)?;
    let mut integ = kind.create();
    integ.prepare(&s, dt)?;
    let mut zero = |_: f64, f: &mut [f64]| f.fill(0.0);
    integ.start(&s, 0.0, &[1.0], &[0.0], &mut zero)?;
    let steps = (t_end / dt).round() as usize;
    for _ in 0..steps {
        integ.step(&s, &mut zero)?;
    }
    let t = integ.state().t;
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    let exact = (-zeta * omega * t).exp() * ((wd * t).cos() + zeta * omega / wd * (wd * t).sin());
    Ok((integ.state().u[0] - exact).abs())
}
