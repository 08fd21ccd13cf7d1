//! Where a case runs: the scene in process, or the packaged FMU through the `fmi` crate
//! (feature `fmu`). Both are driven through [`Session`] by one simulation loop, the same
//! sequence an FMI importer follows: set parameters and inputs at t = 0, initialize, then
//! at every communication point set the inputs and step.

use std::path::Path;

use anyhow::{anyhow, Result};
use models::scene::{self, Scene};

use crate::experiment::{BackendKind, Experiment, Value};

/// One running instance of a scene. Variables are addressed by value reference, looked up
/// by name once per case.
pub trait Session {
    fn reference(&self, name: &str) -> Result<u32>;
    fn set(&mut self, vr: u32, value: &Value) -> Result<()>;
    fn initialize(&mut self) -> Result<()>;
    fn step(&mut self, t: f64, h: f64) -> Result<()>;
    fn get(&mut self, vr: u32) -> Result<f64>;
}

/// A case's recorded outputs: `rows[k] = [t, output…]` after initialization and after
/// every step.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    pub names: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

/// Opens sessions of an experiment's scene on its backend.
pub enum Backend {
    InProcess(String),
    #[cfg(feature = "fmu")]
    Fmu(Box<crate::fmu_backend::FmuBackend>),
}

impl Backend {
    pub fn new(e: &Experiment) -> Result<Self> {
        match e.backend {
            BackendKind::InProcess => Ok(Self::InProcess(e.scene.clone())),
            #[cfg(feature = "fmu")]
            BackendKind::Fmu => Ok(Self::Fmu(Box::new(crate::fmu_backend::FmuBackend::load(
                e.fmu.as_deref().ok_or_else(|| anyhow!("no FMU given"))?,
            )?))),
            #[cfg(not(feature = "fmu"))]
            BackendKind::Fmu => Err(anyhow!(
                "`backend` = \"fmu\": this harness was built without the FMU backend; \
                 rebuild with `--features fmu` (needs libclang for the `fmi` crate's bindgen)"
            )),
        }
    }

    /// A fresh session.
    pub fn open(&self) -> Result<Box<dyn Session + '_>> {
        match self {
            Self::InProcess(name) => Ok(Box::new(InProcess(scene::create(name)?))),
            #[cfg(feature = "fmu")]
            Self::Fmu(f) => Ok(Box::new(f.open()?)),
        }
    }
}

/// The scene linked into the harness.
struct InProcess(Box<dyn Scene>);

impl Session for InProcess {
    fn reference(&self, name: &str) -> Result<u32> {
        Ok(self.0.lookup(name)?)
    }

    fn set(&mut self, vr: u32, value: &Value) -> Result<()> {
        match value {
            Value::Real(x) => self.0.set_real(vr, &[*x])?,
            Value::Text(s) => self.0.set_string(vr, s)?,
        }
        Ok(())
    }

    fn initialize(&mut self) -> Result<()> {
        Ok(self.0.initialize()?)
    }

    fn step(&mut self, t: f64, h: f64) -> Result<()> {
        Ok(self.0.do_step(t, h)?)
    }

    fn get(&mut self, vr: u32) -> Result<f64> {
        let mut x = [0.0];
        self.0.get_real(vr, &mut x)?;
        Ok(x[0])
    }
}

/// Runs one case: `settings` before initialization, the experiment's inputs at every
/// communication point, its recorded outputs after initialization and after every step.
pub fn simulate(
    session: &mut dyn Session,
    e: &Experiment,
    settings: &[(String, Value)],
) -> Result<Series> {
    for (name, value) in settings {
        let vr = session.reference(name)?;
        session
            .set(vr, value)
            .map_err(|err| anyhow!("setting `{name}` = {value}: {err:#}"))?;
    }
    let inputs = e
        .inputs
        .iter()
        .map(|(name, table)| Ok((session.reference(name)?, name, table)))
        .collect::<Result<Vec<_>>>()?;
    let record = e
        .record
        .iter()
        .map(|name| session.reference(name))
        .collect::<Result<Vec<_>>>()?;
    let set_inputs = |session: &mut dyn Session, t: f64| -> Result<()> {
        for &(vr, name, table) in &inputs {
            let x = table.at(t);
            session
                .set(vr, &Value::Real(x))
                .map_err(|err| anyhow!("input `{name}` = {x} at t = {t} s: {err:#}"))?;
        }
        Ok(())
    };
    let outputs = |session: &mut dyn Session, t: f64| -> Result<Vec<f64>> {
        let mut row = Vec::with_capacity(record.len() + 1);
        row.push(t);
        for &vr in &record {
            row.push(session.get(vr)?);
        }
        Ok(row)
    };
    set_inputs(session, 0.0)?;
    session.initialize()?;
    let mut rows = vec![outputs(session, 0.0)?];
    for k in 0..e.steps() {
        let t = k as f64 * e.step;
        set_inputs(session, t)?;
        session
            .step(t, e.step)
            .map_err(|err| anyhow!("step at t = {t} s: {err:#}"))?;
        rows.push(outputs(session, t + e.step)?);
    }
    Ok(Series {
        names: e.record.clone(),
        rows,
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

    /// The column of an output.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self.names.iter().position(|n| n == name)? + 1;
        Some(self.rows.iter().map(|r| r[j]).collect())
    }
}
