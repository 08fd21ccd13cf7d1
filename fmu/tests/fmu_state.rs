//! FMU states through the C ABI, FMI 2 and FMI 3, both models: a state taken mid-run and
//! set back into the same instance, set into another instance, and serialized then
//! deserialized into a fresh instance continues bit for bit as the uninterrupted run (a
//! fresh instance needs no initialization: the state carries the phase). Bytes of another
//! model, another build, another format version, damaged or not a state at all are refused
//! with a message saying which; 1,000 get/set/free cycles leave the memory the thread holds
//! exactly where it was.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::ffi::{c_char, CStr, CString};
use std::ptr::{null, null_mut};
use std::sync::Mutex;

use fmu::fmi2::*;
use fmu::fmi3::*;
use fmu::instance::fmi2_scalars;
use fmu::model::{Model, MODELS};

const OK: i32 = 0;
const ERROR: i32 = 3;

/// Counts the bytes each thread holds (allocated minus freed).
struct Counting;

thread_local! {
    static HELD: Cell<isize> = const { Cell::new(0) };
}

fn held(change: isize) {
    let _ = HELD.try_with(|h| h.set(h.get() + change));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        held(layout.size() as isize);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        held(-(layout.size() as isize));
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        held(new_size as isize - layout.size() as isize);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// A run of one model: parameters, then inputs before each step, outputs after it.
struct Run {
    model: &'static Model,
    parameters: &'static [(&'static str, f64)],
    inputs: fn(usize) -> Vec<(&'static str, f64)>,
    outputs: &'static [&'static str],
    h: f64,
}

const CUTBLOCK: Run = Run {
    model: &MODELS[1],
    parameters: &[("cells_x", 6.0), ("cells_y", 4.0), ("cells_z", 3.0)],
    inputs: |k| vec![("scalpel_x", 17.0 * k as f64), ("pull", 0.9 * k as f64)],
    outputs: &["reaction_force", "cut_opening", "bottom_lift"],
    h: 1.0,
};

const ABDOMEN: Run = Run {
    model: &MODELS[0],
    parameters: &[("target_triangles", 300.0)],
    inputs: |k| vec![("press_force", 0.02 * k as f64)],
    outputs: &["floor_stress_mean", "apex_uy"],
    h: 0.01,
};

/// The messages an FMI 3 instance logged with Error status (the FMI 2 logger is variadic,
/// which Rust cannot define; the refusals are the same code in both versions).
static ERRORS: Mutex<Vec<String>> = Mutex::new(Vec::new());

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
trait Abi {
    fn instantiate(run: &Run) -> *mut std::ffi::c_void;
    fn initialize(c: *mut std::ffi::c_void, run: &Run);
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

struct Fmi2;
struct Fmi3;

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
    fn initialize(c: *mut std::ffi::c_void, run: &Run) {
        unsafe {
            assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
            for &(n, v) in run.parameters {
                assert_eq!(Self::set(c, run, n, v), OK);
            }
            assert_eq!(fmi2EnterInitializationMode(c), OK);
            assert_eq!(fmi2ExitInitializationMode(c), OK);
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
    fn initialize(c: *mut std::ffi::c_void, run: &Run) {
        unsafe {
            for &(n, v) in run.parameters {
                assert_eq!(Self::set(c, run, n, v), OK);
            }
            assert_eq!(
                fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
                OK
            );
            assert_eq!(fmi3ExitInitializationMode(c), OK);
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
fn steps<A: Abi>(c: *mut std::ffi::c_void, run: &Run, from: usize, to: usize) -> Vec<u64> {
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

const AT: usize = 3;
const END: usize = 7;

/// The three ways back: the same instance, another one, and bytes into a fresh one.
fn continues<A: Abi>(run: &Run) {
    let a = A::instantiate(run);
    A::initialize(a, run);
    steps::<A>(a, run, 0, AT);
    let mut state = null_mut();
    assert_eq!(A::get_state(a, &mut state), OK);
    let bytes = A::serialize(a, state);
    let expected = steps::<A>(a, run, AT, END);
    // Back in the same instance.
    assert_eq!(A::set_state(a, state), OK);
    assert_eq!(steps::<A>(a, run, AT, END), expected, "same instance");
    // In another instance, initialized or not.
    let b = A::instantiate(run);
    assert_eq!(A::set_state(b, state), OK);
    assert_eq!(steps::<A>(b, run, AT, END), expected, "another instance");
    // From the bytes, in a fresh instance.
    let c = A::instantiate(run);
    let mut read = null_mut();
    assert_eq!(A::deserialize(c, &bytes, &mut read), OK);
    assert_eq!(A::set_state(c, read), OK);
    assert_eq!(steps::<A>(c, run, AT, END), expected, "from bytes");
    // The state is the same written twice.
    assert_eq!(A::serialize(c, read), bytes);
    for (i, mut s) in [(a, state), (c, read)] {
        assert_eq!(A::free_state(i, &mut s), OK);
        assert!(s.is_null());
    }
    for i in [a, b, c] {
        A::free(i);
    }
}

#[test]
fn a_state_continues_bit_for_bit_in_fmi2() {
    continues::<Fmi2>(&CUTBLOCK);
    continues::<Fmi2>(&ABDOMEN);
}

#[test]
fn a_state_continues_bit_for_bit_in_fmi3() {
    continues::<Fmi3>(&CUTBLOCK);
    continues::<Fmi3>(&ABDOMEN);
}

/// The bytes of a state of `run`'s model after one step.
fn bytes_of<A: Abi>(run: &Run) -> Vec<u8> {
    let c = A::instantiate(run);
    A::initialize(c, run);
    steps::<A>(c, run, 0, 1);
    let mut s = null_mut();
    assert_eq!(A::get_state(c, &mut s), OK);
    let bytes = A::serialize(c, s);
    A::free_state(c, &mut s);
    A::free(c);
    bytes
}

/// `bytes` with the header field at `at` (after magic and version) replaced, checksum fixed.
fn with_crc(mut bytes: Vec<u8>) -> Vec<u8> {
    let n = bytes.len() - 4;
    let crc = crc32fast::hash(&bytes[..n]);
    bytes[n..].copy_from_slice(&crc.to_le_bytes());
    bytes
}

/// Deserializing `bytes` into a cut-block instance is refused; the message logged.
fn refused(bytes: &[u8]) -> String {
    let c = Fmi3::instantiate(&CUTBLOCK);
    ERRORS.lock().unwrap().clear();
    let mut s = null_mut();
    assert_eq!(Fmi3::deserialize(c, bytes, &mut s), ERROR);
    assert!(s.is_null());
    Fmi3::free(c);
    ERRORS.lock().unwrap().join("\n")
}

#[test]
fn foreign_and_damaged_bytes_are_refused_saying_why() {
    let _one = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let own = bytes_of::<Fmi3>(&CUTBLOCK);
    let e = refused(&bytes_of::<Fmi3>(&ABDOMEN));
    assert!(
        e.contains("is of the `abdomen` model; this FMU is `cutblock`"),
        "{e}"
    );
    let e = refused(b"hello, this is no state");
    assert!(e.contains("not a serialized tissuefmu FMU state"), "{e}");
    let mut damaged = own.clone();
    let middle = damaged.len() / 2;
    damaged[middle] ^= 1;
    let e = refused(&damaged);
    assert!(e.contains("corrupted: its checksum does not match"), "{e}");
    let e = refused(&own[..own.len() - 9]);
    assert!(e.contains("corrupted") || e.contains("truncated"), "{e}");
    let mut version = own.clone();
    version[16] = 9;
    let e = refused(&with_crc(version));
    assert!(
        e.contains("format version 9; this build reads version 1"),
        "{e}"
    );
    // Another build: the same model's name, another token.
    let name = 1 + own[20] as usize;
    let mut build = own.clone();
    build[20 + name + 1] ^= 0x20;
    let e = refused(&with_crc(build));
    assert!(
        e.contains("comes from another build of the `cutblock` FMU"),
        "{e}"
    );
    // A state of the abdomen set in a cut-block instance of the same library.
    let a = Fmi3::instantiate(&ABDOMEN);
    let mut s = null_mut();
    assert_eq!(Fmi3::get_state(a, &mut s), OK);
    let c = Fmi3::instantiate(&CUTBLOCK);
    ERRORS.lock().unwrap().clear();
    assert_eq!(Fmi3::set_state(c, s), ERROR);
    let e = ERRORS.lock().unwrap().join("\n");
    assert!(
        e.contains("an FMU state of the `abdomen` model cannot be set in a `cutblock`"),
        "{e}"
    );
    Fmi3::free_state(a, &mut s);
    Fmi3::free(a);
    Fmi3::free(c);
}

/// Tests that read the shared error log take turns.
static SERIAL: Mutex<()> = Mutex::new(());

/// Getting, setting and freeing a state 1,000 times gives back every byte: the thread holds
/// as much after as before.
#[test]
fn a_thousand_get_set_free_cycles_leave_memory_flat() {
    let c = Fmi2::instantiate(&CUTBLOCK);
    Fmi2::initialize(c, &CUTBLOCK);
    steps::<Fmi2>(c, &CUTBLOCK, 0, 2);
    let cycle = || {
        let mut s = null_mut();
        assert_eq!(Fmi2::get_state(c, &mut s), OK);
        assert_eq!(Fmi2::set_state(c, s), OK);
        assert_eq!(Fmi2::free_state(c, &mut s), OK);
    };
    for _ in 0..10 {
        cycle();
    }
    let before = HELD.with(Cell::get);
    for _ in 0..1000 {
        cycle();
    }
    assert_eq!(HELD.with(Cell::get) - before, 0);
    Fmi2::free(c);
}
