//! The FMI 2.0 functions called as an importer calls them (in process, through the C ABI):
//! state machine, bad input, bit-equality with the in-process scene, exact time landing,
//! reset, repeated instantiation, concurrency, and a random-call fuzz.

// Unsafe code: these tests call the FMI 2.0 C ABI.
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::ffi::{c_char, CString};
use std::ptr::{null, null_mut};

use fmu::exports::EXPORTS;
use fmu::fmi2::*;
use models::scene::cutblock::CutBlock;
use models::scene::Scene;

const OK: fmi2Status = 0;
const WARNING: fmi2Status = 1;
const ERROR: fmi2Status = 3;

fn cutblock_guid() -> CString {
    CString::new(EXPORTS[1].token()).unwrap()
}

fn instantiate() -> fmi2Component {
    let name = CString::new("test").unwrap();
    let guid = cutblock_guid();
    let c = unsafe { fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), null(), null(), 0, 0) };
    assert!(!c.is_null());
    c
}

/// FMI 2 value reference of a scalar by name (the addressing the model description uses).
fn vr(name: &str) -> fmi2ValueReference {
    let scene = CutBlock::new();
    fmu::addressing::fmi2_scalars(scene.variables())
        .iter()
        .position(|s| s.name == name)
        .unwrap() as u32
}

fn set(c: fmi2Component, name: &str, x: f64) -> fmi2Status {
    unsafe { fmi2SetReal(c, &vr(name), 1, &x) }
}

fn get(c: fmi2Component, name: &str) -> f64 {
    let mut x = f64::NAN;
    assert_eq!(
        unsafe { fmi2GetReal(c, &vr(name), 1, &mut x) },
        OK,
        "{name}"
    );
    x
}

/// A small block so that each step costs microseconds.
const SMALL: [(&str, f64); 3] = [("cells_x", 2.0), ("cells_y", 4.0), ("cells_z", 3.0)];

fn initialized() -> fmi2Component {
    let c = instantiate();
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        for (n, v) in SMALL {
            assert_eq!(set(c, n, v), OK);
        }
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
    }
    c
}

#[test]
fn outputs_equal_the_in_process_scene_to_the_last_bit() {
    let c = initialized();
    let mut scene = CutBlock::new();
    for (n, v) in SMALL {
        scene.set(n, v).unwrap();
    }
    scene.initialize(0.0).unwrap();
    let names = [
        "reaction_force",
        "cut_opening",
        "bottom_lift",
        "x_contraction",
        "max_von_mises",
        "profile_x50[90]",
    ];
    for (k, (pull, x)) in [(2.0, 0.0), (5.0, 50.0), (10.0, 100.0)]
        .into_iter()
        .enumerate()
    {
        assert_eq!(set(c, "pull", pull), OK);
        assert_eq!(set(c, "scalpel_x", x), OK);
        // The default law (neo-Hookean) is valid at these loads: no step warns.
        assert_eq!(unsafe { fmi2DoStep(c, k as f64, 1.0, 1) }, OK, "step {k}");
        scene.set("pull", pull).unwrap();
        scene.set("scalpel_x", x).unwrap();
        scene.do_step(k as f64, 1.0).unwrap();
        for name in names {
            let expect = if let Some(base) = name.strip_suffix("[90]") {
                let mut p = vec![0.0; 181];
                scene.get_real(scene.lookup(base).unwrap(), &mut p).unwrap();
                p[90]
            } else {
                scene.get(name).unwrap()
            };
            assert_eq!(get(c, name).to_bits(), expect.to_bits(), "{name}");
        }
    }
    unsafe { fmi2FreeInstance(c) };
}

/// The hyper-reduced abdomen (trained at initialization, deterministically) through the C
/// ABI equals the in-process scene to the last bit, its error indicator too.
#[test]
fn the_reduced_abdomen_equals_the_in_process_scene_to_the_last_bit() {
    use models::scene::abdomen::Abdomen;
    let scalars = fmu::addressing::fmi2_scalars(Abdomen::new().variables());
    let vr = |name: &str| scalars.iter().position(|s| s.name == name).unwrap() as u32;
    let name = CString::new("reduced").unwrap();
    let token = CString::new(EXPORTS[0].token()).unwrap();
    let c = unsafe { fmi2Instantiate(name.as_ptr(), 1, token.as_ptr(), null(), null(), 0, 0) };
    assert!(!c.is_null());
    let reduced = CString::new("reduced").unwrap();
    let mut scene = Abdomen::new();
    scene.set_str("model_order", "reduced").unwrap();
    scene.set("target_triangles", 200.0).unwrap();
    scene.initialize(0.0).unwrap();
    unsafe {
        assert_eq!(
            fmi2SetString(c, &vr("model_order"), 1, &reduced.as_ptr()),
            OK
        );
        assert_eq!(fmi2SetReal(c, &vr("target_triangles"), 1, &200.0), OK);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        // An output read in Initialization Mode: the state at rest has no residual.
        let mut eta = f64::NAN;
        assert_eq!(fmi2GetReal(c, &vr("error_indicator"), 1, &mut eta), OK);
        assert_eq!(eta, 0.0);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
    }
    for k in 0..20 {
        let t = f64::from(k) * 0.05;
        assert_eq!(unsafe { fmi2DoStep(c, t, 0.05, 1) }, OK, "step {k}");
        scene.do_step(t, 0.05).unwrap();
        for name in [
            "floor_stress_mean",
            "floor_stress_max",
            "apex_uy",
            "cavity_vm_max",
            "error_indicator",
        ] {
            let mut x = f64::NAN;
            assert_eq!(unsafe { fmi2GetReal(c, &vr(name), 1, &mut x) }, OK);
            assert_eq!(
                x.to_bits(),
                scene.get(name).unwrap().to_bits(),
                "{name}, step {k}"
            );
        }
    }
    unsafe { fmi2FreeInstance(c) };
}

#[test]
fn calls_in_the_wrong_state_and_bad_values_are_errors() {
    let c = instantiate();
    unsafe {
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 1), ERROR);
        assert_eq!(fmi2ExitInitializationMode(c), ERROR);
        let mut x = 0.0;
        assert_eq!(fmi2GetReal(c, &vr("reaction_force"), 1, &mut x), ERROR);
        assert_eq!(set(c, "E", 0.0), ERROR);
        assert_eq!(set(c, "nu", 0.5), ERROR);
        assert_eq!(set(c, "E", f64::NAN), ERROR);
        assert_eq!(fmi2SetReal(c, &100_000, 1, &1.0), ERROR);
        assert_eq!(fmi2SetReal(c, null(), 1, null()), ERROR);
        assert_eq!(
            fmi2GetInteger(c, null(), 0, null_mut()),
            ERROR,
            "no get before initialization mode"
        );
        assert_eq!(fmi2DoStep(null_mut(), 0.0, 1.0, 1), ERROR);
        // Still usable after refused values.
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        // Fixed parameters are frozen now; tunable ones and inputs are not.
        assert_eq!(set(c, "cells_x", 3.0), ERROR);
        assert_eq!(set(c, "E", 0.05), OK);
        assert_eq!(fmi2DoStep(c, 0.0, -1.0, 1), ERROR);
        assert_eq!(
            fmi2DoStep(c, 5.0, 1.0, 1),
            ERROR,
            "wrong communication point"
        );
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 1), OK);
        assert_eq!(fmi2GetInteger(c, &0, 1, null_mut()), ERROR);
        assert_eq!(fmi2GetInteger(c, null(), 0, null_mut()), OK);
        fmi2FreeInstance(c);
    }
    let bad = CString::new("{00000000-0000-0000-0000-000000000000}").unwrap();
    let c = unsafe { fmi2Instantiate(c"x".as_ptr(), 1, bad.as_ptr(), null(), null(), 0, 0) };
    assert!(c.is_null());
    let c = unsafe {
        fmi2Instantiate(
            c"x".as_ptr(),
            0,
            cutblock_guid().as_ptr(),
            null(),
            null(),
            0,
            0,
        )
    };
    assert!(c.is_null(), "model exchange is refused");
}

#[test]
fn a_scene_error_in_a_step_is_an_error_status_and_reset_recovers() {
    let c = instantiate();
    unsafe {
        for (n, v) in SMALL {
            set(c, n, v);
        }
        assert_eq!(set(c, "cut_depth", 17.0), OK);
        fmi2EnterInitializationMode(c);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        set(c, "scalpel_x", 100.0);
        assert_eq!(
            fmi2DoStep(c, 0.0, 1.0, 1),
            ERROR,
            "a cut that separates the block"
        );
        assert_eq!(
            fmi2DoStep(c, 1.0, 1.0, 1),
            ERROR,
            "no further steps after an error"
        );
        assert_eq!(fmi2Reset(c), OK);
        for (n, v) in SMALL {
            assert_eq!(set(c, n, v), OK);
        }
        fmi2EnterInitializationMode(c);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        set(c, "pull", 3.0);
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 1), OK);
        fmi2FreeInstance(c);
    }
}

#[test]
fn reset_returns_to_the_start_values() {
    let c = initialized();
    let first = {
        set(c, "pull", 4.0);
        unsafe { fmi2DoStep(c, 0.0, 0.5, 1) };
        get(c, "reaction_force")
    };
    unsafe {
        assert_eq!(fmi2Reset(c), OK);
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
    }
    unsafe { fmi2EnterInitializationMode(c) };
    assert_eq!(get(c, "cells_x"), 6.0, "start value after reset");
    assert_eq!(get(c, "pull"), 0.0);
    for (n, v) in SMALL {
        set(c, n, v);
    }
    unsafe { fmi2ExitInitializationMode(c) };
    set(c, "pull", 4.0);
    unsafe { fmi2DoStep(c, 0.0, 0.5, 1) };
    assert_eq!(get(c, "reaction_force").to_bits(), first.to_bits());
    unsafe { fmi2FreeInstance(c) };
}

/// 2¹⁸ steps of 2⁻¹⁰ s land on t = 256 s exactly (a binary fraction: no rounding
/// anywhere), and 250,000 steps on fmpy's grid t_k = k · 10⁻³ s with h_k = t_{k+1} − t_k
/// are all accepted and end within one ulp of 250 s.
#[test]
fn many_steps_land_exactly_on_the_communication_points() {
    let c = initialized();
    let h = 1.0 / 1024.0;
    for k in 0..262_144u32 {
        assert_eq!(unsafe { fmi2DoStep(c, f64::from(k) * h, h, 1) }, OK);
    }
    let mut last = 0.0;
    unsafe { fmi2GetRealStatus(c, 2, &mut last) };
    assert_eq!(last, 256.0);
    unsafe { fmi2FreeInstance(c) };

    let c = initialized();
    let t = |k: u32| f64::from(k) * 1e-3;
    for k in 0..250_000u32 {
        assert_eq!(
            unsafe { fmi2DoStep(c, t(k), t(k + 1) - t(k), 1) },
            OK,
            "{k}"
        );
    }
    unsafe { fmi2GetRealStatus(c, 2, &mut last) };
    assert!((last - 250.0).abs() <= 250.0 * f64::EPSILON, "{last}");
    unsafe { fmi2FreeInstance(c) };
}

/// The global allocator of this test binary counts the bytes each thread holds (allocated
/// minus freed), so that a test measures its own allocations whatever the tests running
/// alongside do. (Memory the C code of METIS takes with malloc is not counted.)
struct Counting;

thread_local! {
    static HELD: Cell<isize> = const { Cell::new(0) };
}

fn held(change: isize) {
    // `try_with`: allocations while the thread's locals are torn down are not counted.
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

/// Bytes this thread holds.
fn held_bytes() -> isize {
    HELD.with(Cell::get)
}

/// Instantiating, running and freeing an instance gives back every byte it took: after a
/// warm-up, 1,000 cycles leave the bytes this thread holds exactly where they were. The
/// cycles run on a rayon pool of one thread: the cut block solves on rayon's threads, and
/// there its steps stay on the thread whose bytes are counted.
#[test]
fn a_thousand_instantiate_run_free_cycles_do_not_grow_memory() {
    let cycle = || {
        let c = initialized();
        set(c, "pull", 1.0);
        unsafe {
            fmi2DoStep(c, 0.0, 1.0, 1);
            fmi2Terminate(c);
            fmi2FreeInstance(c);
        }
    };
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let growth = one.install(|| {
        for _ in 0..10 {
            cycle();
        }
        let before = held_bytes();
        for _ in 0..1000 {
            cycle();
        }
        held_bytes() - before
    });
    println!("bytes held after 1000 more cycles: {growth:+}");
    assert_eq!(growth, 0);
}

#[test]
fn two_instances_on_two_threads_match_single_runs() {
    let run = |pull: f64| -> Vec<u64> {
        let c = initialized();
        let mut out = Vec::new();
        for k in 0..20 {
            set(c, "pull", pull * k as f64 / 20.0);
            set(c, "scalpel_x", 5.0 * k as f64);
            unsafe { fmi2DoStep(c, k as f64, 1.0, 1) };
            out.push(get(c, "reaction_force").to_bits());
        }
        unsafe { fmi2FreeInstance(c) };
        out
    };
    let alone = (run(10.0), run(6.0));
    let a = std::thread::spawn(move || run(10.0));
    let b = std::thread::spawn(move || run(6.0));
    assert_eq!((a.join().unwrap(), b.join().unwrap()), alone);
}

#[test]
fn random_call_sequences_never_crash() {
    // A deterministic xorshift stream drives calls with random arguments.
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let n_scalars = fmu::addressing::fmi2_scalars(CutBlock::new().variables()).len() as u64;
    let mut c = instantiate();
    for _ in 0..4000 {
        let r = next();
        let vr = (r >> 8) as u32 % (n_scalars as u32 + 3);
        let x = match r % 7 {
            0 => f64::NAN,
            1 => -1.0,
            2 => 1e300,
            _ => ((r >> 20) % 200) as f64 / 2.0,
        };
        let mut out = 0.0;
        let mut s: *const c_char = null();
        let call = (r >> 4) % 12;
        let status = unsafe {
            match call {
                0 => fmi2SetReal(c, &vr, 1, &x),
                1 => fmi2GetReal(c, &vr, 1, &mut out),
                2 => fmi2EnterInitializationMode(c),
                3 => fmi2ExitInitializationMode(c),
                4 => fmi2DoStep(c, x, 1.0, 1),
                5 => fmi2Terminate(c),
                6 => fmi2Reset(c),
                7 => fmi2GetString(c, &vr, 1, &mut s),
                8 => fmi2SetString(c, &vr, 1, &c"delete".as_ptr()),
                9 => fmi2SetupExperiment(c, 0, 0.0, x, 0, 0.0),
                10 => {
                    // Keep meshes small so the fuzz stays fast.
                    for (n, v) in SMALL {
                        set(c, n, v);
                    }
                    OK
                }
                _ => {
                    fmi2FreeInstance(c);
                    c = instantiate();
                    OK
                }
            }
        };
        // OK, Warning or Error: nothing here may be fatal, and no step is discarded.
        // (A step from a time that is not finite, in the phase where steps are allowed:
        // `importer_calls.rs`.)
        assert!([OK, WARNING, ERROR].contains(&status), "status {status}");
    }
    unsafe { fmi2FreeInstance(c) };
}

static ALLOCATIONS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);

unsafe extern "C" fn counting_allocate(_n: usize, _size: usize) -> *mut std::ffi::c_void {
    ALLOCATIONS.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
    null_mut()
}

/// Every capability flag of the FMI 2 description holds: variable communication steps
/// work; FMU state, which the description declares absent, is refused; and the importer's
/// memory functions are never called (`canNotUseMemoryManagementFunctions="true"`).
#[test]
fn capability_flags_are_honoured() {
    let xml = fmu::xml::fmi2(&EXPORTS[1]);
    for (flag, value) in [
        ("canHandleVariableCommunicationStepSize", true),
        ("canNotUseMemoryManagementFunctions", true),
        ("canGetAndSetFMUstate", true),
        ("canSerializeFMUstate", true),
    ] {
        assert!(xml.contains(&format!(r#"{flag}="{value}""#)), "{flag}");
    }
    let functions = fmi2CallbackFunctions {
        logger: None,
        allocateMemory: Some(counting_allocate),
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: null_mut(),
    };
    let name = CString::new("flags").unwrap();
    let guid = cutblock_guid();
    let c = unsafe { fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), null(), &functions, 0, 0) };
    assert!(!c.is_null());
    unsafe {
        for (n, v) in SMALL {
            assert_eq!(set(c, n, v), OK);
        }
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), OK);
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        let mut t = 0.0;
        for h in [0.1, 0.35, 1e-3, 2.0] {
            assert_eq!(fmi2DoStep(c, t, h, 1), OK, "h = {h}");
            t += h;
        }
        let mut state: fmi2FMUstate = null_mut();
        assert_eq!(fmi2GetFMUstate(c, &mut state), OK);
        let mut size = 0;
        assert_eq!(fmi2SerializedFMUstateSize(c, state, &mut size), OK);
        assert!(size > 0);
        assert_eq!(fmi2FreeFMUstate(c, &mut state), OK);
        assert!(state.is_null());
        fmi2FreeInstance(c);
    }
    assert_eq!(ALLOCATIONS.load(std::sync::atomic::Ordering::SeqCst), 0);
}

/// `fmi2GetStatus` and `fmi2CancelStep` answer as the standard allows for an FMU whose steps
/// never return fmi2Pending: the status is not available (fmi2Discard), there is nothing to
/// cancel (fmi2Error); neither changes the instance, which steps on. A stop time set in
/// `fmi2SetupExperiment` is honoured.
#[test]
fn status_queries_cancel_and_the_stop_time() {
    const DISCARD: fmi2Status = 2;
    let c = initialized();
    let mut status = OK;
    unsafe {
        assert_eq!(fmi2GetStatus(c, 0, &mut status), DISCARD);
        assert_eq!(fmi2CancelStep(c), ERROR);
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 1), OK);
        let mut last = 0.0;
        assert_eq!(fmi2GetRealStatus(c, 2, &mut last), OK);
        assert_eq!(last, 1.0);
        fmi2FreeInstance(c);
    }
    let c = instantiate();
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 1.5), OK);
        for (n, v) in SMALL {
            assert_eq!(set(c, n, v), OK);
        }
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        assert_eq!(fmi2ExitInitializationMode(c), OK);
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 1), OK);
        assert_eq!(fmi2DoStep(c, 1.0, 1.0, 1), ERROR, "past the stop time");
        assert_eq!(fmi2DoStep(c, 1.0, 0.5, 1), OK, "up to it");
        fmi2FreeInstance(c);
    }
}
