//! Experiment files (TOML): the scene, its base configuration, the parameters to vary, the
//! inputs over time, the outputs to record, the backend and the parallelism. The format,
//! key by key, is documented in `docs/reference/experiment-files.md`; the shipped
//! experiments (`experiments/*.toml`) are examples of it and are compiled into the harness
//! ([`SHIPPED`]). [`Experiment::parse`] checks everything it can before any case runs —
//! names against the scene's variable table, values against their ranges, the input
//! tables, the backend — and names the bad key in its error.
//!
//! Inputs follow the simulation loop's rule ([`super::simulate()`]): sampled at the start of
//! each communication step and held over it, as FMI importers do.
//!
//! Parameter names are the scene's parameters and inputs, plus the scene's generator
//! parameters ([`models::scene::Scene::generator_parameters`]; for the abdomen
//! `anatomy.<field>`, the fields of its outline generator): a case that sets any of them gets
//! a configuration file the scene generates from its defaults with those values changed.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::{bail, ensure, Context, Result};
use models::scene::{self, Causality, Scene, Variable, VariableKind};
use serde::Deserialize;

use super::backend::BackendKind;
use super::design::{self, Block, DesignPoint};
use super::simulate::{check_times, InputTable, Schedule, Value};

/// The shipped experiments by name (`experiments/<name>.toml`), compiled in so that a copied
/// binary runs them without the source tree.
pub const SHIPPED: [(&str, &str); 6] = [
    (
        "pelvis_sweep",
        include_str!("../../../experiments/pelvis_sweep.toml"),
    ),
    (
        "cutblock_sweep",
        include_str!("../../../experiments/cutblock_sweep.toml"),
    ),
    (
        "clinical_rest",
        include_str!("../../../experiments/clinical_rest.toml"),
    ),
    (
        "clinical_cough",
        include_str!("../../../experiments/clinical_cough.toml"),
    ),
    (
        "clinical_valsalva",
        include_str!("../../../experiments/clinical_valsalva.toml"),
    ),
    (
        "clinical_bear_down",
        include_str!("../../../experiments/clinical_bear_down.toml"),
    ),
];

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
    #[serde(default)]
    start_time: f64,
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
    /// The experiment's name.
    pub name: String,
    /// What the experiment is for, in words (empty if not given).
    pub description: String,
    /// The scene every case runs (e.g. `abdomen`, `cutblock`).
    pub scene: String,
    /// Where the cases run: in process or through the FMU.
    pub backend: BackendKind,
    /// The FMU for the `fmu` backend (absolute).
    pub fmu: Option<PathBuf>,
    /// Start time of every case (s).
    pub start_time: f64,
    /// Stop time of every case (s).
    pub stop_time: f64,
    /// Communication step (s); a whole number of steps spans start to stop.
    pub step: f64,
    /// Cases in parallel; 0 = one per core.
    pub jobs: usize,
    /// The scalar outputs every case records, in order.
    pub record: Vec<String>,
    /// The recorded output whose peak the report plots against each parameter.
    pub metric: String,
    /// Base parameter values, which each case's values override.
    pub parameters: BTreeMap<String, Value>,
    /// Input tables by input name, the same for every case.
    pub inputs: BTreeMap<String, InputTable>,
    /// The cases of all `[[sweep]]` blocks, numbered from 0.
    pub cases: Vec<DesignPoint>,
    /// The TOML text the experiment was read from.
    pub source: String,
}

impl Experiment {
    /// A shipped experiment by name ([`SHIPPED`]).
    pub fn shipped(name: &str) -> Result<Self> {
        let text = models::scene::shipped(&SHIPPED, name).map_err(|names| {
            anyhow::anyhow!(
                "no experiment file `{name}` and no shipped experiment of that name ({names})"
            )
        })?;
        Self::parse(text, Path::new(".")).with_context(|| format!("shipped experiment {name}"))
    }

    /// The experiment `arg` names: a file if there is one, otherwise a shipped experiment
    /// (a name without `/` or `.toml`).
    pub fn open(arg: &Path) -> Result<Self> {
        let text = arg.to_string_lossy();
        if arg.is_file() || text.contains(['/', '\\']) || text.ends_with(".toml") {
            Self::load(arg)
        } else {
            Self::shipped(&text)
        }
    }

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
        check_times(file.start_time, file.stop_time, file.step)?;
        let metric = check_record(table, &file.record, file.metric.as_deref())?;
        for (name, value) in &file.parameters {
            check_value(scene.as_ref(), name, value)
                .with_context(|| format!("`parameters.{name}`"))?;
        }
        for (name, input) in &file.inputs {
            check_input(&file.scene, table, name, input)?;
        }
        let cases = design::expand(&file.sweep)?;
        for case in &cases {
            for (name, value) in &case.values {
                check_value(scene.as_ref(), name, value)
                    .with_context(|| format!("`sweep` case {}: parameter `{name}`", case.id))?;
            }
            check_generator_conflict(scene.as_ref(), &file.parameters, &case.values)
                .with_context(|| format!("`sweep` case {}", case.id))?;
        }
        let fmu = check_backend(file.backend, file.fmu, base)?;
        let experiment = Self {
            name: file.name,
            description: file.description,
            scene: file.scene,
            backend: file.backend,
            fmu,
            start_time: file.start_time,
            stop_time: file.stop_time,
            step: file.step,
            jobs: file.jobs,
            record: file.record,
            metric,
            parameters: file.parameters,
            inputs: file.inputs,
            cases,
            source: text.to_string(),
        };
        for case in &experiment.cases {
            experiment.check_case(case).with_context(|| {
                let values: Vec<String> = case
                    .values
                    .iter()
                    .map(|(k, v)| format!("{k} = {v}"))
                    .collect();
                format!("`sweep` case {} ({})", case.id, values.join(", "))
            })?;
        }
        Ok(experiment)
    }

    /// A case's settings on a fresh scene: each value set (the scene refuses what it
    /// cannot take, e.g. an unknown choice), then the whole checked ([`Scene::check`]:
    /// values that must fit together, a configuration that resolves) — before any case
    /// runs. A generated configuration is checked as it is generated.
    fn check_case(&self, case: &DesignPoint) -> Result<()> {
        let settings = self.settings(case, Path::new("."))?;
        let mut scene = scene::create(&self.scene)?;
        for (name, value) in &settings.values {
            if let (Some((path, _)), Value::Text(s)) = (&settings.config, value) {
                if Path::new(s) == path {
                    continue;
                }
            }
            let vr = scene.lookup(name)?;
            match value {
                Value::Real(x) => scene.set_real(vr, &[*x]),
                Value::Text(s) => scene.set_string(vr, s),
            }
            .with_context(|| format!("`{name}` = {value}"))?;
        }
        Ok(scene.check()?)
    }

    /// This experiment with each Latin hypercube drawn anew with at most `samples` points
    /// (same ranges and seed) and each grid range at most `levels`, named `<name>_quick`:
    /// the quick report's version of a long sweep (every design, fewer cases), its file
    /// written back as TOML so that its folder holds what reproduces it.
    pub fn thinned(&self, samples: usize, levels: usize) -> Result<Self> {
        let mut file: toml::Table = toml::from_str(&self.source)?;
        file.insert("name".into(), format!("{}_quick", self.name).into());
        if let Some(fmu) = &self.fmu {
            file.insert("fmu".into(), fmu.display().to_string().into());
        }
        let cap = |value: &mut toml::Value, most: usize| {
            if let Some(n) = value.as_integer() {
                *value = n.min(most as i64).into();
            }
        };
        let blocks = file.get_mut("sweep").and_then(toml::Value::as_array_mut);
        for block in blocks
            .into_iter()
            .flatten()
            .filter_map(toml::Value::as_table_mut)
        {
            if let Some(n) = block.get_mut("samples") {
                cap(n, samples);
            }
            let ranges = block.get_mut("ranges").and_then(toml::Value::as_table_mut);
            for (_, range) in ranges.into_iter().flat_map(|r| r.iter_mut()) {
                if let Some(l) = range.as_table_mut().and_then(|r| r.get_mut("levels")) {
                    cap(l, levels);
                }
            }
        }
        Self::parse(&toml::to_string(&file)?, Path::new("."))
            .with_context(|| format!("{} thinned", self.name))
    }

    /// What a case with `settings` runs: this experiment's times, inputs and outputs.
    pub fn schedule<'a>(&'a self, settings: &'a [(String, Value)]) -> Schedule<'a> {
        Schedule {
            start_time: self.start_time,
            stop_time: self.stop_time,
            step: self.step,
            settings,
            inputs: &self.inputs,
            record: &self.record,
        }
    }

    /// The cases run at a time: `jobs`, or for 0 the threads of rayon's global pool (one
    /// per core, or `harness --jobs`).
    pub fn threads(&self) -> usize {
        match self.jobs {
            0 => rayon::current_num_threads(),
            n => n,
        }
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
    /// generator parameters (`anatomy.*`) turned into a configuration file in `configs` —
    /// returned as its path and text for the caller to write.
    pub fn settings(&self, case: &DesignPoint, configs: &Path) -> Result<Settings> {
        let scene = scene::create(&self.scene)?;
        let generated: Vec<String> = scene
            .generator_parameters()
            .into_iter()
            .map(|g| g.name)
            .collect();
        let mut merged = self.parameters.clone();
        merged.extend(case.values.clone());
        let mut fields = Vec::new();
        let mut settings = Settings::default();
        for (name, value) in &merged {
            match value {
                Value::Real(x) if generated.contains(name) => fields.push((name.as_str(), *x)),
                _ => settings.values.push((name.clone(), value.clone())),
            }
        }
        if !fields.is_empty() {
            let config = scene.generate_configuration(
                &format!("case_{:04}", case.id),
                &format!("generated by the harness for case {}", case.id),
                &fields,
            )?;
            let path = std::path::absolute(configs.join(format!("case_{:04}.toml", case.id)))?;
            settings.values.push((
                config.parameter.into(),
                Value::Text(path.display().to_string()),
            ));
            settings.config = Some((path, config.text));
        }
        Ok(settings)
    }
}

/// What a case sets before initialization, and the configuration file it needs written.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Settings {
    /// Name and value of each variable to set: the base parameters overridden by the case's
    /// values, with the generated configuration's path among them if there is one.
    pub values: Vec<(String, Value)>,
    /// The generated configuration file's path and text, if the case sets generator
    /// parameters.
    pub config: Option<(PathBuf, String)>,
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

/// Checks a parameter value against the scene's table or its generator parameters.
fn check_value(scene: &dyn Scene, name: &str, value: &Value) -> Result<()> {
    let table = scene.variables();
    if !table.iter().any(|v| v.name == name) {
        let generators = scene.generator_parameters();
        if !generators.iter().any(|g| g.name == name) {
            let names: Vec<String> = generators.into_iter().map(|g| g.name).collect();
            if names.is_empty() {
                bail!("no variable named `{name}`");
            }
            bail!(
                "no variable named `{name}`, nor a generator parameter ({})",
                names.join(", ")
            );
        }
        let Value::Real(x) = value else {
            bail!("`{name}` = \"{value}\" must be a number");
        };
        scene.generate_configuration("check", "", &[(name, *x)])?;
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

/// A case may not both set a parameter and generate it from generator parameters (the
/// abdomen: `configuration` and `anatomy.*`).
fn check_generator_conflict(
    scene: &dyn Scene,
    base: &BTreeMap<String, Value>,
    case: &BTreeMap<String, Value>,
) -> Result<()> {
    let names = || base.keys().chain(case.keys());
    let generators = scene.generator_parameters();
    let Some(g) = names().find_map(|n| generators.iter().find(|g| g.name == *n)) else {
        return Ok(());
    };
    let target = scene.generate_configuration("check", "", &[])?.parameter;
    if names().any(|n| n == target) {
        bail!(
            "sets both `{target}` and `{}`; generator parameters generate the {target}",
            g.name
        );
    }
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
        assert_eq!(e.schedule(&[]).steps(), 10);
        assert_eq!(e.metric, "floor_stress_max");
        assert_eq!(e.varied(), ["configuration", "anatomy.outlet"]);
        let s = e.settings(&e.cases[3], Path::new("/runs/configs")).unwrap();
        let config = s.values.iter().find(|(n, _)| n == "configuration").unwrap();
        assert_eq!(config.1, Value::Text("/runs/configs/case_0003.toml".into()));
        let (path, text) = s.config.unwrap();
        assert_eq!(path, Path::new("/runs/configs/case_0003.toml"));
        assert!(text.contains("outlet = 115.0"), "{text}");
    }

    /// The shipped pelvis sweep thinned as the quick report runs it: its five
    /// configurations, 8 of 32 Latin hypercube samples, 3 of 5 levels on each of its five
    /// grids; the written file reads back as the same plan.
    #[test]
    fn a_thinned_sweep_keeps_every_block_with_fewer_points() {
        let full = Experiment::shipped("pelvis_sweep").unwrap();
        let quick = full.thinned(8, 3).unwrap();
        assert_eq!((full.cases.len(), quick.cases.len()), (62, 5 + 8 + 5 * 3));
        assert_eq!(quick.name, "pelvis_sweep_quick");
        assert_eq!(quick.varied(), full.varied());
        assert_eq!(quick.step, full.step);
        let again = Experiment::parse(&quick.source, Path::new(".")).unwrap();
        assert_eq!(again.cases, quick.cases);
        // The grids keep their ends: outlet 95, 115 and 135 mm.
        let outlets: Vec<&Value> = quick
            .cases
            .iter()
            .filter(|c| c.design == design::Design::Grid)
            .filter_map(|c| c.values.get("anatomy.outlet"))
            .collect();
        let mm = [95.0, 115.0, 135.0].map(Value::Real);
        assert_eq!(outlets, mm.iter().collect::<Vec<_>>());
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
}
