//! The FMI state machine, apart from the instance that runs it: the status a call returns,
//! the phases of an instance's life cycle, the calls the machine distinguishes and in which
//! phases the standard allows each (FMI 2.0 §4.2.4; FMI 3.0 §4.2 co-simulation without
//! event mode), and which step times and sizes it allows. The instance checks every call
//! here; its saved states record the phase.

use models::error::seconds;

use crate::exports::Version;

/// Call status, shared by FMI 2 and FMI 3 (same codes 0–4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// `fmi2OK` / `fmi3OK` (FMI 2.0 §2.1.3): the call succeeded.
    Ok = 0,
    /// `fmi2Warning` / `fmi3Warning` (FMI 2.0 §2.1.3): the call succeeded, with a
    /// non-critical problem; here, the scene's warnings (category
    /// `logStatusWarning`).
    Warning = 1,
    /// `fmi2Discard` / `fmi3Discard` (FMI 2.0 §2.1.3): the call did not succeed and changed
    /// nothing, but the simulation can go on; here, from the FMI 2 status queries for a
    /// status they do not offer.
    Discard = 2,
    /// `fmi2Error` / `fmi3Error` (FMI 2.0 §2.1.3): the call failed; here, for a call the
    /// phase does not allow, a bad argument, a scene failure or a caught panic.
    Error = 3,
    /// `fmi2Fatal` / `fmi3Fatal` (FMI 2.0 §2.1.3): the model computations of all instances
    /// are corrupted. Never returned here: a caught panic is an Error.
    Fatal = 4,
}

/// Where the instance is in its life cycle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum Phase {
    /// After instantiation or reset (FMI 2.0 §4.2.4 *instantiated*, FMI 3.0
    /// *Instantiated*): values and the experiment can be set, and with FMI 3
    /// values read.
    Instantiated,
    /// Initialization Mode (FMI 2.0 §4.2.4 *Initialization Mode*), from
    /// `EnterInitializationMode` to `ExitInitializationMode`: inputs and parameters can be
    /// set and outputs read.
    Initialization,
    /// Stepping after initialization (FMI 2.0 §4.2.4 *slaveInitialized*, always
    /// *stepComplete* as steps finish before they return; FMI 3.0 *Step Mode*).
    Step,
    /// After `Terminate` (FMI 2.0 §4.2.4 *terminated*, FMI 3.0 *Terminated*): values can
    /// still be read, and the instance reset or freed.
    Terminated,
    /// A step or the initialization failed: reads, terminate, reset, free, debug logging and
    /// the FMU-state calls remain allowed ([`Call::allowed`]).
    Error,
}

/// The calls the state machine distinguishes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Call {
    /// Setting up the experiment (start and stop time): `fmi2SetupExperiment`. FMI 3 does
    /// this in `fmi3EnterInitializationMode`.
    SetupExperiment,
    /// Entering Initialization Mode: `fmi2EnterInitializationMode`,
    /// `fmi3EnterInitializationMode`.
    EnterInitialization,
    /// Leaving Initialization Mode: `fmi2ExitInitializationMode`,
    /// `fmi3ExitInitializationMode`.
    ExitInitialization,
    /// Setting variable values (`fmi2SetReal` …, `fmi3SetFloat64` …), of every value type.
    Set,
    /// Getting variable values (`fmi2GetReal` …, `fmi3GetFloat64` …), of every value type.
    Get,
    /// Stepping: `fmi2DoStep`, `fmi3DoStep`; also `fmi3EnterStepMode`, allowed in the same
    /// phase.
    DoStep,
    /// Ending the simulation: `fmi2Terminate`, `fmi3Terminate`.
    Terminate,
    /// Going back to the state after instantiation: `fmi2Reset`, `fmi3Reset`.
    Reset,
    /// Setting the log categories: `fmi2SetDebugLogging`, `fmi3SetDebugLogging`.
    SetDebugLogging,
    /// Getting, setting, freeing, serializing and deserializing FMU states.
    State,
}

impl Call {
    /// Phases in which the call is allowed (FMI 2.0 §4.2.4 state machine; FMI 3.0 §4.2
    /// co-simulation without event mode, where variables can also be read when
    /// instantiated).
    pub fn allowed(self, phase: Phase, version: Version) -> bool {
        use Phase::*;
        match self {
            Call::SetupExperiment | Call::EnterInitialization => phase == Instantiated,
            Call::ExitInitialization => phase == Initialization,
            Call::Set => matches!(phase, Instantiated | Initialization | Step),
            Call::Get => {
                matches!(phase, Initialization | Step | Terminated | Error)
                    || (phase == Instantiated && version == Version::Fmi3)
            }
            Call::DoStep => phase == Step,
            Call::Terminate => matches!(phase, Step | Error),
            Call::Reset | Call::SetDebugLogging | Call::State => true,
        }
    }
}

/// Why a step from `current` by `h` is refused, if it is, for an instance at `time` with the
/// importer's `stop` time: a time or size that is not finite (and positive), a time other
/// than the instance's (`fmi2DoStep` / `fmi3DoStep` must start at it), a step past the
/// stop time.
pub fn refused_step(time: f64, stop: Option<f64>, current: f64, h: f64) -> Option<String> {
    let tolerance = 1e-9 * current.abs().max(h).max(1.0);
    if !current.is_finite() {
        Some(format!(
            "currentCommunicationPoint = {current} s is not finite"
        ))
    } else if !(h.is_finite() && h > 0.0) {
        Some(format!(
            "communicationStepSize = {h} s must be finite and > 0"
        ))
    } else if (current - time).abs() > tolerance {
        Some(format!(
            "currentCommunicationPoint {} s does not match the instance time {} s",
            seconds(current),
            seconds(time)
        ))
    } else {
        let stop = stop.filter(|&s| current + h > s + tolerance)?;
        Some(format!(
            "a step from t = {} s by {} s would pass the stop time {} s the importer set",
            seconds(current),
            seconds(h),
            seconds(stop)
        ))
    }
}
