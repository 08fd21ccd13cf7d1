//! One FMI version's calls behind one trait ([`Abi`]), so that a test of the C ABI runs
//! in FMI 2 and FMI 3 alike, and the runs of both models the tests share.

use std::ffi::{c_char, CStr, CString};
use std::ptr::{null, null_mut};
use std::sync::Mutex;

use fmu::addressing::fmi2_scalars;
use fmu::exports::{Export, EXPORTS};
use fmu::fmi2::*;
use fmu::fmi3::*;

/// The OK status, the same number in both versions.
pub const OK: i32 = 0;
/// The Error status, the same number in both versions.
pub const ERROR: i32 = 3;

/// A run of one model: parameters, then inputs before each step, outputs after it.
pub struct Run {
    pub model: &'static Export,
    pub parameters: &'static [(&'static str, f64)],
    pub inputs: fn(usize) -> Vec<(&'static str, f64)>,
    pub outputs: &'static [&'static str],
    pub h: f64,
}

pub const CUTBLOCK: Run = Run {
    model: &EXPORTS[1],
    parameters: &[("cells_x", 6.0), ("cells_y", 4.0), ("cells_z", 3.0)],
    inputs: |k| vec![("scalpel_x", 17.0 * k as f64), ("pull", 0.9 * k as f64)],
    outputs: &["reaction_force", "cut_opening", "bottom_lift"],
    h: 1.0,
};

pub const ABDOMEN: Run = Run {
    model: &EXPORTS[0],
    parameters: &[("target_triangles", 300.0)],
    inputs: |k| vec![("press_force", 0.02 * k as f64)],
    outputs: &["floor_stress_mean", "apex_uy"],
    h: 0.01,
};

/// The messages an FMI 3 instance logged with Error status (the FMI 2 logger is variadic,
/// which Rust cannot define; the refusals are the same code in both versions).
pub static ERRORS: Mutex<Vec<String>> = Mutex::new(Vec::new());

unsafe extern "C" fn log3(
    _env: *mut std::ffi::c_void,
    status: fmi3Status,
    _category: *const c_char,
    message: *const c_char,
) {
    if status == ERROR {
        let text = unsafe { CStr::from_ptr(message) }
            .to_string_lossy()
            .into_owned();
        ERRORS.lock().unwrap().push(text);
    }
}

/// One FMI version's calls, so the same tests run both.
#[allow(dead_code, reason = "each test binary calls the part it needs")]
pub trait Abi {
    fn instantiate(run: &Run) -> *mut std::ffi::c_void;
    /// Enters and leaves Initialization Mode at start time 0 (FMI 2: after setting up the
    /// experiment): the statuses of the calls.
    fn initialization(c: *mut std::ffi::c_void) -> Vec<i32>;
    /// Sets the run's parameters and initializes; every call returns OK.
    fn initialize(c: *mut std::ffi::c_void, run: &Run) {
        for &(n, v) in run.parameters {
            assert_eq!(Self::set(c, run, n, v), OK, "{n} = {v}");
        }
        assert!(Self::initialization(c).iter().all(|&s| s == OK));
    }
    fn set(c: *mut std::ffi::c_void, run: &Run, name: &str, x: f64) -> i32;
    fn get(c: *mut std::ffi::c_void, run: &Run, name: &str) -> f64;
    fn step(c: *mut std::ffi::c_void, t: f64, h: f64) -> i32;
    fn get_state(c: *mut std::ffi::c_void, s: &mut *mut std::ffi::c_void) -> i32;
    fn set_state(c: *mut std::ffi::c_void, s: *mut std::ffi::c_void) -> i32;
    fn free_state(c: *mut std::ffi::c_void, s: &mut *mut std::ffi::c_void) -> i32;
    fn serialize(c: *mut std::ffi::c_void, s: *mut std::ffi::c_void) -> Vec<u8>;
    fn deserialize(c: *mut std::ffi::c_void, bytes: &[u8], s: &mut *mut std::ffi::c_void) -> i32;
    fn free(c: *mut std::ffi::c_void);
}

/// The FMI 2.0 calls.
pub struct Fmi2;
/// The FMI 3.0 calls.
pub struct Fmi3;

fn vr2(run: &Run, name: &str) -> u32 {
    fmi2_scalars((run.model.create)().variables())
        .iter()
        .position(|s| s.name == name)
        .unwrap() as u32
}

impl Abi for Fmi2 {
    fn instantiate(run: &Run) -> *mut std::ffi::c_void {
        let name = CString::new("state").unwrap();
        let token = CString::new(run.model.token()).unwrap();
        let functions = fmi2CallbackFunctions {
            logger: None,
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: null_mut(),
        };
        let c =
            unsafe { fmi2Instantiate(name.as_ptr(), 1, token.as_ptr(), null(), &functions, 0, 0) };
        assert!(!c.is_null());
        c
    }
    fn initialization(c: *mut std::ffi::c_void) -> Vec<i32> {
        unsafe {
            vec![
                fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
                fmi2EnterInitializationMode(c),
                fmi2ExitInitializationMode(c),
            ]
        }
    }
    fn set(c: *mut std::ffi::c_void, run: &Run, name: &str, x: f64) -> i32 {
        unsafe { fmi2SetReal(c, &vr2(run, name), 1, &x) }
    }
    fn get(c: *mut std::ffi::c_void, run: &Run, name: &str) -> f64 {
        let mut x = f64::NAN;
        assert_eq!(unsafe { fmi2GetReal(c, &vr2(run, name), 1, &mut x) }, OK);
        x
    }
    fn step(c: *mut std::ffi::c_void, t: f64, h: f64) -> i32 {
        unsafe { fmi2DoStep(c, t, h, 1) }
    }
    fn get_state(c: *mut std::ffi::c_void, s: &mut *mut std::ffi::c_void) -> i32 {
        unsafe { fmi2GetFMUstate(c, s) }
    }
    fn set_state(c: *mut std::ffi::c_void, s: *mut std::ffi::c_void) -> i32 {
        unsafe { fmi2SetFMUstate(c, s) }
    }
    fn free_state(c: *mut std::ffi::c_void, s: &mut *mut std::ffi::c_void) -> i32 {
        unsafe { fmi2FreeFMUstate(c, s) }
    }
    fn serialize(c: *mut std::ffi::c_void, s: *mut std::ffi::c_void) -> Vec<u8> {
        let mut size = 0;
        assert_eq!(unsafe { fmi2SerializedFMUstateSize(c, s, &mut size) }, OK);
        let mut bytes = vec![0u8; size];
        assert_eq!(
            unsafe { fmi2SerializeFMUstate(c, s, bytes.as_mut_ptr().cast(), size) },
            OK
        );
        bytes
    }
    fn deserialize(c: *mut std::ffi::c_void, bytes: &[u8], s: &mut *mut std::ffi::c_void) -> i32 {
        unsafe { fmi2DeSerializeFMUstate(c, bytes.as_ptr().cast(), bytes.len(), s) }
    }
    fn free(c: *mut std::ffi::c_void) {
        unsafe { fmi2FreeInstance(c) }
    }
}

impl Abi for Fmi3 {
    fn instantiate(run: &Run) -> *mut std::ffi::c_void {
        let name = CString::new("state").unwrap();
        let token = CString::new(run.model.token()).unwrap();
        let c = unsafe {
            fmi3InstantiateCoSimulation(
                name.as_ptr(),
                token.as_ptr(),
                null(),
                false,
                false,
                false,
                false,
                null(),
                0,
                null_mut(),
                Some(log3),
                null(),
            )
        };
        assert!(!c.is_null());
        c
    }
    fn initialization(c: *mut std::ffi::c_void) -> Vec<i32> {
        unsafe {
            vec![
                fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
                fmi3ExitInitializationMode(c),
            ]
        }
    }
    fn set(c: *mut std::ffi::c_void, run: &Run, name: &str, x: f64) -> i32 {
        let vr = (run.model.create)().lookup(name).unwrap();
        unsafe { fmi3SetFloat64(c, &vr, 1, &x, 1) }
    }
    fn get(c: *mut std::ffi::c_void, run: &Run, name: &str) -> f64 {
        let vr = (run.model.create)().lookup(name).unwrap();
        let mut x = f64::NAN;
        assert_eq!(unsafe { fmi3GetFloat64(c, &vr, 1, &mut x, 1) }, OK);
        x
    }
    fn step(c: *mut std::ffi::c_void, t: f64, h: f64) -> i32 {
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        unsafe {
            fmi3DoStep(
                c,
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        }
    }
    fn get_state(c: *mut std::ffi::c_void, s: &mut *mut std::ffi::c_void) -> i32 {
        unsafe { fmi3GetFMUState(c, s) }
    }
    fn set_state(c: *mut std::ffi::c_void, s: *mut std::ffi::c_void) -> i32 {
        unsafe { fmi3SetFMUState(c, s) }
    }
    fn free_state(c: *mut std::ffi::c_void, s: &mut *mut std::ffi::c_void) -> i32 {
        unsafe { fmi3FreeFMUState(c, s) }
    }
    fn serialize(c: *mut std::ffi::c_void, s: *mut std::ffi::c_void) -> Vec<u8> {
        let mut size = 0;
        assert_eq!(unsafe { fmi3SerializedFMUStateSize(c, s, &mut size) }, OK);
        let mut bytes = vec![0u8; size];
        assert_eq!(
            unsafe { fmi3SerializeFMUState(c, s, bytes.as_mut_ptr(), size) },
            OK
        );
        bytes
    }
    fn deserialize(c: *mut std::ffi::c_void, bytes: &[u8], s: &mut *mut std::ffi::c_void) -> i32 {
        unsafe { fmi3DeserializeFMUState(c, bytes.as_ptr(), bytes.len(), s) }
    }
    fn free(c: *mut std::ffi::c_void) {
        unsafe { fmi3FreeInstance(c) }
    }
}

/// Steps `from..to` with the run's inputs; every output's bits after each.
pub fn steps<A: Abi>(c: *mut std::ffi::c_void, run: &Run, from: usize, to: usize) -> Vec<u64> {
    let mut out = Vec::new();
    for k in from..to {
        for (n, v) in (run.inputs)(k) {
            assert_eq!(A::set(c, run, n, v), OK);
        }
        assert!(A::step(c, k as f64 * run.h, run.h) <= 1, "step {k}");
        out.extend(run.outputs.iter().map(|n| A::get(c, run, n).to_bits()));
    }
    out
}
