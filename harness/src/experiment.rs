//! Experiment files (TOML, in `experiments/`): the scene, its base configuration, the
//! parameters to vary, the inputs over time, the outputs to record, the backend and the
//! parallelism. [`Experiment::load`] checks everything it can before any case runs — names
//! against the scene's variable table, values against their ranges, the input tables, the
//! backend — and names the bad key in its error. Example (`experiments/pelvis_sweep.toml`):
//!
//! ```toml
//! name = "pelvis_sweep"
//! scene = "abdomen"
//! backend = "in-process"        # or "fmu" (then `fmu = "path/to/abdomen-fmi2.fmu"`)
//! stop_time = 1.0               # s
//! step = 0.01                   # communication step, s
//! jobs = 2                      # cases run in parallel (0: one per core)
//! record = ["floor_stress_max", "floor_stress_mean"]
//! metric = "floor_stress_max"   # the output whose peak the report plots
//!
//! [parameters]                  # base configuration, applied before initialization
//! target_triangles = 2000
//!
//! [inputs.press_force]          # an input over time, piecewise linear
//! time = [0.0, 0.5, 1.0]
//! value = [0.0, 0.4, 0.4]
//!
//! [[sweep]]                     # blocks of cases; the plan is their concatenation
//! design = "list"               # list: the value lists are zipped
//! values = { configuration = ["normal", "narrow", "wide"] }
//!
//! [[sweep]]
//! design = "latin-hypercube"    # or "grid" (each range then needs `levels`)
//! samples = 16
//! seed = 1
//! ranges = { "anatomy.outlet" = { min = 95.0, max = 135.0 }, wall_E = { min = 0.01, max = 0.1, log = true } }
//! ```
//!
//! Inputs are sampled at the start of each communication step and held over it, as FMI
//! importers do: the outputs at t + step respond to the inputs at t.
//!
//! Parameter names are the scene's parameters and inputs, plus, for the abdomen,
//! `anatomy.<field>` for the fields of the outline generator
//! ([`models::scene::abdomen::anatomy::Anatomy`]): a case that sets any of them gets a
//! configuration file generated from the default anatomy with those fields changed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, ensure, Context, Result};
use models::scene::abdomen::anatomy::Anatomy;
use models::scene::{self, Causality, Variable, VariableKind};
use serde::{Deserialize, Serialize};

use crate::design::{self, Block};

/// A parameter value: a number or a text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Value {
    Real(f64),
    Text(String),
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Real(x) => write!(f, "{x}"),
            Value::Text(s) => f.write_str(s),
        }
    }
}

/// Where a case runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BackendKind {
    /// The scene linked into the harness.
    #[default]
    InProcess,
    /// The packaged FMU, loaded through the `fmi` crate (FMI 2 co-simulation).
    Fmu,
}

/// An input given as a piecewise-linear function of time, held constant beyond its ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputTable {
    pub time: Vec<f64>,
    pub value: Vec<f64>,
}

impl InputTable {
    /// The value at time `t` (linear interpolation; constant extrapolation).
    pub fn at(&self, t: f64) -> f64 {
        let k = self.time.partition_point(|&s| s <= t);
        if k == 0 {
            return self.value[0];
        }
        if k == self.time.len() {
            return self.value[k - 1];
        }
        let (t0, t1) = (self.time[k - 1], self.time[k]);
        let w = (t - t0) / (t1 - t0);
        self.value[k - 1] + w * (self.value[k] - self.value[k - 1])
    }

    fn check(&self, key: &str) -> Result<()> {
        ensure!(
            !self.time.is_empty() && self.time.len() == self.value.len(),
            "`{key}`: `time` and `value` must be non-empty and of equal length (got {} and {})",
            self.time.len(),
            self.value.len()
        );
        for w in self.time.windows(2) {
            ensure!(
                w[1] > w[0],
                "`{key}.time` must increase strictly: {} is followed by {}",
                w[0],
                w[1]
            );
        }
        if let Some(x) = self.time.iter().chain(&self.value).find(|x| !x.is_finite()) {
            bail!("`{key}` holds the non-finite value {x}");
        }
        Ok(())
    }
}

/// The file as written, before checking.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    name: String,
    #[serde(default)]
    description: String,
    scene: String,
    #[serde(default)]
    backend: BackendKind,
    fmu: Option<PathBuf>,
    stop_time: f64,
    step: f64,
    #[serde(default)]
    jobs: usize,
    record: Vec<String>,
    metric: Option<String>,
    #[serde(default)]
    parameters: BTreeMap<String, Value>,
    #[serde(default)]
    inputs: BTreeMap<String, InputTable>,
    #[serde(default)]
    sweep: Vec<Block>,
}

/// A checked experiment.
#[derive(Debug, Clone)]
pub struct Experiment {
    pub name: String,
    pub description: String,
    pub scene: String,
    pub backend: BackendKind,
    /// The FMU for the `fmu` backend (absolute).
    pub fmu: Option<PathBuf>,
    pub stop_time: f64,
    pub step: f64,
    /// Cases in parallel; 0 = one per core.
    pub jobs: usize,
    pub record: Vec<String>,
    /// The recorded output whose peak the report plots against each parameter.
    pub metric: String,
    pub parameters: BTreeMap<String, Value>,
    pub inputs: BTreeMap<String, InputTable>,
    pub cases: Vec<Case>,
    /// The TOML text the experiment was read from.
    pub source: String,
}

/// One case of the plan: the values it varies (applied over the base parameters).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Case {
    pub id: usize,
    /// The `[[sweep]]` block it comes from and that block's design.
    pub block: usize,
    pub design: crate::design::Design,
    pub values: BTreeMap<String, Value>,
}

/// Prefix of the abdomen's anatomy parameters.
pub const ANATOMY: &str = "anatomy.";

impl Experiment {
    /// Reads and checks an experiment file; relative paths in it are relative to its folder.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read experiment file {}", path.display()))?;
        let base = path.parent().unwrap_or(Path::new("."));
        Self::parse(&text, base).with_context(|| format!("experiment file {}", path.display()))
    }

    /// Parses and checks experiment TOML; `base` resolves relative paths.
    pub fn parse(text: &str, base: &Path) -> Result<Self> {
        let file: File = toml::from_str(text)?;
        let scene = scene::create(&file.scene).context("`scene`")?;
        let table = scene.variables();
        check_times(file.stop_time, file.step)?;
        let metric = check_record(table, &file.record, file.metric.as_deref())?;
        for (name, value) in &file.parameters {
            check_value(&file.scene, table, name, value)
                .with_context(|| format!("`parameters.{name}`"))?;
        }
        for (name, input) in &file.inputs {
            check_input(&file.scene, table, name, input)?;
        }
        let cases = design::expand(&file.sweep)?;
        for case in &cases {
            for (name, value) in &case.values {
                check_value(&file.scene, table, name, value)
                    .with_context(|| format!("`sweep` case {}: parameter `{name}`", case.id))?;
            }
            check_anatomy_conflict(&file.parameters, &case.values)
                .with_context(|| format!("`sweep` case {}", case.id))?;
        }
        let fmu = check_backend(file.backend, file.fmu, base)?;
        Ok(Self {
            name: file.name,
            description: file.description,
            scene: file.scene,
            backend: file.backend,
            fmu,
            stop_time: file.stop_time,
            step: file.step,
            jobs: file.jobs,
            record: file.record,
            metric,
            parameters: file.parameters,
            inputs: file.inputs,
            cases,
            source: text.to_string(),
        })
    }

    /// Number of communication steps.
    pub fn steps(&self) -> usize {
        (self.stop_time / self.step).round() as usize
    }

    /// The names every case varies, in plan order.
    pub fn varied(&self) -> Vec<String> {
        let mut names: Vec<String> = Vec::new();
        for c in &self.cases {
            for k in c.values.keys() {
                if !names.contains(k) {
                    names.push(k.clone());
                }
            }
        }
        names
    }

    /// The settings of a case: base parameters overridden by the case's values, with any
    /// `anatomy.*` values turned into a configuration file in `configs` — returned as its
    /// path and TOML text for the caller to write.
    pub fn settings(&self, case: &Case, configs: &Path) -> Result<Settings> {
        let mut merged = self.parameters.clone();
        merged.extend(case.values.clone());
        let mut anatomy = Anatomy::default();
        let mut generated = false;
        let mut settings = Settings::default();
        for (name, value) in merged {
            match (name.strip_prefix(ANATOMY), &value) {
                (Some(field), Value::Real(x)) => {
                    set_anatomy(&mut anatomy, field, *x)?;
                    generated = true;
                }
                _ => settings.values.push((name, value)),
            }
        }
        if generated {
            let config = models::scene::abdomen::config::PelvisConfig {
                name: format!("case_{:04}", case.id),
                description: format!("generated by the harness for case {}", case.id),
                control_points: None,
                anatomy: Some(anatomy),
            };
            let path = std::path::absolute(configs.join(format!("case_{:04}.toml", case.id)))?;
            settings.values.push((
                "configuration".into(),
                Value::Text(path.display().to_string()),
            ));
            settings.config = Some((path, toml::to_string(&config)?));
        }
        Ok(settings)
    }
}

/// What a case sets before initialization, and the configuration file it needs written.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Settings {
    pub values: Vec<(String, Value)>,
    pub config: Option<(PathBuf, String)>,
}

/// Stop time and communication step: positive, and a whole number of steps.
fn check_times(stop_time: f64, step: f64) -> Result<()> {
    ensure!(
        stop_time.is_finite() && stop_time > 0.0,
        "`stop_time` = {stop_time} must be positive"
    );
    ensure!(
        step.is_finite() && step > 0.0 && step <= stop_time,
        "`step` = {step} must be positive and at most `stop_time` = {stop_time}"
    );
    let steps = stop_time / step;
    ensure!(
        (steps - steps.round()).abs() < 1e-9 * steps,
        "`stop_time` = {stop_time} is not a whole number of `step` = {step}"
    );
    Ok(())
}

/// The recorded outputs exist and are scalar; returns the metric (default: the first).
fn check_record(table: &[Variable], record: &[String], metric: Option<&str>) -> Result<String> {
    ensure!(!record.is_empty(), "`record` lists no outputs");
    for (i, name) in record.iter().enumerate() {
        check_output(table, name).with_context(|| format!("`record[{i}]`"))?;
    }
    let metric = metric.unwrap_or(&record[0]).to_string();
    ensure!(
        record.contains(&metric),
        "`metric` = \"{metric}\" is not one of the recorded outputs"
    );
    Ok(metric)
}

/// An input table: the variable is an input, the table is well formed, values in range.
fn check_input(scene: &str, table: &[Variable], name: &str, input: &InputTable) -> Result<()> {
    let key = format!("inputs.{name}");
    let v = find(table, name).with_context(|| format!("`{key}`"))?;
    ensure!(
        v.causality == Causality::Input,
        "`{key}`: `{name}` is not an input of the {scene} scene"
    );
    input.check(&key)?;
    for &x in &input.value {
        check_range(v, x).with_context(|| format!("`{key}.value`"))?;
    }
    Ok(())
}

/// The FMU file for the `fmu` backend (absolute), none for in-process.
fn check_backend(
    backend: BackendKind,
    fmu: Option<PathBuf>,
    base: &Path,
) -> Result<Option<PathBuf>> {
    match (backend, fmu) {
        (BackendKind::Fmu, None) => bail!("`backend` = \"fmu\" needs `fmu`, the .fmu file"),
        (BackendKind::Fmu, Some(p)) => {
            let p = base.join(p);
            ensure!(p.is_file(), "`fmu`: no file {}", p.display());
            Ok(Some(std::path::absolute(&p)?))
        }
        (BackendKind::InProcess, Some(_)) => {
            bail!("`fmu` is given but `backend` is \"in-process\"")
        }
        (BackendKind::InProcess, None) => Ok(None),
    }
}

fn find<'a>(table: &'a [Variable], name: &str) -> Result<&'a Variable> {
    table
        .iter()
        .find(|v| v.name == name)
        .with_context(|| format!("no variable named `{name}`"))
}

fn check_output(table: &[Variable], name: &str) -> Result<()> {
    let v = find(table, name)?;
    ensure!(
        v.causality == Causality::Output,
        "`{name}` is not an output"
    );
    ensure!(
        v.len == 1,
        "`{name}` is an array of {} values; sweeps record scalar outputs",
        v.len
    );
    Ok(())
}

fn check_range(v: &Variable, x: f64) -> Result<()> {
    ensure!(
        x.is_finite() && x >= v.min && x <= v.max,
        "value {x} for `{}` is outside [{}, {}]",
        v.name,
        v.min,
        v.max
    );
    Ok(())
}

/// Checks a parameter value against the scene's table (or the anatomy generator).
fn check_value(scene: &str, table: &[Variable], name: &str, value: &Value) -> Result<()> {
    if let Some(field) = name.strip_prefix(ANATOMY) {
        ensure!(
            scene == "abdomen",
            "`{name}`: anatomy parameters exist for the abdomen scene only"
        );
        let Value::Real(x) = value else {
            bail!("`{name}` = \"{value}\" must be a number");
        };
        let mut a = Anatomy::default();
        set_anatomy(&mut a, field, *x)?;
        a.control_points()?;
        return Ok(());
    }
    let v = find(table, name)?;
    ensure!(
        v.causality != Causality::Output,
        "`{name}` is an output and cannot be set"
    );
    match (v.kind, value) {
        (VariableKind::Real, Value::Real(x)) => check_range(v, *x),
        (VariableKind::String, Value::Text(_)) => Ok(()),
        (VariableKind::Real, Value::Text(s)) => bail!("`{name}` = \"{s}\" must be a number"),
        (VariableKind::String, Value::Real(x)) => bail!("`{name}` = {x} must be a text"),
    }
}

/// A case may not both name a configuration and generate one from anatomy parameters.
fn check_anatomy_conflict(
    base: &BTreeMap<String, Value>,
    case: &BTreeMap<String, Value>,
) -> Result<()> {
    let names = || base.keys().chain(case.keys());
    let anatomy = names().find(|n| n.starts_with(ANATOMY));
    match (anatomy, names().any(|n| n == "configuration")) {
        (Some(a), true) => {
            bail!("sets both `configuration` and `{a}`; anatomy parameters generate the configuration")
        }
        _ => Ok(()),
    }
}

/// Sets one field of the anatomy by name, through its serde representation so that the
/// field list stays the generator's.
fn set_anatomy(anatomy: &mut Anatomy, field: &str, value: f64) -> Result<()> {
    let mut table = toml::Table::try_from(*anatomy)?;
    ensure!(
        table.contains_key(field),
        "`{ANATOMY}{field}`: the anatomy has no field `{field}` (fields: {})",
        table.keys().cloned().collect::<Vec<_>>().join(", ")
    );
    table.insert(field.into(), toml::Value::Float(value));
    *anatomy = table.try_into()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const GOOD: &str = r#"
name = "t"
scene = "abdomen"
stop_time = 0.1
step = 0.01
record = ["floor_stress_max"]
[parameters]
target_triangles = 300
[inputs.press_force]
time = [0.0, 0.1]
value = [0.0, 0.2]
[[sweep]]
design = "list"
values = { configuration = ["normal", "wide"] }
[[sweep]]
design = "grid"
ranges = { "anatomy.outlet" = { min = 100.0, max = 130.0, levels = 3 } }
"#;

    fn err(text: &str) -> String {
        format!("{:#}", Experiment::parse(text, Path::new(".")).unwrap_err())
    }

    #[test]
    fn a_good_file_expands_to_its_cases() {
        let e = Experiment::parse(GOOD, Path::new(".")).unwrap();
        assert_eq!(e.cases.len(), 5);
        assert_eq!(e.steps(), 10);
        assert_eq!(e.metric, "floor_stress_max");
        assert_eq!(e.varied(), ["configuration", "anatomy.outlet"]);
        let s = e.settings(&e.cases[3], Path::new("/runs/configs")).unwrap();
        let config = s.values.iter().find(|(n, _)| n == "configuration").unwrap();
        assert_eq!(config.1, Value::Text("/runs/configs/case_0003.toml".into()));
        let (path, text) = s.config.unwrap();
        assert_eq!(path, Path::new("/runs/configs/case_0003.toml"));
        assert!(text.contains("outlet = 115.0"), "{text}");
    }

    #[test]
    fn bad_keys_and_values_are_named() {
        let cases = [
            (GOOD.replace("stop_time", "stoptime"), "stoptime"),
            (
                GOOD.replace("target_triangles = 300", "target_triangles = 10"),
                "parameters.target_triangles",
            ),
            (
                GOOD.replace("floor_stress_max\"]", "floor_stres\"]"),
                "floor_stres",
            ),
            (GOOD.replace("\"wide\"", "3.0"), "configuration"),
            (GOOD.replace("outlet", "outlett"), "outlett"),
            (GOOD.replace("max = 130.0", "max = 300.0"), "anatomy.outlet"),
            (
                GOOD.replace("value = [0.0, 0.2]", "value = [0.0]"),
                "inputs.press_force",
            ),
            (
                GOOD.replace("time = [0.0, 0.1]", "time = [0.1, 0.0]"),
                "inputs.press_force.time",
            ),
            (GOOD.replace("step = 0.01", "step = 0.03"), "whole number"),
            (GOOD.replace("\"grid\"", "\"sobol\""), "sobol"),
            (
                GOOD.replace("scene = \"abdomen\"", "scene = \"liver\""),
                "liver",
            ),
            (
                GOOD.replace("[parameters]", "[parameters]\nconfiguration = \"wide\""),
                "anatomy.outlet",
            ),
            (
                GOOD.replace(
                    "record = [\"floor_stress_max\"]",
                    "record = [\"floor_stress_max\"]\nbackend = \"fmu\"",
                ),
                "needs `fmu`",
            ),
        ];
        for (text, needle) in cases {
            let e = err(&text);
            assert!(e.contains(needle), "error `{e}` should name `{needle}`");
        }
    }

    #[test]
    fn input_tables_interpolate_and_hold() {
        let t = InputTable {
            time: vec![0.0, 1.0, 3.0],
            value: vec![0.0, 2.0, 4.0],
        };
        assert_eq!(t.at(-1.0), 0.0);
        assert_eq!(t.at(0.5), 1.0);
        assert_eq!(t.at(2.0), 3.0);
        assert_eq!(t.at(5.0), 4.0);
    }
}
