//! Sweeps: the cases of an experiment run in parallel (rayon) with a progress bar
//! (indicatif). Each finished case is written atomically to `cases/case_NNNN.csv`, a failed
//! one to `cases/case_NNNN.error` with its message, so that an interrupted sweep, run again
//! on the same folder, skips the finished cases, retries the failed ones and loses nothing.
//! The folder also holds the experiment as run, the case plan (`plan.csv`), `plan.json` (the
//! resolved settings of every case, which the Dask runner in `harness/python/` reads; a re-run
//! whose plan differs is refused) and `summary.csv` (one row per case).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use rayon::prelude::*;
use serde::Serialize;

use super::backend::Backend;
use super::design::Design;
use super::experiment::Experiment;
use super::simulate::{simulate, InputTable, Series, Value};
use crate::atomic::write_atomic;

/// How one case ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// Peak (largest value over time) and final value of every recorded output.
    Finished {
        /// Largest value over time, one per recorded output.
        peak: Vec<f64>,
        /// Final value, one per recorded output.
        last: Vec<f64>,
    },
    /// The case's error message (`did not run` if it has none).
    Failed(String),
}

/// One row of the summary.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseResult {
    /// The case's number.
    pub id: usize,
    /// The `[[sweep]]` block the case comes from.
    pub block: usize,
    /// That block's design.
    pub design: Design,
    /// The values the case varies, by parameter name.
    pub values: BTreeMap<String, Value>,
    /// Its outputs' peaks and final values, or its error.
    pub outcome: Outcome,
}

/// What a sweep left behind.
#[derive(Debug, Clone)]
pub struct Sweep {
    /// The sweep's folder.
    pub dir: PathBuf,
    /// Every case's result, in case order.
    pub results: Vec<CaseResult>,
    /// Cases run now (the rest were already finished).
    pub ran: usize,
    /// Wall time of this run of the sweep (s).
    pub seconds: f64,
}

/// The resolved plan the Dask runner reads.
#[derive(Serialize)]
struct Plan<'a> {
    scene: &'a str,
    start_time: f64,
    stop_time: f64,
    step: f64,
    record: &'a [String],
    inputs: &'a BTreeMap<String, InputTable>,
    cases: Vec<PlanCase>,
}

#[derive(Serialize)]
struct PlanCase {
    id: usize,
    settings: BTreeMap<String, Value>,
}

fn case_path(dir: &Path, id: usize, ext: &str) -> PathBuf {
    dir.join("cases").join(format!("case_{id:04}.{ext}"))
}

/// The plan as CSV: case id and the values it varies.
fn plan_csv(e: &Experiment) -> Result<Vec<u8>> {
    let varied = e.varied();
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(std::iter::once("case").chain(varied.iter().map(String::as_str)))?;
    for c in &e.cases {
        let row = varied
            .iter()
            .map(|k| c.values.get(k).map(Value::to_string).unwrap_or_default());
        w.write_record(std::iter::once(c.id.to_string()).chain(row))?;
    }
    Ok(w.into_inner()?)
}

/// Prepares the folder without running anything: refuses a folder that holds a different
/// plan (cases, settings, inputs, outputs, times: anything that changes results), then writes
/// the experiment, `plan.csv`, `plan.json` and the generated configuration files. Returns
/// each case's settings.
pub fn prepare(e: &Experiment, dir: &Path) -> Result<Vec<Vec<(String, Value)>>> {
    let configs = dir.join("configs");
    let settings = e
        .cases
        .iter()
        .map(|c| e.settings(c, &configs))
        .collect::<Result<Vec<_>>>()?;
    let plan = Plan {
        scene: &e.scene,
        start_time: e.start_time,
        stop_time: e.stop_time,
        step: e.step,
        record: &e.record,
        inputs: &e.inputs,
        cases: e
            .cases
            .iter()
            .zip(&settings)
            .map(|(c, s)| PlanCase {
                id: c.id,
                settings: s.values.iter().cloned().collect(),
            })
            .collect(),
    };
    let json = serde_json::to_string_pretty(&plan)?;
    let json_path = dir.join("plan.json");
    if let Ok(old) = std::fs::read_to_string(&json_path) {
        if old != json {
            bail!(
                "{} holds a sweep with a different plan (cases, settings, inputs, outputs or \
                 times); choose another output folder or delete that one",
                dir.display()
            );
        }
    }
    std::fs::create_dir_all(dir.join("cases"))
        .with_context(|| format!("cannot create {}", dir.display()))?;
    for (path, text) in settings.iter().filter_map(|s| s.config.as_ref()) {
        std::fs::create_dir_all(&configs)?;
        write_atomic(path, text.as_bytes())?;
    }
    write_atomic(&dir.join("experiment.toml"), e.source.as_bytes())?;
    write_atomic(&dir.join("plan.csv"), &plan_csv(e)?)?;
    write_atomic(&json_path, json.as_bytes())?;
    Ok(settings.into_iter().map(|s| s.values).collect())
}

fn progress(n: usize) -> ProgressBar {
    let bar = ProgressBar::new(n as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{elapsed_precise} [{bar:30}] {pos}/{len} cases, {rate}, ETA {eta}",
        )
        .expect("the template is valid")
        .with_key(
            "rate",
            |s: &indicatif::ProgressState, w: &mut dyn std::fmt::Write| {
                let _ = write!(w, "{:.2} cases/s", s.per_sec());
            },
        )
        .progress_chars("=> "),
    );
    bar
}

/// Runs every case not yet finished in `dir`, then writes `summary.csv`.
pub fn run(e: &Experiment, dir: &Path) -> Result<Sweep> {
    let start = Instant::now();
    let backend = Backend::new(e.backend, &e.scene, e.fmu.as_deref())?;
    let settings = prepare(e, dir)?;
    let pending: Vec<usize> = e
        .cases
        .iter()
        .map(|c| c.id)
        .filter(|&id| !case_path(dir, id, "csv").is_file())
        .collect();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(e.threads())
        .build()?;
    let bar = progress(pending.len());
    pool.install(|| {
        pending.par_iter().try_for_each(|&id| {
            let outcome = run_case(&backend, e, &settings[id]);
            record(dir, id, outcome, &bar)
        })
    })?;
    bar.finish_and_clear();
    let results = collect(e, dir)?;
    write_atomic(&dir.join("summary.csv"), &summary_csv(e, &results)?)?;
    Ok(Sweep {
        dir: dir.to_path_buf(),
        results,
        ran: pending.len(),
        seconds: start.elapsed().as_secs_f64(),
    })
}

/// Runs one case, giving its series and the model's warnings; a panic is
/// turned into its failure, like an error.
fn run_case(
    backend: &Backend,
    e: &Experiment,
    settings: &[(String, Value)],
) -> Result<(Series, Vec<String>)> {
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        backend
            .open()
            .and_then(|mut s| simulate(s.as_mut(), &e.schedule(settings)))
            .map(|run| (run.series, run.warnings))
    }))
    .unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| panic.downcast_ref::<&str>().copied())
            .unwrap_or("unknown panic");
        Err(anyhow::anyhow!("the case panicked: {what}"))
    })
}

/// Writes a case's result: its CSV (removing an earlier failure), or its error.
/// The model's warnings are printed above the progress bar.
fn record(
    dir: &Path,
    id: usize,
    outcome: Result<(Series, Vec<String>)>,
    bar: &ProgressBar,
) -> Result<()> {
    let error = case_path(dir, id, "error");
    match outcome {
        Ok((series, warnings)) => {
            for w in warnings {
                bar.println(format!("case {id}: warning: {w}"));
            }
            write_atomic(&case_path(dir, id, "csv"), &series.to_csv()?)?;
            if error.is_file() {
                std::fs::remove_file(&error)?;
            }
        }
        Err(err) => {
            let message = format!("{err:#}");
            bar.println(format!("case {id} failed: {message}"));
            write_atomic(&error, message.as_bytes())?;
        }
    }
    bar.inc(1);
    Ok(())
}

/// Reads every case's file back.
fn collect(e: &Experiment, dir: &Path) -> Result<Vec<CaseResult>> {
    e.cases
        .iter()
        .map(|c| {
            let csv = case_path(dir, c.id, "csv");
            let outcome = if csv.is_file() {
                let s = Series::read_csv(&csv)?;
                let peak = (1..=e.record.len())
                    .map(|j| {
                        s.rows
                            .iter()
                            .map(|r| r[j])
                            .fold(f64::NEG_INFINITY, f64::max)
                    })
                    .collect();
                let last = s.rows.last().map(|r| r[1..].to_vec()).unwrap_or_default();
                Outcome::Finished { peak, last }
            } else {
                let path = case_path(dir, c.id, "error");
                Outcome::Failed(
                    std::fs::read_to_string(&path).unwrap_or_else(|_| "did not run".into()),
                )
            };
            Ok(CaseResult {
                id: c.id,
                block: c.block,
                design: c.design,
                values: c.values.clone(),
                outcome,
            })
        })
        .collect()
}

fn summary_csv(e: &Experiment, results: &[CaseResult]) -> Result<Vec<u8>> {
    let varied = e.varied();
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["case".to_string(), "status".to_string()];
    header.extend(varied.iter().cloned());
    header.extend(e.record.iter().map(|r| format!("{r}_peak")));
    header.extend(e.record.iter().map(|r| format!("{r}_final")));
    header.push("error".into());
    w.write_record(&header)?;
    for r in results {
        let mut row = vec![r.id.to_string()];
        let values = varied
            .iter()
            .map(|k| r.values.get(k).map(Value::to_string).unwrap_or_default());
        match &r.outcome {
            Outcome::Finished { peak, last } => {
                row.push("finished".into());
                row.extend(values);
                row.extend(peak.iter().chain(last).map(|x| format!("{x:?}")));
                row.push(String::new());
            }
            Outcome::Failed(message) => {
                row.push("failed".into());
                row.extend(values);
                row.extend(std::iter::repeat_n(String::new(), 2 * e.record.len()));
                row.push(message.clone());
            }
        }
        w.write_record(&row)?;
    }
    Ok(w.into_inner()?)
}

impl CaseResult {
    /// The peak of output `j` of the recorded list, if the case finished.
    pub fn peak(&self, j: usize) -> Option<f64> {
        match &self.outcome {
            Outcome::Finished { peak, .. } => Some(peak[j]),
            Outcome::Failed(_) => None,
        }
    }
}
