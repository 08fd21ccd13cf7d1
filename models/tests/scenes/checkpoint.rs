//! A scene's saved state continues bit for bit: run, save, run on and record; then restore
//! the state into a fresh scene (and back into the first one) and run the same steps: every
//! output equals, to the last bit. Covered: every integrator, full and modal order, finite
//! strain (Newton's kept tangent), a stiffness change before the save and one pending at
//! it, a save inside Houbolt's start; the cut block with a growing cut, linear and
//! neo-Hookean, tet4 and tet10 (also in advances within a cell, where the uninterrupted run
//! reuses the replaced solver's storage), flank contact, a material change pending at the
//! save.

use models::scene::abdomen::Abdomen;
use models::scene::cutblock::CutBlock;
use models::scene::{outputs, Scene, SceneState};

/// Settings (reals, strings) before initialization.
type Settings<'a> = (&'a [(&'a str, f64)], &'a [(&'a str, &'a str)]);

/// Inputs and tunable parameters set before step k.
type Inputs = fn(usize) -> Vec<(&'static str, f64)>;

fn set(scene: &mut dyn Scene, name: &str, value: f64) {
    let vr = scene.lookup(name).unwrap();
    scene.set_real(vr, &[value]).unwrap();
}

fn build(make: fn() -> Box<dyn Scene>, (reals, strings): Settings<'_>) -> Box<dyn Scene> {
    let mut s = make();
    for &(n, v) in reals {
        set(s.as_mut(), n, v);
    }
    for &(n, v) in strings {
        let vr = s.lookup(n).unwrap();
        s.set_string(vr, v).unwrap();
    }
    s
}

/// Steps `from..to` of size `h` with `inputs`, every output's bits after each.
fn run(s: &mut dyn Scene, inputs: Inputs, h: f64, from: usize, to: usize) -> Vec<u64> {
    let outs: Vec<(u32, usize)> = outputs(s.variables()).map(|v| (v.vr, v.len)).collect();
    let mut bits = Vec::new();
    for k in from..to {
        for (n, v) in inputs(k) {
            set(s, n, v);
        }
        s.do_step(k as f64 * h, h).unwrap();
        for &(vr, len) in &outs {
            let mut x = vec![0.0; len];
            s.get_real(vr, &mut x).unwrap();
            bits.extend(x.iter().map(|x| x.to_bits()));
        }
    }
    bits
}

/// Saves after `at` steps; the rest of the run from the saved state, in a fresh scene and
/// in the first one set back, equals the uninterrupted run.
fn continues(
    make: fn() -> Box<dyn Scene>,
    settings: Settings<'_>,
    inputs: Inputs,
    h: f64,
    at: usize,
    steps: usize,
) -> SceneState {
    let mut a = build(make, settings);
    a.initialize(0.0).unwrap();
    run(a.as_mut(), inputs, h, 0, at);
    let saved = a.save();
    let expected = run(a.as_mut(), inputs, h, at, steps);
    let mut b = make();
    b.restore(&saved).unwrap();
    // (Compared as text: the outputs' slots in the values are NaN, which equals nothing.)
    assert_eq!(
        format!("{:?}", b.save()),
        format!("{saved:?}"),
        "a restored scene saves what it was given"
    );
    assert_eq!(
        run(b.as_mut(), inputs, h, at, steps),
        expected,
        "fresh scene"
    );
    a.restore(&saved).unwrap();
    assert_eq!(run(a.as_mut(), inputs, h, at, steps), expected, "set back");
    saved
}

fn abdomen() -> Box<dyn Scene> {
    Box::new(Abdomen::new())
}

fn cutblock() -> Box<dyn Scene> {
    Box::new(CutBlock::new())
}

const COARSE: [(&str, f64); 2] = [("target_triangles", 300.0), ("max_step", 1e-3)];

#[test]
fn the_abdomen_continues_bit_for_bit_with_every_integrator() {
    let none: Inputs = |_| Vec::new();
    for integrator in ["houbolt", "newmark"] {
        continues(
            abdomen,
            (&COARSE, &[("integrator", integrator)]),
            none,
            5e-3,
            7,
            15,
        );
    }
    // The explicit schemes below their stability limits.
    let fine = [("target_triangles", 300.0), ("max_step", 1e-5)];
    for integrator in ["central_difference", "rk4"] {
        continues(
            abdomen,
            (
                &fine,
                &[("integrator", integrator), ("kinematics", "linear")],
            ),
            none,
            2e-4,
            7,
            15,
        );
    }
    // Inside Houbolt's start: one substep per step, saved after the first.
    let one = [("target_triangles", 300.0), ("max_step", 5e-3)];
    continues(abdomen, (&one, &[]), none, 5e-3, 1, 6);
}

#[test]
fn the_abdomen_continues_bit_for_bit_in_modal_order_and_at_finite_strain() {
    let press: Inputs = |k| vec![("press_force", 0.01 * k as f64)];
    continues(
        abdomen,
        (
            &COARSE,
            &[("model_order", "modal"), ("kinematics", "linear")],
        ),
        press,
        5e-3,
        7,
        15,
    );
    continues(
        abdomen,
        (&COARSE, &[("kinematics", "finite")]),
        press,
        5e-3,
        7,
        15,
    );
}

#[test]
fn the_abdomen_continues_across_stiffness_changes() {
    // Changed at step 3 (applied before the save) and at step 7 (pending at the save).
    let stiffen: Inputs = |k| match k {
        3 => vec![("floor_E", 0.1)],
        7 => vec![("cavity_E", 0.008)],
        _ => Vec::new(),
    };
    for (order, kinematics) in [("full", "finite"), ("modal", "linear")] {
        continues(
            abdomen,
            (
                &COARSE,
                &[("model_order", order), ("kinematics", kinematics)],
            ),
            stiffen,
            5e-3,
            7,
            12,
        );
    }
    // The pending change: set, then saved before the step that applies it.
    let mut a = build(abdomen, (&COARSE, &[]));
    a.initialize(0.0).unwrap();
    run(a.as_mut(), |_| Vec::new(), 5e-3, 0, 4);
    set(a.as_mut(), "floor_E", 0.3);
    let saved = a.save();
    let expected = run(a.as_mut(), |_| Vec::new(), 5e-3, 4, 8);
    let mut b = abdomen();
    b.restore(&saved).unwrap();
    assert_eq!(run(b.as_mut(), |_| Vec::new(), 5e-3, 4, 8), expected);
}

#[test]
fn the_cut_block_continues_bit_for_bit() {
    let small = [("cells_x", 6.0), ("cells_y", 4.0), ("cells_z", 3.0)];
    let cut_and_pull: Inputs = |k| vec![("scalpel_x", 15.0 * k as f64), ("pull", 0.7 * k as f64)];
    // Advances of 0.5 mm within a cell: the uninterrupted run builds each topology into
    // the storage of the solver the advance before replaced (`Spare`), the restored one its
    // first after the save afresh.
    let advance: Inputs = |k| vec![("scalpel_x", 20.0 + 0.5 * k as f64), ("pull", 5.0)];
    for (inputs, steps) in [(cut_and_pull, 7), (advance, 8)] {
        for material in ["linear", "neo-hookean"] {
            for element in ["tet4", "tet10"] {
                continues(
                    cutblock,
                    (&small, &[("material", material), ("element", element)]),
                    inputs,
                    1.0,
                    3,
                    steps,
                );
            }
        }
    }
    // The blade still: Newton keeps its factorization from step to step (restored with the
    // state), and nothing its iterations on it remember outlives an increment.
    let pull: Inputs = |k| vec![("scalpel_x", 50.0), ("pull", 0.7 * k as f64)];
    continues(
        cutblock,
        (&small, &[("material", "neo-hookean")]),
        pull,
        1.0,
        3,
        7,
    );
    // Flanks in contact under a press; a material change pending at the save (step 4).
    let press: Inputs = |k| match k {
        0 => vec![("scalpel_x", 50.0)],
        4 => vec![("E", 0.05)],
        _ => vec![("press_force", 0.3 * k as f64)],
    };
    let settings: Settings<'_> = (&small, &[("material", "neo-hookean")]);
    let saved = continues(cutblock, settings, press, 1.0, 3, 7);
    let SceneState::CutBlock(_) = saved else {
        panic!("a cut-block state");
    };
}

#[test]
fn a_state_is_refused_by_the_other_scene_and_before_any_build_restores_the_values() {
    let a = build(abdomen, (&COARSE, &[]));
    let e = cutblock().restore(&a.save()).unwrap_err().to_string();
    assert!(e.contains("abdomen") && e.contains("cut block"), "{e}");
    // Saved before initialization: the values come back, nothing is built.
    let mut b = abdomen();
    b.restore(&a.save()).unwrap();
    let mut x = [0.0];
    b.get_real(b.lookup("target_triangles").unwrap(), &mut x)
        .unwrap();
    assert_eq!(x[0], 300.0);
    assert!(b.get_real(b.lookup("apex_uy").unwrap(), &mut x).is_err());
    b.initialize(0.0).unwrap();
}
