//! One run of a scene in process, written as a time-series CSV (`harness simulate`): what
//! the Python tests compare the packaged FMUs with, and a quick look at a scene. It goes
//! through the one simulation loop, so its input rule is the sweeps' and the FMU backend's.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use models::scene::{self, VariableKind};

use crate::atomic::write_atomic;
use crate::sweep::simulate::check_times;
use crate::sweep::{simulate, InProcess, InputTable, Schedule, Value};

/// What `harness simulate` was asked for.
#[derive(Debug, Clone)]
pub struct Request<'a> {
    /// The scene to run (e.g. `abdomen`, `cutblock`).
    pub scene: &'a str,
    /// Start time (s).
    pub start_time: f64,
    /// Stop time (s).
    pub stop_time: f64,
    /// Communication step (s).
    pub step: f64,
    /// `name=value` parameter settings.
    pub set: &'a [String],
    /// A CSV `time,<input>,…`: piecewise-linear input tables.
    pub inputs: Option<&'a Path>,
    /// The outputs to record (an array output gives one column per element).
    pub record: &'a [String],
    /// Where to write the CSV; standard output when `None`.
    pub out: Option<&'a Path>,
}

/// Parses `name=value` settings, reading the value as the variable's kind.
fn settings(scene_name: &str, set: &[String]) -> Result<Vec<(String, Value)>> {
    let scene = scene::create(scene_name)?;
    set.iter()
        .map(|item| {
            let Some((name, text)) = item.split_once('=') else {
                bail!("`--set {item}`: write name=value");
            };
            let vr = scene
                .lookup(name)
                .with_context(|| format!("`--set {item}`"))?;
            let value = match scene.variables()[vr as usize].kind {
                VariableKind::String => Value::Text(text.to_string()),
                VariableKind::Real => Value::Real(text.parse().with_context(|| {
                    format!("`--set {item}`: `{name}` takes a number, not `{text}`")
                })?),
            };
            Ok((name.to_string(), value))
        })
        .collect()
}

/// Runs the request; returns the file written, if any.
pub fn command(request: &Request) -> Result<Option<PathBuf>> {
    check_times(request.start_time, request.stop_time, request.step)?;
    let settings = settings(request.scene, request.set)?;
    let inputs = match request.inputs {
        Some(path) => InputTable::read_csv(path)?,
        None => BTreeMap::new(),
    };
    let schedule = Schedule {
        start_time: request.start_time,
        stop_time: request.stop_time,
        step: request.step,
        settings: &settings,
        inputs: &inputs,
        record: request.record,
    };
    let mut session = InProcess(scene::create(request.scene)?);
    let run = simulate(&mut session, &schedule)?;
    for w in &run.warnings {
        eprintln!("warning: {w}");
    }
    let csv = run.series.to_csv()?;
    match request.out {
        Some(path) => {
            write_atomic(path, &csv)?;
            Ok(Some(path.to_path_buf()))
        }
        None => {
            use std::io::Write as _;
            std::io::stdout().write_all(&csv)?;
            Ok(None)
        }
    }
}
