//! The model-independent FMI instance: the state machine that checks every call against the
//! states in which the standard allows it, value-reference mapping for FMI 2 (indexed
//! scalars) and FMI 3 (arrays), error reporting through the logger, and the scene behind it.
//! The ABI files only convert C arguments and call into this.

use std::ffi::CString;
use std::path::PathBuf;

use models::scene::{Causality, ErrorKind, Scene, SceneError, Variable, VariableKind};

use crate::model::Model;

/// Call status, shared by FMI 2 and FMI 3 (same codes 0–4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
}

/// Where the instance is in its life cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    Instantiated,
    Initialization,
    Step,
    Terminated,
    /// A step or the initialization failed: only get, reset and free are allowed.
    Error,
}

/// The calls the state machine distinguishes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Call {
    SetupExperiment,
    EnterInitialization,
    ExitInitialization,
    Set,
    Get,
    DoStep,
    Terminate,
    Reset,
    SetDebugLogging,
}

impl Call {
    /// Phases in which the call is allowed (FMI 2.0 §4.2.4 state machine; FMI 3.0 §4.2
    /// co-simulation without event mode has the same structure).
    fn allowed(self, phase: Phase) -> bool {
        use Phase::*;
        match self {
            Call::SetupExperiment | Call::EnterInitialization => phase == Instantiated,
            Call::ExitInitialization => phase == Initialization,
            Call::Set => matches!(phase, Instantiated | Initialization | Step),
            Call::Get => matches!(phase, Initialization | Step | Terminated | Error),
            Call::DoStep => phase == Step,
            Call::Terminate => matches!(phase, Step | Error),
            Call::Reset | Call::SetDebugLogging => true,
        }
    }
}

/// The logger: (status, category, message).
pub type Log = Box<dyn Fn(Status, &str, &str) + Send>;

/// One FMI 2 scalar: a scalar variable, or element `index` of an array variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Scalar {
    pub name: String,
    pub scene_vr: u32,
    pub index: usize,
}

/// The FMI 2 scalars of a variable table, in value-reference order.
pub fn fmi2_scalars(vars: &[Variable]) -> Vec<Scalar> {
    vars.iter()
        .flat_map(|v| {
            (0..v.len).map(move |i| Scalar {
                name: if v.len == 1 {
                    v.name.clone()
                } else {
                    format!("{}[{i}]", v.name)
                },
                scene_vr: v.vr,
                index: i,
            })
        })
        .collect()
}

/// FMI 3 value reference of the independent variable `time`.
pub fn time_vr(vars: &[Variable]) -> u32 {
    vars.len() as u32
}

/// How value references address values.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Addressing {
    /// FMI 2: one value per reference; arrays as indexed scalars.
    Scalars,
    /// FMI 3: a reference per variable, `len` values each; plus `time`.
    Arrays,
}

/// An FMI instance.
pub struct Instance {
    pub name: String,
    model: &'static Model,
    scene: Box<dyn Scene>,
    phase: Phase,
    time: f64,
    resources: Option<PathBuf>,
    log: Log,
    log_calls: bool,
    scalars: Vec<Scalar>,
    buffer: Vec<f64>,
    strings: Vec<CString>,
}

impl Instance {
    /// Creates the scene named by `token` (FMI 2 GUID / FMI 3 instantiation token), with
    /// resources at `location` (any of the forms [`crate::uri::resource_dir`] accepts). On
    /// failure the reason goes to `log` and the result is `None`.
    pub fn create(
        token: Option<&str>,
        name: &str,
        location: Option<&str>,
        log: Log,
        log_calls: bool,
    ) -> Option<Self> {
        let fail = |m: &str| {
            log(Status::Error, "logStatusError", m);
            None
        };
        let Some(token) = token else {
            return fail("the instantiation token / GUID is missing");
        };
        let Some(model) = Model::by_token(token) else {
            return fail(&format!(
                "instantiation token / GUID `{token}` matches no model in this binary (is the modelDescription.xml from another build?)"
            ));
        };
        let resources = match location
            .filter(|l| !l.is_empty())
            .map(crate::uri::resource_dir)
        {
            None => None,
            Some(Ok(dir)) => Some(dir),
            Some(Err(m)) => return fail(&m),
        };
        let mut scene = (model.create)();
        if let Some(dir) = &resources {
            scene.set_resource_dir(dir);
        }
        Some(Self {
            name: name.to_string(),
            scalars: fmi2_scalars(scene.variables()),
            model,
            scene,
            phase: Phase::Instantiated,
            time: 0.0,
            resources,
            log,
            log_calls,
            buffer: Vec::new(),
            strings: Vec::new(),
        })
    }

    /// A heap-allocated instance as the opaque handle the C ABI hands out, or null.
    pub fn into_handle(instance: Option<Self>) -> *mut std::ffi::c_void {
        instance.map_or(std::ptr::null_mut(), |i| {
            Box::into_raw(Box::new(i)) as *mut std::ffi::c_void
        })
    }

    /// After a caught panic: only get, reset and free remain allowed.
    pub fn poison(&mut self) {
        self.phase = Phase::Error;
    }

    pub fn phase(&self) -> Phase {
        self.phase
    }

    pub fn time(&self) -> f64 {
        self.time
    }

    /// Logs an error (always) and returns `status`.
    pub fn error(&self, status: Status, message: &str) -> Status {
        (self.log)(status, "logStatusError", message);
        status
    }

    /// Turns call logging on or off (category `logCalls`). Unknown categories are an error.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> Status {
        for c in categories {
            if c != "logCalls" && c != "logStatusError" {
                return self.error(
                    Status::Error,
                    &format!("unknown log category `{c}` (have logStatusError, logCalls)"),
                );
            }
        }
        self.log_calls =
            on && (categories.is_empty() || categories.iter().any(|c| c == "logCalls"));
        Status::Ok
    }

    /// Checks that `call` is allowed now; logs and returns Error otherwise.
    pub fn check(&self, call: Call, function: &str) -> Result<(), Status> {
        if self.log_calls {
            (self.log)(
                Status::Ok,
                "logCalls",
                &format!("{function} (phase {:?})", self.phase),
            );
        }
        if call.allowed(self.phase) {
            Ok(())
        } else {
            Err(self.error(
                Status::Error,
                &format!("{function} is not allowed in phase {:?}", self.phase),
            ))
        }
    }

    /// Logs a scene error, named by its kind when the model failed while running.
    fn fail(&self, e: &SceneError) -> Status {
        match e.kind() {
            ErrorKind::Runtime => self.error(Status::Error, &format!("{}: {e}", e.kind())),
            ErrorKind::Usage | ErrorKind::Configuration => {
                self.error(Status::Error, &e.to_string())
            }
        }
    }

    pub fn setup_experiment(&mut self, start: f64) -> Status {
        if !start.is_finite() {
            return self.error(Status::Error, &format!("start time {start} is not finite"));
        }
        self.time = start;
        Status::Ok
    }

    pub fn enter_initialization(&mut self) -> Status {
        self.phase = Phase::Initialization;
        Status::Ok
    }

    /// Builds the scene (mesh, factorization) and solves the initial state.
    pub fn exit_initialization(&mut self) -> Status {
        match self.scene.initialize() {
            Ok(()) => {
                self.phase = Phase::Step;
                Status::Ok
            }
            Err(e) => {
                self.phase = Phase::Error;
                self.fail(&e)
            }
        }
    }

    /// Advances to exactly `current + h`.
    pub fn do_step(&mut self, current: f64, h: f64) -> Status {
        if !(h.is_finite() && h > 0.0) {
            return self.error(
                Status::Error,
                &format!("communication step size {h} must be finite and > 0"),
            );
        }
        let tolerance = 1e-9 * current.abs().max(h).max(1.0);
        if (current - self.time).abs() > tolerance {
            return self.error(
                Status::Error,
                &format!(
                    "currentCommunicationPoint {current} does not match the instance time {}",
                    self.time
                ),
            );
        }
        match self.scene.do_step(current, h) {
            Ok(()) => {
                self.time = current + h;
                Status::Ok
            }
            Err(e) => {
                self.phase = Phase::Error;
                self.fail(&e)
            }
        }
    }

    pub fn terminate(&mut self) -> Status {
        self.phase = Phase::Terminated;
        Status::Ok
    }

    /// Back to the state after instantiation: a fresh scene with start values.
    pub fn reset(&mut self) -> Status {
        self.scene = (self.model.create)();
        if let Some(dir) = &self.resources {
            self.scene.set_resource_dir(dir);
        }
        self.phase = Phase::Instantiated;
        self.time = 0.0;
        Status::Ok
    }

    fn variable(&self, vr: u32) -> Option<&Variable> {
        self.scene.variables().get(vr as usize)
    }

    /// Resolves references to (scene vr, element index, value count) per reference.
    fn resolve(
        &self,
        addressing: Addressing,
        vrs: &[u32],
    ) -> Result<Vec<(u32, usize, usize)>, String> {
        vrs.iter()
            .map(|&vr| match addressing {
                Addressing::Scalars => self
                    .scalars
                    .get(vr as usize)
                    .map(|s| (s.scene_vr, s.index, 1))
                    .ok_or_else(|| format!("unknown value reference {vr}")),
                Addressing::Arrays if vr == time_vr(self.scene.variables()) => Ok((vr, 0, 1)),
                Addressing::Arrays => self
                    .variable(vr)
                    .map(|v| (vr, 0, v.len))
                    .ok_or_else(|| format!("unknown value reference {vr}")),
            })
            .collect()
    }

    /// Resolved references whose value counts add up to `n_values`; logs and returns Error
    /// otherwise.
    fn references(
        &self,
        addressing: Addressing,
        vrs: &[u32],
        n_values: usize,
    ) -> Result<Vec<(u32, usize, usize)>, Status> {
        let refs = self
            .resolve(addressing, vrs)
            .map_err(|m| self.error(Status::Error, &m))?;
        let needed: usize = refs.iter().map(|r| r.2).sum();
        if needed != n_values {
            return Err(self.error(
                Status::Error,
                &format!("{n_values} values given for {needed} expected"),
            ));
        }
        Ok(refs)
    }

    /// Sets real values.
    pub fn set_reals(&mut self, addressing: Addressing, vrs: &[u32], values: &[f64]) -> Status {
        let refs = match self.references(addressing, vrs, values.len()) {
            Ok(r) => r,
            Err(s) => return s,
        };
        let mut at = 0;
        for (vr, index, n) in refs {
            if vr == time_vr(self.scene.variables()) {
                return self.error(
                    Status::Error,
                    "the independent variable `time` cannot be set",
                );
            }
            let result = if index > 0 || self.variable(vr).is_some_and(|v| v.len != n) {
                Err(SceneError::NotSettable {
                    name: self
                        .scalars
                        .iter()
                        .find(|s| s.scene_vr == vr)
                        .map_or(String::new(), |s| s.name.clone()),
                    reason: "array elements are outputs",
                })
            } else {
                self.scene.set_real(vr, &values[at..at + n])
            };
            if let Err(e) = result {
                return self.fail(&e);
            }
            at += n;
        }
        Status::Ok
    }

    /// Gets real values (outputs are computed on the first request after a step).
    pub fn get_reals(&mut self, addressing: Addressing, vrs: &[u32], values: &mut [f64]) -> Status {
        let refs = match self.references(addressing, vrs, values.len()) {
            Ok(r) => r,
            Err(s) => return s,
        };
        let mut at = 0;
        for (vr, index, n) in refs {
            if vr == time_vr(self.scene.variables()) {
                values[at] = self.time;
                at += 1;
                continue;
            }
            let Some(len) = self.variable(vr).map(|v| v.len) else {
                return self.error(Status::Error, &format!("unknown value reference {vr}"));
            };
            if self.phase == Phase::Initialization
                && self
                    .variable(vr)
                    .is_some_and(|v| v.causality == Causality::Output)
            {
                return self.error(Status::Error, "outputs are available after initialization (fmi2ExitInitializationMode / fmi3ExitInitializationMode)");
            }
            self.buffer.resize(len, 0.0);
            if let Err(e) = self.scene.get_real(vr, &mut self.buffer) {
                return self.fail(&e);
            }
            values[at..at + n].copy_from_slice(&self.buffer[index..index + n]);
            at += n;
        }
        Status::Ok
    }

    /// Sets string parameters.
    pub fn set_strings(
        &mut self,
        addressing: Addressing,
        vrs: &[u32],
        values: &[String],
    ) -> Status {
        let refs = match self.resolve(addressing, vrs) {
            Ok(r) => r,
            Err(m) => return self.error(Status::Error, &m),
        };
        for ((vr, _, _), value) in refs.into_iter().zip(values) {
            if let Err(e) = self.scene.set_string(vr, value) {
                return self.fail(&e);
            }
        }
        Status::Ok
    }

    /// Gets string variables; the returned C strings stay valid until the next call.
    pub fn get_strings(
        &mut self,
        addressing: Addressing,
        vrs: &[u32],
    ) -> Result<&[CString], Status> {
        let refs = self
            .resolve(addressing, vrs)
            .map_err(|m| self.error(Status::Error, &m))?;
        self.strings.clear();
        for (vr, _, _) in refs {
            let kind = self.variable(vr).map(|v| v.kind);
            if kind != Some(VariableKind::String) {
                return Err(self.error(
                    Status::Error,
                    &format!("value reference {vr} is not a string"),
                ));
            }
            let s = self.scene.get_string(vr).map_err(|e| self.fail(&e))?;
            self.strings.push(CString::new(s).unwrap_or_default());
        }
        Ok(&self.strings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    type Lines = Arc<Mutex<Vec<(Status, String, String)>>>;

    fn instance(log_calls: bool) -> (Instance, Lines) {
        let lines: Lines = Arc::default();
        let sink = lines.clone();
        let log: Log = Box::new(move |s, c, m| sink.lock().unwrap().push((s, c.into(), m.into())));
        let token = crate::model::MODELS[1].token();
        (
            Instance::create(Some(&token), "t", None, log, log_calls).unwrap(),
            lines,
        )
    }

    #[test]
    fn runtime_failures_and_configuration_errors_are_named_as_such() {
        let (mut i, lines) = instance(false);
        let vr = |i: &Instance, name: &str| i.scene.lookup(name).unwrap();
        let support = vr(&i, "support");
        assert_eq!(
            i.set_strings(Addressing::Arrays, &[support], &["glued".into()]),
            Status::Error
        );
        let (cells_x, depth) = (vr(&i, "cells_x"), vr(&i, "cut_depth"));
        i.set_reals(Addressing::Arrays, &[cells_x, depth], &[2.0, 17.0]);
        i.enter_initialization();
        assert_eq!(i.exit_initialization(), Status::Ok);
        let (pull, scalpel) = (vr(&i, "pull"), vr(&i, "scalpel_x"));
        i.set_reals(Addressing::Arrays, &[pull, scalpel], &[1.0, 100.0]);
        assert_eq!(i.do_step(0.0, 1.0), Status::Error);
        let logged = lines.lock().unwrap().clone();
        assert!(
            logged[0]
                .2
                .starts_with("invalid configuration: support `glued`"),
            "{:?}",
            logged[0]
        );
        let last = &logged.last().unwrap().2;
        assert!(
            last.starts_with("runtime failure: the cut separates the block"),
            "{last}"
        );
    }

    #[test]
    fn errors_are_logged_with_the_variable_and_calls_only_when_asked() {
        let (mut i, lines) = instance(false);
        let nu = i.scene.lookup("nu").unwrap();
        assert_eq!(
            i.set_reals(Addressing::Arrays, &[nu], &[0.5]),
            Status::Error
        );
        assert!(i.check(Call::DoStep, "fmi2DoStep").is_err());
        let logged = lines.lock().unwrap().clone();
        assert_eq!(logged.len(), 2);
        assert!(logged
            .iter()
            .all(|(s, c, _)| *s == Status::Error && c == "logStatusError"));
        assert!(logged[0].2.contains("`nu`"), "{:?}", logged[0]);
        assert!(logged[1]
            .2
            .contains("fmi2DoStep is not allowed in phase Instantiated"));
        // Call logging: off by default, on by category.
        assert_eq!(i.set_debug_logging(true, &["logCalls".into()]), Status::Ok);
        i.check(Call::Set, "fmi2SetReal").unwrap();
        assert_eq!(lines.lock().unwrap().last().unwrap().1, "logCalls");
        assert_eq!(
            i.set_debug_logging(true, &["logStatusError".into()]),
            Status::Ok
        );
        let before = lines.lock().unwrap().len();
        i.check(Call::Set, "fmi2SetReal").unwrap();
        assert_eq!(lines.lock().unwrap().len(), before, "logCalls not enabled");
        assert_eq!(
            i.set_debug_logging(true, &["logEverything".into()]),
            Status::Error
        );
    }
}
