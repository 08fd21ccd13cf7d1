//! The cut-block scene against exact solutions, against itself (refinement, monotonicity,
//! symmetry) and against the numbers seed 002 reports.

use models::scene::cutblock::{CutBlock, Setting, ACCURATE, PROFILE_STATIONS};
use models::scene::{Scene, SceneError};

/// The cut block with `settings` and `strings` set, initialized; the linear law unless
/// `strings` names another (most tests here hold the linear model to exact solutions).
fn scene(settings: &[(&str, f64)], strings: &[(&str, &str)]) -> CutBlock {
    let mut s = CutBlock::new();
    for (name, v) in settings {
        s.set(name, *v).unwrap();
    }
    for (name, v) in [("material", "linear")].iter().chain(strings) {
        let vr = s.lookup(name).unwrap();
        s.set_string(vr, v).unwrap();
    }
    s.initialize(0.0).unwrap();
    s
}

fn step(s: &mut CutBlock, inputs: &[(&str, f64)]) {
    for (name, v) in inputs {
        s.set(name, *v).unwrap();
    }
    s.do_step(0.0, 1.0).unwrap();
}

fn get(s: &mut CutBlock, name: &str) -> f64 {
    s.get(name).unwrap()
}

fn reaction(settings: &[(&str, f64)], inputs: &[(&str, f64)]) -> f64 {
    let mut s = scene(settings, &[]);
    step(&mut s, inputs);
    get(&mut s, "reaction_force")
}

#[test]
fn sliding_supports_give_exact_uniaxial_tension() {
    let (e, nu, pull) = (0.05, 0.43, 2.0);
    let mut s = scene(
        &[("E", e), ("nu", nu), ("cut_depth", 0.0)],
        &[("support", "sliding")],
    );
    step(&mut s, &[("pull", pull)]);
    let (lx, ly, lz) = (100.0, 80.0, 17.0);
    let strain = pull / ly;
    let force = get(&mut s, "reaction_force");
    let exact = e * lx * lz * strain;
    assert!(
        ((force - exact) / exact).abs() < 1e-10,
        "{force} vs {exact}"
    );
    let (mesh, u) = s.field().unwrap();
    for (n, p) in mesh.nodes().iter().enumerate() {
        let expect = [-nu * strain * p[0], strain * p[1], -nu * strain * p[2]];
        for d in 0..3 {
            assert!(
                (u[3 * n + d] - expect[d]).abs() < 1e-10 * pull,
                "node {n} dof {d}"
            );
        }
    }
}

#[test]
fn clamped_reaction_force_converges_under_refinement() {
    // Uncut and cut block at 0.5×, 1×, 2× the seed's cells.
    for depth in [0.0, 8.5] {
        let f: Vec<f64> = [0.5, 1.0, 2.0]
            .iter()
            .map(|m| {
                let cells = [
                    ("cells_x", 6.0 * m),
                    ("cells_y", 16.0 * m),
                    ("cells_z", 14.0 * m),
                    ("cut_depth", depth),
                ];
                reaction(&cells, &[("pull", 10.0), ("scalpel_x", 100.0)])
            })
            .collect();
        let (d1, d2) = ((f[1] - f[0]).abs(), (f[2] - f[1]).abs());
        println!(
            "depth {depth}: reaction at 0.5x, 1x, 2x cells: {f:.4?}; changes {d1:.4} then {d2:.4}"
        );
        assert!(d2 < 0.7 * d1, "not converging: {f:?}");
    }
}

#[test]
fn zero_depth_equals_uncut_and_cuts_weaken_monotonically() {
    let uncut = reaction(
        &[("cut_depth", 0.0)],
        &[("pull", 10.0), ("scalpel_x", 100.0)],
    );
    let before_scalpel = reaction(&[], &[("pull", 10.0), ("scalpel_x", 0.0)]);
    assert_eq!(uncut, before_scalpel);
    let mut previous = uncut;
    for depth in [2.0, 5.0, 8.5, 12.0] {
        let f = reaction(
            &[("cut_depth", depth)],
            &[("pull", 10.0), ("scalpel_x", 100.0)],
        );
        assert!(f < previous, "depth {depth}: {f} not below {previous}");
        previous = f;
    }
    let mut s = scene(&[], &[]);
    let mut previous = f64::INFINITY;
    for x in [0.0, 20.0, 40.0, 60.0, 80.0, 100.0] {
        step(&mut s, &[("pull", 10.0), ("scalpel_x", x)]);
        let f = get(&mut s, "reaction_force");
        let grew = get(&mut s, "cut_length") > 0.0;
        assert!(
            f < previous || !grew,
            "scalpel {x}: {f} not below {previous}"
        );
        previous = f;
    }
}

/// `CutBlock::profile` at the output lines reads exactly what the `profile_x*` outputs read;
/// off the block there is no surface.
#[test]
fn profiles_at_any_line_read_as_the_outputs_do() {
    let s = CutBlock::new();
    let stations: Vec<f64> = (0..PROFILE_STATIONS).map(|i| 0.5 * i as f64).collect();
    assert!(matches!(
        s.profile(50.0, &stations),
        Err(SceneError::NotInitialized { .. })
    ));
    let mut s = scene(&[], &[]);
    step(&mut s, &[("pull", 10.0), ("scalpel_x", 100.0)]);
    for x in [25, 50, 75] {
        let mut output = vec![0.0; PROFILE_STATIONS];
        let vr = s.lookup(&format!("profile_x{x}")).unwrap();
        s.get_real(vr, &mut output).unwrap();
        let line = s.profile(f64::from(x), &stations).unwrap();
        assert_eq!(
            line.iter().map(|z| z.to_bits()).collect::<Vec<_>>(),
            output.iter().map(|z| z.to_bits()).collect::<Vec<_>>(),
            "x = {x}"
        );
    }
    let between = s.profile(37.5, &stations).unwrap();
    assert!(between.iter().filter(|z| z.is_finite()).count() > 150);
    assert!(s
        .profile(130.0, &stations)
        .unwrap()
        .iter()
        .all(|z| z.is_nan()));
}

#[test]
fn full_length_cut_is_mirror_symmetric_in_x() {
    let mut s = scene(&[], &[]);
    step(&mut s, &[("pull", 10.0), ("scalpel_x", 100.0)]);
    let (mesh, u) = s.field().unwrap();
    let key = |p: &[f64; 3]| [p[0], p[1], p[2]].map(|c| (c * 1e6).round() as i64);
    let mut at: std::collections::HashMap<[i64; 3], Vec<usize>> = Default::default();
    for (n, p) in mesh.nodes().iter().enumerate() {
        at.entry(key(p)).or_default().push(n);
    }
    let scale = u.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let mut checked = 0;
    for (n, p) in mesh.nodes().iter().enumerate() {
        let mirror = at[&key(&[100.0 - p[0], p[1], p[2]])].clone();
        // Duplicated flank nodes share a position: pair the one on the same side.
        let m = *mirror
            .iter()
            .min_by(|&&a, &&b| {
                let d = |k: usize| (u[3 * k + 1] - u[3 * n + 1]).abs();
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        assert!(
            (u[3 * n] + u[3 * m]).abs() < 1e-9 * scale,
            "u_x at node {n}"
        );
        assert!((u[3 * n + 1] - u[3 * m + 1]).abs() < 1e-9 * scale);
        assert!((u[3 * n + 2] - u[3 * m + 2]).abs() < 1e-9 * scale);
        checked += 1;
    }
    assert_eq!(checked, mesh.nodes().len());
}

#[test]
fn loads_only_reuse_the_factorization_material_refactorizes_cut_rebuilds() {
    let mut s = scene(&[], &[]);
    let w0 = s.work();
    assert_eq!(
        (w0.topology_builds, w0.factorizations, w0.solves),
        (1, 1, 1)
    );
    for pull in [1.0, 2.0, 3.0] {
        step(&mut s, &[("pull", pull), ("press_force", pull * 0.1)]);
    }
    let w = s.work();
    assert_eq!((w.topology_builds, w.factorizations, w.solves), (1, 1, 4));
    step(&mut s, &[("E", 0.05)]);
    assert_eq!(s.work().factorizations, 2);
    step(&mut s, &[("scalpel_x", 40.0)]);
    assert_eq!(s.work().topology_builds, 2);
    assert_eq!(s.work().factorizations, 3);
}

#[test]
fn separating_cut_is_refused_with_a_clear_error() {
    let mut s = scene(&[("cut_depth", 17.0)], &[]);
    s.set("pull", 10.0).unwrap();
    s.set("scalpel_x", 100.0).unwrap();
    let err = s.do_step(0.0, 1.0).unwrap_err();
    assert!(matches!(err, SceneError::Separated { .. }), "{err}");
    assert_eq!(err.kind(), models::scene::ErrorKind::Runtime);
    assert!(
        err.to_string()
            .contains("separates the block into 2 bodies"),
        "{err}"
    );
    // The scene keeps its last good state, and a partial through-cut is fine.
    assert_eq!(get(&mut s, "cut_length"), 0.0);
    s.set("scalpel_x", 50.0).unwrap();
    s.do_step(0.0, 1.0).unwrap();
    assert!(get(&mut s, "reaction_force") > 0.0);
}

#[test]
fn hard_cases_edge_cut_zero_pull_and_press_on_the_flank() {
    // Cut one cell from the clamped face and one cell from the pulled face.
    for y in [5.0, 75.0] {
        let f = reaction(&[("y_cut", y)], &[("pull", 10.0), ("scalpel_x", 100.0)]);
        assert!(f.is_finite() && f > 0.0);
    }
    // Zero pull, no press: nothing moves.
    let mut s = scene(&[], &[]);
    step(&mut s, &[("scalpel_x", 100.0)]);
    assert_eq!(get(&mut s, "reaction_force"), 0.0);
    assert_eq!(
        s.field()
            .unwrap()
            .1
            .iter()
            .fold(0.0f64, |a, b| a.max(b.abs())),
        0.0
    );
    // Press on the flank at the tip of a half-length cut: the surface goes down, the force
    // balances through the supports.
    step(&mut s, &[("scalpel_x", 50.0), ("press_force", 0.5)]);
    let mut p = vec![0.0; PROFILE_STATIONS];
    s.get_real(s.lookup("profile_x50").unwrap(), &mut p)
        .unwrap();
    let lowest = p
        .iter()
        .copied()
        .filter(|z| z.is_finite())
        .fold(f64::INFINITY, f64::min);
    assert!(lowest < 17.0, "{lowest}");
    // 5 N (at the tip of a 40 mm cut) folds the flanks past the small-sliding range in one
    // go; split into parts, the load converges with the flanks apart. (At a 50 mm cut, where
    // this ran with five tetrahedra per cube, the springs now linearize again where they
    // hold and no warning is said: penetration 2.7 µm, 2026-11-27.)
    let mut s = scene(&[], &[]);
    step(&mut s, &[("scalpel_x", 40.0), ("press_force", 5.0)]);
    let depth = get(&mut s, "penetration");
    println!("linear, press 5 N on the flank: penetration {depth:e} mm");
    assert!(depth < 5e-3, "{depth}");
    // Its springs could not be linearized again where they hold: the answer keeps them
    // where they were caught, and says so once.
    let warnings = s.take_warnings();
    assert_eq!(
        warnings
            .iter()
            .filter(|w| w.contains("could not be linearized again"))
            .count(),
        1,
        "{warnings:?}"
    );
}

#[test]
fn near_incompressible_force_grows_with_nu_and_stays_finite() {
    let mut previous = 0.0;
    for nu in [0.3, 0.43, 0.49, 0.499, 0.4999] {
        let f = reaction(&[("nu", nu)], &[("pull", 10.0), ("scalpel_x", 100.0)]);
        println!("nu = {nu}: reaction {f:.4} N");
        assert!(f.is_finite() && f > previous);
        previous = f;
    }
}

/// The accurate setting sets the law, the element, the cells and the grading it names on a
/// scene (each read back changed from what it was), and the scene builds with them: tet10
/// on 7 × 18 × 10 cubes has (2·7 + 1)(2·18 + 1)(2·10 + 1) nodes uncut.
#[test]
fn the_accurate_setting_applies_its_parameters() {
    let mut s = CutBlock::new();
    let material = s.lookup("material").unwrap();
    s.set_string(material, "linear").unwrap();
    let defaults = ["cells_x", "cells_y", "cells_z", "mesh_grading"].map(|n| get(&mut s, n));
    ACCURATE.apply(&mut s).unwrap();
    let applied = ["cells_x", "cells_y", "cells_z", "mesh_grading"].map(|n| get(&mut s, n));
    assert_eq!(defaults, [6.0, 16.0, 14.0, 1.0]);
    assert_eq!(applied, [7.0, 18.0, 10.0, 2.25]);
    for (name, value) in [("material", "neo-hookean"), ("element", "tet10")] {
        let vr = s.lookup(name).unwrap();
        assert_eq!(s.get_string(vr).unwrap(), value);
    }
    s.initialize(0.0).unwrap();
    s.do_step(0.0, 1.0).unwrap();
    let (solid, _) = s.field().unwrap();
    assert_eq!(solid.nodes().len(), 15 * 37 * 21);
}

/// The settings the examples name: `accurate`, or a law and an element on the default
/// cells; an unknown law or element is refused naming it.
#[test]
fn a_named_setting_is_the_accurate_one_or_a_law_on_the_default_cells() {
    assert_eq!(Setting::named("accurate", "tet4").unwrap(), ACCURATE);
    let linear = Setting::named("linear", "tet4").unwrap();
    assert_eq!(
        (linear.law.name(), linear.element.name()),
        ("linear", "tet4")
    );
    assert_eq!((linear.cells, linear.grading), ([6.0, 16.0, 14.0], 1.0));
    for (material, element, named) in [("rubber", "tet4", "rubber"), ("linear", "hex8", "hex8")] {
        let err = Setting::named(material, element).unwrap_err().to_string();
        assert!(err.contains(named), "{err}");
    }
}

#[test]
fn bad_values_are_refused_by_name() {
    let mut s = CutBlock::new();
    for (name, v) in [
        ("E", 0.0),
        ("E", f64::NAN),
        ("nu", 0.5),
        ("cells_x", 0.0),
        ("mesh_grading", 0.5),
        ("mesh_grading", 5.0),
    ] {
        let err = s.set(name, v).unwrap_err().to_string();
        assert!(err.contains(name), "{err}");
    }
    s.set("cells_x", 2.5).unwrap();
    let err = s.initialize(0.0).unwrap_err().to_string();
    assert!(
        err.contains("cells_x") && err.contains("whole number"),
        "{err}"
    );
    let mut s = CutBlock::new();
    let vr = s.lookup("cut_strategy").unwrap();
    assert!(s
        .set_string(vr, "laser")
        .unwrap_err()
        .to_string()
        .contains("laser"));
    s.set("y_cut", 80.0).unwrap();
    assert!(s.initialize(0.0).unwrap_err().to_string().contains("y_cut"));
}

#[test]
fn deletion_strategy_is_softer_than_duplication_and_opens_by_a_layer() {
    let mut dup = scene(&[], &[]);
    let mut del = scene(&[], &[("cut_strategy", "delete")]);
    for s in [&mut dup, &mut del] {
        step(s, &[("pull", 10.0), ("scalpel_x", 100.0)]);
    }
    let (fd, fe) = (
        get(&mut dup, "reaction_force"),
        get(&mut del, "reaction_force"),
    );
    let (od, oe) = (get(&mut dup, "cut_opening"), get(&mut del, "cut_opening"));
    println!(
        "duplicate: F = {fd:.4} N, opening {od:.3} mm; delete: F = {fe:.4} N, opening {oe:.3} mm"
    );
    assert!(fe < fd);
    // The deleted layer is 5 mm thick at the seed's mesh.
    assert!(oe > od && oe > 5.0);
}

#[test]
fn gripping_the_pulled_face_stiffens_the_block() {
    let uncut = [("cut_depth", 0.0)];
    let clamped = reaction(&uncut, &[("pull", 10.0)]);
    let mut s = scene(&uncut, &[("support", "gripped")]);
    step(&mut s, &[("pull", 10.0)]);
    let gripped = get(&mut s, "reaction_force");
    let (solid, u) = s.field().unwrap();
    let pulled = (0..solid.nodes().len()).filter(|&n| solid.nodes()[n][1] == 80.0);
    for n in pulled {
        assert_eq!((u[3 * n], u[3 * n + 1], u[3 * n + 2]), (0.0, 10.0, 0.0));
    }
    assert!(gripped > clamped, "{gripped} vs {clamped}");
}

/// Largest overlap in y of twin flank nodes (duplicates of one node, y < y_cut side first).
fn twin_overlap(s: &CutBlock) -> f64 {
    let (mesh, u) = s.field().unwrap();
    let mut at: std::collections::HashMap<[i64; 3], Vec<usize>> = Default::default();
    for (n, p) in mesh.nodes().iter().enumerate() {
        at.entry(p.map(|c| (c * 1e6).round() as i64))
            .or_default()
            .push(n);
    }
    at.values()
        .filter(|v| v.len() == 2)
        .map(|v| {
            let y = |n: usize| u[3 * n + 1];
            // The original node (lower index) is on the front flank.
            y(v[0].min(v[1])) - y(v[0].max(v[1]))
        })
        .fold(0.0, f64::max)
}

fn compressed(contact: &str, pull: f64) -> CutBlock {
    let mut s = scene(&[], &[("contact", contact)]);
    step(&mut s, &[("pull", pull), ("scalpel_x", 100.0)]);
    s
}

#[test]
fn closing_flanks_are_kept_apart_by_contact() {
    let (mut with, mut without) = (compressed("penalty", -3.0), compressed("none", -3.0));
    let (fw, fo) = (
        get(&mut with, "reaction_force"),
        get(&mut without, "reaction_force"),
    );
    let (pw, po) = (get(&mut with, "penetration"), twin_overlap(&without));
    let points = get(&mut with, "contact_points");
    println!("compressed by 3 mm: reaction with contact {fw:.4} N, without {fo:.4} N; penetration {pw:.6} mm vs {po:.4} mm; {points} contact points");
    // Compression: the reaction is negative; contact makes the block stiffer.
    assert!(fw < fo && fo < 0.0, "{fw} {fo}");
    assert!(points > 0.0);
    // The penetration left by the penalty (measured 0.00017 mm, as docs/theory/cutblock.md
    // says) is four orders of magnitude below what the flanks overlap without contact
    // (1.90 mm).
    assert!(pw < 2e-4, "{pw}");
    assert!((po - 1.90).abs() < 0.01, "{po}");
}

#[test]
fn open_flanks_give_the_contact_free_answer() {
    let (mut with, mut without) = (compressed("penalty", 10.0), compressed("none", 10.0));
    assert_eq!(get(&mut with, "contact_points"), 0.0);
    let (fw, fo) = (
        get(&mut with, "reaction_force"),
        get(&mut without, "reaction_force"),
    );
    assert!(((fw - fo) / fo).abs() < 1e-10, "{fw} vs {fo}");
    // Open flanks cost no extra factorization.
    assert_eq!(with.work().factorizations, 2);
}

/// cells 400 × 400 × 400 lie inside the declared ranges; the model would need hundreds of
/// gigabytes. It is refused by its estimate before anything is allocated (the message is
/// the estimate's: a real allocation of that size would abort the test), and a model that
/// fits still builds.
#[test]
fn a_block_above_the_memory_limit_is_refused_before_it_is_allocated() {
    let mut s = CutBlock::new();
    for c in ["cells_x", "cells_y", "cells_z"] {
        s.set(c, 400.0).unwrap();
    }
    let e = s.initialize(0.0).unwrap_err().to_string();
    assert!(
        e.contains("the block mesh and its sparse system") && e.contains("memory_limit = 8000 MB"),
        "{e}"
    );
    // The default block (about 15 MB with its factor) builds under 100 MB, not under 5 MB.
    scene(&[("memory_limit", 100.0)], &[]);
    let mut s = CutBlock::new();
    s.set("memory_limit", 5.0).unwrap();
    let e = s.initialize(0.0).unwrap_err().to_string();
    assert!(e.contains("memory_limit = 5 MB"), "{e}");
}

/// No adhesion and no memory: a cut closed by compression and then pulled open ends as a
/// cut pulled open at once (no node held), and a cut pulled open and then closed by a
/// negative pull, with or without a press on the flank, ends as a cut closed at once (the
/// same nodes held) — reaction and opening to 1e-9 — for the linear and the neo-Hookean
/// law, with the full cut and with the front inside a cell of the uniform grid. Before the
/// springs were linearized again where they hold, the neo-Hookean full cut closed without
/// a press ended 8e-8 apart in the reaction and 1.4e-5 mm in the opening. (The
/// re-linearization stops at changes of 1e-6 of B; the pairs then agreed to 2e-13,
/// measured 2026-11-27: the margin to 1e-9 is measured, not derived.)
#[test]
fn contact_does_not_depend_on_the_loading_history() {
    let mut failures = Vec::new();
    for (material, front) in [
        ("linear", 100.0),
        ("neo-hookean", 100.0),
        ("linear", 58.3),
        ("neo-hookean", 58.3),
    ] {
        // (pull, press) at each step; returns reaction, opening and the held nodes.
        let run = |loads: &[(f64, f64)]| {
            let mut s = scene(&[], &[("material", material)]);
            for &(pull, press) in loads {
                step(
                    &mut s,
                    &[("scalpel_x", front), ("pull", pull), ("press_force", press)],
                );
            }
            [
                get(&mut s, "reaction_force"),
                get(&mut s, "cut_opening"),
                get(&mut s, "contact_points"),
            ]
        };
        let pairs = [
            (
                "opened",
                run(&[(-3.0, 0.0), (10.0, 0.0)]),
                run(&[(10.0, 0.0)]),
            ),
            (
                "closed",
                run(&[(10.0, 0.0), (-3.0, 0.0)]),
                run(&[(-3.0, 0.0)]),
            ),
            (
                "closed and pressed",
                run(&[(10.0, 0.0), (-3.0, 0.5)]),
                run(&[(-3.0, 0.5)]),
            ),
        ];
        for (end, history, straight) in pairs {
            println!("{material}, front {front}, {end}: {history:?} vs straight {straight:?}");
            let same = history[2] == straight[2]
                && (history[2] == 0.0) == (end == "opened")
                && (history[0] - straight[0]).abs() <= 1e-9 * straight[0].abs()
                && (history[1] - straight[1]).abs() <= 1e-9 * straight[1].abs();
            if !same {
                failures.push(format!(
                    "{material}, front {front}, {end}: {history:?} vs straight {straight:?}"
                ));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Small-strain limit: the neo-Hookean and linear answers (reaction, bottom lift, opening)
/// differ by a relative amount proportional to the pull (×0.1 for a pull ten times smaller,
/// within 20 %), the first-order agreement of the two laws; at 0.001 mm all three agree to
/// 1.5e-4. Measured at 0.01 mm: reaction 2e-6 (tet4) and 1.04e-4 (tet10, whose crack tip
/// resolves larger strains), bottom lift 1.0e-3 / 1.4e-3, opening 4e-4 / 5e-4.
#[test]
fn neo_hookean_at_a_hundredth_of_a_millimetre_equals_linear() {
    for element in ["tet4", "tet10"] {
        let run = |material: &str, pull: f64| {
            let mut s = scene(
                &[("cells_x", 3.0), ("cells_y", 8.0), ("cells_z", 7.0)],
                &[("material", material), ("element", element)],
            );
            step(&mut s, &[("scalpel_x", 100.0), ("pull", pull)]);
            ["reaction_force", "bottom_lift", "cut_opening"].map(|o| get(&mut s, o))
        };
        let differences = [0.01, 0.001].map(|pull| {
            let (linear, finite) = (run("linear", pull), run("neo-hookean", pull));
            println!("{element}, pull {pull}: linear {linear:?}, neo-Hookean {finite:?}");
            std::array::from_fn::<f64, 3, _>(|k| ((linear[k] - finite[k]) / linear[k]).abs())
        });
        println!("{element}: relative differences {differences:?}");
        for k in 0..3 {
            assert!(differences[1][k] <= 1.5e-4, "{element}: {differences:?}");
            let ratio = differences[1][k] / differences[0][k];
            assert!((ratio - 0.1).abs() < 0.02, "{element}: {differences:?}");
        }
    }
}

fn neo_hookean(settings: &[(&str, f64)]) -> CutBlock {
    scene(settings, &[("material", "neo-hookean")])
}

/// Hard cases with the neo-Hookean law: a 30 mm pull (37.5 % nominal strain) converges, the
/// force between two and three times the 10 mm one (an incompressible neo-Hookean bar has
/// the nominal stress μ(λ − λ⁻²): 2.5 times as much at the block's stretch 1.375 as at
/// 1.125; 17.98 N against 6.85 N measured, 2.6); a 10 mm compression closes
/// the cut on contact, the flanks penetrating by less than a quarter of the scanner noise
/// (0.005 mm; 0.00039 measured, 2026-11-27); ν = 0.499 converges, stiffer than ν = 0.45;
/// the flank pressed at the tip of a half cut with 2 N or 5 N converges on contact, with
/// 20 N at once is refused naming `press_force`, the unloaded state and its outputs kept.
#[test]
fn neo_hookean_hard_cases_converge_or_fail_keeping_the_last_state() {
    let mut s = neo_hookean(&[]);
    step(&mut s, &[("scalpel_x", 100.0), ("pull", 10.0)]);
    let at_10 = get(&mut s, "reaction_force");
    s.set("pull", 30.0).unwrap();
    s.do_step(1.0, 1.0).unwrap();
    let at_30 = get(&mut s, "reaction_force");
    println!("pull 30 mm converged: {at_30:.4} N (10 mm: {at_10:.4} N)");
    assert!(
        at_30 > 2.0 * at_10 && at_30 < 3.0 * at_10,
        "{at_30} vs {at_10}"
    );

    let mut s = neo_hookean(&[]);
    step(&mut s, &[("scalpel_x", 100.0), ("pull", -10.0)]);
    let (f, depth, held) = (
        get(&mut s, "reaction_force"),
        get(&mut s, "penetration"),
        get(&mut s, "contact_points"),
    );
    println!("pull −10 mm: {f:.4} N, penetration {depth:e} mm, {held} held");
    assert!(f < 0.0 && held > 0.0 && depth < 5e-3, "{f} {depth} {held}");

    let force_at = |nu: f64| {
        let mut s = neo_hookean(&[("nu", nu)]);
        step(&mut s, &[("scalpel_x", 100.0), ("pull", 10.0)]);
        get(&mut s, "reaction_force")
    };
    let (stiff, soft) = (force_at(0.499), force_at(0.45));
    println!("ν = 0.499: {stiff:.4} N, ν = 0.45: {soft:.4} N");
    assert!(stiff.is_finite() && stiff > soft, "{stiff} vs {soft}");

    // Pressing the flank at the tip of a half cut: 2 N and 5 N at once close the cut onto
    // contact (penetration 1.1 and 2.7 µm, below the small-sliding limit of 5 µm). 20 N at
    // once folds the flanks beyond the contact's small-sliding range: refused, naming
    // press_force, with the unloaded state and its outputs kept.
    for press in [2.0, 5.0] {
        let mut s = neo_hookean(&[]);
        step(&mut s, &[("scalpel_x", 50.0), ("press_force", press)]);
        let at = ["reaction_force", "penetration", "contact_points"].map(|o| get(&mut s, o));
        println!("press {press} N on the flank: {at:?}");
        assert!(at[1] < 5e-3 && at[2] > 0.0, "{at:?}");
    }
    let mut s = neo_hookean(&[]);
    step(&mut s, &[("scalpel_x", 50.0)]);
    s.set("press_force", 20.0).unwrap();
    let e = s.do_step(1.0, 1.0).unwrap_err();
    println!("press 20 N: {e}");
    assert!(
        e.to_string().contains("press_force") && e.to_string().contains("small-sliding"),
        "{e}"
    );
    let field = s
        .field()
        .unwrap()
        .1
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()));
    assert_eq!(field, 0.0, "the unloaded state is kept");
    for output in [
        "reaction_force",
        "penetration",
        "contact_points",
        "cut_opening",
    ] {
        assert_eq!(get(&mut s, output), 0.0, "{output} of the unloaded state");
    }
}

/// A press whose flank contact set cycles when it is applied at once is retried in parts,
/// as one that slides the flanks through each other is: the default block, fully cut and
/// closed by a 1 mm compression, pressed by 0.5 N (at once the held set came back after 7
/// solves and the step failed, 2026-11-28), converges with the flanks held apart within the
/// small-sliding limit (5 µm), the top pressed down and the block still in compression.
#[test]
fn a_press_whose_contact_set_cycles_at_once_converges_in_parts() {
    let mut s = neo_hookean(&[]);
    step(&mut s, &[("scalpel_x", 100.0), ("pull", -1.0)]);
    step(&mut s, &[("press_force", 0.5)]);
    let at = [
        "reaction_force",
        "penetration",
        "contact_points",
        "bottom_lift",
    ]
    .map(|o| get(&mut s, o));
    println!("pull −1 mm, then press 0.5 N: {at:?}");
    assert!(
        at[0] < 0.0 && at[1] < 5e-3 && at[2] > 0.0 && at[3] < 0.0,
        "{at:?}"
    );
}

/// A press on closed flanks says once per run that its answer may depend on the loading
/// history (one step or two end apart there, docs/theory/cutblock.md); a press on open
/// flanks and flanks closed without a press do not.
#[test]
fn a_press_on_closed_flanks_warns_once_that_its_answer_may_depend_on_the_history() {
    let mut s = neo_hookean(&[]);
    let press_warnings = |s: &mut CutBlock| {
        s.take_warnings()
            .iter()
            .filter(|w| w.contains("acts on closed flanks"))
            .count()
    };
    step(
        &mut s,
        &[("scalpel_x", 100.0), ("pull", 5.0), ("press_force", 0.25)],
    );
    assert_eq!(get(&mut s, "contact_points"), 0.0, "open flanks");
    assert_eq!(press_warnings(&mut s), 0);
    step(&mut s, &[("pull", -2.0), ("press_force", 0.0)]);
    assert!(get(&mut s, "contact_points") > 0.0, "closed flanks");
    assert_eq!(press_warnings(&mut s), 0);
    step(&mut s, &[("press_force", 0.25)]);
    assert_eq!(press_warnings(&mut s), 1);
    step(&mut s, &[("press_force", 0.3)]);
    assert!(get(&mut s, "contact_points") > 0.0, "still closed");
    assert_eq!(press_warnings(&mut s), 0, "once per run");
}

/// A pull change that would take more than `MAX_INCREMENTS` Newton load increments is
/// refused before any work, naming `max_increment` and the change, and the scene stays
/// usable: the declared minimum `max_increment` = 1e-6 mm with a 1 mm pull (10⁶
/// increments) is refused; 1,000 increments are allowed.
#[test]
fn a_pull_change_of_too_many_newton_increments_is_refused_by_name() {
    use models::scene::cutblock::MAX_INCREMENTS;
    let mut s = neo_hookean(&[("cells_x", 2.0), ("cells_y", 4.0), ("cells_z", 2.0)]);
    step(&mut s, &[("max_increment", 1e-6), ("scalpel_x", 100.0)]);
    s.set("pull", 1.0).unwrap();
    let e = s.do_step(1.0, 1.0).unwrap_err();
    assert!(matches!(e, SceneError::TooManyIncrements { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("pull changes by 1 mm")
            && text.contains("max_increment = 0.000001 mm")
            && text.contains("1000000 Newton load increments"),
        "{text}"
    );
    assert_eq!(
        get(&mut s, "reaction_force"),
        0.0,
        "the unloaded state is kept"
    );
    // Exactly the limit is allowed.
    let before = s.work().increments;
    step(&mut s, &[("max_increment", 1.0 / MAX_INCREMENTS)]);
    assert!(get(&mut s, "reaction_force") > 0.0);
    assert_eq!(s.work().increments - before, MAX_INCREMENTS as u64);
}

/// The load increments are a path to the equilibrium, not part of it: the seed's scenario
/// (full cut, 10 mm pull in one step) in increments of 1, 2.5, 5 (the default) and 10 mm gives
/// the same reaction, opening and lift to 1e-8, neo-Hookean and St. Venant–Kirchhoff.
#[test]
fn the_load_increment_does_not_change_the_equilibrium() {
    for material in ["neo-hookean", "stvk"] {
        let at = |max_increment: f64| {
            let mut s = scene(
                &[("max_increment", max_increment)],
                &[("material", material)],
            );
            step(&mut s, &[("scalpel_x", 100.0), ("pull", 10.0)]);
            ["reaction_force", "cut_opening", "bottom_lift"].map(|name| get(&mut s, name))
        };
        let default = at(5.0);
        for max_increment in [1.0, 2.5, 10.0] {
            for (a, b) in at(max_increment).iter().zip(&default) {
                assert!(
                    (a - b).abs() <= 1e-8 * b.abs(),
                    "{material}, max_increment {max_increment}: {a} vs {b}"
                );
            }
        }
    }
}

/// The largest nodal u_z along the bottom line on the cut plane (y = 45 mm, z = 0).
fn nodal_lift(s: &CutBlock) -> f64 {
    let (solid, u) = s.field().unwrap();
    let p = solid.nodes();
    (0..p.len())
        .filter(|&n| p[n][2] == 0.0 && p[n][1] == 45.0)
        .map(|n| u[3 * n + 2])
        .fold(f64::NEG_INFINITY, f64::max)
}

/// An advance that leaves a sliver at an end face starts from the path extrapolated on the
/// old mesh slid to the new front, not on its own nodes (the accurate setting at a 10 mm
/// pull: from 52 to 53 mm the node plane at 99.904 mm leaves a 0.096 mm cell at the far
/// face, which the nodes' displacements extrapolated through 50, 51 and 52 mm invert; the
/// advance then went back to the unloaded block, 21 iterations and 6 factorizations along
/// `blade_path` on 2026-12-06): it does not go back to the unloaded block, and takes fewer
/// than two thirds of the iterations of the block cut to 53 mm unloaded and then pulled
/// (measured 10 against 21), to the same equilibrium.
#[test]
fn an_advance_that_leaves_a_sliver_starts_on_the_slid_mesh() {
    let mut s = CutBlock::new();
    ACCURATE.apply(&mut s).unwrap();
    s.initialize(0.0).unwrap();
    for input in [
        ("pull", 10.0),
        ("scalpel_x", 50.0),
        ("scalpel_x", 51.0),
        ("scalpel_x", 52.0),
    ] {
        step(&mut s, &[input]);
    }
    let before = s.work();
    step(&mut s, &[("scalpel_x", 53.0)]);
    let work = s.work();
    assert_eq!(
        work.analyses, before.analyses,
        "52 and 53 mm have one pattern"
    );
    assert_eq!(
        work.returns_to_unloaded, before.returns_to_unloaded,
        "no return to the unloaded block"
    );
    let iterations = work.iterations - before.iterations;
    let mut plain = CutBlock::new();
    ACCURATE.apply(&mut plain).unwrap();
    plain.initialize(0.0).unwrap();
    step(&mut plain, &[("scalpel_x", 53.0)]);
    let before = plain.work();
    step(&mut plain, &[("pull", 10.0)]);
    let plain_iterations = plain.work().iterations - before.iterations;
    println!(
        "iterations {iterations} from the slid mesh, {plain_iterations} from the unloaded block"
    );
    assert!(
        3 * iterations < 2 * plain_iterations,
        "{iterations} against {plain_iterations}"
    );
    for name in ["reaction_force", "bottom_lift"] {
        let (a, b) = (get(&mut s, name), get(&mut plain, name));
        assert!((a / b - 1.0).abs() < 1e-9, "{name}: {a} against {b}");
    }
}

/// The bottom lift is the maximum of the element field along its line: with tet10 above
/// every nodal value where the peak falls inside an edge (the graded full cut at a 10 mm
/// pull, neo-Hookean: measured 3.011396 against 3.011086 mm on 2026-11-27).
#[test]
fn the_bottom_lift_is_the_fields_maximum_along_its_line() {
    let strings = [("material", "neo-hookean"), ("element", "tet10")];
    let mut s = scene(&[("mesh_grading", 2.0)], &strings);
    step(&mut s, &[("pull", 10.0), ("scalpel_x", 100.0)]);
    let (lift, nodal) = (get(&mut s, "bottom_lift"), nodal_lift(&s));
    assert!(lift > nodal + 2e-4 && lift < nodal + 5e-4, "{lift} {nodal}");
}

/// A blade advance that changes the mesh (the accurate setting at a 10 mm pull: from 53 to
/// 54 mm the cell at x = 100 mm vanishes) starts Newton from the equilibria at 51, 52 and
/// 53 mm extrapolated to 54 mm on the old mesh slid there and carried onto the new one, and
/// the new mesh's path from the equilibrium at 53 mm carried onto it: the advance to 54 mm
/// takes fewer than half the iterations of the same advance from the last equilibrium
/// carried over (the block cut to 53 mm unloaded, then pulled: no equilibrium of its path
/// is under the pull, so none is carried either; measured 5 against 19, 2026-12-06), and
/// so does the next one to 55 mm (measured 7 against 19); both end at the same equilibria.
#[test]
fn an_advance_that_changes_the_mesh_starts_from_the_extrapolated_path() {
    let advances = |steps: &[(&str, f64)]| {
        let mut s = CutBlock::new();
        ACCURATE.apply(&mut s).unwrap();
        s.initialize(0.0).unwrap();
        for &input in steps {
            step(&mut s, &[input]);
        }
        [54.0, 55.0].map(|x| {
            let before = s.work();
            step(&mut s, &[("scalpel_x", x)]);
            let after = s.work();
            let changed = after.analyses - before.analyses == 1;
            assert_eq!(changed, x == 54.0, "the mesh changes at 54 mm only");
            let outputs = ["reaction_force", "bottom_lift"].map(|n| get(&mut s, n));
            (after.iterations - before.iterations, outputs)
        })
    };
    let along = advances(&[
        ("pull", 10.0),
        ("scalpel_x", 51.0),
        ("scalpel_x", 52.0),
        ("scalpel_x", 53.0),
    ]);
    let plain = advances(&[("scalpel_x", 53.0), ("pull", 10.0)]);
    for ((iterations, outputs), (plain_iterations, plain_outputs)) in along.iter().zip(&plain) {
        println!(
            "iterations {iterations} along the path, {plain_iterations} from the last equilibrium"
        );
        assert!(
            2 * iterations < *plain_iterations,
            "{along:?} against {plain:?}"
        );
        for (a, b) in outputs.iter().zip(plain_outputs) {
            assert!((a / b - 1.0).abs() < 1e-9, "{a} against {b}");
        }
    }
}
