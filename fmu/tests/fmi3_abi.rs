//! The FMI 3.0 functions called as an importer calls them (in process, through the C ABI):
//! what FMI 3 allows that FMI 2 does not (reading variables when instantiated), event mode
//! refused as the description says, zero references accepted for every type, outputs read
//! in Initialization Mode, and a logger that calls back into the FMU.

// Unsafe code: these tests call the FMI 3.0 C ABI.
#![allow(unsafe_code)]

use std::ffi::{c_char, c_void, CStr, CString};
use std::ptr::{null, null_mut};
use std::sync::atomic::{AtomicUsize, Ordering};

use fmu::exports::EXPORTS;
use fmu::fmi3::*;

const OK: fmi3Status = 0;
const ERROR: fmi3Status = 3;

fn vr(name: &str) -> fmi3ValueReference {
    let scene = (EXPORTS[1].create)();
    scene.lookup(name).unwrap()
}

fn instantiate(event_mode: bool, env: *mut c_void, log: fmi3LogMessageCallback) -> fmi3Instance {
    let name = CString::new("t").unwrap();
    let token = CString::new(EXPORTS[1].token()).unwrap();
    unsafe {
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            null(),
            false,
            false,
            event_mode,
            false,
            null(),
            0,
            env,
            log,
            null(),
        )
    }
}

fn get(c: fmi3Instance, name: &str) -> (fmi3Status, f64) {
    let mut x = f64::NAN;
    let s = unsafe { fmi3GetFloat64(c, &vr(name), 1, &mut x, 1) };
    (s, x)
}

fn set(c: fmi3Instance, name: &str, x: f64) -> fmi3Status {
    unsafe { fmi3SetFloat64(c, &vr(name), 1, &x, 1) }
}

static EVENT_MODE_MESSAGES: AtomicUsize = AtomicUsize::new(0);

unsafe extern "C" fn count_event_mode(
    _env: *mut c_void,
    _status: fmi3Status,
    _category: *const c_char,
    message: *const c_char,
) {
    let text = unsafe { CStr::from_ptr(message) }.to_string_lossy();
    if text.contains("eventModeUsed") && text.contains("hasEventMode = false") {
        EVENT_MODE_MESSAGES.fetch_add(1, Ordering::SeqCst);
    }
}

#[test]
fn event_mode_is_refused_with_a_message() {
    let c = instantiate(true, null_mut(), Some(count_event_mode));
    assert!(c.is_null());
    assert_eq!(EVENT_MODE_MESSAGES.load(Ordering::SeqCst), 1);
}

#[test]
fn parameters_read_when_instantiated_outputs_in_initialization_mode() {
    let c = instantiate(false, null_mut(), None);
    assert_eq!(
        get(c, "cells_x"),
        (OK, 6.0),
        "FMI 3: readable when instantiated"
    );
    assert_eq!(get(c, "reaction_force").0, ERROR, "not calculated yet");
    for (n, v) in [
        ("cells_x", 2.0),
        ("cells_y", 4.0),
        ("cells_z", 3.0),
        ("pull", 3.0),
    ] {
        assert_eq!(set(c, n, v), OK);
    }
    unsafe {
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            OK
        );
        let (s, initial) = get(c, "reaction_force");
        assert_eq!(s, OK);
        assert!(initial > 0.0);
        assert_eq!(fmi3ExitInitializationMode(c), OK);
        assert_eq!(get(c, "reaction_force"), (OK, initial));
        fmi3FreeInstance(c);
    }
}

#[test]
fn zero_references_are_fine_for_every_type() {
    let c = instantiate(false, null_mut(), None);
    unsafe {
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            OK
        );
        assert_eq!(fmi3GetInt32(c, null(), 0), OK);
        assert_eq!(fmi3SetBoolean(c, null(), 0), OK);
        assert_eq!(fmi3GetFloat64(c, null(), 0, null_mut(), 0), OK);
        assert_eq!(fmi3SetString(c, null(), 0, null(), 0), OK);
        assert_eq!(fmi3GetInt32(c, &vr("E"), 1), ERROR, "no Int32 variables");
        fmi3FreeInstance(c);
    }
}

/// What the re-entrant logger saw: the value it read back from inside the callback.
static READ_IN_LOGGER: AtomicUsize = AtomicUsize::new(0);

/// A logger that reads a parameter of the same instance while it handles a message.
unsafe extern "C" fn reads_back(
    env: *mut c_void,
    _status: fmi3Status,
    _category: *const c_char,
    _message: *const c_char,
) {
    let c = unsafe { *(env as *const fmi3Instance) };
    let mut x = 0.0;
    let status = unsafe { fmi3GetFloat64(c, &vr("E"), 1, &mut x, 1) };
    if status == OK && x == 0.0385 {
        READ_IN_LOGGER.fetch_add(1, Ordering::SeqCst);
    }
}

/// The instance hands its messages to the logger after it has released itself, so a
/// logger that calls back into the FMU works on an instance of its own (no aliasing).
#[test]
fn a_logger_may_call_back_into_the_instance() {
    let mut handle: fmi3Instance = null_mut();
    let env = &mut handle as *mut fmi3Instance as *mut c_void;
    handle = instantiate(false, env, Some(reads_back));
    assert!(!handle.is_null());
    unsafe {
        assert_eq!(
            fmi3EnterInitializationMode(handle, false, 0.0, 0.0, false, 0.0),
            OK
        );
        assert_eq!(set(handle, "nu", 0.7), ERROR, "logs an error");
        assert_eq!(
            fmi3DoStep(
                handle,
                0.0,
                1.0,
                false,
                null_mut(),
                null_mut(),
                null_mut(),
                null_mut()
            ),
            ERROR
        );
    }
    assert_eq!(READ_IN_LOGGER.load(Ordering::SeqCst), 2);
    unsafe { fmi3FreeInstance(handle) };
}

/// Every capability flag of the FMI 3 description holds: variable communication steps
/// work (and land where they should); FMU state, event mode and intermediate update, which
/// the description declares absent, are refused with an error status.
#[test]
fn capability_flags_are_honoured() {
    let xml = fmu::xml::fmi3(&EXPORTS[1]);
    for flag in [
        "canHandleVariableCommunicationStepSize",
        "canGetAndSetFMUState",
        "canSerializeFMUState",
    ] {
        assert!(xml.contains(&format!(r#"{flag}="true""#)), "{flag}");
    }
    for flag in ["hasEventMode", "providesIntermediateUpdate"] {
        assert!(xml.contains(&format!(r#"{flag}="false""#)), "{flag}");
    }
    let c = instantiate(false, null_mut(), None);
    for (n, v) in [("cells_x", 2.0), ("cells_y", 4.0), ("cells_z", 3.0)] {
        assert_eq!(set(c, n, v), OK);
    }
    unsafe {
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            OK
        );
        assert_eq!(fmi3ExitInitializationMode(c), OK);
        let mut last = 0.0;
        let mut t = 0.0;
        for h in [0.1, 0.35, 1e-3, 2.0] {
            let status = fmi3DoStep(
                c,
                t,
                h,
                false,
                null_mut(),
                null_mut(),
                null_mut(),
                &mut last,
            );
            assert_eq!(status, OK, "h = {h}");
            t += h;
            assert_eq!(last, t);
        }
        let mut state: fmi3FMUState = null_mut();
        assert_eq!(fmi3GetFMUState(c, &mut state), OK);
        let mut size = 0;
        assert_eq!(fmi3SerializedFMUStateSize(c, state, &mut size), OK);
        assert!(size > 0);
        assert_eq!(fmi3FreeFMUState(c, &mut state), OK);
        assert!(state.is_null());
        assert_eq!(fmi3EnterEventMode(c), ERROR);
        assert_eq!(fmi3GetDirectionalDerivative(c), ERROR);
        fmi3FreeInstance(c);
    }
}

/// Terminated: no more steps, outputs still readable; `fmi3Reset` goes back to the state
/// after instantiation with the start values, and the same run then gives the same results
/// bit for bit. A stop time given to `fmi3EnterInitializationMode` is honoured.
#[test]
fn terminated_refuses_steps_and_reset_starts_over() {
    let c = instantiate(false, null_mut(), None);
    let run = |c: fmi3Instance| -> u64 {
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        unsafe {
            for (n, v) in [("cells_x", 2.0), ("cells_y", 4.0), ("cells_z", 3.0)] {
                assert_eq!(set(c, n, v), OK);
            }
            assert_eq!(
                fmi3EnterInitializationMode(c, false, 0.0, 0.0, true, 2.0),
                OK
            );
            assert_eq!(fmi3ExitInitializationMode(c), OK);
            assert_eq!(set(c, "pull", 2.0), OK);
            let step = |t: f64,
                        h: f64,
                        event: &mut bool,
                        terminate: &mut bool,
                        early: &mut bool,
                        last: &mut f64| {
                fmi3DoStep(c, t, h, true, event, terminate, early, last)
            };
            assert_eq!(
                step(0.0, 1.0, &mut event, &mut terminate, &mut early, &mut last),
                OK
            );
            assert_eq!(
                step(1.0, 1.5, &mut event, &mut terminate, &mut early, &mut last),
                ERROR,
                "past the stop time"
            );
            assert_eq!(
                step(1.0, 1.0, &mut event, &mut terminate, &mut early, &mut last),
                OK
            );
            assert_eq!(last, 2.0);
            assert_eq!(fmi3Terminate(c), OK);
            assert_eq!(
                step(2.0, 1.0, &mut event, &mut terminate, &mut early, &mut last),
                ERROR,
                "terminated"
            );
        }
        let (status, force) = get(c, "reaction_force");
        assert_eq!(status, OK, "outputs stay readable when terminated");
        force.to_bits()
    };
    let first = run(c);
    assert_eq!(unsafe { fmi3Reset(c) }, OK);
    assert_eq!(get(c, "cells_x"), (OK, 6.0), "start values after the reset");
    assert_eq!(run(c), first);
    unsafe { fmi3FreeInstance(c) };
}
