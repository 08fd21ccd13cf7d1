//! The full-order implicit step on the default abdomen at small strain against a plain
//! reference: the same scheme written out as in seed 003 App. B (divisions and all), with
//! faer's own sparse Cholesky solver (64-bit indices, its own ordering and sweeps) and
//! faer's sparse products. The project's step — its own panel sweeps, 32-bit indices,
//! precomputed coefficients and gathered products — must give the same displacements to
//! 1e-12 relative.

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, SparseColMatRef};
use faer::{Col, Side};
use models::scene::abdomen::Abdomen;
use models::scene::Scene;
use models::solve::{IntegratorKind, Structure};

const DT: f64 = 1e-3;

/// The default abdomen at small strain: its linear system is what the plain reference
/// steps.
fn default_abdomen() -> Abdomen {
    let mut scene = Abdomen::new();
    scene.set_str("kinematics", "linear").unwrap();
    scene.initialize(0.0).unwrap();
    scene
}

/// A pressing force (N/mm): 0.8 sin(π t).
fn press(t: f64) -> f64 {
    0.8 * (std::f64::consts::PI * t).sin()
}

/// c_m M + c_c C + K (the three share one pattern).
fn effective(s: &Structure, c_m: f64, c_c: f64) -> SparseColMat<usize, f64> {
    let (m, c, k) = (s.mass(), s.damping_matrix(), s.stiffness());
    let values = (m.val().iter().zip(c.val()).zip(k.val()))
        .map(|((m, c), k)| c_m * m + c_c * c + k)
        .collect();
    SparseColMat::new(k.symbolic().to_owned().unwrap(), values)
}

fn product(a: SparseColMatRef<'_, usize, f64>, x: &Col<f64>) -> Col<f64> {
    a * x
}

/// `steps` steps from rest: two of Newmark's average acceleration, then Houbolt
/// (seed 003 eq. B.15–B.17), written out plainly.
fn reference(s: &Structure, unit: &[f64], steps: usize) -> Vec<f64> {
    let n = s.n();
    let (m, c) = (s.mass(), s.damping_matrix());
    let f = |t: f64| Col::<f64>::from_fn(n, |i| press(t) * unit[i]);
    let newmark = effective(s, 4.0 / (DT * DT), 2.0 / DT)
        .sp_cholesky(Side::Lower)
        .unwrap();
    let houbolt = effective(s, 2.0 / (DT * DT), 11.0 / (6.0 * DT))
        .sp_cholesky(Side::Lower)
        .unwrap();
    let zero = || Col::<f64>::zeros(n);
    let (mut u, mut v, mut a) = (zero(), zero(), zero());
    let mut history = vec![u.clone()];
    for step in 1..=2 {
        let t = step as f64 * DT;
        let x_m = Col::from_fn(n, |i| 4.0 / (DT * DT) * u[i] + 4.0 / DT * v[i] + a[i]);
        let x_c = Col::from_fn(n, |i| 2.0 / DT * u[i] + v[i]);
        let rhs = f(t) + product(m, &x_m) + product(c, &x_c);
        let u1 = newmark.solve(&rhs);
        let a1 = Col::from_fn(n, |i| {
            4.0 / (DT * DT) * (u1[i] - u[i]) - 4.0 / DT * v[i] - a[i]
        });
        v = Col::from_fn(n, |i| v[i] + 0.5 * DT * (a[i] + a1[i]));
        (u, a) = (u1, a1);
        history.push(u.clone());
    }
    for step in 3..=steps {
        let t = step as f64 * DT;
        let (u1, u2) = (&history[history.len() - 2], &history[history.len() - 3]);
        let x_m = Col::from_fn(n, |i| (5.0 * u[i] - 4.0 * u1[i] + u2[i]) / (DT * DT));
        let x_c = Col::from_fn(n, |i| (3.0 * u[i] - 1.5 * u1[i] + u2[i] / 3.0) / DT);
        let rhs = f(t) + product(m, &x_m) + product(c, &x_c);
        u = houbolt.solve(&rhs);
        history.push(u.clone());
    }
    u.iter().copied().collect()
}

fn relative_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = a
        .iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
    diff / scale
}

#[test]
fn the_houbolt_step_matches_the_plain_reference_to_1e_12() {
    let scene = default_abdomen();
    let (s, unit) = scene.system().unwrap();
    let steps = 300;
    let mut h = IntegratorKind::Houbolt.create();
    h.prepare(s, DT).unwrap();
    let mut load = |t: f64, f: &mut [f64]| {
        for (f, u) in f.iter_mut().zip(unit) {
            *f = press(t) * u;
        }
    };
    let zero = vec![0.0; s.n()];
    h.start(s, 0.0, &zero, &zero, &mut load).unwrap();
    for _ in 0..steps {
        h.step(s, &mut load).unwrap();
    }
    let expected = reference(s, unit, steps);
    let diff = relative_difference(&h.state().u, &expected);
    eprintln!("Houbolt, {steps} steps: largest difference {diff:.1e} of the peak");
    assert!(diff < 1e-12, "{diff:e}");
}

#[test]
fn the_solve_matches_faers_solver_to_1e_12() {
    let scene = default_abdomen();
    let (s, _) = scene.system().unwrap();
    let (c_m, c_c) = (2.0 / (DT * DT), 11.0 / (6.0 * DT));
    let a = effective(s, c_m, c_c);
    let mut chol = s.analyze().unwrap();
    chol.factorize(a.as_ref()).unwrap();
    let b: Vec<f64> = (0..s.n()).map(|i| ((i * 37) % 101) as f64 - 50.0).collect();
    let mut x = b.clone();
    chol.solve_in_place(&mut x);
    let expected = a
        .sp_cholesky(Side::Lower)
        .unwrap()
        .solve(Col::<f64>::from_fn(s.n(), |i| b[i]));
    let expected: Vec<f64> = expected.iter().copied().collect();
    let diff = relative_difference(&x, &expected);
    eprintln!("solve: largest difference {diff:.1e} of the peak");
    assert!(diff < 1e-12, "{diff:e}");
}
