//! Speed versus error for the abdomen scene: for each mesh size, integrator and time step,
//! the set-up time, the time per step and the error of the pelvic-floor stress history
//! against a converged reference (finest mesh, smallest step, Houbolt); and a stability table
//! of what each integrator does on the hard cases. Results go to a CSV written atomically.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use models::scene::abdomen::Abdomen;

use crate::sweep::{simulate, simulate_observed, InProcess, Schedule, Value};

/// One measured case.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    pub triangles: usize,
    pub integrator: String,
    pub dt: f64,
    pub setup_ms: f64,
    pub step_ms: f64,
    /// Max over the run of |σ_floor,max − reference| / max |reference|.
    pub error: f64,
}

/// The study: mesh targets, integrators, steps, simulated time.
#[derive(Debug, Clone)]
pub struct Study {
    pub meshes: Vec<usize>,
    pub integrators: Vec<&'static str>,
    pub steps: Vec<f64>,
    pub duration: f64,
    /// Reference: mesh target and step (Houbolt).
    pub reference: (usize, f64),
}

impl Default for Study {
    fn default() -> Self {
        Self {
            meshes: vec![1500, 6000],
            integrators: vec!["houbolt", "newmark"],
            steps: vec![1e-3, 2e-3, 5e-3, 1e-2],
            duration: 0.5,
            reference: (12000, 2.5e-4),
        }
    }
}

/// The settings of one configuration of the abdomen.
fn settings(triangles: usize, integrator: &str, dt: f64) -> Vec<(String, Value)> {
    vec![
        ("target_triangles".into(), Value::Real(triangles as f64)),
        ("max_step".into(), Value::Real(dt)),
        ("integrator".into(), Value::Text(integrator.into())),
    ]
}

/// Samples of `floor_stress_max` every 10 ms over `duration`, with set-up and mean step time.
fn run(
    triangles: usize,
    integrator: &str,
    dt: f64,
    duration: f64,
) -> Result<(Vec<f64>, f64, f64, usize)> {
    let settings = settings(triangles, integrator, dt);
    let record = ["floor_stress_max".to_string()];
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: duration,
        step: 1e-2,
        settings: &settings,
        inputs: &BTreeMap::new(),
        record: &record,
    };
    let mut session = InProcess(Box::new(Abdomen::new()));
    let run = simulate(&mut session, &schedule)?;
    let n_tri = session.0.meshed().map_or(0, |m| m.mesh.triangles().len());
    let samples = run.series.column("floor_stress_max").context("recorded")?;
    let steps = (duration / dt).round().max(1.0);
    Ok((
        samples[1..].to_vec(),
        run.setup.as_secs_f64() * 1e3,
        run.stepping.as_secs_f64() * 1e3 / steps,
        n_tri,
    ))
}

/// Runs the study.
pub fn measure(study: &Study) -> Result<Vec<Case>> {
    let (reference, _, _, _) = run(
        study.reference.0,
        "houbolt",
        study.reference.1,
        study.duration,
    )?;
    let scale = reference
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()))
        .max(1e-300);
    let mut cases = Vec::new();
    for &mesh in &study.meshes {
        for &integrator in &study.integrators {
            for &dt in &study.steps {
                let (samples, setup_ms, step_ms, triangles) =
                    run(mesh, integrator, dt, study.duration)?;
                let error = samples
                    .iter()
                    .zip(&reference)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max)
                    / scale;
                cases.push(Case {
                    triangles,
                    integrator: integrator.to_string(),
                    dt,
                    setup_ms,
                    step_ms,
                    error,
                });
            }
        }
    }
    Ok(cases)
}

/// What an integrator did on a hard case.
#[derive(Debug, Clone, PartialEq)]
pub struct Stability {
    pub case: &'static str,
    pub integrator: &'static str,
    pub outcome: String,
}

/// A hard case: label, parameter settings, step.
type HardCase = (&'static str, &'static [(&'static str, f64)], f64);

/// Runs each integrator on the hard cases for 0.1 s at a small mesh and says what happened:
/// "bounded (peak |u| …)", or the error the scene reported.
pub fn stability() -> Vec<Stability> {
    let cases: [HardCase; 4] = [
        ("ν = 0.499", &[("cavity_nu", 0.499)], 1e-3),
        (
            "line elements 1e6 × stiffer",
            &[("wall_E", 5e3), ("diaphragm_E", 5e3), ("floor_E", 5e3)],
            1e-3,
        ),
        ("huge dt (0.1 s)", &[], 0.1),
        ("dt = 1 ms (above explicit limits)", &[], 1e-3),
    ];
    let mut out = Vec::new();
    for (case, extra, dt) in cases {
        for integrator in ["houbolt", "newmark", "central_difference", "rk4"] {
            let mut settings = settings(800, integrator, dt);
            settings.extend(extra.iter().map(|&(k, v)| (k.to_string(), Value::Real(v))));
            let schedule = Schedule {
                start_time: 0.0,
                stop_time: ((0.1 / dt).round()).max(1.0) * dt,
                step: dt,
                settings: &settings,
                inputs: &BTreeMap::new(),
                record: &[],
            };
            let mut peak: f64 = 0.0;
            let observe = |s: &mut InProcess<Abdomen>, _| {
                let u =
                    s.0.field()
                        .map_or(0.0, |f| f.u.iter().fold(0.0f64, |a, b| a.max(b.abs())));
                peak = peak.max(u);
                Ok(())
            };
            let outcome = match simulate_observed(
                &mut InProcess(Box::new(Abdomen::new())),
                &schedule,
                observe,
            ) {
                Ok(_) => format!("bounded (peak |u| {peak:.3e} mm)"),
                Err(e) => format!(
                    "refused: {}",
                    e.root_cause()
                        .to_string()
                        .split(';')
                        .next()
                        .unwrap_or_default()
                ),
            };
            out.push(Stability {
                case,
                integrator,
                outcome,
            });
        }
    }
    out
}

/// Writes the cases as CSV to `path` (atomically, [`crate::atomic::write_atomic`]).
pub fn write_csv(cases: &[Case], path: &Path) -> Result<PathBuf> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "triangles",
        "integrator",
        "dt_s",
        "setup_ms",
        "step_ms",
        "relative_error",
    ])?;
    for c in cases {
        w.write_record([
            c.triangles.to_string(),
            c.integrator.clone(),
            format!("{:e}", c.dt),
            format!("{:.3}", c.setup_ms),
            format!("{:.4}", c.step_ms),
            format!("{:.4e}", c.error),
        ])?;
    }
    crate::atomic::write_atomic(path, &w.into_inner()?)?;
    Ok(path.to_path_buf())
}

/// The Pareto front of (cost, error) points: those no other point beats in both, by cost.
pub fn pareto(points: &[(f64, f64)]) -> Vec<(f64, f64)> {
    let mut sorted = points.to_vec();
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut front: Vec<(f64, f64)> = Vec::new();
    for p in sorted {
        if front.last().is_none_or(|l| p.1 < l.1) {
            front.push(p);
        }
    }
    front
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn error_falls_with_the_step_and_the_csv_is_complete() {
        let study = Study {
            meshes: vec![600],
            integrators: vec!["houbolt", "newmark"],
            steps: vec![2e-3, 1e-2],
            duration: 0.2,
            reference: (600, 2.5e-4),
        };
        let cases = measure(&study).unwrap();
        assert_eq!(cases.len(), 4);
        for pair in cases.chunks(2) {
            println!("{pair:?}");
            // Same mesh as the reference: what remains is the time-step error, smaller at 2 ms.
            assert!(pair[0].error < pair[1].error, "{pair:?}");
            assert!(pair.iter().all(|c| c.step_ms > 0.0 && c.error.is_finite()));
        }
        let dir = std::env::temp_dir().join(format!("speed-error-{}", std::process::id()));
        let path = write_csv(&cases, &dir.join("speed_error.csv")).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(text.lines().count(), 5);
        let files = std::fs::read_dir(&dir).unwrap().count();
        assert_eq!(files, 1, "no temporary file is left beside the CSV");
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn explicit_schemes_above_their_limit_are_refused_and_implicit_ones_stay_bounded() {
        let table = stability();
        let outcome = |case: &str, integ: &str| {
            table
                .iter()
                .find(|s| s.case == case && s.integrator == integ)
                .unwrap()
                .outcome
                .clone()
        };
        for integ in ["central_difference", "rk4"] {
            let o = outcome("dt = 1 ms (above explicit limits)", integ);
            assert!(
                o.starts_with("refused") && o.contains("unstable"),
                "{integ}: {o}"
            );
        }
        for integ in ["houbolt", "newmark"] {
            for case in [
                "ν = 0.499",
                "line elements 1e6 × stiffer",
                "huge dt (0.1 s)",
            ] {
                assert!(
                    outcome(case, integ).starts_with("bounded"),
                    "{integ} {case}"
                );
            }
        }
    }

    #[test]
    fn the_pareto_front_keeps_only_unbeaten_points() {
        let pts = [(3.0, 0.1), (1.0, 0.5), (2.0, 0.6), (4.0, 0.01), (5.0, 0.05)];
        assert_eq!(pareto(&pts), [(1.0, 0.5), (3.0, 0.1), (4.0, 0.01)]);
    }
}
