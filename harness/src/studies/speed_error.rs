//! Speed versus error for the abdomen scene (issues 12 and 26): for each model form and
//! cavity discretization (kinematics, element, formulation and mesh grading), mesh size,
//! model order, integrator and time step, the set-up time, the time per step and the error
//! of the pelvic-floor stress (mean and max), diaphragm apex and floor midpoint histories
//! over the first press against a reference of the right physics — finite strain, the 6-node
//! displacement element on a fine graded mesh (`mesh_grading` = ½, where the outputs
//! converge at the element's order) — so that the linear model's form error shows on the
//! front beside the discretization errors. The reference's own mesh error is estimated
//! twice, from the static outputs at the peak press: by Richardson extrapolation on its
//! graded family (target/16, /4, /1) and by its distance from the Richardson extrapolation
//! of an independent family, uniform nested meshes; its time-step error by halving the step
//! on the family's coarsest mesh. The apex and the floor midpoint are fixed points of every
//! mesh's boundary sampling, so every case measures the same points. Results go to a CSV
//! written atomically.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{ensure, Context, Result};
use models::scene::abdomen::Abdomen;
use models::scene::Scene;
use models::verify::richardson::{extrapolate, RichardsonEstimate};

use crate::sweep::{simulate, InProcess, Schedule, Session, Value};

/// The outputs whose histories are compared.
pub const QUANTITIES: [&str; 4] = [
    "floor_stress_mean",
    "floor_stress_max",
    "apex_uy",
    "floor_mid_uy",
];
/// Their indices in [`Abdomen::evaluate`]'s outputs.
const STATIC_INDEX: [usize; 4] = [0, 1, 7, 9];
/// How many quantities are compared.
const N: usize = QUANTITIES.len();
/// The interval the histories are sampled at (s): the communication step of every case.
const SAMPLE: f64 = 2e-2;
/// The press of the static outputs: the default press's peak (N/mm).
const PEAK: f64 = 0.8;

/// A model form and cavity discretization (kinematics, element, formulation,
/// `mesh_grading`) and the target triangle counts it is run at.
#[derive(Debug, Clone)]
pub struct Discretization {
    /// The scene's `kinematics`: `finite` or `linear`.
    pub kinematics: &'static str,
    /// The cavity element: `tri3` or `tri6`.
    pub element: &'static str,
    /// The `formulation`: `displacement` or `mixed`.
    pub formulation: &'static str,
    /// The `mesh_grading` exponent β (0: uniform).
    pub grading: f64,
    /// The `target_triangles` of its meshes.
    pub targets: Vec<usize>,
}

/// The reference: finite strain, the 6-node displacement element on `target` triangles
/// graded by `grading`, Houbolt at `dt`. Its error estimates use graded meshes of target/16
/// and target/4 and uniform nested ones (target/64 split into four 1–3 times).
#[derive(Debug, Clone, Copy)]
pub struct ReferenceSetting {
    /// The reference mesh's `target_triangles`.
    pub target: usize,
    /// Its `mesh_grading` exponent β.
    pub grading: f64,
    /// Its time step (s).
    pub dt: f64,
}

/// The study: discretizations, model orders, integrators, steps, simulated time and the
/// reference.
#[derive(Debug, Clone)]
pub struct Study {
    /// The model forms and discretizations, each with its meshes.
    pub discretizations: Vec<Discretization>,
    /// The `model_order`s; all but `full` only where the kinematics is linear.
    pub orders: Vec<&'static str>,
    /// The integrators (e.g. `houbolt`, `newmark`).
    pub integrators: Vec<&'static str>,
    /// The time steps (s); each must divide the 20 ms sampling interval.
    pub steps: Vec<f64>,
    /// Simulated time of every case (s).
    pub duration: f64,
    /// The reference's setting.
    pub reference: ReferenceSetting,
}

impl Default for Study {
    fn default() -> Self {
        let d = |kinematics, element, formulation, grading, targets: &[usize]| Discretization {
            kinematics,
            element,
            formulation,
            grading,
            targets: targets.to_vec(),
        };
        Self {
            discretizations: vec![
                // 750 graded: the scene's default mesh.
                d("finite", "tri6", "displacement", 0.5, &[750, 3000, 12000]),
                d("finite", "tri6", "displacement", 0.0, &[750, 3000]),
                d("finite", "tri6", "mixed", 0.5, &[750, 3000]),
                d("linear", "tri6", "displacement", 0.5, &[750, 3000, 12000]),
                d("linear", "tri3", "displacement", 0.0, &[750, 3000, 12000]),
            ],
            orders: vec!["full", "modal"],
            integrators: vec!["houbolt", "newmark"],
            steps: vec![5e-3, 1e-2, 2e-2],
            duration: 1.0,
            reference: ReferenceSetting {
                target: 48000,
                grading: 0.5,
                dt: 1.25e-3,
            },
        }
    }
}

impl Study {
    /// The cases the study runs, in order: every discretization and mesh, order (the
    /// reduced orders only for linear kinematics), integrator and step.
    fn settings(&self) -> Vec<Setting<'static>> {
        let mut settings = Vec::new();
        for d in &self.discretizations {
            for &triangles in &d.targets {
                // The reduced orders reduce the linear equation of motion.
                let orders = self
                    .orders
                    .iter()
                    .filter(|&&o| o == "full" || d.kinematics == "linear");
                for &order in orders {
                    for &integrator in &self.integrators {
                        for &dt in &self.steps {
                            settings.push(Setting {
                                kinematics: d.kinematics,
                                element: d.element,
                                formulation: d.formulation,
                                grading: d.grading,
                                triangles,
                                subdivisions: 0,
                                order,
                                integrator,
                                dt,
                            });
                        }
                    }
                }
            }
        }
        settings
    }

    /// How many cases the study runs.
    pub fn case_count(&self) -> usize {
        self.settings().len()
    }

    /// The quick report's study: the same model forms on their coarsest mesh, both orders
    /// and integrators at 10 and 20 ms, against a reference on 12,000 graded triangles whose
    /// own error is estimated as in the full study (its families: graded 750 / 3,000 /
    /// 12,000 and uniform nested 187 × 4¹⁻³).
    pub fn quick() -> Self {
        let full = Self::default();
        Self {
            discretizations: full
                .discretizations
                .into_iter()
                .map(|d| Discretization {
                    targets: d.targets[..1].to_vec(),
                    ..d
                })
                .collect(),
            steps: vec![1e-2, 2e-2],
            reference: ReferenceSetting {
                target: 12000,
                grading: 0.5,
                dt: 2.5e-3,
            },
            ..full
        }
    }
}

/// How far the reference itself is from the converged answer, per quantity (relative to the
/// peak of its history).
#[derive(Debug, Clone)]
pub struct ReferenceError {
    /// Triangles of the reference's mesh.
    pub triangles: usize,
    /// The static outputs at the peak press on the graded family (coarsest first).
    pub graded_values: [[f64; 3]; N],
    /// Richardson extrapolation of the static output on the reference's graded family, or
    /// why there is none.
    pub graded: [Result<RichardsonEstimate, String>; N],
    /// The same on uniform nested meshes: an independent estimate of the converged value.
    pub uniform: [Result<RichardsonEstimate, String>; N],
    /// Relative mesh error estimate of the reference: the larger of the graded family's
    /// Richardson error and the distance of the reference's static output from the uniform
    /// family's extrapolation (NaN if neither exists).
    pub mesh_error: [f64; N],
    /// Relative time-step error estimate at the reference step.
    pub time_error: [f64; N],
}

/// One measured case.
#[derive(Debug, Clone, PartialEq)]
pub struct AbdomenRun {
    /// The scene's `kinematics`.
    pub kinematics: &'static str,
    /// The cavity element.
    pub element: &'static str,
    /// The `formulation`.
    pub formulation: &'static str,
    /// The `mesh_grading` exponent β.
    pub grading: f64,
    /// Triangles of the case's mesh as built.
    pub triangles: usize,
    /// The `model_order`.
    pub order: &'static str,
    /// The integrator.
    pub integrator: String,
    /// The time step (s), the scene's `max_step`.
    pub dt: f64,
    /// Set-up time: the parameters set and the scene initialized (ms).
    pub setup_ms: f64,
    /// Mean stepping time per time step `dt` (ms).
    pub step_ms: f64,
    /// Per quantity: max over the run of |q − q_ref| / max |q_ref|.
    pub errors: [f64; N],
}

impl AbdomenRun {
    /// The largest of the errors.
    pub fn error(&self) -> f64 {
        self.errors.iter().fold(0.0, |a, &b| a.max(b))
    }

    /// Stepping time per simulated second (ms).
    pub fn ms_per_second(&self) -> f64 {
        self.step_ms / self.dt
    }
}

/// A configuration of the abdomen: parameter settings.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Setting<'a> {
    pub(crate) kinematics: &'a str,
    pub(crate) element: &'a str,
    pub(crate) formulation: &'a str,
    pub(crate) grading: f64,
    pub(crate) triangles: usize,
    pub(crate) subdivisions: u32,
    pub(crate) order: &'a str,
    pub(crate) integrator: &'a str,
    pub(crate) dt: f64,
}

impl Setting<'_> {
    pub(crate) fn values(&self) -> Vec<(String, Value)> {
        vec![
            ("kinematics".into(), Value::Text(self.kinematics.into())),
            ("element".into(), Value::Text(self.element.into())),
            ("formulation".into(), Value::Text(self.formulation.into())),
            ("mesh_grading".into(), Value::Real(self.grading)),
            (
                "target_triangles".into(),
                Value::Real(self.triangles as f64),
            ),
            (
                "mesh_subdivisions".into(),
                Value::Real(f64::from(self.subdivisions)),
            ),
            ("model_order".into(), Value::Text(self.order.into())),
            ("max_step".into(), Value::Real(self.dt)),
            ("integrator".into(), Value::Text(self.integrator.into())),
        ]
    }
}

/// A run's histories of [`QUANTITIES`] every [`SAMPLE`] over `duration`, set-up and mean
/// step time (ms), and the triangles of its mesh.
struct Measured {
    histories: [Vec<f64>; N],
    setup_ms: f64,
    step_ms: f64,
    triangles: usize,
}

fn run(setting: Setting, duration: f64) -> Result<Measured> {
    let settings = setting.values();
    let record = QUANTITIES.map(str::to_string);
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: duration,
        step: SAMPLE,
        settings: &settings,
        inputs: &BTreeMap::new(),
        record: &record,
    };
    let mut session = InProcess(Box::new(Abdomen::new()));
    let run = simulate(&mut session, &schedule)
        .with_context(|| format!("speed–error case {setting:?}"))?;
    let triangles = session.0.meshed().map_or(0, |m| m.mesh.triangles().len());
    let mut histories: [Vec<f64>; N] = Default::default();
    for (history, name) in histories.iter_mut().zip(QUANTITIES) {
        *history = run.series.column(name).context("recorded")?[1..].to_vec();
    }
    let steps = (duration / setting.dt).round().max(1.0);
    Ok(Measured {
        histories,
        setup_ms: run.setup.as_secs_f64() * 1e3,
        step_ms: run.stepping.as_secs_f64() * 1e3 / steps,
        triangles,
    })
}

/// max_k |a_k − b_k| / max_k |b_k|.
fn relative_deviation(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-300);
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

/// The reference histories and their estimated errors.
pub struct AbdomenReference {
    histories: [Vec<f64>; N],
    /// The reference's estimated mesh and time-step errors.
    pub error: ReferenceError,
}

/// Runs the reference and estimates its mesh and time-step errors.
pub fn reference(setting: ReferenceSetting, duration: f64) -> Result<AbdomenReference> {
    let graded = |target: usize, dt: f64| Setting {
        kinematics: "finite",
        element: "tri6",
        formulation: "displacement",
        grading: setting.grading,
        triangles: target,
        subdivisions: 0,
        order: "full",
        integrator: "houbolt",
        dt,
    };
    // The reference run beside its error estimates (none of them is timed): on two cores
    // the run takes about as long as the rest.
    let (fine, estimates) = rayon::join(
        || run(graded(setting.target, setting.dt), duration),
        || {
            // Time step: halving it on the coarsest mesh of the family; Houbolt is second
            // order, so the error at dt is 4/3 of the change.
            let coarse = graded(setting.target / 16, setting.dt);
            let halved = Setting {
                dt: setting.dt / 2.0,
                ..coarse
            };
            // Mesh: the static outputs at the peak press on the graded family and on
            // uniform nested meshes of the same sizes.
            let uniform = [1, 2, 3].map(|subdivisions| Setting {
                grading: 0.0,
                triangles: setting.target / 64,
                subdivisions,
                ..graded(0, setting.dt)
            });
            let statics = |settings: [Setting; 3]| -> Result<Vec<Vec<f64>>> {
                settings.into_iter().map(static_outputs).collect()
            };
            anyhow::Ok((
                [run(coarse, duration)?, run(halved, duration)?],
                statics([16, 4, 1].map(|d| graded(setting.target / d, setting.dt)))?,
                statics(uniform)?,
            ))
        },
    );
    let (fine, ([coarse, halved], graded_statics, uniform_statics)) = (fine?, estimates?);
    let peak = |k: usize| fine.histories[k].iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let time_error: [f64; N] = std::array::from_fn(|k| {
        4.0 / 3.0 * relative_deviation(&coarse.histories[k], &halved.histories[k])
    });
    let fit = |statics: &[Vec<f64>], k: usize| {
        let values = [0, 1, 2].map(|i| statics[i][STATIC_INDEX[k]]);
        extrapolate(values, 2.0).map_err(|e| e.to_string())
    };
    let graded_values: [[f64; 3]; N] =
        std::array::from_fn(|k| [0, 1, 2].map(|i| graded_statics[i][STATIC_INDEX[k]]));
    let graded: [_; N] = std::array::from_fn(|k| fit(&graded_statics, k));
    let uniform: [_; N] = std::array::from_fn(|k| fit(&uniform_statics, k));
    let mesh_error: [f64; N] = std::array::from_fn(|k| {
        let own = graded[k].as_ref().map_or(f64::NAN, |e| e.error);
        let reference = graded_statics[2][STATIC_INDEX[k]];
        let independent = uniform[k]
            .as_ref()
            .map_or(f64::NAN, |e| (e.value - reference).abs());
        own.max(independent) / peak(k).max(1e-300)
    });
    Ok(AbdomenReference {
        error: ReferenceError {
            triangles: fine.triangles,
            graded_values,
            graded,
            uniform,
            mesh_error,
            time_error,
        },
        histories: fine.histories,
    })
}

/// The static outputs of `setting`'s mesh and discretization under the press [`PEAK`].
fn static_outputs(setting: Setting) -> Result<Vec<f64>> {
    let mut session = InProcess(Box::new(Abdomen::new()));
    for (name, value) in setting.values() {
        let r = session.reference(&name)?;
        session.set(r, &value)?;
    }
    let s = &mut session.0;
    s.initialize(0.0)?;
    let u = s.static_displacement(PEAK)?;
    Ok(s.evaluate(&u, PEAK)?)
}

/// Runs the study's cases against `reference`, reporting each finished case to `progress`.
/// Steps that do not divide the sampling interval ([`SAMPLE`]) are refused.
pub fn measure(
    study: &Study,
    reference: &AbdomenReference,
    mut progress: impl FnMut(&AbdomenRun),
) -> Result<Vec<AbdomenRun>> {
    for &dt in &study.steps {
        ensure!(
            dt <= SAMPLE && (SAMPLE / dt - (SAMPLE / dt).round()).abs() < 1e-9,
            "speed–error step dt = {dt} s must divide the sampling interval {SAMPLE} s"
        );
    }
    let mut cases = Vec::new();
    for setting in study.settings() {
        let m = run(setting, study.duration)?;
        let errors: [f64; N] =
            std::array::from_fn(|k| relative_deviation(&m.histories[k], &reference.histories[k]));
        let case = AbdomenRun {
            kinematics: setting.kinematics,
            element: setting.element,
            formulation: setting.formulation,
            grading: setting.grading,
            triangles: m.triangles,
            order: setting.order,
            integrator: setting.integrator.to_string(),
            dt: setting.dt,
            setup_ms: m.setup_ms,
            step_ms: m.step_ms,
            errors,
        };
        progress(&case);
        cases.push(case);
    }
    Ok(cases)
}

/// The cheapest case (stepping time per simulated second) within `tolerance`, if any.
pub fn cheapest(cases: &[AbdomenRun], tolerance: f64) -> Option<&AbdomenRun> {
    cases
        .iter()
        .filter(|c| c.error() <= tolerance)
        .min_by(|a, b| a.ms_per_second().total_cmp(&b.ms_per_second()))
}

/// Writes the cases as CSV to `path` (atomically, [`crate::atomic::write_atomic`]).
pub fn write_csv(cases: &[AbdomenRun], path: &Path) -> Result<PathBuf> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "kinematics",
        "element",
        "formulation",
        "mesh_grading",
        "triangles",
        "model_order",
        "integrator",
        "dt_s",
        "setup_ms",
        "step_ms",
        "ms_per_simulated_s",
        "error_floor_stress_mean",
        "error_floor_stress_max",
        "error_apex_uy",
        "error_floor_mid_uy",
    ])?;
    for c in cases {
        w.write_record([
            c.kinematics.to_string(),
            c.element.to_string(),
            c.formulation.to_string(),
            c.grading.to_string(),
            c.triangles.to_string(),
            c.order.to_string(),
            c.integrator.clone(),
            format!("{:e}", c.dt),
            format!("{:.3}", c.setup_ms),
            format!("{:.4}", c.step_ms),
            format!("{:.1}", c.ms_per_second()),
            format!("{:.4e}", c.errors[0]),
            format!("{:.4e}", c.errors[1]),
            format!("{:.4e}", c.errors[2]),
            format!("{:.4e}", c.errors[3]),
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

    fn small(steps: Vec<f64>) -> Study {
        Study {
            discretizations: vec![Discretization {
                kinematics: "finite",
                element: "tri6",
                formulation: "displacement",
                grading: 0.5,
                targets: vec![3200],
            }],
            orders: vec!["full"],
            integrators: vec!["houbolt", "newmark"],
            steps,
            duration: 0.2,
            reference: ReferenceSetting {
                target: 3200,
                grading: 0.5,
                dt: 1e-3,
            },
        }
    }

    #[test]
    fn error_falls_with_the_step_and_the_csv_is_complete() {
        // The reference on the cases' own mesh: what remains is the time-step error, smaller
        // at 2 ms than at 20 ms.
        let study = small(vec![2e-3, 2e-2]);
        let reference = reference(study.reference, study.duration).unwrap();
        let mut seen = 0;
        let cases = measure(&study, &reference, |_| seen += 1).unwrap();
        assert_eq!((cases.len(), seen), (4, 4));
        // The progress bar's total: the full study runs modal order for linear kinematics
        // only (3 + 2 + 2 finite and 3 + 3 linear meshes, 2 orders for linear, 2
        // integrators, 3 steps), the quick one on each form's coarsest mesh at 2 steps.
        assert_eq!(study.case_count(), 4);
        assert_eq!(Study::default().case_count(), (7 + 6 * 2) * 2 * 3);
        assert_eq!(Study::quick().case_count(), (3 + 2 * 2) * 2 * 2);
        for pair in cases.chunks(2) {
            println!("{pair:?}");
            for k in 0..N {
                assert!(pair[0].errors[k] < pair[1].errors[k], "{pair:?}");
            }
            assert!(pair
                .iter()
                .all(|c| c.step_ms > 0.0 && c.error().is_finite()));
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
    fn the_reference_estimates_its_own_errors() {
        let study = small(vec![1e-2]);
        let r = reference(study.reference, study.duration).unwrap();
        let e = &r.error;
        println!("{e:?}");
        for k in 0..N {
            // Both are estimates, positive and small; the time-step error of Houbolt at 1 ms
            // is below the mesh error of a coarse mesh.
            assert!(e.time_error[k] > 0.0 && e.time_error[k] < 5e-3, "{e:?}");
            assert!(
                e.mesh_error[k] < 0.05 && e.time_error[k] < e.mesh_error[k],
                "{e:?}"
            );
        }
        // The uniform family (50 triangles split up to three times) is in its asymptotic
        // range for the floor stress and the apex; the floor midpoint's changes differ in
        // sign there, so its mesh error rests on the graded family alone.
        for k in 0..3 {
            let fit = e.uniform[k].as_ref().unwrap();
            assert!(fit.order > 0.5 && fit.order < 4.0, "{e:?}");
        }
        assert!(e.graded[3].is_ok(), "{e:?}");
    }

    #[test]
    fn the_cheapest_case_within_a_tolerance_is_found() {
        let case = |dt: f64, step_ms: f64, e: f64| AbdomenRun {
            kinematics: "finite",
            element: "tri6",
            formulation: "displacement",
            grading: 0.0,
            triangles: 100,
            order: "full",
            integrator: "houbolt".into(),
            dt,
            setup_ms: 1.0,
            step_ms,
            errors: [e, e / 2.0, e / 3.0, e / 4.0],
        };
        let cases = [
            case(1e-3, 1.0, 0.02),
            case(1e-2, 2.0, 0.009),
            case(1e-3, 0.5, 0.2),
        ];
        assert_eq!(cheapest(&cases, 0.01), Some(&cases[1]));
        assert_eq!(cheapest(&cases, 0.05).map(|c| c.step_ms), Some(2.0));
        assert_eq!(cheapest(&cases, 1e-3), None);
    }

    #[test]
    fn the_pareto_front_keeps_only_unbeaten_points() {
        let pts = [(3.0, 0.1), (1.0, 0.5), (2.0, 0.6), (4.0, 0.01), (5.0, 0.05)];
        assert_eq!(pareto(&pts), [(1.0, 0.5), (3.0, 0.1), (4.0, 0.01)]);
    }
}
