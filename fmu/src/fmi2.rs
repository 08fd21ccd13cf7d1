//! FMI 2.0 co-simulation ABI: the `fmi2*` C functions. Each converts its arguments and calls
//! the [`Instance`] core inside a panic guard; no scene logic lives here.

#![allow(non_snake_case, non_camel_case_types)]

use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};

use crate::ffi::{guard, slice, slice_mut, text};
use crate::instance::{Addressing, Call, Instance, Log, Status};

pub type fmi2Component = *mut c_void;
pub type fmi2ComponentEnvironment = *mut c_void;
pub type fmi2FMUstate = *mut c_void;
pub type fmi2ValueReference = c_uint;
pub type fmi2Real = f64;
pub type fmi2Integer = c_int;
pub type fmi2Boolean = c_int;
pub type fmi2String = *const c_char;
pub type fmi2Status = c_int;

pub type fmi2CallbackLogger = Option<
    unsafe extern "C" fn(
        fmi2ComponentEnvironment,
        fmi2String,
        fmi2Status,
        fmi2String,
        fmi2String,
        ...
    ),
>;

/// fmi2CallbackFunctions (FMI 2.0 §2.1.5).
#[repr(C)]
pub struct fmi2CallbackFunctions {
    pub logger: fmi2CallbackLogger,
    pub allocateMemory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    pub freeMemory: Option<unsafe extern "C" fn(*mut c_void)>,
    pub stepFinished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    pub componentEnvironment: fmi2ComponentEnvironment,
}

const FMI2_CO_SIMULATION: c_int = 1;
static TYPES_PLATFORM: &CStr = c"default";
static VERSION: &CStr = c"2.0";

/// A logger closure over the importer's callback.
fn logger(functions: *const fmi2CallbackFunctions, name: &str) -> Log {
    // SAFETY: the importer passes a valid callback struct that outlives the instance.
    let (callback, env) = match unsafe { functions.as_ref() } {
        Some(f) => (f.logger, f.componentEnvironment as usize),
        None => (None, 0),
    };
    let name = CString::new(name).unwrap_or_default();
    Box::new(move |status, category, message| {
        if let Some(log) = callback {
            let category = CString::new(category).unwrap_or_default();
            let message = CString::new(message.replace('\0', " ")).unwrap_or_default();
            // SAFETY: FMI 2 logger contract; the message is passed through a "%s" format.
            unsafe {
                log(
                    env as *mut c_void,
                    name.as_ptr(),
                    status as fmi2Status,
                    category.as_ptr(),
                    c"%s".as_ptr(),
                    message.as_ptr(),
                )
            };
        }
    })
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> fmi2String {
    TYPES_PLATFORM.as_ptr()
}

#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> fmi2String {
    VERSION.as_ptr()
}

/// # Safety
/// FMI 2.0 contract for all pointer arguments.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instanceName: fmi2String,
    fmuType: c_int,
    fmuGUID: fmi2String,
    fmuResourceLocation: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    loggingOn: fmi2Boolean,
) -> fmi2Component {
    let result = catch_unwind(AssertUnwindSafe(|| {
        let name = unsafe { text(instanceName) }.unwrap_or_else(|| "tissuefmu".into());
        let log = logger(functions, &name);
        if fmuType != FMI2_CO_SIMULATION {
            log(
                Status::Error,
                "logStatusError",
                "only co-simulation (fmi2CoSimulation) is supported",
            );
            return std::ptr::null_mut();
        }
        let guid = unsafe { text(fmuGUID) };
        let location = unsafe { text(fmuResourceLocation) };
        Instance::into_handle(Instance::create(
            guid.as_deref(),
            &name,
            location.as_deref(),
            log,
            loggingOn != 0,
        ))
    }));
    result.unwrap_or(std::ptr::null_mut())
}

/// # Safety
/// `c` is null or a component from `fmi2Instantiate`, not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    if !c.is_null() {
        let _ = catch_unwind(|| drop(unsafe { Box::from_raw(c as *mut Instance) }));
    }
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: fmi2Component,
    loggingOn: fmi2Boolean,
    n: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    guard(
        c,
        Some((Call::SetDebugLogging, "fmi2SetDebugLogging")),
        |i| {
            let Some(cats) = (unsafe { slice(categories, n) }) else {
                return i.error(Status::Error, "categories is null");
            };
            let cats: Vec<String> = cats
                .iter()
                .map(|&p| unsafe { text(p) }.unwrap_or_default())
                .collect();
            i.set_debug_logging(loggingOn != 0, &cats)
        },
    )
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    _stopTimeDefined: fmi2Boolean,
    _stopTime: fmi2Real,
) -> fmi2Status {
    guard(
        c,
        Some((Call::SetupExperiment, "fmi2SetupExperiment")),
        |i| i.setup_experiment(startTime),
    )
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
    guard(
        c,
        Some((Call::EnterInitialization, "fmi2EnterInitializationMode")),
        Instance::enter_initialization,
    )
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
    guard(
        c,
        Some((Call::ExitInitialization, "fmi2ExitInitializationMode")),
        Instance::exit_initialization,
    )
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
    guard(
        c,
        Some((Call::Terminate, "fmi2Terminate")),
        Instance::terminate,
    )
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
    guard(c, Some((Call::Reset, "fmi2Reset")), Instance::reset)
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    guard(c, Some((Call::Get, "fmi2GetReal")), |i| {
        match unsafe { (slice(vr, n), slice_mut(value, n)) } {
            (Some(vr), Some(value)) => i.get_reals(Addressing::Scalars, vr, value),
            _ => i.error(Status::Error, "fmi2GetReal: null array"),
        }
    })
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    guard(c, Some((Call::Set, "fmi2SetReal")), |i| {
        match unsafe { (slice(vr, n), slice(value, n)) } {
            (Some(vr), Some(value)) => i.set_reals(Addressing::Scalars, vr, value),
            _ => i.error(Status::Error, "fmi2SetReal: null array"),
        }
    })
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *mut fmi2String,
) -> fmi2Status {
    guard(c, Some((Call::Get, "fmi2GetString")), |i| {
        let (Some(vr), Some(value)) = (unsafe { slice(vr, n) }, unsafe { slice_mut(value, n) })
        else {
            return i.error(Status::Error, "fmi2GetString: null array");
        };
        match i.get_strings(Addressing::Scalars, vr) {
            Ok(strings) => {
                for (v, s) in value.iter_mut().zip(strings) {
                    *v = s.as_ptr();
                }
                Status::Ok
            }
            Err(s) => s,
        }
    })
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    n: usize,
    value: *const fmi2String,
) -> fmi2Status {
    guard(c, Some((Call::Set, "fmi2SetString")), |i| {
        let (Some(vr), Some(value)) = (unsafe { slice(vr, n) }, unsafe { slice(value, n) }) else {
            return i.error(Status::Error, "fmi2SetString: null array");
        };
        let Some(values) = value
            .iter()
            .map(|&p| unsafe { text(p) })
            .collect::<Option<Vec<_>>>()
        else {
            return i.error(Status::Error, "fmi2SetString: null or non-UTF-8 string");
        };
        i.set_strings(Addressing::Scalars, vr, &values)
    })
}

/// Integer and Boolean variables do not exist in these models: zero references is fine,
/// any reference is unknown.
fn no_variables(c: fmi2Component, n: usize, function: &str, call: Call) -> fmi2Status {
    guard(c, Some((call, function)), |i| {
        if n == 0 {
            Status::Ok
        } else {
            i.error(
                Status::Error,
                &format!("{function}: the model has no variables of this type"),
            )
        }
    })
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    n: usize,
    _v: *mut fmi2Integer,
) -> fmi2Status {
    no_variables(c, n, "fmi2GetInteger", Call::Get)
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    n: usize,
    _v: *const fmi2Integer,
) -> fmi2Status {
    no_variables(c, n, "fmi2SetInteger", Call::Set)
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    n: usize,
    _v: *mut fmi2Boolean,
) -> fmi2Status {
    no_variables(c, n, "fmi2GetBoolean", Call::Get)
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    n: usize,
    _v: *const fmi2Boolean,
) -> fmi2Status {
    no_variables(c, n, "fmi2SetBoolean", Call::Set)
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: fmi2Component,
    currentCommunicationPoint: fmi2Real,
    communicationStepSize: fmi2Real,
    _noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
) -> fmi2Status {
    guard(c, Some((Call::DoStep, "fmi2DoStep")), |i| {
        i.do_step(currentCommunicationPoint, communicationStepSize)
    })
}

/// Functions for capabilities the model description declares absent.
fn unsupported(c: fmi2Component, function: &str) -> fmi2Status {
    guard(c, None, |i| {
        i.error(
            Status::Error,
            &format!("{function} is not supported (see the model description's capability flags)"),
        )
    })
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    unsupported(c, "fmi2CancelStep")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, _s: *mut fmi2FMUstate) -> fmi2Status {
    unsupported(c, "fmi2GetFMUstate")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, _s: fmi2FMUstate) -> fmi2Status {
    unsupported(c, "fmi2SetFMUstate")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: fmi2Component, _s: *mut fmi2FMUstate) -> fmi2Status {
    unsupported(c, "fmi2FreeFMUstate")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    _s: fmi2FMUstate,
    _n: *mut usize,
) -> fmi2Status {
    unsupported(c, "fmi2SerializedFMUstateSize")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    _s: fmi2FMUstate,
    _b: *mut c_char,
    _n: usize,
) -> fmi2Status {
    unsupported(c, "fmi2SerializeFMUstate")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    _b: *const c_char,
    _n: usize,
    _s: *mut fmi2FMUstate,
) -> fmi2Status {
    unsupported(c, "fmi2DeSerializeFMUstate")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: fmi2Component,
    _u: *const fmi2ValueReference,
    _nu: usize,
    _z: *const fmi2ValueReference,
    _nz: usize,
    _dv: *const fmi2Real,
    _dz: *mut fmi2Real,
) -> fmi2Status {
    unsupported(c, "fmi2GetDirectionalDerivative")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _n: usize,
    _order: *const fmi2Integer,
    _v: *const fmi2Real,
) -> fmi2Status {
    unsupported(c, "fmi2SetRealInputDerivatives")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: fmi2Component,
    _vr: *const fmi2ValueReference,
    _n: usize,
    _order: *const fmi2Integer,
    _v: *mut fmi2Real,
) -> fmi2Status {
    unsupported(c, "fmi2GetRealOutputDerivatives")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    _kind: c_int,
    _value: *mut fmi2Status,
) -> fmi2Status {
    unsupported(c, "fmi2GetStatus")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: fmi2Component,
    kind: c_int,
    value: *mut fmi2Real,
) -> fmi2Status {
    // fmi2LastSuccessfulTime = 2.
    guard(c, None, |i| match (kind, unsafe { value.as_mut() }) {
        (2, Some(v)) => {
            *v = i.time();
            Status::Ok
        }
        _ => i.error(
            Status::Discard,
            "fmi2GetRealStatus: only fmi2LastSuccessfulTime is available",
        ),
    })
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: fmi2Component,
    _kind: c_int,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    unsupported(c, "fmi2GetIntegerStatus")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: fmi2Component,
    kind: c_int,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    // fmi2Terminated = 3: the slave never asks to terminate.
    guard(c, None, |i| match (kind, unsafe { value.as_mut() }) {
        (3, Some(v)) => {
            *v = 0;
            Status::Ok
        }
        _ => i.error(
            Status::Discard,
            "fmi2GetBooleanStatus: only fmi2Terminated is available",
        ),
    })
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: fmi2Component,
    _kind: c_int,
    _value: *mut fmi2String,
) -> fmi2Status {
    unsupported(c, "fmi2GetStringStatus")
}
