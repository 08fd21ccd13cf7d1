//! Abdomen scene benchmarks on the default configuration (6-node triangles graded towards
//! the junctions, 1,013 of them; Houbolt at the default 10 ms step): the finite-strain
//! default in full and in hyper-reduced order, the linear opt-in in full order and in modal
//! order (80 load-dependent Ritz vectors); a step of the pressure-driven press; one step of
//! each discretization and formulation;
//! the FMU's default experiment as a scene run (2 s, 200 steps).
//!
//! Run: `cargo bench -p models --bench abdomen`.

use divan::Bencher;
use models::scene::abdomen::Abdomen;
use models::scene::{Causality, Scene, SceneState};

fn main() {
    divan::main();
}

/// The model forms: the default (finite strain) in full and hyper-reduced order, and the
/// linear opt-in in full and modal order.
const MODELS: [&str; 4] = ["finite", "reduced", "linear", "modal"];

/// The default step (s).
const DT: f64 = 1e-2;

fn initialized(model: &str) -> Abdomen {
    let mut s = Abdomen::new();
    match model {
        "finite" => {}
        "reduced" => s.set_str("model_order", "reduced").unwrap(),
        _ => s.set_str("kinematics", "linear").unwrap(),
    }
    if model == "modal" {
        s.set_str("model_order", "modal").unwrap();
    }
    s.initialize(0.0).unwrap();
    s
}

/// Value references of the outputs, without the cavity-wide ones if not `cavity`.
fn outputs(s: &Abdomen, cavity: bool) -> Vec<u32> {
    s.variables()
        .iter()
        .filter(|v| v.causality == Causality::Output && v.name != "error_indicator")
        .filter(|v| cavity || !v.name.starts_with("cavity_"))
        .map(|v| v.vr)
        .collect()
}

/// Steps `s` to `until` (the press rising) and returns its saved state and time there.
fn pressed(mut s: Abdomen, until: f64) -> (SceneState, f64) {
    let mut t = 0.0;
    while t < until - 1e-9 {
        s.do_step(t, DT).unwrap();
        t += DT;
    }
    (s.save(), t)
}

/// Times `work` on a scene restored from `state` for each iteration (the restore, which
/// rebuilds the model, outside the timing), so every iteration steps from the same state.
fn from_state(bencher: Bencher, (state, t): &(SceneState, f64), work: impl Fn(&mut Abdomen, f64)) {
    let t = *t;
    bencher
        .with_inputs(|| {
            let mut s = Abdomen::new();
            s.restore(state).unwrap();
            s
        })
        .bench_local_values(|mut s| {
            work(&mut s, t);
            s
        });
}

/// Configuration → outline → mesh → assembly → factorization (for modal the basis, the
/// reduced system and the output rows; for reduced the training: static and dynamic
/// finite-strain solves, POD, ECSW).
#[divan::bench(args = MODELS, sample_count = 10)]
fn setup(bencher: Bencher, model: &str) {
    bencher.bench_local(|| initialized(model));
}

/// One Houbolt step of 10 ms half-way up the press (no outputs read), always from the
/// same state (the restore of a reduced model trains it again: ten samples).
#[divan::bench(args = MODELS, sample_count = 10, sample_size = 1)]
fn step(bencher: Bencher, model: &str) {
    let state = pressed(initialized(model), 0.5);
    from_state(bencher, &state, |s, t| s.do_step(t, DT).unwrap());
}

/// One 10 ms step of the pressure-driven press (`press_mode = "pressure"`, the defaults
/// otherwise) with the target rising from 2.00 to 2.04 kPa, from the state after a 0.5 s
/// ramp to 2 kPa: the step is taken again for each trial force (the cost against `step`).
#[divan::bench(args = ["finite", "linear"], sample_count = 10, sample_size = 1)]
fn step_at_pressure(bencher: Bencher, model: &str) {
    let mut s = Abdomen::new();
    s.set_str("press_mode", "pressure").unwrap();
    if model == "linear" {
        s.set_str("kinematics", "linear").unwrap();
    }
    s.initialize(0.0).unwrap();
    let mut t = 0.0;
    for k in 1..=50 {
        s.set("target_pressure", 0.002 * f64::from(k) / 50.0)
            .unwrap();
        s.do_step(t, DT).unwrap();
        t += DT;
    }
    from_state(bencher, &(s.save(), t), |s, t| {
        s.set("target_pressure", 0.00204).unwrap();
        s.do_step(t, DT).unwrap();
    });
}

/// One step and the outputs read: `floor` = all but the two cavity-wide von Mises
/// statistics (floor stresses, triangles along the floor, point displacements), `all`
/// = every output.
#[divan::bench(args = MODELS, consts = [false, true], sample_count = 10, sample_size = 1)]
fn step_with_outputs<const CAVITY: bool>(bencher: Bencher, model: &str) {
    let s = initialized(model);
    let vrs = outputs(&s, CAVITY);
    let state = pressed(s, 0.5);
    from_state(bencher, &state, |s, t| {
        s.do_step(t, DT).unwrap();
        let mut x = [0.0];
        for &vr in &vrs {
            s.get_real(vr, &mut x).unwrap();
        }
    });
}

/// One step and a read of the error indicator (its stiffness factorized by a read before
/// the timing): what the indicator adds to a step when an importer reads it at every one.
#[divan::bench(args = MODELS, sample_count = 10, sample_size = 1)]
fn step_with_indicator(bencher: Bencher, model: &str) {
    let s = initialized(model);
    let vr = s.lookup("error_indicator").unwrap();
    let (state, t) = pressed(s, 0.5);
    let mut x = [0.0];
    bencher
        .with_inputs(|| {
            let mut s = Abdomen::new();
            s.restore(&state).unwrap();
            s.get_real(vr, &mut [0.0]).unwrap();
            s
        })
        .bench_local_values(|mut s| {
            s.do_step(t, DT).unwrap();
            s.get_real(vr, &mut x).unwrap();
            s
        });
}

/// One press (2 s in 200 steps of 10 ms, the peak floor stress read at each) on a model set
/// up outside the timing: the cost of the steps over a whole press, resting phases and the
/// steep rise alike.
#[divan::bench(args = MODELS, sample_count = 5, sample_size = 1)]
fn press(bencher: Bencher, model: &str) {
    bencher
        .with_inputs(|| initialized(model))
        .bench_local_values(|mut s| {
            let vr = s.lookup("floor_stress_max").unwrap();
            let mut x = [0.0];
            for i in 0..200 {
                s.do_step(f64::from(i) * DT, DT).unwrap();
                s.get_real(vr, &mut x).unwrap();
            }
            s
        });
}

/// The FMU's default experiment as a scene run: set-up, then one press (2 s) in 200 steps of
/// 10 ms with the peak floor stress read at each — also a case of the shipped pelvis sweep.
#[divan::bench(args = MODELS, sample_count = 10)]
fn default_experiment(bencher: Bencher, model: &str) {
    bencher.bench_local(|| {
        let mut s = initialized(model);
        let vr = s.lookup("floor_stress_max").unwrap();
        let mut peak = f64::NEG_INFINITY;
        for i in 0..200 {
            s.do_step(f64::from(i) * DT, DT).unwrap();
            let mut x = [0.0];
            s.get_real(vr, &mut x).unwrap();
            peak = peak.max(x[0]);
        }
        peak
    });
}

/// The parts of a full-order Houbolt step on the default abdomen: the history product
/// M x_m + C x_c, and the triangular solves with the effective matrix.
mod full_order_parts {
    use super::*;
    use models::solve::{History, Structure};

    fn system() -> (Abdomen, usize) {
        let s = initialized("linear");
        let n = s.system().expect("initialized").0.n();
        (s, n)
    }

    #[divan::bench]
    fn history_product(bencher: Bencher) {
        let (s, n) = system();
        let structure: &Structure = s.system().unwrap().0;
        let (mut x_m, mut x_c, mut out) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
        let h: Vec<f64> = (0..n).map(|i| (i % 7) as f64).collect();
        let history = History {
            vectors: [&h, &h, &h],
            mass: [5e6, -4e6, 1e6],
            damping: [3e3, -1.5e3, 1e3 / 3.0],
        };
        bencher.bench_local(|| structure.add_history(history, &mut x_m, &mut x_c, &mut out));
    }

    #[divan::bench]
    fn solve(bencher: Bencher) {
        let (s, n) = system();
        let structure = s.system().unwrap().0;
        let mut chol = structure.analyze().unwrap();
        let mut a = vec![0.0; structure.dirichlet().nnz()];
        structure.effective(2e6, 11e3 / 6.0, &mut a);
        chol.factorize(structure.dirichlet().matrix(&a)).unwrap();
        let b: Vec<f64> = (0..n).map(|i| (i % 7) as f64).collect();
        let mut x = b.clone();
        bencher.bench_local(|| {
            x.copy_from_slice(&b);
            chol.solve_in_place(&mut x);
        });
    }
}

/// One full-order Houbolt step (10 ms, half-way up the default press) per model form and
/// discretization: the default (`finite graded 750`: finite strain, displacement tri6,
/// 1,013 triangles graded β = ½), the mixed element at finite strain and ν = 0.4999 on the
/// same mesh, finite strain on the graded 3,000-triangle mesh, the linear opt-in on the
/// default mesh, the seed's 3-node triangles (6,000 uniform) and the 6-node uniform mesh of
/// the defaults before issue 26 (1,500).
mod discretizations {
    use super::*;

    const CASES: [&str; 6] = [
        "finite graded 750",
        "finite mixed 750",
        "finite graded 3000",
        "linear graded 750",
        "linear tri3 6000",
        "linear tri6 1500",
    ];

    fn scene(case: &str) -> Abdomen {
        let words: Vec<&str> = case.split(' ').collect();
        let mut s = Abdomen::new();
        s.set_str("kinematics", words[0]).unwrap();
        match words[1] {
            "mixed" => {
                s.set_str("formulation", "mixed").unwrap();
                s.set("cavity_nu", 0.4999).unwrap();
            }
            "tri3" => {
                s.set_str("element", "tri3").unwrap();
                s.set("mesh_grading", 0.0).unwrap();
            }
            "tri6" => s.set("mesh_grading", 0.0).unwrap(),
            _ => {}
        }
        s.set("target_triangles", words[2].parse().unwrap())
            .unwrap();
        s.initialize(0.0).unwrap();
        s
    }

    #[divan::bench(args = CASES, sample_count = 30)]
    fn step(bencher: Bencher, case: &str) {
        let state = pressed(scene(case), 0.5);
        from_state(bencher, &state, |s, t| s.do_step(t, DT).unwrap());
    }
}
