//! FMI 2.0 co-simulation ABI: the `fmi2*` C functions. Each converts its arguments and calls
//! the [`Instance`] core inside a panic guard; no scene logic lives here.

#![allow(non_snake_case, non_camel_case_types)]
// Unsafe code: the FMI 2.0 C ABI.
#![allow(unsafe_code)]

use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};

use crate::exports::Version;
use crate::ffi::{self, guard};
use crate::instance::{Instance, Log};
use crate::machine::{Call, Status};

/// `fmi2Component` (FMI 2.0 §2.1.2): the opaque instance handle; here a boxed [`Instance`].
pub type fmi2Component = *mut c_void;
/// `fmi2ComponentEnvironment` (FMI 2.0 §2.1.2): the importer's opaque pointer, handed
/// back to its callbacks unchanged.
pub type fmi2ComponentEnvironment = *mut c_void;
/// `fmi2FMUstate` (FMI 2.0 §2.1.2, §2.1.8): an opaque saved FMU state; here a boxed
/// [`crate::state::FmuState`].
pub type fmi2FMUstate = *mut c_void;
/// `fmi2ValueReference` (FMI 2.0 §2.1.2): the handle of a variable, here one per scalar
/// (see [`crate::addressing`]).
pub type fmi2ValueReference = c_uint;
/// `fmi2Real` (FMI 2.0 §2.1.2): C `double`.
pub type fmi2Real = f64;
/// `fmi2Integer` (FMI 2.0 §2.1.2): C `int`.
pub type fmi2Integer = c_int;
/// `fmi2Boolean` (FMI 2.0 §2.1.2): C `int`, `fmi2True` = 1, `fmi2False` = 0.
pub type fmi2Boolean = c_int;
/// `fmi2String` (FMI 2.0 §2.1.2): a NUL-terminated C string (`const char*`).
pub type fmi2String = *const c_char;
/// `fmi2Status` (FMI 2.0 §2.1.3): the status a call returns, codes 0–4 as in [`Status`].
pub type fmi2Status = c_int;

/// `fmi2CallbackLogger` (FMI 2.0 §2.1.5): the importer's printf-style logger (environment,
/// instance name, status, category, format, arguments). Messages are passed through a
/// `"%s"` format.
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
    /// The importer's logger; without one, messages are dropped.
    pub logger: fmi2CallbackLogger,
    /// The importer's `calloc`-like allocator (count, size). Not used: the FMU allocates
    /// its own memory (`canNotUseMemoryManagementFunctions="true"`).
    pub allocateMemory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// The importer's deallocator for memory from `allocateMemory`. Not used.
    pub freeMemory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// Called when an asynchronous `fmi2DoStep` finishes. Not used: `fmi2DoStep` finishes
    /// every step before it returns and never returns `fmi2Pending`.
    pub stepFinished: Option<unsafe extern "C" fn(fmi2ComponentEnvironment, fmi2Status)>,
    /// The importer's pointer, passed back unchanged as the first argument of `logger`.
    pub componentEnvironment: fmi2ComponentEnvironment,
}

const FMI2_CO_SIMULATION: c_int = 1;
static TYPES_PLATFORM: &CStr = c"default";
static VERSION: &CStr = c"2.0";

/// The importer's logger callback, with the instance name it wants in every message.
///
/// # Safety
/// `functions` is null or a valid callback struct that outlives the instance.
unsafe fn logger(functions: *const fmi2CallbackFunctions, name: fmi2String) -> Log {
    let (Some(log), env) = (match unsafe { functions.as_ref() } {
        Some(f) => (f.logger, f.componentEnvironment as usize),
        None => (None, 0),
    }) else {
        return ffi::silent();
    };
    let name = CString::new(unsafe { ffi::text(name) }.unwrap_or_default()).unwrap_or_default();
    ffi::logger(move |status, category, message| {
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
        }
    })
}

/// `fmi2GetTypesPlatform` (FMI 2.0 §2.1.4): the `fmi2TypesPlatform` of the header the FMU
/// was compiled with, `"default"` (the standard's types). A static string; callable at
/// any time, without an instance.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> fmi2String {
    TYPES_PLATFORM.as_ptr()
}

/// `fmi2GetVersion` (FMI 2.0 §2.1.4): the version of `fmi2Functions.h` the FMU was
/// compiled with, `"2.0"`. A static string; callable at any time, without an instance.
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
    let refusal = (fmuType != FMI2_CO_SIMULATION)
        .then_some("only co-simulation (fmi2CoSimulation) is supported");
    unsafe {
        ffi::instantiate(
            Version::Fmi2,
            instanceName,
            fmuGUID,
            fmuResourceLocation,
            logger(functions, instanceName),
            loggingOn != 0,
            refusal,
        )
    }
}

/// # Safety
/// `c` is null or a component from `fmi2Instantiate`, not used afterwards.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
    unsafe { ffi::free(c) }
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
    unsafe { ffi::set_debug_logging(c, "fmi2SetDebugLogging", loggingOn != 0, categories, n) }
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: fmi2Component,
    _toleranceDefined: fmi2Boolean,
    _tolerance: fmi2Real,
    startTime: fmi2Real,
    stopTimeDefined: fmi2Boolean,
    stopTime: fmi2Real,
) -> fmi2Status {
    guard(
        c,
        Some((Call::SetupExperiment, "fmi2SetupExperiment")),
        |i| i.setup_experiment(startTime, (stopTimeDefined != 0).then_some(stopTime)),
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
    unsafe { ffi::get_reals(c, "fmi2GetReal", vr, n, value, n) }
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
    unsafe { ffi::set_reals(c, "fmi2SetReal", vr, n, value, n) }
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
    unsafe { ffi::get_strings(c, "fmi2GetString", vr, n, value, n) }
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
    unsafe { ffi::set_strings(c, "fmi2SetString", vr, n, value, n) }
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
    ffi::no_variables(c, "fmi2GetInteger", Call::Get, n)
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
    ffi::no_variables(c, "fmi2SetInteger", Call::Set, n)
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
    ffi::no_variables(c, "fmi2GetBoolean", Call::Get, n)
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
    ffi::no_variables(c, "fmi2SetBoolean", Call::Set, n)
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

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
    // Steps finish before fmi2DoStep returns: there is never a step to cancel.
    guard(c, None, |i| {
        i.error(
            Status::Error,
            "fmi2CancelStep: can be called when fmi2DoStep returned fmi2Pending, which it \
             never does (steps finish before it returns)",
        )
    })
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: fmi2Component, s: *mut fmi2FMUstate) -> fmi2Status {
    unsafe { ffi::get_state(c, "fmi2GetFMUstate", s) }
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: fmi2Component, s: fmi2FMUstate) -> fmi2Status {
    unsafe { ffi::set_state(c, "fmi2SetFMUstate", s) }
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: fmi2Component, s: *mut fmi2FMUstate) -> fmi2Status {
    unsafe { ffi::free_state(c, "fmi2FreeFMUstate", s) }
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: fmi2Component,
    s: fmi2FMUstate,
    n: *mut usize,
) -> fmi2Status {
    unsafe { ffi::state_size(c, "fmi2SerializedFMUstateSize", s, n) }
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: fmi2Component,
    s: fmi2FMUstate,
    b: *mut c_char,
    n: usize,
) -> fmi2Status {
    unsafe { ffi::serialize_state(c, "fmi2SerializeFMUstate", s, b.cast(), n) }
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: fmi2Component,
    b: *const c_char,
    n: usize,
    s: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe { ffi::deserialize_state(c, "fmi2DeSerializeFMUstate", b.cast(), n, s) }
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
    ffi::unsupported(c, "fmi2GetDirectionalDerivative")
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
    ffi::unsupported(c, "fmi2SetRealInputDerivatives")
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
    ffi::unsupported(c, "fmi2GetRealOutputDerivatives")
}

/// # Safety
/// FMI 2.0 contract.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: fmi2Component,
    _kind: c_int,
    _value: *mut fmi2Status,
) -> fmi2Status {
    // fmi2DoStepStatus and fmi2PendingStatus are defined after fmi2DoStep returned
    // fmi2Pending, which it never does: the status is not available (fmi2Discard).
    guard(c, None, |i| {
        i.error(
            Status::Discard,
            "fmi2GetStatus: no step is pending (fmi2DoStep finishes every step before it \
             returns)",
        )
    })
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
    ffi::unsupported(c, "fmi2GetIntegerStatus")
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
    ffi::unsupported(c, "fmi2GetStringStatus")
}
