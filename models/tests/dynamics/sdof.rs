//! Integrators on the single-degree-of-freedom oscillator against the exact solution and
//! against Houbolt's characteristic equation.

use models::solve::{Damping, IntegratorKind};
use models::verify::oscillator::{free_vibration_error, houbolt_theory, measure, sdof};

/// Observed order p from errors at dt, dt/2, dt/4, … at t = 1.3 T (not a multiple of T/4,
/// where a pure phase error would vanish to first order).
fn orders(kind: IntegratorKind, zeta: f64, dts: &[f64]) -> Vec<f64> {
    let errors: Vec<f64> = dts
        .iter()
        .map(|&dt| free_vibration_error(kind, zeta, dt, 1.3).unwrap())
        .collect();
    println!(
        "{kind:?} zeta={zeta}: errors {}",
        errors
            .iter()
            .map(|e| format!("{e:.3e}"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

#[test]
fn implicit_schemes_are_second_order_with_and_without_damping() {
    let dts = [1.0 / 40.0, 1.0 / 80.0, 1.0 / 160.0, 1.0 / 320.0];
    for kind in [IntegratorKind::Houbolt, IntegratorKind::Newmark] {
        for zeta in [0.0, 0.05] {
            let p = orders(kind, zeta, &dts);
            println!("{kind:?} zeta={zeta}: orders {p:.3?}");
            assert!(p.iter().all(|p| (p - 2.0).abs() < 0.1), "{kind:?} {p:?}");
        }
    }
}

#[test]
fn explicit_schemes_have_their_orders() {
    let dts = [1.0 / 40.0, 1.0 / 80.0, 1.0 / 160.0, 1.0 / 320.0];
    let p = orders(IntegratorKind::CentralDifference, 0.0, &dts);
    assert!(p.iter().all(|p| (p - 2.0).abs() < 0.1), "{p:?}");
    let p = orders(IntegratorKind::Rk4, 0.0, &dts);
    println!("rk4 orders {p:.3?}");
    assert!(p.iter().all(|p| (p - 4.0).abs() < 0.2), "{p:?}");
}

#[test]
fn houbolt_spectral_properties_match_its_characteristic_equation() {
    for ratio in [0.05, 0.1] {
        let theory = houbolt_theory(ratio);
        let measured = measure(IntegratorKind::Houbolt, ratio, 14).unwrap();
        println!(
            "dt/T={ratio}: period elongation theory {:.2}% measured {:.2}%; amplitude decay \
             theory {:.2}% measured {:.2}%",
            100.0 * theory.period_elongation,
            100.0 * measured.period_elongation,
            100.0 * theory.amplitude_decay,
            100.0 * measured.amplitude_decay
        );
        let close = |a: f64, b: f64| ((a - b) / b).abs() < 0.10;
        assert!(close(measured.period_elongation, theory.period_elongation));
        assert!(close(measured.amplitude_decay, theory.amplitude_decay));
    }
}

#[test]
fn newmark_conserves_amplitude_and_houbolt_does_not() {
    let n = measure(IntegratorKind::Newmark, 0.1, 10).unwrap();
    assert!(n.amplitude_decay.abs() < 1e-3, "{n:?}");
    // Newmark's period elongation at Δt/T = 0.1 is Ω/(2 atan(Ω/2)) − 1 ≈ 3.3 %.
    let omega = 2.0 * std::f64::consts::PI * 0.1;
    let expect = omega / (2.0 * (omega / 2.0).atan()) - 1.0;
    assert!(
        ((n.period_elongation - expect) / expect).abs() < 0.05,
        "{n:?} vs {expect}"
    );
    assert!(
        measure(IntegratorKind::Houbolt, 0.1, 10)
            .unwrap()
            .amplitude_decay
            > 0.2
    );
}

#[test]
fn houbolt_start_is_exact_for_a_free_mass_under_constant_force() {
    // K = 0 is allowed here: Houbolt's effective matrix 2M/Δt² is positive definite.
    let s = sdof(2.0, 0.0, Damping::NONE);
    // A structure needs K > 0 only for the explicit schemes' spectrum; Houbolt works.
    let s = s.unwrap();
    let mut h = IntegratorKind::Houbolt.create();
    h.prepare(&s, 0.01).unwrap();
    let mut load = |_: f64, f: &mut [f64]| f[0] = 3.0;
    h.start(&s, 0.0, &[0.5], &[0.2], &mut load).unwrap();
    for _ in 0..100 {
        h.step(&s, &mut load).unwrap();
    }
    let t = h.state().t;
    let exact = 0.5 + 0.2 * t + 0.5 * 1.5 * t * t;
    assert!(
        (h.state().u[0] - exact).abs() < 1e-12,
        "{} vs {exact}",
        h.state().u[0]
    );
    assert!((h.state().v[0] - (0.2 + 1.5 * t)).abs() < 1e-11);
    assert!((h.state().a[0] - 1.5).abs() < 1e-9);
}
