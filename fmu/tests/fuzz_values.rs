//! Every declared value of both FMUs, one test each (cargo-nextest runs each in a process of
//! its own and ends one that runs past its time limit, `.config/nextest.toml`: a hang
//! fails):
//!
//! - **in range** (`in_range::…`), through the FMI 2 C ABI: each settable variable at its
//!   minimum, its maximum and its start value (string parameters: every choice), from the
//!   defaults and from the other kinematics or law. The set returns OK or Warning; the
//!   instance is initialized, stepped three times with every output read after each step
//!   (once at the largest mesh, [`MESH_SIZES`]) and freed. What the model cannot take is
//!   refused with Error (memory_limit, substeps, Newton increments, a configuration file
//!   that does not exist); after an Error the instance still answers reads and refuses
//!   steps; Fatal and Discard are never returned.
//! - **refused** (`refused::…`), through the instance core the ABI calls: each settable
//!   variable below its minimum, above its maximum, NaN, +∞ and −∞ (string parameters: a
//!   choice that does not exist). Each set returns Error with a message naming the
//!   variable and changes nothing: the instance then initializes with the variable at its
//!   start value and steps with OK.

// Unsafe code: the fuzz calls the FMI 2.0 C ABI.
#![allow(unsafe_code)]

use std::ffi::CString;
use std::ptr::null;
use std::sync::Arc;

use fmu::addressing::fmi2_scalars;
use fmu::exports::{Version, EXPORTS};
use fmu::fmi2::*;
use fmu::instance::Instance;
use fmu::machine::Status;
use libtest_mimic::{Arguments, Failed, Trial};
use models::scene::{Causality, Start, Variable, VariableKind};

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

/// The settings each in-range case starts from, per model: the defaults (for the abdomen
/// finite strain, whose Newton iterations are where unbounded work could hide), and the
/// other kinematics or law.
fn bases(model: &str) -> [Option<(&'static str, &'static str)>; 2] {
    match model {
        "abdomen" => [None, Some(("kinematics", "linear"))],
        _ => [None, Some(("material", "linear"))],
    }
}

/// The variables that size the mesh. At its maximum such a case is stepped once: a step
/// there takes the work of the first, and the history of three steps is tested at every
/// other value.
const MESH_SIZES: [&str; 5] = [
    "target_triangles",
    "mesh_subdivisions",
    "cells_x",
    "cells_y",
    "cells_z",
];

/// A value a case sets.
#[derive(Debug, Clone)]
enum Value {
    Real(f64),
    Text(&'static str),
}

/// An in-range case: the model, its base setting, the variable, the value and the steps.
#[derive(Debug, Clone)]
struct InRange {
    model: usize,
    base: Option<(&'static str, &'static str)>,
    name: String,
    value: Value,
    steps: u32,
}

/// The settable variables of model `model`.
fn settable(model: usize) -> Vec<Variable> {
    (EXPORTS[model].create)()
        .variables()
        .iter()
        .filter(|v| v.causality != Causality::Output)
        .cloned()
        .collect()
}

/// The values inside a variable's range: minimum, maximum and start (each once), or every
/// choice.
fn in_range_values(model: usize, v: &Variable) -> Vec<Value> {
    match (v.kind, &v.start) {
        (VariableKind::String, _) => {
            let valid = choices(EXPORTS[model].identifier, &v.name).0;
            valid.iter().map(|&s| Value::Text(s)).collect()
        }
        (VariableKind::Real, Start::Real(start)) => {
            let mut values = vec![v.min, v.max];
            if !values.contains(start) {
                values.push(*start);
            }
            values.into_iter().map(Value::Real).collect()
        }
        (VariableKind::Real, _) => unreachable!("settable reals have a start value"),
    }
}

/// The values outside a variable's range: beyond each end, NaN and ±∞ (reals); a choice
/// that does not exist (strings).
fn refused_values(model: usize, v: &Variable) -> Vec<Value> {
    match v.kind {
        VariableKind::String => choices(EXPORTS[model].identifier, &v.name)
            .1
            .map(Value::Text)
            .into_iter()
            .collect(),
        VariableKind::Real => {
            let beyond = |x: f64| x.abs().max(1.0);
            [
                v.min - beyond(v.min),
                v.max + beyond(v.max),
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ]
            .into_iter()
            .map(Value::Real)
            .collect()
        }
    }
}

/// The FMI 2 value reference of a scalar by name.
fn vr(model: usize, name: &str) -> fmi2ValueReference {
    fmi2_scalars((EXPORTS[model].create)().variables())
        .iter()
        .position(|s| s.name == name)
        .unwrap() as u32
}

/// The statuses the standard lets these calls return here.
fn allowed(s: fmi2Status) -> bool {
    matches!(s, OK | WARNING | ERROR)
}

/// Runs an in-range case through the C ABI; fails on a status the standard does not allow
/// here.
fn in_range(case: &InRange) -> Result<(), Failed> {
    let m = &EXPORTS[case.model];
    let name = CString::new("fuzz").unwrap();
    let token = CString::new(m.token()).unwrap();
    let c = unsafe { fmi2Instantiate(name.as_ptr(), 1, token.as_ptr(), null(), null(), 0, 0) };
    if c.is_null() {
        return Err("instantiation failed".into());
    }
    if let Some((name, value)) = case.base {
        let value = CString::new(value).unwrap();
        let status = unsafe { fmi2SetString(c, &vr(case.model, name), 1, &value.as_ptr()) };
        if status != OK {
            return Err(format!("the base setting returned {status}").into());
        }
    }
    let r = vr(case.model, &case.name);
    let set = unsafe {
        match &case.value {
            Value::Real(x) => fmi2SetReal(c, &r, 1, x),
            Value::Text(s) => {
                let s = CString::new(*s).unwrap();
                fmi2SetString(c, &r, 1, &s.as_ptr())
            }
        }
    };
    if !matches!(set, OK | WARNING) {
        return Err(format!("a value in range returned {set} when set").into());
    }
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
        statuses.push(s);
        if failed {
            // After an error: reads are answered (or refused), steps refused, free works.
            let step = unsafe { fmi2DoStep(c, 0.0, h, 1) };
            if step != ERROR {
                return Err(format!("a step after an error returned {step}").into());
            }
            break;
        }
    }
    unsafe { fmi2FreeInstance(c) };
    match statuses.iter().all(|&s| allowed(s)) {
        true => Ok(()),
        false => Err(format!("statuses {statuses:?}").into()),
    }
}

/// An instance of model `model` in FMI 2 on the instance core, its messages kept.
fn instance(model: usize) -> Instance {
    let token = EXPORTS[model].token();
    let silent: fmu::instance::Log = Arc::new(|_, _, _| {});
    Instance::create(Version::Fmi2, Some(&token), "fuzz", None, silent, false).expect("an instance")
}

/// Sets variable `name` of model `model` to each value outside its range: Error naming the
/// variable; then, the mesh small, the instance initializes with the variable still at its
/// start value and steps with OK.
fn refused(model: usize, v: &Variable) -> Result<(), Failed> {
    let mut i = instance(model);
    let r = vr(model, &v.name);
    for value in refused_values(model, v) {
        let status = match &value {
            Value::Real(x) => i.set_reals(&[r], &[*x]),
            Value::Text(s) => i.set_strings(&[r], &[s.to_string()]),
        };
        let messages: Vec<String> = i.take_messages().into_iter().map(|m| m.2).collect();
        if status != Status::Error {
            return Err(format!("{value:?} returned {status:?}").into());
        }
        if !messages.iter().any(|m| m.contains(&v.name)) {
            return Err(format!("{value:?}: no message names `{}`: {messages:?}", v.name).into());
        }
    }
    let small: &[(&str, f64)] = match EXPORTS[model].identifier {
        "abdomen" => &[("target_triangles", 200.0)],
        _ => &[("cells_x", 2.0), ("cells_y", 4.0), ("cells_z", 3.0)],
    };
    for &(name, x) in small.iter().filter(|(n, _)| *n != v.name) {
        i.set_reals(&[vr(model, name)], &[x]);
    }
    let mut statuses = vec![i.setup_experiment(0.0, None), i.enter_initialization()];
    if let Start::Real(start) = &v.start {
        let mut now = [f64::NAN];
        statuses.push(i.get_reals(&[r], &mut now));
        if now[0].to_bits() != start.to_bits() {
            return Err(format!("the refused values left {} at {}", v.name, now[0]).into());
        }
    }
    let h = EXPORTS[model].step_size;
    statuses.extend([i.exit_initialization(), i.do_step(0.0, h)]);
    match statuses.iter().all(|&s| s == Status::Ok) {
        true => Ok(()),
        false => Err(format!(
            "after the refused values: {statuses:?} {:?}",
            i.take_messages()
        )
        .into()),
    }
}

/// The trials: the in-range cases, and the refused values of each settable variable.
fn trials() -> Vec<Trial> {
    let mut out = Vec::new();
    for (model, m) in EXPORTS.iter().enumerate() {
        for v in settable(model) {
            for base in bases(m.identifier) {
                for value in in_range_values(model, &v) {
                    let largest = MESH_SIZES.contains(&v.name.as_str())
                        && matches!(value, Value::Real(x) if x == v.max);
                    let case = InRange {
                        model,
                        base,
                        name: v.name.clone(),
                        value,
                        steps: if largest { 1 } else { 3 },
                    };
                    let base = base.map_or("defaults".into(), |(k, v)| format!("{k}={v}"));
                    let label = match &case.value {
                        Value::Real(x) => format!("{x:e}"),
                        Value::Text(s) => format!("{s:?}"),
                    };
                    let name = format!(
                        "in_range::{}::{}::{}::{label}",
                        m.identifier, base, case.name
                    );
                    out.push(Trial::test(name, move || in_range(&case)));
                }
            }
            let name = format!("refused::{}::{}", m.identifier, v.name);
            out.push(Trial::test(name, move || refused(model, &v)));
        }
    }
    out
}

/// The test binary (`harness = false`): the trials listed and run as libtest does, so that
/// cargo test and cargo-nextest (one process per trial) both run them.
fn main() {
    libtest_mimic::run(&Arguments::from_args(), trials()).exit();
}
