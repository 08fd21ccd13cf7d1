//! The cost of FMU states on the default models after a few steps (abdomen: 5 steps of
//! 10 ms; cut block: full cut and 10 mm pull): taking one, serializing it, and setting it
//! (which rebuilds the model from the saved values), with the serialized size printed; and,
//! to weigh `set` against, reaching the same point from a new instance.
//!
//! Run: `cargo bench -p fmu --bench state`.

// Unsafe code: the benchmark calls the C ABI.
#![allow(unsafe_code)]

use std::ffi::CString;
use std::ptr::{null, null_mut};

use divan::Bencher;
use fmu::addressing::fmi2_scalars;
use fmu::exports::EXPORTS;
use fmu::fmi2::*;

fn main() {
    divan::main();
}

/// An instance of model `m` (0 abdomen, 1 cut block) advanced past its start.
fn advanced(m: usize) -> fmi2Component {
    let token = CString::new(EXPORTS[m].token()).unwrap();
    let c = unsafe { fmi2Instantiate(c"bench".as_ptr(), 1, token.as_ptr(), null(), null(), 0, 0) };
    let scalars = fmi2_scalars((EXPORTS[m].create)().variables());
    let vr = |n: &str| scalars.iter().position(|s| s.name == n).unwrap() as u32;
    unsafe {
        fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
        fmi2EnterInitializationMode(c);
        assert_eq!(fmi2ExitInitializationMode(c), 0);
        if m == 1 {
            fmi2SetReal(c, &vr("scalpel_x"), 1, &100.0);
            fmi2SetReal(c, &vr("pull"), 1, &10.0);
            assert!(fmi2DoStep(c, 0.0, 1.0, 1) <= 1);
        } else {
            for k in 0..5 {
                assert!(fmi2DoStep(c, f64::from(k) * 0.01, 0.01, 1) <= 1);
            }
        }
    }
    c
}

fn state_of(c: fmi2Component) -> fmi2FMUstate {
    let mut s = null_mut();
    assert_eq!(unsafe { fmi2GetFMUstate(c, &mut s) }, 0);
    s
}

#[divan::bench(args = [0, 1])]
fn get(bencher: Bencher, m: usize) {
    let c = advanced(m);
    bencher.bench_local(|| {
        let mut s = state_of(c);
        unsafe { fmi2FreeFMUstate(c, &mut s) };
    });
}

#[divan::bench(args = [0, 1])]
fn serialize(bencher: Bencher, m: usize) {
    let c = advanced(m);
    let mut size = 0;
    bencher.bench_local(|| {
        let s = state_of(c);
        unsafe { fmi2SerializedFMUstateSize(c, s, &mut size) };
        let mut bytes = vec![0u8; size];
        unsafe { fmi2SerializeFMUstate(c, s, bytes.as_mut_ptr().cast(), size) };
        let mut s = s;
        unsafe { fmi2FreeFMUstate(c, &mut s) };
    });
    println!("{}: serialized state {size} bytes", EXPORTS[m].identifier);
}

#[divan::bench(args = [0, 1], sample_count = 20)]
fn set(bencher: Bencher, m: usize) {
    let c = advanced(m);
    let s = state_of(c);
    bencher.bench_local(|| assert_eq!(unsafe { fmi2SetFMUstate(c, s) }, 0));
}

#[divan::bench(args = [0, 1], sample_count = 20)]
fn reach(m: usize) {
    let c = advanced(m);
    unsafe { fmi2FreeInstance(c) };
}
