//! The FMU backend (feature `fmu`): a packaged FMI 2 co-simulation FMU loaded through the
//! `fmi` crate, the path users take. Variables are looked up by name in the FMU's own
//! `modelDescription.xml`; the FMU's error messages, which reach the importer through the
//! FMI logger callback (the `fmi` crate forwards them to the `log` facade), are captured per
//! thread so that a failed case reports the model's own words.

use std::cell::RefCell;
use std::collections::HashMap;
use std::ffi::CString;
use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation as _, Common as _, InstanceCS};
use fmi::traits::FmiImport as _;

use super::simulate::{Reference, Session, Value};

thread_local! {
    static LAST_ERROR: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Keeps the last error-level message logged on each thread.
struct Capture;

impl log::Log for Capture {
    fn enabled(&self, m: &log::Metadata) -> bool {
        m.level() <= log::Level::Warn
    }

    fn log(&self, record: &log::Record) {
        if record.level() == log::Level::Error {
            LAST_ERROR.with(|e| *e.borrow_mut() = Some(record.args().to_string()));
        }
    }

    fn flush(&self) {}
}

static CAPTURE: Capture = Capture;

/// A loaded FMU and the value references of its variables by name.
pub struct FmuBackend {
    import: Fmi2Import,
    variables: HashMap<String, u32>,
    identifier: String,
}

impl FmuBackend {
    pub fn load(path: &Path) -> Result<Self> {
        // Another logger may already be installed (then messages go there instead).
        if log::set_logger(&CAPTURE).is_ok() {
            log::set_max_level(log::LevelFilter::Warn);
        }
        let version = fmi::import::peek_descr_path(path)
            .with_context(|| format!("cannot read FMU {}", path.display()))?
            .fmi_version;
        if !version.starts_with("2.") {
            bail!(
                "`fmu`: {} is an FMI {version} FMU; the FMU backend imports FMI 2.0 \
                 co-simulation FMUs (the bundler writes <model>-fmi2.fmu)",
                path.display()
            );
        }
        let import: Fmi2Import = fmi::import::from_path(path)
            .with_context(|| format!("cannot load FMU {}", path.display()))?;
        let md = import.model_description();
        let identifier = md
            .co_simulation
            .as_ref()
            .map(|cs| cs.model_identifier.clone())
            .with_context(|| format!("{} is not a co-simulation FMU", path.display()))?;
        let variables = md
            .get_model_variables()
            .map(|v| (v.name.clone(), v.value_reference))
            .collect();
        Ok(Self {
            import,
            variables,
            identifier,
        })
    }

    pub fn open(&self) -> Result<FmuSession<'_>> {
        let instance = self
            .import
            .instantiate_cs(&self.identifier, false, true)
            .map_err(|e| failure("fmi2Instantiate", e))?;
        Ok(FmuSession {
            backend: self,
            instance,
        })
    }
}

/// The error of an FMI call, with the message the FMU logged for it if any.
fn failure(call: &str, e: impl std::fmt::Display) -> anyhow::Error {
    match LAST_ERROR.with(|m| m.borrow_mut().take()) {
        Some(message) => anyhow!("{call}: {message}"),
        None => anyhow!("{call} failed: {e}"),
    }
}

/// One instance of the FMU.
pub struct FmuSession<'a> {
    backend: &'a FmuBackend,
    instance: InstanceCS,
}

impl Session for FmuSession<'_> {
    /// A scalar by its name; an array `name` as FMI 2 gives it, the scalars `name[0]`,
    /// `name[1]`, … with consecutive value references.
    fn reference(&self, name: &str) -> Result<Reference> {
        let vars = &self.backend.variables;
        if let Some(&vr) = vars.get(name) {
            return Ok(Reference { vr, len: 1 });
        }
        let element = |i: usize| vars.get(&format!("{name}[{i}]")).copied();
        let vr = element(0).with_context(|| format!("the FMU has no variable named `{name}`"))?;
        let len = (0..).take_while(|&i| element(i).is_some()).count();
        if (0..len).any(|i| element(i) != Some(vr + i as u32)) {
            bail!("the elements of `{name}` do not have consecutive value references");
        }
        Ok(Reference { vr, len })
    }

    fn set(&mut self, r: Reference, value: &Value) -> Result<()> {
        match value {
            Value::Real(x) => self
                .instance
                .set_real(&[r.vr], &[*x])
                .map(drop)
                .map_err(|e| failure("fmi2SetReal", e)),
            Value::Text(s) => self
                .instance
                .set_string(&[r.vr], &[CString::new(s.as_str())?])
                .map_err(|e| failure("fmi2SetString", e)),
        }
    }

    fn initialize(&mut self) -> Result<()> {
        self.instance
            .setup_experiment(None, 0.0, None)
            .map_err(|e| failure("fmi2SetupExperiment", e))?;
        self.instance
            .enter_initialization_mode()
            .map_err(|e| failure("fmi2EnterInitializationMode", e))?;
        self.instance
            .exit_initialization_mode()
            .map_err(|e| failure("fmi2ExitInitializationMode", e))?;
        Ok(())
    }

    fn step(&mut self, t: f64, h: f64) -> Result<()> {
        self.instance
            .do_step(t, h, true)
            .map_err(|e| failure("fmi2DoStep", e))?;
        Ok(())
    }

    fn get(&mut self, r: Reference, out: &mut [f64]) -> Result<()> {
        let array: Vec<u32>;
        let vrs = if r.len == 1 {
            std::slice::from_ref(&r.vr)
        } else {
            array = (r.vr..r.vr + r.len as u32).collect();
            &array
        };
        self.instance
            .get_real(vrs, out)
            .map_err(|e| failure("fmi2GetReal", e))?;
        Ok(())
    }
}
