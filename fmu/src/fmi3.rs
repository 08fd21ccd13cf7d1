//! FMI 3.0 co-simulation ABI: the `fmi3*` C functions. Like [`crate::fmi2`], each converts
//! its arguments and calls the [`Instance`] core inside a panic guard. Arrays (the laser
//! profiles) are arrays: one value reference, `len` values. Model exchange and scheduled
//! execution are not offered: their instantiation returns null, and the functions that only
//! they use report an error.

#![allow(non_snake_case, non_camel_case_types)]
// Unsafe code: the FMI 3.0 C ABI.
#![allow(unsafe_code)]

use std::ffi::{c_char, c_int, c_uint, c_void, CStr};

use crate::exports::Version;
use crate::ffi::{self, guard};
use crate::instance::{Instance, Log};
use crate::machine::{Call, Status};

/// `fmi3Instance` (FMI 3.0 §2.2.3): the opaque instance handle; here a boxed [`Instance`].
pub type fmi3Instance = *mut c_void;
/// `fmi3InstanceEnvironment` (FMI 3.0 §2.2.3): the importer's opaque pointer, handed
/// back to its `logMessage` callback unchanged.
pub type fmi3InstanceEnvironment = *mut c_void;
/// `fmi3ValueReference` (FMI 3.0 §2.2.3): the handle of a variable, here one per
/// variable (arrays whole) plus `time` (see [`crate::addressing`]).
pub type fmi3ValueReference = c_uint;
/// `fmi3Float64` (FMI 3.0 §2.2.3): C `double`.
pub type fmi3Float64 = f64;
/// `fmi3Boolean` (FMI 3.0 §2.2.3): C `bool`.
pub type fmi3Boolean = bool;
/// `fmi3FMUState` (FMI 3.0 §2.2.3): an opaque saved FMU state; here a boxed
/// [`crate::state::FmuState`].
pub type fmi3FMUState = *mut c_void;
/// `fmi3String` (FMI 3.0 §2.2.3): a NUL-terminated C string (`const char*`).
pub type fmi3String = *const c_char;
/// `fmi3Status` (FMI 3.0 §2.2.4): the status a call returns, codes 0–4 as in [`Status`].
pub type fmi3Status = c_int;

/// `fmi3LogMessageCallback` (FMI 3.0 §2.3.1): the importer's `logMessage` callback
/// (environment, status, category, message); without one, messages are dropped.
pub type fmi3LogMessageCallback =
    Option<unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String)>;

static VERSION: &CStr = c"3.0";

/// The importer's logMessage callback.
fn logger(callback: fmi3LogMessageCallback, env: fmi3InstanceEnvironment) -> Log {
    let Some(log) = callback else {
        return ffi::silent();
    };
    let env = env as usize;
    ffi::logger(move |status, category, message| {
        // SAFETY: FMI 3 logMessage contract.
        unsafe {
            log(
                env as *mut c_void,
                status as fmi3Status,
                category.as_ptr(),
                message.as_ptr(),
            )
        }
    })
}

/// `fmi3GetVersion` (FMI 3.0 §2.2.5): the version of `fmi3Functions.h` the FMU was
/// compiled with, `"3.0"`. A static string; callable at any time, without an instance.
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetVersion() -> fmi3String {
    VERSION.as_ptr()
}

/// Event mode is refused: the model description says `hasEventMode="false"`.
///
/// # Safety
/// FMI 3.0 contract for all pointer arguments.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    _nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _intermediateUpdate: *const c_void,
) -> fmi3Instance {
    let refusal = eventModeUsed.then_some(
        "eventModeUsed = true: this FMU has no event mode (hasEventMode = false); instantiate \
         with eventModeUsed = false",
    );
    unsafe {
        ffi::instantiate(
            Version::Fmi3,
            instanceName,
            instantiationToken,
            resourcePath,
            logger(logMessage, instanceEnvironment),
            loggingOn,
            refusal,
        )
    }
}

/// Model exchange is not offered.
#[unsafe(no_mangle)]
pub extern "C" fn fmi3InstantiateModelExchange() -> fmi3Instance {
    std::ptr::null_mut()
}

/// Scheduled execution is not offered.
#[unsafe(no_mangle)]
pub extern "C" fn fmi3InstantiateScheduledExecution() -> fmi3Instance {
    std::ptr::null_mut()
}

/// # Safety
/// `c` is null or an instance from fmi3InstantiateCoSimulation, not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeInstance(c: fmi3Instance) {
    unsafe { ffi::free(c) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    c: fmi3Instance,
    loggingOn: fmi3Boolean,
    n: usize,
    categories: *const fmi3String,
) -> fmi3Status {
    unsafe { ffi::set_debug_logging(c, "fmi3SetDebugLogging", loggingOn, categories, n) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    c: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    stopTimeDefined: fmi3Boolean,
    stopTime: fmi3Float64,
) -> fmi3Status {
    guard(
        c,
        Some((Call::EnterInitialization, "fmi3EnterInitializationMode")),
        |i| match i.setup_experiment(startTime, stopTimeDefined.then_some(stopTime)) {
            Status::Ok => i.enter_initialization(),
            s => s,
        },
    )
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3ExitInitializationMode(c: fmi3Instance) -> fmi3Status {
    guard(
        c,
        Some((Call::ExitInitialization, "fmi3ExitInitializationMode")),
        Instance::exit_initialization,
    )
}

/// Without event mode, co-simulation is in step mode after initialization.
///
/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterStepMode(c: fmi3Instance) -> fmi3Status {
    guard(c, Some((Call::DoStep, "fmi3EnterStepMode")), |_| Status::Ok)
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Terminate(c: fmi3Instance) -> fmi3Status {
    guard(
        c,
        Some((Call::Terminate, "fmi3Terminate")),
        Instance::terminate,
    )
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Reset(c: fmi3Instance) -> fmi3Status {
    guard(c, Some((Call::Reset, "fmi3Reset")), Instance::reset)
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFloat64(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3Float64,
    n: usize,
) -> fmi3Status {
    unsafe { ffi::get_reals(c, "fmi3GetFloat64", vr, nvr, values, n) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFloat64(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3Float64,
    n: usize,
) -> fmi3Status {
    unsafe { ffi::set_reals(c, "fmi3SetFloat64", vr, nvr, values, n) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetString(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *mut fmi3String,
    n: usize,
) -> fmi3Status {
    unsafe { ffi::get_strings(c, "fmi3GetString", vr, nvr, values, n) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetString(
    c: fmi3Instance,
    vr: *const fmi3ValueReference,
    nvr: usize,
    values: *const fmi3String,
    n: usize,
) -> fmi3Status {
    unsafe { ffi::set_strings(c, "fmi3SetString", vr, nvr, values, n) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DoStep(
    c: fmi3Instance,
    currentCommunicationPoint: fmi3Float64,
    communicationStepSize: fmi3Float64,
    _noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
    eventHandlingNeeded: *mut fmi3Boolean,
    terminateSimulation: *mut fmi3Boolean,
    earlyReturn: *mut fmi3Boolean,
    lastSuccessfulTime: *mut fmi3Float64,
) -> fmi3Status {
    guard(c, Some((Call::DoStep, "fmi3DoStep")), |i| {
        let status = i.do_step(currentCommunicationPoint, communicationStepSize);
        // SAFETY: the importer passes valid out-pointers (null ones are skipped).
        unsafe {
            for flag in [eventHandlingNeeded, terminateSimulation, earlyReturn] {
                if let Some(f) = flag.as_mut() {
                    *f = false;
                }
            }
            if let Some(t) = lastSuccessfulTime.as_mut() {
                *t = i.time();
            }
        }
        status
    })
}

/// Exports `fmi3Get<Type>` / `fmi3Set<Type>` for the value types these FMUs do not have:
/// no references is fine, any reference is unknown (as in FMI 2). They read their first
/// three arguments, (instance, valueReferences, nValueReferences), which every get and set
/// function of FMI 3 starts with; with the C calling convention the caller cleans up the
/// rest.
macro_rules! no_variables {
    ($($name:ident: $call:ident),* $(,)?) => {$(
        /// A value type these FMUs do not have.
        ///
        /// # Safety
        /// FMI 3.0 contract.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(
            c: fmi3Instance,
            _vr: *const fmi3ValueReference,
            nvr: usize,
        ) -> fmi3Status {
            ffi::no_variables(c, stringify!($name), Call::$call, nvr)
        }
    )*};
}

no_variables!(
    fmi3GetFloat32: Get,
    fmi3GetInt8: Get,
    fmi3GetUInt8: Get,
    fmi3GetInt16: Get,
    fmi3GetUInt16: Get,
    fmi3GetInt32: Get,
    fmi3GetUInt32: Get,
    fmi3GetInt64: Get,
    fmi3GetUInt64: Get,
    fmi3GetBoolean: Get,
    fmi3GetBinary: Get,
    fmi3SetFloat32: Set,
    fmi3SetInt8: Set,
    fmi3SetUInt8: Set,
    fmi3SetInt16: Set,
    fmi3SetUInt16: Set,
    fmi3SetInt32: Set,
    fmi3SetUInt32: Set,
    fmi3SetInt64: Set,
    fmi3SetUInt64: Set,
    fmi3SetBoolean: Set,
    fmi3SetBinary: Set,
);

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFMUState(c: fmi3Instance, s: *mut fmi3FMUState) -> fmi3Status {
    unsafe { ffi::get_state(c, "fmi3GetFMUState", s) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFMUState(c: fmi3Instance, s: fmi3FMUState) -> fmi3Status {
    unsafe { ffi::set_state(c, "fmi3SetFMUState", s) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeFMUState(c: fmi3Instance, s: *mut fmi3FMUState) -> fmi3Status {
    unsafe { ffi::free_state(c, "fmi3FreeFMUState", s) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    c: fmi3Instance,
    s: fmi3FMUState,
    n: *mut usize,
) -> fmi3Status {
    unsafe { ffi::state_size(c, "fmi3SerializedFMUStateSize", s, n) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    c: fmi3Instance,
    s: fmi3FMUState,
    b: *mut u8,
    n: usize,
) -> fmi3Status {
    unsafe { ffi::serialize_state(c, "fmi3SerializeFMUState", s, b, n) }
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    c: fmi3Instance,
    b: *const u8,
    n: usize,
    s: *mut fmi3FMUState,
) -> fmi3Status {
    unsafe { ffi::deserialize_state(c, "fmi3DeserializeFMUState", b, n, s) }
}

/// Exports `fmi3<name>` for the functions of capabilities these FMUs do not have (clocks,
/// derivatives, events, model exchange). Each reports an error through the
/// logger. They read only their first argument, the instance: with the C calling
/// convention the remaining arguments are the caller's to clean up.
macro_rules! unsupported {
    ($($name:ident),* $(,)?) => {$(
        /// Not supported by these FMUs (see the model description's capability flags).
        ///
        /// # Safety
        /// FMI 3.0 contract.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(c: fmi3Instance) -> fmi3Status {
            ffi::unsupported(c, stringify!($name))
        }
    )*};
}

unsupported!(
    fmi3EnterEventMode,
    fmi3GetClock,
    fmi3SetClock,
    fmi3GetNumberOfVariableDependencies,
    fmi3GetVariableDependencies,
    fmi3GetDirectionalDerivative,
    fmi3GetAdjointDerivative,
    fmi3EnterConfigurationMode,
    fmi3ExitConfigurationMode,
    fmi3GetIntervalDecimal,
    fmi3GetIntervalFraction,
    fmi3GetShiftDecimal,
    fmi3GetShiftFraction,
    fmi3SetIntervalDecimal,
    fmi3SetIntervalFraction,
    fmi3SetShiftDecimal,
    fmi3SetShiftFraction,
    fmi3EvaluateDiscreteStates,
    fmi3UpdateDiscreteStates,
    fmi3EnterContinuousTimeMode,
    fmi3CompletedIntegratorStep,
    fmi3SetTime,
    fmi3SetContinuousStates,
    fmi3GetContinuousStateDerivatives,
    fmi3GetEventIndicators,
    fmi3GetContinuousStates,
    fmi3GetNominalsOfContinuousStates,
    fmi3GetNumberOfEventIndicators,
    fmi3GetNumberOfContinuousStates,
    fmi3GetOutputDerivatives,
    fmi3ActivateModelPartition,
);
