//! Every declared value through the C ABI: for each variable of both FMUs that an importer
//! sets — its minimum, its maximum and its start value (string parameters: every choice and
//! a wrong one) — an FMI 2 instance is set up with it, initialized, stepped three times with
//! every output read after each step (once at the largest mesh, [`MESH_SIZES`]), and freed.
//! Each case runs in a child process (this test binary run again for that one case): no
//! case may abort or return fmi2Fatal, and after an error the instance must still answer
//! reads and refuse steps cleanly. What the model cannot take is refused
//! by name (memory_limit, substeps, Newton increments); what it can take finishes in
//! bounded work.

use std::ffi::CString;
use std::process::Command;
use std::ptr::null;
use std::time::{Duration, Instant};

use fmu::fmi2::*;
use fmu::instance::fmi2_scalars;
use fmu::model::MODELS;
use models::scene::{Causality, Start, VariableKind};

const OK: fmi2Status = 0;
const WARNING: fmi2Status = 1;
const ERROR: fmi2Status = 3;

/// Values of each string parameter of a model that a set accepts (for `configuration` any
/// text: a name or a path, resolved at initialization), and one it refuses; every string
/// parameter must be listed here.
fn choices(model: &str, name: &str) -> (&'static [&'static str], Option<&'static str>) {
    let (valid, wrong): (&'static [&'static str], &'static str) = match (model, name) {
        (_, "configuration") => {
            return (
                &["", "narrow", "wide", "no_such_pelvis", "/no/such/file.toml"],
                None,
            )
        }
        (_, "abdominal_wall") => (&["free", "fixed"], "floating"),
        (_, "integrator") => (
            &["houbolt", "newmark", "central_difference", "rk4"],
            "euler",
        ),
        (_, "model_order") => (
            &[
                "full",
                "modal",
                "eigenmodes",
                "eigenmodes_truncated",
                "reduced",
            ],
            "half",
        ),
        ("abdomen", "element") => (&["tri3", "tri6"], "tet4"),
        ("cutblock", "element") => (&["tet4", "tet10"], "tri6"),
        (_, "formulation") => (&["displacement", "mixed"], "hybrid"),
        (_, "kinematics") => (&["linear", "finite"], "corotational"),
        (_, "cut_strategy") => (&["duplicate", "delete"], "melt"),
        (_, "support") => (&["clamped", "gripped", "sliding"], "glued"),
        (_, "contact") => (&["penalty", "none"], "mortar"),
        (_, "material") => (&["linear", "neo-hookean", "stvk"], "ogden"),
        ("abdomen", "costal_margin") => (&["fixed", "free"], "loose"),
        _ => panic!("string parameter `{name}` of {model} has no choices listed in this test"),
    };
    (valid, Some(wrong))
}

/// The settings each case starts from, per model: the defaults (for the abdomen finite
/// strain, whose Newton iterations are where unbounded work could hide), and the other
/// kinematics or law.
fn bases(model: &str) -> [Option<(&'static str, &'static str)>; 2] {
    match model {
        "abdomen" => [None, Some(("kinematics", "linear"))],
        _ => [None, Some(("material", "neo-hookean"))],
    }
}

/// The variables that size the mesh. At its maximum such a case is stepped once: a step
/// there takes the work of the first, and the history of three steps is tested at every
/// other value. (The largest mesh accepted, 192,000 triangles at `mesh_subdivisions` = 4,
/// took 123 s of the fuzz's 152 s when stepped three times, 2026-11-27.)
const MESH_SIZES: [&str; 5] = [
    "target_triangles",
    "mesh_subdivisions",
    "cells_x",
    "cells_y",
    "cells_z",
];

/// A case: the model, its base setting, the variable, the value it gets and how many steps
/// it takes.
#[derive(Debug, Clone)]
struct Case {
    model: usize,
    base: Option<(&'static str, &'static str)>,
    name: String,
    value: Value,
    steps: u32,
}

#[derive(Debug, Clone)]
enum Value {
    Real(f64),
    Text(&'static str),
    /// A choice the model does not offer: refused when set.
    Wrong(&'static str),
}

fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for (model, m) in MODELS.iter().enumerate() {
        let scene = (m.create)();
        for v in scene.variables() {
            if v.causality == Causality::Output {
                continue;
            }
            let values: Vec<Value> = match (v.kind, &v.start) {
                (VariableKind::String, _) => {
                    let (valid, wrong) = choices(m.identifier, &v.name);
                    let mut values: Vec<Value> = valid.iter().map(|&s| Value::Text(s)).collect();
                    values.extend(wrong.map(Value::Wrong));
                    values
                }
                (VariableKind::Real, Start::Real(start)) => [v.min, v.max, *start]
                    .into_iter()
                    .map(Value::Real)
                    .collect(),
                (VariableKind::Real, _) => unreachable!("settable reals have a start value"),
            };
            let largest = |value: &Value| {
                MESH_SIZES.contains(&v.name.as_str())
                    && matches!(value, Value::Real(x) if *x == v.max)
            };
            for base in bases(m.identifier) {
                out.extend(values.iter().map(|value| Case {
                    model,
                    base,
                    name: v.name.clone(),
                    value: value.clone(),
                    steps: if largest(value) { 1 } else { 3 },
                }));
            }
        }
    }
    out
}

/// The FMI 2 value reference of a scalar by name.
fn vr(model: usize, name: &str) -> fmi2ValueReference {
    fmi2_scalars((MODELS[model].create)().variables())
        .iter()
        .position(|s| s.name == name)
        .unwrap() as u32
}

/// Runs one case in this process; panics on a status the standard does not allow here.
fn run(case: &Case) -> Vec<fmi2Status> {
    let m = &MODELS[case.model];
    let name = CString::new("fuzz").unwrap();
    let token = CString::new(m.token()).unwrap();
    let c = unsafe { fmi2Instantiate(name.as_ptr(), 1, token.as_ptr(), null(), null(), 0, 0) };
    assert!(!c.is_null());
    if let Some((name, value)) = case.base {
        let value = CString::new(value).unwrap();
        let status = unsafe { fmi2SetString(c, &vr(case.model, name), 1, &value.as_ptr()) };
        assert_eq!(status, OK, "the base setting");
    }
    let r = vr(case.model, &case.name);
    let set = unsafe {
        match &case.value {
            Value::Real(x) => fmi2SetReal(c, &r, 1, x),
            Value::Text(s) | Value::Wrong(s) => {
                let s = CString::new(*s).unwrap();
                fmi2SetString(c, &r, 1, &s.as_ptr())
            }
        }
    };
    let expected = if matches!(case.value, Value::Wrong(_)) {
        ERROR
    } else {
        OK
    };
    assert_eq!(
        set, expected,
        "a declared value is accepted, another refused, when set"
    );
    let mut statuses = vec![set];
    unsafe {
        statuses.push(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0));
        statuses.push(fmi2EnterInitializationMode(c));
        statuses.push(fmi2ExitInitializationMode(c));
    }
    let h = if m.identifier == "cutblock" {
        1.0
    } else {
        0.01
    };
    let scene = (m.create)();
    let outputs: Vec<u32> = fmi2_scalars(scene.variables())
        .iter()
        .enumerate()
        .filter(|(_, s)| scene.variables()[s.scene_vr as usize].causality == Causality::Output)
        .map(|(k, _)| k as u32)
        .collect();
    let mut failed = statuses[3] == ERROR;
    for k in 0..case.steps {
        if !failed {
            let s = unsafe { fmi2DoStep(c, f64::from(k) * h, h, 1) };
            statuses.push(s);
            failed = s == ERROR;
        }
        let mut values = vec![0.0; outputs.len()];
        let s = unsafe { fmi2GetReal(c, outputs.as_ptr(), outputs.len(), values.as_mut_ptr()) };
        assert!(matches!(s, OK | WARNING | ERROR), "read: status {s}");
        if failed {
            // After an error: reads are answered (or refused), steps refused, free works.
            let step = unsafe { fmi2DoStep(c, 0.0, h, 1) };
            assert_eq!(step, ERROR, "a step after an error is refused");
            break;
        }
    }
    assert!(
        statuses.iter().all(|s| matches!(*s, OK | WARNING | ERROR)),
        "{statuses:?}"
    );
    unsafe { fmi2FreeInstance(c) };
    statuses
}

/// The test (a harness of its own, `harness = false`): run with `FUZZ_CASE` = k it is the
/// child that runs case k; without, the parent that runs every case in children.
fn main() {
    if let Ok(index) = std::env::var("FUZZ_CASE") {
        let case = &cases()[index.parse::<usize>().unwrap()];
        let statuses = run(case);
        println!("{case:?} -> {statuses:?}");
        return;
    }
    // The parent: one test, listed and run as libtest does (so that cargo test and
    // cargo-nextest both find it).
    let trial = libtest_mimic::Trial::test(
        "every_declared_value_runs_or_is_refused",
        every_declared_value_runs_or_is_refused,
    );
    libtest_mimic::run(&libtest_mimic::Arguments::from_args(), vec![trial]).exit();
}

fn every_declared_value_runs_or_is_refused() -> Result<(), libtest_mimic::Failed> {
    let exe = std::env::current_exe().unwrap();
    let all = cases();
    let mut failures = Vec::new();
    let start = Instant::now();
    let spawn = |index: usize| {
        let child = Command::new(&exe)
            .env("FUZZ_CASE", index.to_string())
            .stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        (index, child, Instant::now())
    };
    // Two cases at a time (2 cores), each to its end: a case passes by what its calls
    // return, whatever it takes (the slowest refusals build a 500,000-triangle mesh first);
    // its time is printed, not judged (a case that never ends shows as the test nextest
    // names slow).
    let mut pending = 0..all.len();
    let mut running: Vec<_> = pending.by_ref().take(2).map(spawn).collect();
    while !running.is_empty() {
        std::thread::sleep(Duration::from_millis(20));
        let mut k = 0;
        while k < running.len() {
            let (index, child, begun) = &mut running[k];
            let case = &all[*index];
            let seconds = begun.elapsed().as_secs_f64();
            match child.try_wait().unwrap() {
                None => {
                    k += 1;
                    continue;
                }
                Some(s) if s.success() => {
                    if seconds > 5.0 {
                        println!("{case:?}: {seconds:.1} s");
                    }
                }
                Some(s) => {
                    let (_, child, _) = running.swap_remove(k);
                    let out = child.wait_with_output().unwrap();
                    failures.push(format!(
                        "{case:?}: exit {s}: {}{}",
                        String::from_utf8_lossy(&out.stdout),
                        String::from_utf8_lossy(&out.stderr)
                    ));
                    running.extend(pending.next().map(spawn));
                    continue;
                }
            }
            running.swap_remove(k);
            running.extend(pending.next().map(spawn));
        }
    }
    println!(
        "{} cases in {:.0} s",
        all.len(),
        start.elapsed().as_secs_f64()
    );
    if failures.is_empty() {
        Ok(())
    } else {
        Err(failures.join("\n").into())
    }
}
