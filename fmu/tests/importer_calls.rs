//! Calls the standard allows an importer, through the C ABI in FMI 2 and FMI 3, both models:
//! a step from a time that is not finite, or by a size that is not finite and positive, and
//! a value out of range or not finite, are refused with Error and the instance steps on; a step far below the model's step leaves
//! the steps after it as they were; two identical runs serialize to identical bytes; and a
//! parameter that cannot act under the present settings returns Warning, where the default
//! run returns OK.

// Unsafe code: these tests call the C ABI.
#![allow(unsafe_code)]

use std::ptr::null_mut;

mod common;
use common::{steps, Abi, Fmi2, Fmi3, Run, ABDOMEN, CUTBLOCK, ERROR, ERRORS, OK};

/// The Warning status, the same number in both versions.
const WARNING: i32 = 1;

/// Steps from a time or by a size that is not valid: Error, the time unchanged (the next
/// valid step from it is OK and the run continues as one without the refused calls).
fn bad_steps_are_refused<A: Abi>(run: &Run) {
    let plain = A::instantiate(run);
    A::initialize(plain, run);
    let expected = steps::<A>(plain, run, 0, 3);
    let c = A::instantiate(run);
    A::initialize(c, run);
    let mut got = steps::<A>(c, run, 0, 1);
    let t = run.h;
    for current in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        assert_eq!(A::step(c, current, run.h), ERROR, "from t = {current}");
    }
    for h in [f64::NAN, f64::INFINITY, 0.0, -run.h] {
        assert_eq!(A::step(c, t, h), ERROR, "by h = {h}");
    }
    got.extend(steps::<A>(c, run, 1, 3));
    assert_eq!(got, expected);
    A::free(c);
    A::free(plain);
}

#[test]
fn a_step_from_a_time_that_is_not_finite_is_refused_and_the_run_goes_on() {
    for run in [&CUTBLOCK, &ABDOMEN] {
        bad_steps_are_refused::<Fmi2>(run);
        bad_steps_are_refused::<Fmi3>(run);
    }
    let said = ERRORS.lock().unwrap().join("\n");
    for what in [
        "currentCommunicationPoint = NaN s is not finite",
        "communicationStepSize = 0 s must be finite and > 0",
    ] {
        assert!(said.contains(what), "{what}: {said}");
    }
}

/// Bad values through the C ABI: a stiffness of 0, below 0, NaN or +inf before and after
/// initialization, and the run's first (fixed) parameter after it, are each Error; the
/// instance goes on as if they had not been made.
fn bad_values_are_refused<A: Abi>(run: &Run, stiffness: &str) {
    let plain = A::instantiate(run);
    A::initialize(plain, run);
    let expected = steps::<A>(plain, run, 0, 2);
    let bad = [0.0, -1.0, f64::NAN, f64::INFINITY];
    let c = A::instantiate(run);
    for x in bad {
        assert_eq!(A::set(c, run, stiffness, x), ERROR, "{stiffness} = {x}");
    }
    A::initialize(c, run);
    for x in bad {
        assert_eq!(A::set(c, run, stiffness, x), ERROR, "{stiffness} = {x}");
    }
    let (fixed, value) = run.parameters[0];
    assert_eq!(
        A::set(c, run, fixed, value + 1.0),
        ERROR,
        "{fixed} after initialization"
    );
    assert_eq!(steps::<A>(c, run, 0, 2), expected);
    A::free(c);
    A::free(plain);
}

#[test]
fn bad_values_are_refused_by_name_in_both_models() {
    for (run, stiffness) in [(&CUTBLOCK, "E"), (&ABDOMEN, "floor_E")] {
        bad_values_are_refused::<Fmi2>(run, stiffness);
        bad_values_are_refused::<Fmi3>(run, stiffness);
    }
    let said = ERRORS.lock().unwrap().join("\n");
    for what in [
        "for `E` is out of range",
        "for `floor_E` is out of range",
        "`target_triangles`",
    ] {
        assert!(said.contains(what), "{what}: {said}");
    }
}

/// The run's outputs after each of `n` steps of `run.h`, with a step of `tiny` inserted
/// before step 3 if given.
fn with_tiny_step<A: Abi>(run: &Run, tiny: Option<f64>, n: usize) -> Vec<f64> {
    let c = A::instantiate(run);
    A::initialize(c, run);
    let mut t = 0.0;
    let mut out = Vec::new();
    for k in 0..n {
        for (name, x) in (run.inputs)(k) {
            assert_eq!(A::set(c, run, name, x), OK);
        }
        if let Some(h) = tiny.filter(|_| k == 3) {
            assert_eq!(A::step(c, t, h), OK, "the step of {h} s");
            t += h;
        }
        assert_eq!(A::step(c, t, run.h), OK, "step {k}");
        t += run.h;
        out.extend(run.outputs.iter().map(|name| A::get(c, run, name)));
    }
    A::free(c);
    out
}

/// A step of 1e-16 s or 1e-10 s in the middle of the run: every output of every later step
/// within 1e-12 of the largest, relative, of the run without it. (The cut block is
/// quasi-static, its state a function of its inputs: there this checks that the instance's
/// clock takes the tiny step, so that the next steps from the new time are accepted.)
fn tiny_steps_change_nothing<A: Abi>(run: &Run) {
    let n = 6;
    let plain = with_tiny_step::<A>(run, None, n);
    for tiny in [1e-16, 1e-10] {
        let with = with_tiny_step::<A>(run, Some(tiny), n);
        for (k, name) in run.outputs.iter().enumerate() {
            let column = |rows: &[f64]| -> Vec<f64> {
                rows.iter()
                    .skip(k)
                    .step_by(run.outputs.len())
                    .copied()
                    .collect()
            };
            let (a, b) = (column(&plain), column(&with));
            let size = a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
            let gap = a
                .iter()
                .zip(&b)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                gap <= 1e-12 * size,
                "{} after a step of {tiny} s: {name} off by {gap:e} of {size:e}",
                run.model.identifier
            );
        }
    }
}

#[test]
fn a_step_far_below_the_models_step_leaves_the_next_steps_as_they_were() {
    for run in [&CUTBLOCK, &ABDOMEN] {
        tiny_steps_change_nothing::<Fmi2>(run);
        tiny_steps_change_nothing::<Fmi3>(run);
    }
}

/// The bytes of the state after three steps of a fresh instance.
fn state_after_three_steps<A: Abi>(run: &Run) -> Vec<u8> {
    let c = A::instantiate(run);
    A::initialize(c, run);
    steps::<A>(c, run, 0, 3);
    let mut s = null_mut();
    assert_eq!(A::get_state(c, &mut s), OK);
    let bytes = A::serialize(c, s);
    assert_eq!(A::free_state(c, &mut s), OK);
    A::free(c);
    bytes
}

#[test]
fn identical_runs_serialize_to_identical_bytes() {
    for run in [&CUTBLOCK, &ABDOMEN] {
        assert_eq!(
            state_after_three_steps::<Fmi2>(run),
            state_after_three_steps::<Fmi2>(run),
            "{} in FMI 2",
            run.model.identifier
        );
        assert_eq!(
            state_after_three_steps::<Fmi3>(run),
            state_after_three_steps::<Fmi3>(run),
            "{} in FMI 3",
            run.model.identifier
        );
    }
}

/// The statuses of setting the run's parameters, `extra` and initializing.
fn initialization_with<A: Abi>(run: &Run, extra: Option<(&str, f64)>) -> Vec<i32> {
    let c = A::instantiate(run);
    let mut statuses: Vec<i32> = run
        .parameters
        .iter()
        .chain(extra.as_ref())
        .map(|&(name, x)| A::set(c, run, name, x))
        .collect();
    statuses.extend(A::initialization(c));
    A::free(c);
    statuses
}

/// The wall's modulus, set with the wall held (the default), cannot act: the initialization
/// returns Warning (the set itself is OK: whether it acts is known when the values are
/// complete). At its start value, nothing warns.
fn an_inert_parameter_warns<A: Abi>() {
    assert!(initialization_with::<A>(&ABDOMEN, None)
        .iter()
        .all(|&s| s == OK));
    assert!(initialization_with::<A>(&ABDOMEN, Some(("wall_E", 0.0225)))
        .iter()
        .all(|&s| s == OK));
    let statuses = initialization_with::<A>(&ABDOMEN, Some(("wall_E", 0.03)));
    assert_eq!(
        statuses.iter().filter(|&&s| s == WARNING).count(),
        1,
        "{statuses:?}"
    );
    assert!(
        statuses.iter().all(|&s| s == OK || s == WARNING),
        "{statuses:?}"
    );
}

#[test]
fn a_parameter_that_cannot_act_returns_warning() {
    an_inert_parameter_warns::<Fmi2>();
    an_inert_parameter_warns::<Fmi3>();
}
