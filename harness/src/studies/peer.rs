//! The problem of the peer benchmark (`benches/peer`): the default abdomen's full-order
//! matrices on the free dofs (M, C, K in Matrix Market), its pressing load, the end of a
//! Houbolt run computed here, and this project's times on the same matrices (medians). The
//! Python side steps the same problem with scipy's `splu` and with CHOLMOD, checks that it
//! ends where the run here ended, and sets the times side by side — one run, one machine.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result};
use models::scene::abdomen::Abdomen;
use models::scene::Scene;
use models::solve::{IntegratorKind, Structure};
use nalgebra_sparse::CscMatrix;
use serde::Serialize;

use crate::atomic::write_atomic;

/// Step size of the exported run (the abdomen's default `max_step`).
const DT: f64 = 1e-3;

/// This project's times on the exported matrices (seconds, medians).
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Timing {
    /// A Houbolt step: load, history products, triangular solves, history update.
    pub step: f64,
    /// The two triangular solves alone, with the Houbolt effective matrix.
    pub solve: f64,
    /// A numeric factorization of the Houbolt effective matrix.
    pub factor: f64,
}

/// What `problem.json` holds besides the matrix files.
#[derive(Serialize)]
struct Problem<'a> {
    /// Equations (free dofs), stored entries of K, stored entries of the Cholesky factor.
    n: usize,
    nnz: usize,
    nnz_factor: usize,
    dt: f64,
    /// Houbolt steps taken, the first two by Newmark's average-acceleration method (the
    /// starting procedure of `models::solve::houbolt`), from rest at t = 0.
    steps: usize,
    /// The load is f(t) = p(t) · unit_load with p(t) = force + amplitude · sin(2π frequency t).
    force: f64,
    amplitude: f64,
    frequency: f64,
    unit_load: &'a [f64],
    /// Displacement after `steps` steps.
    u_final: &'a [f64],
    rust: Timing,
}

/// Writes `M.mtx`, `C.mtx`, `K.mtx` and `problem.json` into `out` for a run of `steps` steps
/// and returns the times measured on them.
pub fn export(out: &Path, steps: usize) -> Result<Timing> {
    anyhow::ensure!(
        steps >= 10,
        "steps = {steps}: the peer run needs at least 10"
    );
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let mut scene = Abdomen::new();
    scene.initialize(0.0)?;
    let [force, amplitude, frequency] =
        ["press_force", "press_amplitude", "press_frequency"].map(|name| scene.get(name));
    let (force, amplitude, frequency) = (force?, amplitude?, frequency?);
    let (s, unit_load) = scene.system().context("the abdomen is initialized")?;
    for (name, a) in [
        ("M", s.mass()),
        ("C", s.damping_matrix()),
        ("K", s.stiffness()),
    ] {
        let csc = CscMatrix::try_from_csc_data(
            a.nrows(),
            a.ncols(),
            a.symbolic().col_ptr().to_vec(),
            a.symbolic().row_idx().to_vec(),
            a.val().to_vec(),
        )
        .map_err(|e| anyhow::anyhow!("{name} is not a valid CSC matrix: {e}"))?;
        // The format's banner is `%%MatrixMarket`; nalgebra-sparse 0.12 writes it in lower
        // case, which scipy's reader (fast_matrix_market) refuses.
        let text = nalgebra_sparse::io::save_to_matrix_market_str(&csc).replacen(
            "%%matrixmarket",
            "%%MatrixMarket",
            1,
        );
        write_atomic(&out.join(format!("{name}.mtx")), text.as_bytes())?;
    }
    let press = |t: f64| force + amplitude * (2.0 * std::f64::consts::PI * frequency * t).sin();
    let (u_final, step) = run(s, unit_load, press, steps)?;
    let (solve, factor, nnz_factor) = solve_and_factor(s, unit_load, steps)?;
    let rust = Timing {
        step,
        solve,
        factor,
    };
    let problem = Problem {
        n: s.n(),
        nnz: s.stiffness().val().len(),
        nnz_factor,
        dt: DT,
        steps,
        force,
        amplitude,
        frequency,
        unit_load,
        u_final: &u_final,
        rust,
    };
    write_atomic(
        &out.join("problem.json"),
        serde_json::to_string_pretty(&problem)?.as_bytes(),
    )?;
    Ok(rust)
}

/// A Houbolt run from rest: the final displacement and the median time of a Houbolt step
/// (the two starter steps excluded).
fn run(
    s: &Structure,
    unit_load: &[f64],
    press: impl Fn(f64) -> f64,
    steps: usize,
) -> Result<(Vec<f64>, f64)> {
    let mut h = IntegratorKind::Houbolt.create();
    h.prepare(s, DT)?;
    let mut load = |t: f64, f: &mut [f64]| {
        let p = press(t);
        f.iter_mut().zip(unit_load).for_each(|(f, u)| *f = p * u);
    };
    let zero = vec![0.0; s.n()];
    h.start(s, 0.0, &zero, &zero, &mut load)?;
    let mut times = Vec::with_capacity(steps);
    for _ in 0..steps {
        let t0 = Instant::now();
        h.step(s, &mut load)?;
        times.push(t0.elapsed().as_secs_f64());
    }
    Ok((h.state().u.clone(), median(&mut times[2..])))
}

/// Median times of the triangular solves and of the numeric factorization of the Houbolt
/// effective matrix 2/Δt² M + 11/(6Δt) C + K, and the factor's size.
fn solve_and_factor(s: &Structure, rhs: &[f64], solves: usize) -> Result<(f64, f64, usize)> {
    let mut chol = s.analyze()?;
    let mut values = vec![0.0; s.dirichlet().nnz()];
    s.effective(2.0 / (DT * DT), 11.0 / (6.0 * DT), &mut values);
    let a = s.dirichlet().matrix(&values);
    let mut factor: Vec<f64> = (0..5)
        .map(|_| {
            let t0 = Instant::now();
            chol.factorize(a).map(|()| t0.elapsed().as_secs_f64())
        })
        .collect::<Result<_, _>>()?;
    let mut x = rhs.to_vec();
    let mut solve: Vec<f64> = (0..solves)
        .map(|_| {
            x.copy_from_slice(rhs);
            let t0 = Instant::now();
            chol.solve_in_place(&mut x);
            t0.elapsed().as_secs_f64()
        })
        .collect();
    Ok((median(&mut solve), median(&mut factor), chol.factor_nnz()))
}

fn median(x: &mut [f64]) -> f64 {
    x.sort_by(f64::total_cmp);
    x[x.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_export_reads_back_as_the_scene_system() {
        let dir = tempfile::tempdir().unwrap();
        let timing = export(dir.path(), 10).unwrap();
        assert!(timing.step > 0.0 && timing.solve > 0.0 && timing.factor > 0.0);
        let problem: serde_json::Value =
            serde_json::from_slice(&std::fs::read(dir.path().join("problem.json")).unwrap())
                .unwrap();
        let n = problem["n"].as_u64().unwrap() as usize;
        let mut scene = Abdomen::new();
        scene.initialize(0.0).unwrap();
        let (s, _) = scene.system().unwrap();
        assert_eq!(n, s.n());
        for (name, a) in [("M", s.mass()), ("K", s.stiffness())] {
            let text = std::fs::read_to_string(dir.path().join(format!("{name}.mtx"))).unwrap();
            assert!(text.starts_with("%%MatrixMarket matrix coordinate real general"));
            let coo = nalgebra_sparse::io::load_coo_from_matrix_market_str::<f64>(&text).unwrap();
            assert_eq!((coo.nrows(), coo.nnz()), (n, a.val().len()));
            // Written in full precision: every value reads back bit for bit.
            let csc = nalgebra_sparse::CscMatrix::from(&coo);
            assert_eq!(csc.values(), a.val(), "{name}");
        }
        assert_eq!(problem["u_final"].as_array().unwrap().len(), n);
    }
}
