//! The model-independent FMI instance: the state machine that checks every call against the
//! states in which the standard allows it, value-reference mapping for FMI 2 (indexed
//! scalars) and FMI 3 (arrays), error reporting, and the scene behind it. The ABI files only
//! convert C arguments and call into this.
//!
//! - **Initialization Mode** follows FMI 2.0 §4.2.4 / FMI 3.0 §4.2: inputs and parameters
//!   can be set and outputs read there. The scene is built on the first read of an output
//!   (or at `ExitInitializationMode`) from the values set so far; a value set after that
//!   build makes the next read build again, and `ExitInitializationMode` builds only if no
//!   build is current.
//! - **Messages** are queued while a call runs and handed to the importer's logger by
//!   the ABI guard (`ffi::guard`) after the call has released the instance, so a logger that calls
//!   back into the FMU never aliases it.
//! - **Sets of several values** are checked as a whole: if any value is refused, the values
//!   set before it in the same call are restored and the call changes nothing.

use std::ffi::CString;
use std::sync::Arc;

use models::error::seconds;
use models::scene::{Causality, ErrorKind, Scene, SceneError, Variable, VariableKind};

use crate::addressing::{Addressing, Resolved};
use crate::exports::{Export, Version};
use crate::machine::{refused_step, Call, Phase, Status};
use crate::state::{FmuState, InstanceState};

/// The logger: (status, category, message).
pub type Log = Arc<dyn Fn(Status, &str, &str) + Send + Sync>;

/// A queued log message: status, category, text.
pub type Message = (Status, &'static str, String);

/// An FMI instance.
pub struct Instance {
    /// The instance name the importer gave (`tissuefmu` if it gave none or an invalid one).
    pub name: String,
    model: &'static Export,
    version: Version,
    scene: Box<dyn Scene>,
    phase: Phase,
    /// Whether the scene is initialized with every value set so far.
    built: bool,
    /// Why the initialization failed, for the messages of later calls.
    failure: Option<String>,
    start_time: f64,
    /// The stop time the importer defined, if any: no step may pass it.
    stop_time: Option<f64>,
    time: f64,
    log: Log,
    messages: Vec<Message>,
    log_calls: bool,
    addressing: Addressing,
    buffer: Vec<f64>,
    strings: Vec<CString>,
}

impl Instance {
    /// Creates the scene named by `token` (FMI 2 GUID / FMI 3 instantiation token); a
    /// resource `location` must be one of the forms [`crate::uri::resource_dir`] accepts
    /// (the scenes carry their data and read none). On failure the reason goes to `log` and
    /// the result is `None`.
    pub fn create(
        version: Version,
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
        let Some(model) = Export::by_token(token) else {
            return fail(&format!(
                "instantiation token / GUID `{token}` matches no model in this binary (is the modelDescription.xml from another build?)"
            ));
        };
        // The scenes carry their shipped data; a location is still checked, so that a
        // malformed one is reported rather than ignored.
        if let Some(Err(m)) = location
            .filter(|l| !l.is_empty())
            .map(crate::uri::resource_dir)
        {
            return fail(&m);
        }
        let scene = (model.create)();
        Some(Self {
            name: name.to_string(),
            addressing: Addressing::new(version, scene.variables()),
            model,
            version,
            scene,
            phase: Phase::Instantiated,
            built: false,
            failure: None,
            start_time: 0.0,
            stop_time: None,
            time: 0.0,
            log,
            messages: Vec::new(),
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

    /// After a caught panic: the error phase (reads, terminate, reset, free and the FMU-state
    /// calls remain allowed).
    pub fn poison(&mut self) {
        self.phase = Phase::Error;
    }

    /// Where the instance is in its life cycle.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The instance time: the start time until a step succeeds, then the end of the last
    /// successful step (FMI 2 `fmi2LastSuccessfulTime`, FMI 3 `lastSuccessfulTime`).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The logger, for the ABI guard (`ffi::guard`) to hand the queued messages to.
    pub fn logger(&self) -> Log {
        self.log.clone()
    }

    /// The messages queued since the last call, in order.
    pub fn take_messages(&mut self) -> Vec<Message> {
        std::mem::take(&mut self.messages)
    }

    /// Queues an error message (always logged) and returns `status`.
    pub fn error(&mut self, status: Status, message: &str) -> Status {
        self.messages
            .push((status, "logStatusError", message.to_string()));
        status
    }

    /// Turns call logging on or off (category `logCalls`). Unknown categories are an error.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> Status {
        if let Some(c) = categories.iter().find(|c| {
            !matches!(
                c.as_str(),
                "logCalls" | "logStatusError" | "logStatusWarning"
            )
        }) {
            let message = format!(
                "unknown log category `{c}` (have logStatusError, logStatusWarning, logCalls)"
            );
            return self.error(Status::Error, &message);
        }
        self.log_calls =
            on && (categories.is_empty() || categories.iter().any(|c| c == "logCalls"));
        Status::Ok
    }

    /// Checks that `call` is allowed now; queues a message and returns Error otherwise.
    pub fn check(&mut self, call: Call, function: &str) -> Result<(), Status> {
        if self.log_calls {
            let message = format!("{function} (phase {:?})", self.phase);
            self.messages.push((Status::Ok, "logCalls", message));
        }
        if call.allowed(self.phase, self.version) {
            Ok(())
        } else {
            let message = format!("{function} is not allowed in phase {:?}", self.phase);
            Err(self.error(Status::Error, &message))
        }
    }

    /// Queues a scene error, named by its kind when the model failed while running or its
    /// values describe no valid model, and with the reason when the initialization had
    /// failed.
    fn fail(&mut self, e: &SceneError) -> Status {
        // A configuration error of the scene says so itself; one of the model (an unknown
        // choice, a value out of its range) is named here.
        let mut message = match (e.kind(), e) {
            (ErrorKind::Runtime, _) | (ErrorKind::Configuration, SceneError::Model(_)) => {
                format!("{}: {e}", e.kind())
            }
            _ => e.to_string(),
        };
        if let (SceneError::NotInitialized { .. }, Some(why)) = (e, &self.failure) {
            message += &format!(" (the initialization failed: {why})");
        }
        self.error(Status::Error, &message)
    }

    /// Queues the scene's new warnings (category `logStatusWarning`, always logged) and
    /// returns Warning if there were any.
    fn warn(&mut self) -> Status {
        let warnings = self.scene.take_warnings();
        if warnings.is_empty() {
            return Status::Ok;
        }
        for w in warnings {
            self.messages.push((Status::Warning, "logStatusWarning", w));
        }
        Status::Warning
    }

    /// The start time and, if the importer defines one, the stop time (FMI 2
    /// `fmi2SetupExperiment`, FMI 3 `fmi3EnterInitializationMode`).
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Status {
        if !start.is_finite() {
            return self.error(Status::Error, &format!("start time {start} is not finite"));
        }
        if let Some(stop) = stop.filter(|&s| !(s.is_finite() && s >= start)) {
            let message = format!(
                "stop time {stop} must be finite and not before the start time {} s",
                seconds(start)
            );
            return self.error(Status::Error, &message);
        }
        self.start_time = start;
        self.stop_time = stop;
        self.time = start;
        Status::Ok
    }

    /// Enters Initialization Mode. The scene is not built here but on the first read of an
    /// output or at the exit (see the module documentation).
    pub fn enter_initialization(&mut self) -> Status {
        self.phase = Phase::Initialization;
        Status::Ok
    }

    /// Builds the scene (mesh, factorization) and solves the initial state, unless the
    /// build is current. A failure moves the instance to the error phase.
    fn build(&mut self) -> Status {
        if self.built {
            return Status::Ok;
        }
        if self.log_calls {
            let message = format!(
                "building the model, start time {} s",
                seconds(self.start_time)
            );
            self.messages.push((Status::Ok, "logCalls", message));
        }
        match self.scene.initialize(self.start_time) {
            Ok(()) => {
                self.built = true;
                self.warn()
            }
            Err(e) => {
                self.phase = Phase::Error;
                self.failure = Some(e.to_string());
                self.fail(&e)
            }
        }
    }

    /// Before a value is set in Initialization Mode after a build: a fresh scene with the
    /// values set so far (the next read or the exit builds it again).
    fn unbuild(&mut self) -> Result<(), SceneError> {
        if self.phase != Phase::Initialization || !self.built {
            return Ok(());
        }
        let mut fresh = (self.model.create)();
        let settable: Vec<(u32, VariableKind)> = self
            .scene
            .variables()
            .iter()
            .filter(|v| v.causality != Causality::Output)
            .map(|v| (v.vr, v.kind))
            .collect();
        for (vr, kind) in settable {
            match kind {
                VariableKind::Real => {
                    let mut x = [0.0];
                    self.scene.get_real(vr, &mut x)?;
                    fresh.set_real(vr, &x)?;
                }
                VariableKind::String => fresh.set_string(vr, &self.scene.get_string(vr)?)?,
            }
        }
        self.scene = fresh;
        self.built = false;
        Ok(())
    }

    /// Leaves Initialization Mode, building the scene if no build is current.
    pub fn exit_initialization(&mut self) -> Status {
        match self.build() {
            s @ (Status::Ok | Status::Warning) => {
                self.phase = Phase::Step;
                s
            }
            s => s,
        }
    }

    /// Advances to exactly `current + h`.
    pub fn do_step(&mut self, current: f64, h: f64) -> Status {
        if let Some(why) = refused_step(self.time, self.stop_time, current, h) {
            return self.error(Status::Error, &why);
        }
        match self.scene.do_step(current, h) {
            Ok(()) => {
                self.time = current + h;
                self.warn()
            }
            Err(e) => {
                self.phase = Phase::Error;
                self.fail(&e)
            }
        }
    }

    /// Ends the simulation: the scene is kept, its values can still be read, and the
    /// instance can be reset or freed.
    pub fn terminate(&mut self) -> Status {
        self.phase = Phase::Terminated;
        Status::Ok
    }

    /// The instance's state now (FMU state): phase, times and the scene's state.
    pub fn get_state(&self) -> FmuState {
        FmuState::new(
            self.model.identifier,
            InstanceState {
                phase: self.phase,
                built: self.built,
                failure: self.failure.clone(),
                start_time: self.start_time,
                stop_time: self.stop_time,
                time: self.time,
            },
            self.scene.save(),
        )
    }

    /// Puts a state back (into this instance or another of the same model); the instance
    /// then continues as the one the state was taken from. A state of another model, or one
    /// the scene refuses, is an error and changes nothing.
    pub fn set_state(&mut self, state: &FmuState) -> Status {
        if state.model != self.model.identifier {
            let message = format!(
                "an FMU state of the `{}` model cannot be set in a `{}` instance",
                state.model, self.model.identifier
            );
            return self.error(Status::Error, &message);
        }
        if let Err(e) = self.scene.restore(&state.scene) {
            return self.error(
                Status::Error,
                &format!("the FMU state could not be set: {e}"),
            );
        }
        let s = &state.instance;
        self.phase = s.phase;
        self.built = s.built;
        self.failure.clone_from(&s.failure);
        self.start_time = s.start_time;
        self.stop_time = s.stop_time;
        self.time = s.time;
        Status::Ok
    }

    /// The serialized form of `state` (see [`crate::state`]).
    pub fn serialize<'s>(&mut self, state: &'s FmuState) -> Result<&'s [u8], Status> {
        state
            .bytes(self.model)
            .map_err(|m| self.error(Status::Error, &m))
    }

    /// A state from serialized bytes, refused with the reason if they are not a state of
    /// this model and build.
    pub fn deserialize(&mut self, bytes: &[u8]) -> Result<FmuState, Status> {
        FmuState::from_bytes(self.model, bytes).map_err(|m| {
            let message = format!("the serialized FMU state is refused: {m}");
            self.error(Status::Error, &message)
        })
    }

    /// Back to the state after instantiation: a fresh scene with start values.
    pub fn reset(&mut self) -> Status {
        self.scene = (self.model.create)();
        self.phase = Phase::Instantiated;
        self.built = false;
        self.failure = None;
        self.start_time = 0.0;
        self.stop_time = None;
        self.time = 0.0;
        Status::Ok
    }

    fn variable(&self, vr: u32) -> Option<&Variable> {
        self.scene.variables().get(vr as usize)
    }

    /// Resolved references whose value counts add up to `n_values`; queues a message and
    /// returns Error otherwise.
    fn references(&mut self, vrs: &[u32], n_values: usize) -> Result<Vec<Resolved>, Status> {
        let refs = self
            .addressing
            .resolve_values(self.scene.variables(), vrs, n_values);
        refs.map_err(|m| self.error(Status::Error, &m))
    }

    /// The name of a resolved reference as the model description spells it.
    fn name_of(&self, r: Resolved) -> String {
        self.addressing.name_of(self.scene.variables(), r)
    }

    /// Sets real values; all or none.
    pub fn set_reals(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        let refs = match self.references(vrs, values.len()) {
            Ok(r) => r,
            Err(s) => return s,
        };
        if let Some(m) = refs
            .iter()
            .find_map(|&r| self.addressing.unsettable(self.scene.variables(), r))
        {
            return self.error(Status::Error, &m);
        }
        let mut at = 0;
        let items: Vec<(u32, &[f64])> = refs
            .iter()
            .map(|r| {
                at += r.len;
                (r.vr, &values[at - r.len..at])
            })
            .collect();
        let result = self.apply(
            &items,
            |scene, vr| {
                let mut old = vec![0.0; scene.variables()[vr as usize].len];
                scene.get_real(vr, &mut old).map(|()| old)
            },
            |scene, vr, x: &[f64]| scene.set_real(vr, x),
        );
        match result {
            // A value that cannot act under the present settings is warned of.
            Ok(()) => self.warn(),
            Err(e) => self.fail(&e),
        }
    }

    /// Sets string parameters; all or none.
    pub fn set_strings(&mut self, vrs: &[u32], values: &[String]) -> Status {
        let refs = match self.references(vrs, values.len()) {
            Ok(r) => r,
            Err(s) => return s,
        };
        if let Some(m) = refs
            .iter()
            .find_map(|&r| self.addressing.unsettable(self.scene.variables(), r))
        {
            return self.error(Status::Error, &m);
        }
        let items: Vec<(u32, &str)> = refs
            .iter()
            .zip(values)
            .map(|(r, v)| (r.vr, v.as_str()))
            .collect();
        let result = self.apply(
            &items,
            |scene, vr| scene.get_string(vr),
            |scene, vr, s: &str| scene.set_string(vr, s),
        );
        match result {
            // A value that cannot act under the present settings is warned of.
            Ok(()) => self.warn(),
            Err(e) => self.fail(&e),
        }
    }

    /// Sets `items` in order; if one is refused, restores the ones set before it (in reverse
    /// order, each to the value `read` gave before the call) and returns the refusal.
    fn apply<T: ?Sized, Old: std::borrow::Borrow<T>>(
        &mut self,
        items: &[(u32, &T)],
        read: impl Fn(&mut dyn Scene, u32) -> Result<Old, SceneError>,
        write: impl Fn(&mut dyn Scene, u32, &T) -> Result<(), SceneError>,
    ) -> Result<(), SceneError> {
        if items.is_empty() {
            return Ok(());
        }
        self.unbuild()?;
        if let [(vr, value)] = items {
            return write(self.scene.as_mut(), *vr, value);
        }
        let old = items
            .iter()
            .map(|&(vr, _)| read(self.scene.as_mut(), vr))
            .collect::<Result<Vec<_>, _>>()?;
        for (k, &(vr, value)) in items.iter().enumerate() {
            if let Err(e) = write(self.scene.as_mut(), vr, value) {
                for (&(vr, _), previous) in items[..k].iter().zip(&old).rev() {
                    // Restores a value this scene held a moment ago.
                    let _ = write(self.scene.as_mut(), vr, previous.borrow());
                }
                return Err(e);
            }
        }
        Ok(())
    }

    /// Builds the scene in Initialization Mode before an output is read.
    fn ready_for(&mut self, refs: &[Resolved]) -> Status {
        let outputs = refs.iter().any(|r| {
            self.variable(r.vr)
                .is_some_and(|v| v.causality == Causality::Output)
        });
        if self.phase == Phase::Initialization && outputs {
            self.build()
        } else {
            Status::Ok
        }
    }

    /// Gets real values (outputs are computed on the first request after a step).
    pub fn get_reals(&mut self, vrs: &[u32], values: &mut [f64]) -> Status {
        let refs = match self.references(vrs, values.len()) {
            Ok(r) => r,
            Err(s) => return s,
        };
        let ready = self.ready_for(&refs);
        if matches!(ready, Status::Error | Status::Fatal) {
            return ready;
        }
        let mut at = 0;
        for r in refs {
            let Some(len) = self.variable(r.vr).map(|v| v.len) else {
                values[at] = self.time;
                at += 1;
                continue;
            };
            self.buffer.resize(len, 0.0);
            if let Err(e) = self.scene.get_real(r.vr, &mut self.buffer) {
                return self.fail(&e);
            }
            values[at..at + r.len].copy_from_slice(&self.buffer[r.index..r.index + r.len]);
            at += r.len;
        }
        ready
    }

    /// Gets string variables; the returned C strings stay valid until the next call.
    pub fn get_strings(&mut self, vrs: &[u32]) -> Result<&[CString], Status> {
        let refs = self.references(vrs, vrs.len())?;
        self.strings.clear();
        for r in refs {
            if self.variable(r.vr).map(|v| v.kind) != Some(VariableKind::String) {
                let message = format!("`{}` is not a string", self.name_of(r));
                return Err(self.error(Status::Error, &message));
            }
            let s = match self.scene.get_string(r.vr) {
                Ok(s) => s,
                Err(e) => return Err(self.fail(&e)),
            };
            self.strings.push(CString::new(s).unwrap_or_default());
        }
        Ok(&self.strings)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::addressing::fmi2_scalars;
    use crate::exports::EXPORTS;

    /// A cut-block instance of `version` and the value references of its variables by name.
    fn instance(version: Version, log_calls: bool) -> (Instance, impl Fn(&str) -> u32) {
        let token = EXPORTS[1].token();
        let i = Instance::create(version, Some(&token), "t", None, ffi_silent(), log_calls);
        let scene = (EXPORTS[1].create)();
        let names: Vec<String> = match version {
            Version::Fmi2 => fmi2_scalars(scene.variables())
                .into_iter()
                .map(|s| s.name)
                .collect(),
            Version::Fmi3 => scene.variables().iter().map(|v| v.name.clone()).collect(),
        };
        let vr = move |name: &str| names.iter().position(|n| n == name).unwrap() as u32;
        (i.unwrap(), vr)
    }

    fn ffi_silent() -> Log {
        Arc::new(|_, _, _| {})
    }

    fn texts(i: &mut Instance) -> Vec<String> {
        i.take_messages().into_iter().map(|m| m.2).collect()
    }

    const SMALL: [(&str, f64); 3] = [("cells_x", 2.0), ("cells_y", 4.0), ("cells_z", 3.0)];

    fn small(i: &mut Instance, vr: &impl Fn(&str) -> u32) {
        let vrs: Vec<u32> = SMALL.iter().map(|(n, _)| vr(n)).collect();
        let values: Vec<f64> = SMALL.iter().map(|p| p.1).collect();
        assert_eq!(i.set_reals(&vrs, &values), Status::Ok);
    }

    /// A stop time the importer defines is honoured: steps up to it go, one past it is an
    /// error naming both times (rounded: `0.3 s`, not `0.30000000000000004 s`), and the
    /// instance stays at its last time, usable; a stop time before the start is refused.
    #[test]
    fn the_stop_time_is_honoured_and_times_print_rounded() {
        let (mut i, vr) = instance(Version::Fmi2, false);
        assert_eq!(i.setup_experiment(0.0, Some(-1.0)), Status::Error);
        assert!(texts(&mut i)[0].contains("stop time -1 must be finite and not before"));
        assert_eq!(i.setup_experiment(0.0, Some(0.3)), Status::Ok);
        small(&mut i, &vr);
        i.enter_initialization();
        assert_eq!(i.exit_initialization(), Status::Ok);
        for k in 0..3 {
            assert_eq!(i.do_step(f64::from(k) * 0.1, 0.1), Status::Ok, "step {k}");
        }
        assert_eq!(i.time(), 0.1 + 0.1 + 0.1);
        assert_eq!(i.do_step(0.1 + 0.1 + 0.1, 0.1), Status::Error);
        let message = texts(&mut i).join("\n");
        assert!(
            message.contains("a step from t = 0.3 s by 0.1 s would pass the stop time 0.3 s"),
            "{message}"
        );
        assert_eq!(i.do_step(0.5, 0.1), Status::Error);
        let message = texts(&mut i).join("\n");
        assert!(
            message
                .contains("currentCommunicationPoint 0.5 s does not match the instance time 0.3 s"),
            "{message}"
        );
        assert_eq!(
            i.phase(),
            Phase::Step,
            "a refused step leaves the instance usable"
        );
        assert_eq!(i.reset(), Status::Ok);
        assert_eq!(i.setup_experiment(0.0, None), Status::Ok);
    }

    #[test]
    fn errors_are_queued_with_the_variable_and_calls_only_when_asked() {
        let (mut i, vr) = instance(Version::Fmi3, false);
        assert_eq!(i.set_reals(&[vr("nu")], &[0.5]), Status::Error);
        assert!(i.check(Call::DoStep, "fmi3DoStep").is_err());
        let logged = i.take_messages();
        assert_eq!(logged.len(), 2);
        assert!(logged
            .iter()
            .all(|(s, c, _)| *s == Status::Error && *c == "logStatusError"));
        assert!(logged[0].2.contains("`nu`"), "{:?}", logged[0]);
        assert!(logged[1]
            .2
            .contains("fmi3DoStep is not allowed in phase Instantiated"));
        // Call logging: off by default, on by category.
        assert_eq!(i.set_debug_logging(true, &["logCalls".into()]), Status::Ok);
        i.check(Call::Set, "fmi3SetFloat64").unwrap();
        assert_eq!(i.take_messages()[0].1, "logCalls");
        assert_eq!(
            i.set_debug_logging(true, &["logStatusError".into()]),
            Status::Ok
        );
        i.check(Call::Set, "fmi3SetFloat64").unwrap();
        assert!(i.take_messages().is_empty(), "logCalls not enabled");
        assert_eq!(
            i.set_debug_logging(true, &["logEverything".into()]),
            Status::Error
        );
    }

    #[test]
    fn runtime_failures_and_configuration_errors_are_named_as_such() {
        let (mut i, vr) = instance(Version::Fmi3, false);
        assert_eq!(
            i.set_strings(&[vr("support")], &["glued".into()]),
            Status::Error
        );
        i.set_reals(&[vr("cells_x"), vr("cut_depth")], &[2.0, 17.0]);
        i.enter_initialization();
        assert_eq!(i.exit_initialization(), Status::Ok);
        i.set_reals(&[vr("pull"), vr("scalpel_x")], &[1.0, 100.0]);
        assert_eq!(i.do_step(0.0, 1.0), Status::Error);
        let logged = texts(&mut i);
        assert!(
            logged[0].starts_with("invalid configuration: unknown support `glued`"),
            "{logged:?}"
        );
        let last = logged.last().unwrap();
        assert!(
            last.starts_with("runtime failure: the cut separates the block"),
            "{last}"
        );
    }

    /// Outputs read in Initialization Mode equal those after the exit; a value set after a
    /// read is taken into account by the next read; the exit builds only when no build is
    /// current.
    #[test]
    fn initialization_mode_builds_on_demand_and_exit_does_not_build_again() {
        for version in [Version::Fmi2, Version::Fmi3] {
            let (mut i, vr) = instance(version, true);
            small(&mut i, &vr);
            // The linear law: twice E and twice the pull give four times the force.
            assert_eq!(
                i.set_strings(&[vr("material")], &["linear".into()]),
                Status::Ok
            );
            i.enter_initialization();
            let mut force = [0.0];
            assert_eq!(i.set_reals(&[vr("pull")], &[0.5]), Status::Ok);
            assert_eq!(i.get_reals(&[vr("reaction_force")], &mut force), Status::Ok);
            assert!(force[0] > 0.0);
            // A fixed parameter and an input set after the read: the next read rebuilds.
            assert_eq!(
                i.set_reals(&[vr("E"), vr("pull")], &[0.077, 1.0]),
                Status::Ok
            );
            let mut again = [0.0];
            assert_eq!(i.get_reals(&[vr("reaction_force")], &mut again), Status::Ok);
            let ratio = again[0] / force[0];
            assert!((ratio - 4.0).abs() < 1e-9, "2 × E, 2 × pull: {ratio}");
            assert_eq!(i.exit_initialization(), Status::Ok);
            let mut after = [0.0];
            assert_eq!(i.get_reals(&[vr("reaction_force")], &mut after), Status::Ok);
            assert_eq!(after[0].to_bits(), again[0].to_bits());
            let builds = texts(&mut i)
                .iter()
                .filter(|m| m.starts_with("building the model"))
                .count();
            assert_eq!(
                builds, 2,
                "{version:?}: two reads with a set between, no third"
            );
        }
    }

    /// The linear law beyond 5 % strain: the step returns Warning once per run, with the
    /// strain in the message; later steps are Ok; a reset starts a new run.
    #[test]
    fn the_linear_law_warns_once_per_run_beyond_its_strain() {
        let (mut i, vr) = instance(Version::Fmi3, false);
        small(&mut i, &vr);
        assert_eq!(
            i.set_strings(&[vr("material")], &["linear".into()]),
            Status::Ok
        );
        i.enter_initialization();
        assert_eq!(i.exit_initialization(), Status::Ok);
        assert_eq!(i.set_reals(&[vr("pull")], &[1.0]), Status::Ok);
        assert_eq!(i.do_step(0.0, 1.0), Status::Ok, "1.25 % strain");
        assert_eq!(i.set_reals(&[vr("pull")], &[12.0]), Status::Ok);
        assert_eq!(i.do_step(1.0, 1.0), Status::Warning);
        let logged = i.take_messages();
        assert_eq!(logged.len(), 1);
        let (status, category, text) = &logged[0];
        assert_eq!((*status, *category), (Status::Warning, "logStatusWarning"));
        assert!(
            text.contains("principal strain is") && text.contains("neo-hookean"),
            "{text}"
        );
        assert_eq!(i.do_step(2.0, 1.0), Status::Ok, "once per run");
        i.reset();
        small(&mut i, &vr);
        i.set_strings(&[vr("material")], &["linear".into()]);
        i.set_reals(&[vr("pull")], &[12.0]);
        i.enter_initialization();
        assert_eq!(
            i.exit_initialization(),
            Status::Warning,
            "a new run warns again"
        );
    }

    #[test]
    fn a_failed_initialization_names_itself_in_later_reads() {
        let (mut i, vr) = instance(Version::Fmi2, false);
        assert_eq!(i.set_reals(&[vr("y_cut")], &[80.0]), Status::Ok);
        i.enter_initialization();
        let mut x = [0.0];
        assert_eq!(i.get_reals(&[vr("reaction_force")], &mut x), Status::Error);
        assert_eq!(i.phase(), Phase::Error);
        i.take_messages();
        assert_eq!(i.get_reals(&[vr("bottom_lift")], &mut x), Status::Error);
        let m = texts(&mut i).pop().unwrap();
        assert!(
            m.contains("`bottom_lift` is not available")
                && m.contains("the initialization failed: invalid configuration: y_cut = 80"),
            "{m}"
        );
    }

    /// A set of several values is all or nothing, in every phase.
    #[test]
    fn a_refused_value_leaves_every_value_of_the_call_unchanged() {
        let (mut i, vr) = instance(Version::Fmi3, false);
        let read = |i: &mut Instance, names: &[&str]| {
            let vrs: Vec<u32> = names.iter().map(|n| vr(n)).collect();
            let mut x = vec![0.0; vrs.len()];
            assert_eq!(i.get_reals(&vrs, &mut x), Status::Ok);
            x
        };
        let names = ["E", "pull", "nu"];
        let before = read(&mut i, &names);
        let vrs: Vec<u32> = names.iter().map(|n| vr(n)).collect();
        assert_eq!(i.set_reals(&vrs, &[0.05, 3.0, 0.7]), Status::Error);
        assert_eq!(read(&mut i, &names), before);
        let strings = [vr("cut_strategy"), vr("support")];
        assert_eq!(
            i.set_strings(&strings, &["delete".into(), "glued".into()]),
            Status::Error
        );
        assert_eq!(i.scene.get_string(vr("cut_strategy")).unwrap(), "duplicate");
        // An output among the values: refused before anything is set.
        assert_eq!(
            i.set_reals(&[vr("E"), vr("reaction_force")], &[0.05, 1.0]),
            Status::Error
        );
        assert_eq!(read(&mut i, &["E"]), [before[0]]);
        // No references: nothing to do, and fine.
        assert_eq!(i.set_reals(&[], &[]), Status::Ok);
        assert_eq!(i.get_reals(&[], &mut []), Status::Ok);
    }
}
