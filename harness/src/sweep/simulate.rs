//! The one simulation loop. Every run of a scene over time — a sweep case, a study, the
//! FMU backend, the reference runs the Python tests compare the FMUs with (`harness
//! simulate`) — goes through [`simulate`], which follows the sequence an FMI importer does:
//! set the parameters, set the inputs at the start time, initialize, record the outputs;
//! then for every communication step set the inputs, step, record the outputs.
//!
//! **The input rule**: an input is sampled at the start of each communication step and held
//! over it, as FMI importers do; the outputs at t + h respond to the inputs at t. Inputs are
//! given as piecewise-linear tables ([`InputTable`]), held constant beyond their ends.

use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

use anyhow::{bail, ensure, Context, Result};
use serde::{Deserialize, Serialize};

/// A parameter value: a number or a text.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum Value {
    /// A number.
    Real(f64),
    /// A text (the value of a string parameter).
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

/// An input given as a piecewise-linear function of time, held constant beyond its ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputTable {
    /// Breakpoint times (s), strictly increasing.
    pub time: Vec<f64>,
    /// The input's value at each breakpoint.
    pub value: Vec<f64>,
}

impl InputTable {
    /// A constant input.
    pub fn constant(value: f64) -> Self {
        Self {
            time: vec![0.0],
            value: vec![value],
        }
    }

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

    /// Checks the table; errors name `key`.
    pub fn check(&self, key: &str) -> Result<()> {
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

    /// One table per input column of a CSV `time,<input>,…`; errors name the file and row.
    pub fn read_csv(path: &Path) -> Result<BTreeMap<String, InputTable>> {
        let mut r = csv::Reader::from_path(path)
            .with_context(|| format!("cannot read input file {}", path.display()))?;
        let names: Vec<String> = r.headers()?.iter().skip(1).map(String::from).collect();
        let mut tables: BTreeMap<String, InputTable> = names
            .iter()
            .map(|n| {
                let empty = InputTable {
                    time: Vec::new(),
                    value: Vec::new(),
                };
                (n.clone(), empty)
            })
            .collect();
        for (i, row) in r.records().enumerate() {
            let row = row.with_context(|| format!("{}: data row {}", path.display(), i + 1))?;
            let x: Vec<f64> = row
                .iter()
                .map(|s| s.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .with_context(|| format!("{}: data row {}", path.display(), i + 1))?;
            ensure!(
                x.len() == names.len() + 1,
                "{}: data row {} has {} values for {} columns",
                path.display(),
                i + 1,
                x.len(),
                names.len() + 1
            );
            for (name, v) in names.iter().zip(&x[1..]) {
                let t = tables.get_mut(name).expect("one table per column");
                t.time.push(x[0]);
                t.value.push(*v);
            }
        }
        for (name, t) in &tables {
            t.check(&format!("{}: {name}", path.display()))?;
        }
        Ok(tables)
    }
}

/// A variable as a session addresses it: its value reference and its number of values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct VariableRef {
    /// The value reference.
    pub vr: u32,
    /// Number of values: 1 for a scalar, n for an array.
    pub len: usize,
}

/// One running instance of a scene. Variables are addressed by [`VariableRef`], looked up by
/// name once per run.
pub trait Session {
    /// The reference of the variable `name`; an error if there is none.
    fn reference(&self, name: &str) -> Result<VariableRef>;
    /// Sets a parameter or an input to `value`.
    fn set(&mut self, r: VariableRef, value: &Value) -> Result<()>;
    /// Initializes at `start_time` (s).
    fn initialize(&mut self, start_time: f64) -> Result<()>;
    /// Advances by one communication step of `h` (s) from time `t` (s).
    fn step(&mut self, t: f64, h: f64) -> Result<()>;
    /// Reads all values of the variable into `out` (of length `r.len`).
    fn get(&mut self, r: VariableRef, out: &mut [f64]) -> Result<()>;
    /// The scene's warnings since the last call (where an input took the model beyond its
    /// validity); none by default.
    fn take_warnings(&mut self) -> Vec<String> {
        Vec::new()
    }
}

/// What a run does: parameters before initialization, inputs over time, the outputs to
/// record, and the communication grid t_k = `start_time` + k · `step` up to `stop_time`,
/// stepped with h_k = t_{k+1} − t_k (the arithmetic fmpy uses, so that both pass the scenes
/// the same times to the last bit).
#[derive(Debug, Clone, Copy)]
pub struct Schedule<'a> {
    /// Start time (s).
    pub start_time: f64,
    /// Stop time (s).
    pub stop_time: f64,
    /// Communication step (s).
    pub step: f64,
    /// Parameter values set before initialization, by name.
    pub settings: &'a [(String, Value)],
    /// Input tables by input name, sampled at the start of each step.
    pub inputs: &'a BTreeMap<String, InputTable>,
    /// The outputs to record, by name.
    pub record: &'a [String],
}

impl Schedule<'_> {
    /// Number of communication steps.
    pub fn steps(&self) -> usize {
        ((self.stop_time - self.start_time) / self.step).round() as usize
    }

    /// The communication point t_k.
    pub fn time(&self, k: usize) -> f64 {
        self.start_time + k as f64 * self.step
    }
}

/// Start and stop time and communication step: finite, stop after start, a positive step,
/// and a whole number of steps between them.
pub fn check_times(start_time: f64, stop_time: f64, step: f64) -> Result<()> {
    ensure!(
        start_time.is_finite(),
        "`start_time` = {start_time} must be finite"
    );
    ensure!(
        stop_time.is_finite() && stop_time > start_time,
        "`stop_time` = {stop_time} must be after `start_time` = {start_time}"
    );
    let span = stop_time - start_time;
    ensure!(
        step.is_finite() && step > 0.0 && step <= span,
        "`step` = {step} must be positive and at most `stop_time` − `start_time` = {span}"
    );
    let steps = span / step;
    ensure!(
        (steps - steps.round()).abs() < 1e-9 * steps,
        "`stop_time` − `start_time` = {span} is not a whole number of `step` = {step}"
    );
    Ok(())
}

/// Recorded outputs: `rows[k] = [t, values…]` after initialization and after every step; an
/// array output of n values gives the columns `name[0]` … `name[n−1]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// The output columns' names, without the time column.
    pub names: Vec<String>,
    /// One row per communication point: the time (s), then the outputs.
    pub rows: Vec<Vec<f64>>,
}

/// A finished run: its outputs and where the time went.
#[derive(Debug, Clone)]
pub struct Run {
    /// The recorded outputs.
    pub series: Series,
    /// Setting the parameters and initializing.
    pub setup: Duration,
    /// All steps together (without the output reads).
    pub stepping: Duration,
    /// The scene's warnings, in order.
    pub warnings: Vec<String>,
}

/// Runs `schedule` on `session`.
pub fn simulate<S: Session + ?Sized>(session: &mut S, schedule: &Schedule) -> Result<Run> {
    simulate_observed(session, schedule, |_, _| Ok(()))
}

/// Runs `schedule` on `session`, calling `observe(session, t)` after initialization and
/// after every step (for what the outputs do not tell, e.g. a whole displacement field).
pub fn simulate_observed<S: Session + ?Sized>(
    session: &mut S,
    schedule: &Schedule,
    mut observe: impl FnMut(&mut S, f64) -> Result<()>,
) -> Result<Run> {
    let start = Instant::now();
    for (name, value) in schedule.settings {
        let r = session.reference(name)?;
        session
            .set(r, value)
            .with_context(|| format!("setting `{name}` = {value}"))?;
    }
    let inputs = schedule
        .inputs
        .iter()
        .map(|(name, table)| Ok((session.reference(name)?, name, table)))
        .collect::<Result<Vec<_>>>()?;
    let mut names = Vec::new();
    let mut record = Vec::new();
    for name in schedule.record {
        let r = session.reference(name)?;
        match r.len {
            1 => names.push(name.clone()),
            n => names.extend((0..n).map(|i| format!("{name}[{i}]"))),
        }
        record.push(r);
    }
    let set_inputs = |session: &mut S, t: f64| -> Result<()> {
        for &(r, name, table) in &inputs {
            let x = table.at(t);
            session
                .set(r, &Value::Real(x))
                .with_context(|| format!("input `{name}` = {x} at t = {t} s"))?;
        }
        Ok(())
    };
    let outputs = |session: &mut S, t: f64| -> Result<Vec<f64>> {
        let mut row = vec![0.0; names.len() + 1];
        row[0] = t;
        let mut at = 1;
        for &r in &record {
            session.get(r, &mut row[at..at + r.len])?;
            at += r.len;
        }
        Ok(row)
    };
    let t0 = schedule.start_time;
    set_inputs(session, t0)?;
    session.initialize(t0)?;
    let setup = start.elapsed();
    let mut warnings = session.take_warnings();
    observe(session, t0)?;
    let mut rows = vec![outputs(session, t0)?];
    let mut stepping = Duration::ZERO;
    for k in 0..schedule.steps() {
        let (t, next) = (schedule.time(k), schedule.time(k + 1));
        set_inputs(session, t)?;
        let begin = Instant::now();
        session
            .step(t, next - t)
            .with_context(|| format!("step at t = {t} s"))?;
        stepping += begin.elapsed();
        warnings.extend(session.take_warnings());
        observe(session, next)?;
        rows.push(outputs(session, next)?);
    }
    Ok(Run {
        series: Series { names, rows },
        setup,
        stepping,
        warnings,
    })
}

impl Series {
    /// Writes `time,<outputs>` rows with full precision.
    pub fn to_csv(&self) -> Result<Vec<u8>> {
        let mut w = csv::Writer::from_writer(Vec::new());
        w.write_record(std::iter::once("time").chain(self.names.iter().map(String::as_str)))?;
        for row in &self.rows {
            w.write_record(row.iter().map(|x| format!("{x:?}")))?;
        }
        Ok(w.into_inner()?)
    }

    /// Reads what [`Series::to_csv`] wrote.
    pub fn read_csv(path: &Path) -> Result<Self> {
        let mut r = csv::Reader::from_path(path)?;
        let names = r.headers()?.iter().skip(1).map(String::from).collect();
        let rows = r
            .records()
            .map(|rec| -> Result<Vec<f64>> { rec?.iter().map(|x| Ok(x.parse::<f64>()?)).collect() })
            .collect::<Result<_>>()?;
        Ok(Self { names, rows })
    }

    /// The column of a scalar output (or of one array element, `name[i]`).
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self.names.iter().position(|n| n == name)? + 1;
        Some(self.rows.iter().map(|r| r[j]).collect())
    }

    /// The values of an array output `name` in row `k`.
    pub fn array(&self, name: &str, k: usize) -> Option<Vec<f64>> {
        let prefix = format!("{name}[");
        let first = self.names.iter().position(|n| n.starts_with(&prefix))? + 1;
        let n = self.names.iter().filter(|n| n.starts_with(&prefix)).count();
        Some(self.rows.get(k)?[first..first + n].to_vec())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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

    /// A session that records what it was told: y(t + h) = the input held over the step.
    #[derive(Default)]
    struct Echo {
        input: f64,
        output: f64,
        calls: Vec<String>,
    }

    impl Session for Echo {
        fn reference(&self, name: &str) -> Result<VariableRef> {
            match name {
                "u" => Ok(VariableRef { vr: 0, len: 1 }),
                "y" => Ok(VariableRef { vr: 1, len: 1 }),
                "pair" => Ok(VariableRef { vr: 2, len: 2 }),
                _ => bail!("no variable named `{name}`"),
            }
        }
        fn set(&mut self, r: VariableRef, value: &Value) -> Result<()> {
            self.calls.push(format!("set {} {value}", r.vr));
            if let Value::Real(x) = value {
                self.input = *x;
            }
            Ok(())
        }
        fn initialize(&mut self, _start_time: f64) -> Result<()> {
            self.calls.push("initialize".into());
            Ok(())
        }
        fn step(&mut self, t: f64, h: f64) -> Result<()> {
            self.calls.push(format!("step {t} {h}"));
            self.output = self.input;
            Ok(())
        }
        fn get(&mut self, r: VariableRef, out: &mut [f64]) -> Result<()> {
            match r.vr {
                1 => out[0] = self.output,
                _ => out.copy_from_slice(&[self.output, -self.output]),
            }
            Ok(())
        }
    }

    #[test]
    fn inputs_are_sampled_at_the_start_of_each_step_and_held() {
        // A ramp whose breakpoint (0.25 s) lies inside a step: what counts is its value at
        // each step's start, 0, 0.2 and 0.4 s.
        let inputs = BTreeMap::from([(
            "u".to_string(),
            InputTable {
                time: vec![0.0, 0.25, 1.0],
                value: vec![0.0, 1.0, 1.0],
            },
        )]);
        let settings = [("p".to_string(), Value::Text("x".into()))];
        let record = ["y".to_string(), "pair".to_string()];
        let schedule = Schedule {
            start_time: 0.0,
            stop_time: 0.6,
            step: 0.2,
            settings: &settings[..0],
            inputs: &inputs,
            record: &record,
        };
        let mut echo = Echo::default();
        let run = simulate(&mut echo, &schedule).unwrap();
        assert_eq!(run.series.names, ["y", "pair[0]", "pair[1]"]);
        let y = run.series.column("y").unwrap();
        assert_eq!(y, [0.0, 0.0, 0.8, 1.0]);
        assert_eq!(run.series.array("pair", 2).unwrap(), [0.8, -0.8]);
        assert_eq!(
            echo.calls[..4],
            ["set 0 0", "initialize", "set 0 0", "step 0 0.2"]
        );
        // A setting that the session does not know is named.
        let bad = Schedule {
            settings: &settings,
            ..schedule
        };
        let e = format!("{:#}", simulate(&mut Echo::default(), &bad).unwrap_err());
        assert!(e.contains("`p`"), "{e}");
    }

    #[test]
    fn input_csv_gives_one_table_per_column_and_names_bad_rows() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("in.csv");
        std::fs::write(&path, "time,pull,press\n0,0,1\n1.5,3,1\n").unwrap();
        let t = InputTable::read_csv(&path).unwrap();
        assert_eq!(t["pull"].at(0.75), 1.5);
        assert_eq!(t["press"].value, [1.0, 1.0]);
        std::fs::write(&path, "time,pull\n0,0\n1,x\n").unwrap();
        let e = format!("{:#}", InputTable::read_csv(&path).unwrap_err());
        assert!(e.contains("in.csv") && e.contains("row 2"), "{e}");
    }
}
