//! FMI 3.0 co-simulation ABI: the `fmi3*` C functions. Like [`crate::fmi2`], each converts
//! its arguments and calls the [`Instance`] core inside a panic guard. Arrays (the laser
//! profiles) are arrays: one value reference, `len` values. Model exchange and scheduled
//! execution are not offered: their instantiation returns null, and the functions that only
//! they use report an error.

#![allow(non_snake_case, non_camel_case_types)]

use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::ffi::{guard, slice, slice_mut, text};
use crate::instance::{Addressing, Call, Instance, Log, Status};

pub type fmi3Instance = *mut c_void;
pub type fmi3InstanceEnvironment = *mut c_void;
pub type fmi3ValueReference = c_uint;
pub type fmi3Float64 = f64;
pub type fmi3Boolean = bool;
pub type fmi3String = *const c_char;
pub type fmi3Status = c_int;

pub type fmi3LogMessageCallback =
    Option<unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String)>;

static VERSION: &CStr = c"3.0";

fn logger(callback: fmi3LogMessageCallback, env: fmi3InstanceEnvironment) -> Log {
    let env = env as usize;
    Box::new(move |status, category, message| {
        if let Some(log) = callback {
            let category = CString::new(category).unwrap_or_default();
            let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
            // SAFETY: FMI 3 logMessage contract.
            unsafe {
                log(
                    env as *mut c_void,
                    status as fmi3Status,
                    category.as_ptr(),
                    message.as_ptr(),
                )
            };
        }
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetVersion() -> fmi3String {
    VERSION.as_ptr()
}

/// # Safety
/// FMI 3.0 contract for all pointer arguments.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instanceName: fmi3String,
    instantiationToken: fmi3String,
    resourcePath: fmi3String,
    _visible: fmi3Boolean,
    loggingOn: fmi3Boolean,
    _eventModeUsed: fmi3Boolean,
    _earlyReturnAllowed: fmi3Boolean,
    _requiredIntermediateVariables: *const fmi3ValueReference,
    _nRequiredIntermediateVariables: usize,
    instanceEnvironment: fmi3InstanceEnvironment,
    logMessage: fmi3LogMessageCallback,
    _intermediateUpdate: *const c_void,
) -> fmi3Instance {
    catch_unwind(AssertUnwindSafe(|| {
        let name = unsafe { text(instanceName) }.unwrap_or_else(|| "tissuefmu".into());
        let log = logger(logMessage, instanceEnvironment);
        let token = unsafe { text(instantiationToken) };
        let location = unsafe { text(resourcePath) };
        Instance::into_handle(Instance::create(
            token.as_deref(),
            &name,
            location.as_deref(),
            log,
            loggingOn,
        ))
    }))
    .unwrap_or(std::ptr::null_mut())
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
    if !c.is_null() {
        let _ = catch_unwind(|| drop(unsafe { Box::from_raw(c as *mut Instance) }));
    }
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
    guard(
        c,
        Some((Call::SetDebugLogging, "fmi3SetDebugLogging")),
        |i| {
            let Some(cats) = (unsafe { slice(categories, n) }) else {
                return i.error(Status::Error, "categories is null");
            };
            let cats: Vec<String> = cats
                .iter()
                .map(|&p| unsafe { text(p) }.unwrap_or_default())
                .collect();
            i.set_debug_logging(loggingOn, &cats)
        },
    )
}

/// # Safety
/// FMI 3.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    c: fmi3Instance,
    _toleranceDefined: fmi3Boolean,
    _tolerance: fmi3Float64,
    startTime: fmi3Float64,
    _stopTimeDefined: fmi3Boolean,
    _stopTime: fmi3Float64,
) -> fmi3Status {
    guard(
        c,
        Some((Call::EnterInitialization, "fmi3EnterInitializationMode")),
        |i| match i.setup_experiment(startTime) {
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
    guard(c, Some((Call::Get, "fmi3GetFloat64")), |i| {
        match unsafe { (slice(vr, nvr), slice_mut(values, n)) } {
            (Some(vr), Some(values)) => i.get_reals(Addressing::Arrays, vr, values),
            _ => i.error(Status::Error, "fmi3GetFloat64: null array"),
        }
    })
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
    guard(c, Some((Call::Set, "fmi3SetFloat64")), |i| {
        match unsafe { (slice(vr, nvr), slice(values, n)) } {
            (Some(vr), Some(values)) => i.set_reals(Addressing::Arrays, vr, values),
            _ => i.error(Status::Error, "fmi3SetFloat64: null array"),
        }
    })
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
    guard(c, Some((Call::Get, "fmi3GetString")), |i| {
        let (Some(vr), Some(values)) = (unsafe { slice(vr, nvr) }, unsafe { slice_mut(values, n) })
        else {
            return i.error(Status::Error, "fmi3GetString: null array");
        };
        if vr.len() != values.len() {
            return i.error(
                Status::Error,
                "fmi3GetString: one value per reference expected",
            );
        }
        match i.get_strings(Addressing::Arrays, vr) {
            Ok(strings) => {
                for (v, s) in values.iter_mut().zip(strings) {
                    *v = s.as_ptr();
                }
                Status::Ok
            }
            Err(s) => s,
        }
    })
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
    guard(c, Some((Call::Set, "fmi3SetString")), |i| {
        let (Some(vr), Some(values)) = (unsafe { slice(vr, nvr) }, unsafe { slice(values, n) })
        else {
            return i.error(Status::Error, "fmi3SetString: null array");
        };
        let Some(values) = values
            .iter()
            .map(|&p| unsafe { text(p) })
            .collect::<Option<Vec<_>>>()
        else {
            return i.error(Status::Error, "fmi3SetString: null or non-UTF-8 string");
        };
        if vr.len() != values.len() {
            return i.error(
                Status::Error,
                "fmi3SetString: one value per reference expected",
            );
        }
        i.set_strings(Addressing::Arrays, vr, &values)
    })
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

/// Exports `fmi3<name>` for the functions of capabilities these FMUs do not have (other
/// value types, FMU state, derivatives, clocks, events, model exchange). Each reports an
/// error through the logger. They read only their first argument, the instance: with the
/// C calling convention the remaining arguments are the caller's to clean up.
macro_rules! unsupported {
    ($($name:ident),* $(,)?) => {$(
        /// Not supported by these FMUs (see the model description's capability flags).
        ///
        /// # Safety
        /// FMI 3.0 contract.
        #[unsafe(no_mangle)]
        pub unsafe extern "C" fn $name(c: fmi3Instance) -> fmi3Status {
            guard(c, None, |i| i.error(Status::Error, concat!(stringify!($name), " is not supported by this FMU")))
        }
    )*};
}

unsupported!(
    fmi3EnterEventMode,
    fmi3GetFloat32,
    fmi3GetInt8,
    fmi3GetUInt8,
    fmi3GetInt16,
    fmi3GetUInt16,
    fmi3GetInt32,
    fmi3GetUInt32,
    fmi3GetInt64,
    fmi3GetUInt64,
    fmi3GetBoolean,
    fmi3GetBinary,
    fmi3GetClock,
    fmi3SetFloat32,
    fmi3SetInt8,
    fmi3SetUInt8,
    fmi3SetInt16,
    fmi3SetUInt16,
    fmi3SetInt32,
    fmi3SetUInt32,
    fmi3SetInt64,
    fmi3SetUInt64,
    fmi3SetBoolean,
    fmi3SetBinary,
    fmi3SetClock,
    fmi3GetNumberOfVariableDependencies,
    fmi3GetVariableDependencies,
    fmi3GetFMUState,
    fmi3SetFMUState,
    fmi3FreeFMUState,
    fmi3SerializedFMUStateSize,
    fmi3SerializeFMUState,
    fmi3DeserializeFMUState,
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
