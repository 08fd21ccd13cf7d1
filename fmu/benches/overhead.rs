//! The cost of the FMI layer: a step through `fmi2DoStep` (with the input set through
//! `fmi2SetReal` and one output read through `fmi2GetReal`) against the same work on the
//! in-process scene, measured in one run.
//!
//! Run: `cargo bench -p fmu --bench overhead`.

// Unsafe code: the benchmark calls the FMI 2.0 C ABI.
#![allow(unsafe_code)]

use std::ffi::CString;
use std::ptr::null;

use divan::Bencher;
use fmu::addressing::fmi2_scalars;
use fmu::exports::EXPORTS;
use fmu::fmi2::*;

fn main() {
    divan::main();
}

/// (model index, input name, input values alternating, output name).
const CASES: [(usize, &str, [f64; 2], &str); 2] = [
    (0, "press_force", [0.1, 0.2], "floor_stress_max"),
    (1, "pull", [5.0, 10.0], "reaction_force"),
];

#[divan::bench(args = [0, 1])]
fn in_process(bencher: Bencher, case: usize) {
    let (model, input, values, output) = CASES[case];
    let mut scene = (EXPORTS[model].create)();
    scene.initialize(0.0).unwrap();
    let (vin, vout) = (scene.lookup(input).unwrap(), scene.lookup(output).unwrap());
    let (mut t, mut k) = (0.0, 0);
    let mut y = [0.0];
    bencher.bench_local(|| {
        k += 1;
        scene.set_real(vin, &[values[k % 2]]).unwrap();
        scene.do_step(t, 1e-3).unwrap();
        t += 1e-3;
        scene.get_real(vout, &mut y).unwrap();
    });
}

#[divan::bench(args = [0, 1])]
fn through_fmi2(bencher: Bencher, case: usize) {
    let (model, input, values, output) = CASES[case];
    let guid = CString::new(EXPORTS[model].token()).unwrap();
    let scalars = fmi2_scalars((EXPORTS[model].create)().variables());
    let vr = |n: &str| scalars.iter().position(|s| s.name == n).unwrap() as u32;
    let (vin, vout) = (vr(input), vr(output));
    let c = unsafe { fmi2Instantiate(c"bench".as_ptr(), 1, guid.as_ptr(), null(), null(), 0, 0) };
    unsafe {
        fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0);
        fmi2EnterInitializationMode(c);
        assert_eq!(fmi2ExitInitializationMode(c), 0);
    }
    let (mut t, mut k) = (0.0, 0);
    let mut y = 0.0;
    bencher.bench_local(|| unsafe {
        k += 1;
        fmi2SetReal(c, &vin, 1, &values[k % 2]);
        fmi2DoStep(c, t, 1e-3, 1);
        t += 1e-3;
        fmi2GetReal(c, &vout, 1, &mut y);
    });
    unsafe { fmi2FreeInstance(c) };
}
