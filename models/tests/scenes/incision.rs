//! The incision follows the blade: it ends where the blade is, at any position, and never
//! heals; the outputs change continuously as the blade advances.

use models::scene::cutblock::{CutBlock, SNAP};
use models::scene::Scene;

/// The cut block with `reals` and `strings` set, initialized.
fn block(reals: &[(&str, f64)], strings: &[(&str, &str)]) -> CutBlock {
    let mut s = CutBlock::new();
    for (name, v) in reals {
        s.set(name, *v).unwrap();
    }
    for (name, v) in strings {
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
    if let Err(e) = s.do_step(0.0, 1.0) {
        panic!("{inputs:?}: {e}");
    }
}

/// Every output, scalars and profiles, in table order.
fn outputs(s: &mut CutBlock) -> Vec<f64> {
    outputs_but(s, &[])
}

/// Every output but those named in `skip`, in table order.
fn outputs_but(s: &mut CutBlock, skip: &[&str]) -> Vec<f64> {
    let outputs: Vec<(u32, usize)> = models::scene::outputs(s.variables())
        .filter(|v| !skip.contains(&v.name.as_str()))
        .map(|v| (v.vr, v.len))
        .collect();
    outputs
        .into_iter()
        .flat_map(|(vr, len)| {
            let mut x = vec![0.0; len];
            s.get_real(vr, &mut x).unwrap();
            x
        })
        .collect()
}

/// Nodes of the solid at `p` (to 1e-9 mm).
fn nodes_at(s: &CutBlock, p: [f64; 3]) -> usize {
    let (solid, _) = s.field().unwrap();
    solid
        .nodes()
        .iter()
        .filter(|q| (0..3).all(|d| (q[d] - p[d]).abs() < 1e-9))
        .count()
}

/// Blade paths with retractions, positions beyond both ends and on the old cell planes:
/// `cut_length` is the furthest position the blade has reached, clamped to the block, to
/// 1e-9 mm, after every step. On the top edge of the cut plane the front is one shared node
/// and the node plane a cell behind it holds two (one per flank); for tet4 and tet10,
/// linear and neo-Hookean.
#[test]
fn the_incision_ends_at_the_furthest_blade_position() {
    let coarse = [
        ("cells_x", 3.0),
        ("cells_y", 4.0),
        ("cells_z", 4.0),
        ("pull", 1.0),
    ];
    // A fixed pseudo-random walk (a linear congruential generator): steps of −15 … +25 mm,
    // kept in 0 … 120 mm.
    let mut state: u64 = 2026;
    let mut x: f64 = 0.0;
    let mut path: Vec<f64> = (0..20)
        .map(|_| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let r = (state >> 11) as f64 / (1u64 << 53) as f64;
            x = (x - 15.0 + 40.0 * r).clamp(0.0, 120.0);
            x
        })
        .collect();
    // Within SNAP h of either end face, where the mesh takes the front as the face.
    let near = 0.5 * SNAP * 100.0 / 3.0;
    path.insert(0, near);
    path.extend([33.333333333333336, 20.0, 100.0 - near, 100.0, 150.0, 0.0]);
    for (material, element) in [
        ("linear", "tet4"),
        ("linear", "tet10"),
        ("neo-hookean", "tet4"),
        ("neo-hookean", "tet10"),
        ("stvk", "tet4"),
        ("stvk", "tet10"),
    ] {
        let strings = [("material", material), ("element", element)];
        let mut s = block(&coarse, &strings);
        let mut furthest: f64 = 0.0;
        for &x in &path {
            step(&mut s, &[("scalpel_x", x)]);
            furthest = furthest.max(x).clamp(0.0, 100.0);
            let length = s.get("cut_length").unwrap();
            assert!(
                (length - furthest).abs() <= 1e-9,
                "{material} {element}, blade {x}: {length} vs {furthest}"
            );
        }
        let mut s = block(&coarse, &strings);
        for x in [41.3, 12.0] {
            step(&mut s, &[("scalpel_x", x)]);
            assert_eq!(s.get("cut_length").unwrap(), 41.3, "{material} {element}");
            assert_eq!(nodes_at(&s, [41.3, 45.0, 17.0]), 1, "{material} {element}");
            let behind = 41.3 - 100.0 / 3.0;
            assert_eq!(
                nodes_at(&s, [behind, 45.0, 17.0]),
                2,
                "{material} {element}"
            );
        }
    }
}

/// Cutting to 60 mm and withdrawing the blade to 40 and then 0 leaves the state of cutting
/// to 60 mm directly: every output, profiles included, within 1e-9 (relative to its scale),
/// for the linear law at a 2 mm pull and the neo-Hookean law (tet4, and tet10 on half the
/// cells) at the seed's 10 mm.
#[test]
fn withdrawing_the_blade_leaves_the_cut_open() {
    for (material, element, cells, pull) in [
        ("linear", "tet4", [6.0, 16.0, 14.0], 2.0),
        ("neo-hookean", "tet4", [6.0, 16.0, 14.0], 10.0),
        ("neo-hookean", "tet10", [3.0, 8.0, 7.0], 10.0),
    ] {
        let reals = [
            ("pull", pull),
            ("cells_x", cells[0]),
            ("cells_y", cells[1]),
            ("cells_z", cells[2]),
        ];
        let strings = [("material", material), ("element", element)];
        let run = |path: &[f64]| {
            let mut s = block(&reals, &strings);
            for &x in path {
                step(&mut s, &[("scalpel_x", x)]);
            }
            outputs(&mut s)
        };
        let (direct, withdrawn) = (run(&[60.0]), run(&[60.0, 40.0, 0.0]));
        let scale = direct
            .iter()
            .filter(|v| v.is_finite())
            .fold(0.0f64, |a, v| a.max(v.abs()));
        for (i, (a, b)) in direct.iter().zip(&withdrawn).enumerate() {
            let same = (a.is_nan() && b.is_nan()) || (a - b).abs() <= 1e-9 * scale;
            assert!(same, "{material} {element}, output value {i}: {a} vs {b}");
        }
        assert!(direct[5] == 60.0 && direct[0] > 0.0, "{direct:?}");
    }
}

/// The default block at a 10 mm pull with the blade advanced in 0.5 mm steps from 0 to
/// 99.5 mm: no step changes the reaction by more than 3 times the mean change per step
/// (issue 27's bound); measured 1.89 times, asserted 2. With the mesh graded towards the cut
/// plane, the crack front, the faces and the tip (`mesh_grading` = 2; x planes at the front
/// ± 100 (k/6)² mm): measured 1.44 times, asserted 1.6 (2026-11-27, cubes split along x;
/// with the five-tetrahedra split 2.17 and 3.04 times, the largest steps where a thin cell
/// had just appeared at x = 0). (The last half millimetre, which cuts the remaining
/// ligament at the far face, is not part of this bound: docs/theory/cutblock.md.)
#[test]
fn outputs_change_continuously_with_the_blade() {
    let path = |grading: f64| {
        let mut s = block(&[("pull", 10.0), ("mesh_grading", grading)], &[]);
        let mut reaction = vec![s.get("reaction_force").unwrap()];
        for k in 1..200 {
            step(&mut s, &[("scalpel_x", 0.5 * f64::from(k))]);
            reaction.push(s.get("reaction_force").unwrap());
        }
        reaction
    };
    // The two gradings' blade paths are independent runs: one on each core.
    let (uniform, graded) = std::thread::scope(|scope| {
        let graded = scope.spawn(|| path(2.0));
        (path(1.0), graded.join().unwrap())
    });
    for (grading, bound, reaction) in [(1.0, 2.0, uniform), (2.0, 1.6, graded)] {
        let changes: Vec<f64> = reaction.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
        let mean = (reaction[0] - reaction[reaction.len() - 1]).abs() / changes.len() as f64;
        let largest = changes.iter().copied().fold(0.0, f64::max);
        println!(
            "β = {grading}: reaction {:.4} → {:.4} N in 0.5 mm steps: mean change {mean:.3e} N, largest {largest:.3e} N ({:.2}×)",
            reaction[0],
            reaction[reaction.len() - 1],
            largest / mean
        );
        assert!(
            largest <= bound * mean,
            "β = {grading}: {largest} vs mean {mean}"
        );
    }
}

/// Asserts that the blade at each of `xs` (at a 5 mm pull, default block) gives the outputs
/// of the blade at `reference`, but those named in `skip`, within `tol`, each relative to
/// its own value, and within `floor` (mm or N) where a value is near zero.
fn assert_outputs_agree(reference: f64, xs: &[f64], skip: &[&str], tol: f64, floor: f64) {
    let at = |x: f64| {
        let mut s = block(&[("pull", 5.0)], &[]);
        step(&mut s, &[("scalpel_x", x)]);
        outputs_but(&mut s, skip)
    };
    let expected = at(reference);
    for &x in xs {
        let mut largest = 0.0f64;
        for (i, (a, b)) in at(x).iter().zip(&expected).enumerate() {
            let allowed = (tol * a.abs().max(b.abs())).max(floor);
            let same = (a.is_nan() && b.is_nan()) || (a - b).abs() <= allowed;
            assert!(
                same,
                "blade {x}, output value {i}: {a} vs {b} at {reference}"
            );
            if !a.is_nan() {
                largest = largest.max((a - b).abs() / allowed);
            }
        }
        println!("blade {x} against {reference}: the largest difference is {largest:.3} of its allowance");
    }
}

/// A blade stopped on a plane of the uniform grid or 1e-6 mm either side gives outputs
/// within 1e-4 of each other (and 1e-9 mm or N where a value is near zero).
#[test]
fn a_blade_on_a_uniform_plane_and_next_to_it_agree() {
    let plane = 100.0 / 3.0;
    assert_outputs_agree(plane, &[plane - 1e-6, plane + 1e-6], &[], 1e-4, 1e-9);
}

/// Where a cell appears at x = 0 — the plane a cell behind the front crosses [`SNAP`] h
/// (h = 100/6 mm) into the block — or the incision begins, the outputs do not jump: a blade
/// 1 % of that width before and after gives outputs within 1e-5 of each other (1e-9 mm or
/// N near zero), and the incision begun at 1.01 SNAP h (0.17 µm) the outputs of the uncut
/// block within 1e-5 (1e-6 mm near zero: the opening of that cut), its length apart. The cubes are split along
/// x so that such thin cells do not lock: with the five-tetrahedra split of seed 002 this
/// test failed, the reaction 4.1830 against 4.1221 N (+1.5 %), and at a 10 mm pull with
/// the former SNAP = 1e-3 the opening at x = 0 jumped by 11 % and the reaction by 0.1 %
/// (measured 2026-11-27). Measured with the split along x: the largest difference 0.80 of its
/// allowance where the cell appears (the thin cell's effect, of the order of its width) and
/// 0.12 where the incision begins.
///
/// `max_von_mises` is left out where the cell appears behind the front: it is a maximum of
/// nodal averages, and the nodes of the end face then average only the thin cell's
/// elements, whose stress is the face's rather than the first cell's: it jumps there, by
/// 13 % at this pull (docs/theory/cutblock.md).
#[test]
fn a_cell_appearing_at_the_end_face_changes_no_output_but_the_stress_maximum() {
    let h = 100.0 / 6.0;
    let enters = h + SNAP * h;
    let eta = 0.01 * SNAP * h;
    assert_outputs_agree(
        enters - eta,
        &[enters + eta],
        &["max_von_mises"],
        1e-5,
        1e-9,
    );
    assert_outputs_agree(0.0, &[1.01 * SNAP * h], &["cut_length"], 1e-5, 1e-6);
}

/// A blade advance under load with a finite-strain law starts Newton from the last
/// equilibrium carried onto the new mesh (the load did not change: an increment per contact
/// set, where the unloaded block needs at least five of 1 mm, `max_increment` = 1), and
/// reuses the pattern and symbolic analysis when the front stays within its cell; it finds
/// the same equilibrium as a block cut there before it was pulled (five 1 mm load
/// increments from the unloaded block, everything analysed anew).
#[test]
fn a_warm_started_blade_advance_finds_the_cold_equilibrium() {
    for (element, cells) in [("tet4", [6.0, 16.0, 14.0]), ("tet10", [3.0, 8.0, 7.0])] {
        let strings = [("material", "neo-hookean"), ("element", element)];
        let reals = [
            ("cells_x", cells[0]),
            ("cells_y", cells[1]),
            ("cells_z", cells[2]),
            ("max_increment", 1.0),
        ];
        let mut warm = block(&reals, &strings);
        step(&mut warm, &[("scalpel_x", 40.0), ("pull", 5.0)]);
        let before = warm.work();
        step(&mut warm, &[("scalpel_x", 41.0)]);
        let increments = warm.work().increments - before.increments;
        assert!(increments < 5, "{element}: the advance started cold");
        assert_eq!(
            warm.work().analyses,
            before.analyses,
            "{element}: 40 -> 41 mm keeps the connectivity, so the analysis is reused"
        );
        assert_eq!(
            warm.work().topology_builds,
            before.topology_builds + 1,
            "{element}"
        );
        let mut cold = block(&reals, &strings);
        step(&mut cold, &[("scalpel_x", 41.0), ("pull", 5.0)]);
        assert!(cold.work().increments >= 5, "{element}");
        let (a, b) = (outputs(&mut warm), outputs(&mut cold));
        // Profile stations beyond the scanned surface read NaN on both.
        let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(
                (x - y).abs() <= 1e-8 * scale || (x.is_nan() && y.is_nan()),
                "{element}: output {k}: warm {x} cold {y}"
            );
        }
    }
}

/// Issue 27's default law is valid where the scene is used: on the defaults (neo-Hookean
/// tet4) the seed's scenario — the full cut pulled 10 mm in one step — and the blade
/// crossing the block in 2 mm steps at a 10 mm pull raise no warning at any step. The
/// linear law on the same path does (beyond its 5 % strain), so the check can fail.
#[test]
fn the_defaults_raise_no_warning_at_the_seeds_pull() {
    let mut seed = block(&[("scalpel_x", 100.0)], &[]);
    step(&mut seed, &[("pull", 10.0)]);
    assert_eq!(
        seed.take_warnings(),
        Vec::<String>::new(),
        "the seed's scenario"
    );
    let blade_path = |strings: &[(&str, &str)]| {
        let mut s = block(&[("pull", 10.0)], strings);
        let mut warnings = s.take_warnings();
        for k in 1..=50 {
            step(&mut s, &[("scalpel_x", 2.0 * f64::from(k))]);
            warnings.extend(s.take_warnings());
        }
        warnings
    };
    assert_eq!(blade_path(&[]), Vec::<String>::new(), "the blade path");
    let linear = blade_path(&[("material", "linear")]);
    assert!(
        linear.iter().any(|w| w.contains("principal strain")),
        "{linear:?}"
    );
}
