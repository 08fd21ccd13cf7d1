//! Where a run happens: the scene linked into the harness ([`InProcess`]), or the packaged
//! FMU through the `fmi` crate (feature `fmu`, `sweep::fmu`). Both are [`Session`]s that
//! the one loop, [`super::simulate()`], drives.

use std::path::Path;

use anyhow::{anyhow, Result};
use models::scene::{self, Scene};
use serde::{Deserialize, Serialize};

use super::simulate::{Session, Value, VariableRef};

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

/// Opens sessions of a scene on a backend.
pub enum Backend {
    /// The scene linked into the harness, by name.
    InProcess(String),
    /// The packaged FMU, loaded once; each session instantiates it anew.
    #[cfg(feature = "fmu")]
    Fmu(Box<super::fmu::FmuBackend>),
}

impl Backend {
    /// The backend for `scene`; the `fmu` kind needs the `.fmu` file.
    pub fn new(kind: BackendKind, scene: &str, fmu: Option<&Path>) -> Result<Self> {
        match kind {
            BackendKind::InProcess => Ok(Self::InProcess(scene.to_string())),
            #[cfg(feature = "fmu")]
            BackendKind::Fmu => Ok(Self::Fmu(Box::new(super::fmu::FmuBackend::load(
                fmu.ok_or_else(|| anyhow!("no FMU given"))?,
            )?))),
            #[cfg(not(feature = "fmu"))]
            BackendKind::Fmu => {
                let _ = fmu;
                Err(anyhow!(
                    "`backend` = \"fmu\": this harness was built without the FMU backend; \
                     rebuild with `--features fmu` (needs libclang for the `fmi` crate's bindgen)"
                ))
            }
        }
    }

    /// A fresh session.
    pub fn open(&self) -> Result<Box<dyn Session + '_>> {
        match self {
            Self::InProcess(name) => Ok(Box::new(InProcess(scene::create(name)?))),
            #[cfg(feature = "fmu")]
            Self::Fmu(f) => f.open(),
        }
    }
}

/// A scene linked into the harness, driven as a session; the scene stays reachable (`.0`)
/// for what only it can tell (its mesh, its whole displacement field).
pub struct InProcess<S: Scene + ?Sized>(pub Box<S>);

impl<S: Scene + ?Sized> Session for InProcess<S> {
    fn reference(&self, name: &str) -> Result<VariableRef> {
        let vr = self.0.lookup(name)?;
        let len = self.0.variables()[vr as usize].len;
        Ok(VariableRef { vr, len })
    }

    fn set(&mut self, r: VariableRef, value: &Value) -> Result<()> {
        match value {
            Value::Real(x) => self.0.set_real(r.vr, &[*x])?,
            Value::Text(s) => self.0.set_string(r.vr, s)?,
        }
        Ok(())
    }

    fn initialize(&mut self, start_time: f64) -> Result<()> {
        Ok(self.0.initialize(start_time)?)
    }

    fn step(&mut self, t: f64, h: f64) -> Result<()> {
        Ok(self.0.do_step(t, h)?)
    }

    fn get(&mut self, r: VariableRef, out: &mut [f64]) -> Result<()> {
        Ok(self.0.get_real(r.vr, out)?)
    }

    fn take_warnings(&mut self) -> Vec<String> {
        self.0.take_warnings()
    }
}
