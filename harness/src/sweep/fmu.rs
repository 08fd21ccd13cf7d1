//! The FMU backend (feature `fmu`): a packaged FMI 2.0 or FMI 3.0 co-simulation FMU loaded
//! through the `fmi` crate, the path users take. Variables are looked up by name in the
//! FMU's own `modelDescription.xml` (an FMI 2 array is its scalars `name[0]`, `name[1]`, …
//! with consecutive value references; an FMI 3 array is one reference). The FMU's error
//! messages, which reach the importer through the FMI logger callback (the `fmi` crate
//! forwards them to the `log` facade), are captured per thread so that a failed case reports
//! the model's own words.

use std::cell::RefCell;
use std::collections::HashMap;
use std::ffi::CString;
use std::path::Path;

use anyhow::{anyhow, bail, Context, Result};
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation as _, Common as _};
use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::{CoSimulation as _, Common as _, Fmi3Model as _, GetSet as _};
use fmi::schema::fmi3::{AbstractVariableTrait as _, ArrayableVariableTrait as _};
use fmi::traits::FmiImport as _;

use super::simulate::{Session, Value, VariableRef};

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

/// The error of an FMI call, with the message the FMU logged for it if any.
fn failure(call: &str, e: impl std::fmt::Display) -> anyhow::Error {
    match LAST_ERROR.with(|m| m.borrow_mut().take()) {
        Some(message) => anyhow!("{call}: {message}"),
        None => anyhow!("{call} failed: {e}"),
    }
}

/// The imported FMU, by FMI version.
enum Import {
    Fmi2(Fmi2Import),
    Fmi3(Fmi3Import),
}

/// A loaded FMU, its model identifier and its variables by name.
pub struct FmuBackend {
    import: Import,
    identifier: String,
    variables: HashMap<String, VariableRef>,
}

/// FMI 2 variables by name, with each array `name[i]` also under `name` if its elements
/// have consecutive value references.
fn fmi2_variables(import: &Fmi2Import) -> HashMap<String, VariableRef> {
    let scalars: Vec<(String, u32)> = import
        .model_description()
        .get_model_variables()
        .map(|v| (v.name.clone(), v.value_reference))
        .collect();
    let mut map: HashMap<String, VariableRef> = scalars
        .iter()
        .map(|(name, vr)| (name.clone(), VariableRef { vr: *vr, len: 1 }))
        .collect();
    for (name, vr) in &scalars {
        let Some(array) = name.strip_suffix("[0]") else {
            continue;
        };
        let len = (0..)
            .take_while(|i| map.get(&format!("{array}[{i}]")).map(|r| r.vr) == Some(vr + *i))
            .count();
        map.insert(array.to_string(), VariableRef { vr: *vr, len });
    }
    map
}

/// FMI 3 variables by name; an array's length is the product of its fixed dimensions.
fn fmi3_variables(import: &Fmi3Import) -> HashMap<String, VariableRef> {
    let vars = &import.model_description().model_variables;
    let mut map: HashMap<String, VariableRef> = vars
        .float64()
        .into_iter()
        .map(|v| {
            let len = v
                .dimensions()
                .iter()
                .map(|d| d.as_fixed().unwrap_or(1) as usize)
                .product();
            (
                v.name().to_string(),
                VariableRef {
                    vr: v.value_reference(),
                    len,
                },
            )
        })
        .collect();
    map.extend(vars.string().into_iter().map(|v| {
        (
            v.name().to_string(),
            VariableRef {
                vr: v.value_reference(),
                len: 1,
            },
        )
    }));
    map
}

impl FmuBackend {
    /// Loads the FMU at `path` (FMI 2.0 or 3.0, co-simulation) and indexes its variables by
    /// name; installs the logger that captures the FMU's error messages unless another
    /// logger is installed.
    pub fn load(path: &Path) -> Result<Self> {
        // Another logger may already be installed (then messages go there instead).
        if log::set_logger(&CAPTURE).is_ok() {
            log::set_max_level(log::LevelFilter::Warn);
        }
        let version = fmi::import::peek_descr_path(path)
            .with_context(|| format!("cannot read FMU {}", path.display()))?
            .fmi_version;
        let load = || format!("cannot load FMU {}", path.display());
        let not_cs = || format!("{} is not a co-simulation FMU", path.display());
        let (import, identifier, variables) = if version.starts_with("2.") {
            let import: Fmi2Import = fmi::import::from_path(path).with_context(load)?;
            let md = import.model_description();
            let cs = md.co_simulation.as_ref().with_context(not_cs)?;
            let identifier = cs.model_identifier.clone();
            let variables = fmi2_variables(&import);
            (Import::Fmi2(import), identifier, variables)
        } else if version.starts_with("3.") {
            let import: Fmi3Import = fmi::import::from_path(path).with_context(load)?;
            let md = import.model_description();
            let cs = md.co_simulation.as_ref().with_context(not_cs)?;
            let identifier = cs.model_identifier.clone();
            let variables = fmi3_variables(&import);
            (Import::Fmi3(import), identifier, variables)
        } else {
            bail!(
                "`fmu`: {} is an FMI {version} FMU; the FMU backend imports FMI 2.0 and 3.0",
                path.display()
            );
        };
        Ok(Self {
            import,
            identifier,
            variables,
        })
    }

    /// A fresh instance.
    pub fn open(&self) -> Result<Box<dyn Session + '_>> {
        Ok(match &self.import {
            Import::Fmi2(import) => Box::new(Fmi2Session {
                backend: self,
                vrs: Vec::new(),
                instance: import
                    .instantiate_cs(&self.identifier, false, true)
                    .map_err(|e| failure("fmi2Instantiate", e))?,
            }),
            Import::Fmi3(import) => Box::new(Fmi3Session {
                backend: self,
                instance: import
                    .instantiate_cs(&self.identifier, false, true, false, false, &[])
                    .map_err(|e| failure("fmi3InstantiateCoSimulation", e))?,
            }),
        })
    }

    fn reference(&self, name: &str) -> Result<VariableRef> {
        self.variables
            .get(name)
            .copied()
            .with_context(|| format!("the FMU has no variable named `{name}`"))
    }
}

/// One FMI 2 instance.
struct Fmi2Session<'a> {
    backend: &'a FmuBackend,
    /// The value references of the array being read (FMI 2 has no arrays), reused from
    /// step to step.
    vrs: Vec<u32>,
    instance: fmi::fmi2::instance::InstanceCS,
}

impl Session for Fmi2Session<'_> {
    fn reference(&self, name: &str) -> Result<VariableRef> {
        self.backend.reference(name)
    }

    fn set(&mut self, r: VariableRef, value: &Value) -> Result<()> {
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

    fn initialize(&mut self, start_time: f64) -> Result<()> {
        self.instance
            .setup_experiment(None, start_time, None)
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

    fn get(&mut self, r: VariableRef, out: &mut [f64]) -> Result<()> {
        self.vrs.clear();
        self.vrs.extend(r.vr..r.vr + r.len as u32);
        self.instance
            .get_real(&self.vrs, out)
            .map_err(|e| failure("fmi2GetReal", e))?;
        Ok(())
    }
}

/// One FMI 3 instance.
struct Fmi3Session<'a> {
    backend: &'a FmuBackend,
    instance: fmi::fmi3::instance::InstanceCS,
}

impl Session for Fmi3Session<'_> {
    fn reference(&self, name: &str) -> Result<VariableRef> {
        self.backend.reference(name)
    }

    fn set(&mut self, r: VariableRef, value: &Value) -> Result<()> {
        match value {
            Value::Real(x) => self
                .instance
                .set_float64(&[r.vr], &[*x])
                .map(drop)
                .map_err(|e| failure("fmi3SetFloat64", e)),
            Value::Text(s) => self
                .instance
                .set_string(&[r.vr], &[CString::new(s.as_str())?])
                .map_err(|e| failure("fmi3SetString", e)),
        }
    }

    fn initialize(&mut self, start_time: f64) -> Result<()> {
        self.instance
            .enter_initialization_mode(None, start_time, None)
            .map_err(|e| failure("fmi3EnterInitializationMode", e))?;
        self.instance
            .exit_initialization_mode()
            .map_err(|e| failure("fmi3ExitInitializationMode", e))?;
        Ok(())
    }

    fn step(&mut self, t: f64, h: f64) -> Result<()> {
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, t);
        self.instance
            .do_step(
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
            .map_err(|e| failure("fmi3DoStep", e))?;
        Ok(())
    }

    fn get(&mut self, r: VariableRef, out: &mut [f64]) -> Result<()> {
        self.instance
            .get_float64(&[r.vr], out)
            .map_err(|e| failure("fmi3GetFloat64", e))?;
        Ok(())
    }
}
