//! Abdomen scene benchmarks on the default configuration (6-node triangles, ≈ 1,500 of them,
//! Houbolt, dt = 1 ms), full order and modal (80 load-dependent Ritz vectors); and one step
//! of each discretization on the mesh where the speed–error study finds the 6-node elements
//! within about 1 %, with the seed's former default (3-node, ≈ 6,000 triangles) beside it.
//!
//! Run: `cargo bench -p models --bench abdomen`.

use divan::Bencher;
use models::scene::abdomen::Abdomen;
use models::scene::{Causality, Scene};

fn main() {
    divan::main();
}

const ORDERS: [&str; 2] = ["full", "modal"];

fn initialized(order: &str) -> Abdomen {
    let mut s = Abdomen::new();
    s.set_str("model_order", order).unwrap();
    s.initialize(0.0).unwrap();
    s
}

/// Value references of the outputs, without the cavity-wide ones if not `cavity`.
fn outputs(s: &Abdomen, cavity: bool) -> Vec<u32> {
    s.variables()
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .filter(|v| cavity || !v.name.starts_with("cavity_"))
        .map(|v| v.vr)
        .collect()
}

/// Configuration → outline → mesh → assembly → factorization (and for modal the basis, the
/// reduced system and the output rows).
#[divan::bench(args = ORDERS, sample_count = 20)]
fn setup(bencher: Bencher, order: &str) {
    bencher.bench_local(|| initialized(order));
}

/// One Houbolt step (no outputs read).
#[divan::bench(args = ORDERS)]
fn step(bencher: Bencher, order: &str) {
    let mut s = initialized(order);
    let mut t = 0.0;
    bencher.bench_local(|| {
        s.do_step(t, 1e-3).unwrap();
        t += 1e-3;
    });
}

/// One step and the outputs read: `floor` = all but the two cavity-wide von Mises
/// statistics (floor stresses, triangles along the floor, point displacements), `all`
/// = every output.
#[divan::bench(args = ORDERS, consts = [false, true])]
fn step_with_outputs<const CAVITY: bool>(bencher: Bencher, order: &str) {
    let mut s = initialized(order);
    let vrs = outputs(&s, CAVITY);
    let mut t = 0.0;
    let mut x = [0.0];
    bencher.bench_local(|| {
        s.do_step(t, 1e-3).unwrap();
        t += 1e-3;
        for &vr in &vrs {
            s.get_real(vr, &mut x).unwrap();
        }
    });
}

/// A sweep case: set-up plus 1 s of simulated time at dt = 1 ms, peak floor stress read
/// every 10 ms.
#[divan::bench(args = ORDERS, sample_count = 10)]
fn sweep_case_one_second(bencher: Bencher, order: &str) {
    bencher.bench_local(|| {
        let mut s = initialized(order);
        let vr = s.lookup("floor_stress_max").unwrap();
        let mut peak = f64::NEG_INFINITY;
        for i in 0..1000 {
            s.do_step(i as f64 * 1e-3, 1e-3).unwrap();
            if i % 10 == 9 {
                let mut x = [0.0];
                s.get_real(vr, &mut x).unwrap();
                peak = peak.max(x[0]);
            }
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
        let s = initialized("full");
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

/// One full-order Houbolt step (dt = 1 ms, the default press) per discretization: `tri3`,
/// `tri6`, `mixed` on the nested mesh of the speed–error study that reaches about 1 % (the
/// 750-triangle base split twice: 12,592 triangles), `tri3 6000` (the default before issue
/// 12), `graded` (tri6 with `mesh_grading` = ½ at 750, 3,000 and 24,000 target triangles:
/// the study's cheapest meshes for 1 % and 0.1 %), and `finite` (tri6, finite strain) on the
/// default mesh after 0.3 s of pressing, where Newton's method has work to do.
mod discretizations {
    use super::*;

    const CASES: [&str; 9] = [
        "tri3 6000",
        "tri3 12592",
        "tri6 12592",
        "mixed 12592",
        "tri6 1500",
        "graded 750",
        "graded 3000",
        "graded 24000",
        "finite 1500",
    ];

    fn scene(case: &str) -> Abdomen {
        let (kind, mesh) = case.split_once(' ').unwrap();
        let mut s = Abdomen::new();
        let (element, formulation, kinematics) = match kind {
            "tri3" => ("tri3", "displacement", "linear"),
            "mixed" => ("tri6", "mixed", "linear"),
            "finite" => ("tri6", "displacement", "finite"),
            _ => ("tri6", "displacement", "linear"),
        };
        s.set_str("element", element).unwrap();
        s.set_str("formulation", formulation).unwrap();
        s.set_str("kinematics", kinematics).unwrap();
        if kind == "graded" {
            s.set("mesh_grading", 0.5).unwrap();
        }
        if mesh == "12592" {
            s.set("target_triangles", 750.0).unwrap();
            s.set("mesh_subdivisions", 2.0).unwrap();
        } else {
            s.set("target_triangles", mesh.parse().unwrap()).unwrap();
        }
        s.initialize(0.0).unwrap();
        s
    }

    #[divan::bench(args = CASES, sample_count = 30)]
    fn step(bencher: Bencher, case: &str) {
        let mut s = scene(case);
        let mut t = 0.0;
        while t < 0.3 {
            s.do_step(t, 1e-3).unwrap();
            t += 1e-3;
        }
        bencher.bench_local(|| {
            s.do_step(t, 1e-3).unwrap();
            t += 1e-3;
        });
    }
}
