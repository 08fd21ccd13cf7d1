//! The abdomen scene: shipped configurations, the seed's findings, the quasi-static limit,
//! mesh convergence and hard cases.

use models::scene::abdomen::Abdomen;
use models::scene::{Scene, SceneError};
use models::verify::richardson;

fn scene(strings: &[(&str, &str)], reals: &[(&str, f64)]) -> Abdomen {
    Abdomen::initialized(strings, reals).unwrap()
}

/// Runs `seconds` at dt = 1 ms and returns the peak of each named output over the run.
fn peaks(s: &mut Abdomen, seconds: f64, names: &[&str]) -> Vec<f64> {
    let mut peak = vec![f64::NEG_INFINITY; names.len()];
    let steps = (seconds / 1e-3).round() as usize;
    for i in 0..steps {
        s.do_step(i as f64 * 1e-3, 1e-3).unwrap();
        for (p, n) in peak.iter_mut().zip(names) {
            *p = p.max(s.get(n).unwrap());
        }
    }
    peak
}

const FLOOR: [&str; 2] = ["floor_stress_mean", "floor_stress_max"];

/// Peak mean floor stress over the first press on the defaults (kPa) as the README and
/// docs/verification.md quote it from the report's findings table: a narrower pelvis loads
/// the floor more on this model form (seed 003 found the reverse on its own).
const QUOTED_PEAK_MEAN_KPA: [(&str, f64); 3] =
    [("narrow", 5.080), ("normal", 4.691), ("wide", 4.245)];

/// The shipped configurations run on the defaults through the peak of the press (finite
/// strain, 10 ms steps) with no validity warning and positive pelvic-floor stresses, and
/// the narrow, normal and wide pelvises give the quoted peaks (to their last digit) in
/// that order.
#[test]
fn shipped_configurations_run_within_their_validity() {
    let mut means = Vec::new();
    for cfg in ["narrow", "normal", "wide", "lordotic", "tilted"] {
        let mut s = scene(&[("configuration", cfg)], &[]);
        let m = s.meshed().unwrap();
        // Graded meshes keep all but a few triangles at the boundary above the angle limit.
        assert!(m.min_angle > 10.0, "{cfg}: min angle {}", m.min_angle);
        let mut peak = [0.0f64; 2];
        for i in 0..100 {
            s.do_step(i as f64 * 1e-2, 1e-2).unwrap();
            for (p, n) in peak.iter_mut().zip(FLOOR) {
                *p = p.max(s.get(n).unwrap());
            }
        }
        let warnings = s.take_warnings();
        println!(
            "{cfg}: peak floor stress mean {:.5} MPa, max {:.5} MPa",
            peak[0], peak[1]
        );
        assert!(warnings.is_empty(), "{cfg}: {warnings:?}");
        assert!(peak.iter().all(|x| x.is_finite() && *x > 0.0), "{cfg}");
        means.push((cfg, peak[0] * 1e3));
    }
    for ((cfg, quoted), (_, kpa)) in QUOTED_PEAK_MEAN_KPA.iter().zip(&means) {
        assert!(
            (kpa - quoted).abs() < 6e-4,
            "{cfg}: {kpa:.4} kPa, quoted {quoted}"
        );
    }
    assert!(
        means[0].1 > means[1].1 && means[1].1 > means[2].1,
        "{means:?}"
    );
}

/// With the abdominal wall free, a wall 10 times stiffer bulges less under the default
/// press (finite strain, static).
#[test]
fn a_stiffer_free_wall_bulges_less() {
    let bulge = |wall_e: f64| {
        let s = scene(&[("abdominal_wall", "free")], &[("wall_E", wall_e)]);
        let u = s.static_displacement(0.8).unwrap();
        s.evaluate(&u, 0.8).unwrap()[WALL_MID_UX]
    };
    let (soft, stiff) = (bulge(0.0225), bulge(0.225));
    println!("wall midpoint {soft:.3} → {stiff:.3} mm");
    assert!(stiff > 0.0 && stiff < 0.8 * soft, "{soft} {stiff}");
}

/// Σ|u_x| / Σ|u_y| over all nodes.
fn horizontal_share(s: &mut Abdomen) -> f64 {
    let u = s.field().unwrap().u;
    let sx: f64 = u.iter().step_by(2).map(|x| x.abs()).sum();
    let sy: f64 = u.iter().skip(1).step_by(2).map(|y| y.abs()).sum();
    sx / sy
}

#[test]
fn a_free_wall_lets_the_field_move_more_horizontally() {
    let mut free = scene(&[("abdominal_wall", "free")], &[]);
    let mut fixed = scene(&[("abdominal_wall", "fixed")], &[]);
    peaks(&mut free, 0.5, &[]);
    peaks(&mut fixed, 0.5, &[]);
    let (a, b) = (horizontal_share(&mut free), horizontal_share(&mut fixed));
    println!("horizontal/vertical displacement: free wall {a:.3}, fixed wall {b:.3}");
    assert!(a > b);
}

#[test]
fn slow_pressing_matches_the_static_solution() {
    // At 0.01 Hz the press rises over 50 s. With mass-proportional damping α = 5 1/s every
    // mode's free response decays as e^(−αt/2), i.e. within about 2 s, so the response must
    // follow the static one; compare at the press's peak (finite strain, the default).
    let mut s = scene(
        &[],
        &[
            ("target_triangles", 600.0),
            ("press_frequency", 0.01),
            ("max_step", 0.05),
        ],
    );
    let steps = 1000;
    for i in 0..steps {
        s.do_step(i as f64 * 0.05, 0.05).unwrap();
    }
    assert!((s.time() - 50.0).abs() < 1e-9);
    let dynamic = s.field().unwrap().u.to_vec();
    let stat = s.static_displacement(0.8).unwrap();
    let diff: f64 = dynamic
        .iter()
        .zip(&stat)
        .map(|(a, b)| (a - b).powi(2))
        .sum::<f64>()
        .sqrt();
    let norm: f64 = stat.iter().map(|b| b * b).sum::<f64>().sqrt();
    println!(
        "quasi-static: |u_dyn - u_static| / |u_static| = {:.3e}",
        diff / norm
    );
    assert!(diff / norm < 1.5e-5, "{}", diff / norm);
}

/// Indices of the floor stress (mean, max) and the apex's, the floor midpoint's and the
/// wall midpoint's displacement in the outputs.
const FLOOR_MEAN: usize = 0;
const FLOOR_MAX: usize = 1;
const APEX_UY: usize = 7;
const FLOOR_MID_UY: usize = 9;
const WALL_MID_UX: usize = 10;

/// The static outputs under the default press on the mesh given by `settings`.
fn static_outputs(settings: &[(&str, f64)]) -> Vec<f64> {
    let s = scene(&[("kinematics", "linear")], settings);
    let u = s.static_displacement(0.8).unwrap();
    s.evaluate(&u, 0.8).unwrap()
}

/// Mesh convergence of the linear model's static outputs on graded meshes (β = ½,
/// `mesh_grading`; 750 / 3,000 / 12,000 target triangles, h halved twice): the mean floor
/// stress at the 6-node element's stress order 2 (measured 2.18), the apex faster
/// (measured 3.59); the finest mesh within 0.03 % of the extrapolation of both (measured
/// 0.022 % and 0.003 %).
#[test]
fn static_outputs_converge_at_the_elements_order_on_graded_meshes() {
    let graded = [750.0, 3000.0, 12000.0]
        .map(|n| static_outputs(&[("target_triangles", n), ("mesh_grading", 0.5)]));
    for (k, name, order) in [
        (FLOOR_MEAN, "floor stress mean", 2.0),
        (APEX_UY, "apex", 3.0),
    ] {
        let values = [graded[0][k], graded[1][k], graded[2][k]];
        let fit = richardson::extrapolate(values, 2.0).unwrap();
        let finest = (values[2] - fit.value).abs() / fit.value.abs();
        println!(
            "{name}: {values:?} → {:.6e}, order {:.2}, finest {finest:.1e}",
            fit.value, fit.order
        );
        assert!(fit.order > order - 0.3, "{name}: order {}", fit.order);
        assert!(finest < 3e-4, "{name}: {finest:e}");
    }
}

/// The finite-strain default (issue 26) on graded meshes of 750 / 3,000 / 12,000 target
/// triangles (h halved twice): the floor midpoint's descent converges at the 6-node
/// element's order 2 (measured 2.02), the apex faster (measured 3.43); the default mesh's
/// static floor stress, mean and max, lies within 0.1 % of the finest (measured 0.05 % and
/// 0.06 %; `harness speed-error` puts the default run 0.39 % / 0.74 % from its dynamic
/// reference on 48,998 triangles).
#[test]
fn the_finite_strain_default_converges_at_the_elements_order_on_graded_meshes() {
    let outputs = [750.0, 3000.0, 12000.0].map(|n| {
        let s = scene(&[], &[("target_triangles", n)]);
        let u = s.static_displacement(0.8).unwrap();
        s.evaluate(&u, 0.8).unwrap()
    });
    // The floor midpoint at the element's order (within 0.3 of it), the apex at least as
    // fast.
    for (k, name, order, within) in [
        (FLOOR_MID_UY, "floor midpoint", 2.0, 0.3),
        (APEX_UY, "apex", 3.0, f64::INFINITY),
    ] {
        let values = outputs.each_ref().map(|o| o[k]);
        let fit = richardson::extrapolate(values, 2.0).unwrap();
        println!("{name}: {values:?}, order {:.2}", fit.order);
        assert!(
            fit.order > order - 0.3 && fit.order < order + within,
            "{name}: order {}",
            fit.order
        );
    }
    for k in [FLOOR_MEAN, FLOOR_MAX] {
        let gap = (outputs[0][k] / outputs[2][k] - 1.0).abs();
        println!(
            "floor stress {k}: default mesh {:.4e} against {:.4e}: {gap:.1e}",
            outputs[0][k], outputs[2][k]
        );
        assert!(gap < 1e-3, "{k}: {gap:e}");
    }
}

/// On a graded mesh of 40,000 target triangles (membrane segments down to 4 µm at the part
/// ends) the static solve meets a tangent that is not positive definite (the slack
/// membranes' negative geometric stiffness, which grows as a segment shortens); Newton then
/// goes on with the tangent at rest added (`SHIFTS` in `solve/newton/statics.rs`; before,
/// the solve failed, and with it `report --full`'s 48,000-triangle reference). Its answer
/// continues the graded family's convergence: the mean floor stress and the floor
/// midpoint's descent move less from 12,000 to 40,000 triangles than from 3,000 to 12,000
/// (the maximum, at the junction's singularity, does not converge and is not compared).
#[test]
fn a_fine_graded_mesh_solves_where_slack_membranes_make_the_tangent_indefinite() {
    let outputs = [3000.0, 12000.0, 40000.0].map(|n| {
        let s = scene(&[], &[("target_triangles", n)]);
        let u = s.static_displacement(0.8).unwrap();
        s.evaluate(&u, 0.8).unwrap()
    });
    for k in [FLOOR_MEAN, FLOOR_MID_UY] {
        let [coarse, middle, fine] = outputs.each_ref().map(|o| o[k]);
        println!("output {k}: {coarse:.6e}, {middle:.6e}, {fine:.6e}");
        assert!((fine - middle).abs() < (middle - coarse).abs(), "{k}");
    }
}

/// The pelvic floor stiffened twentyfold at 0.2 s, mid-press: 0.1 s later it descends less
/// than without the change, but not twenty times less (the contents' compliance in series
/// with the floor's is unchanged), and the run goes on to the peak of the press.
#[test]
fn stiffness_change_mid_run_takes_effect_and_continues() {
    const STIFFER: f64 = 20.0;
    let descent = |change: bool| {
        let mut s = scene(&[], &[]);
        for i in 0..30 {
            if change && i == 20 {
                s.set("floor_E", 0.05 * STIFFER).unwrap();
            }
            s.do_step(f64::from(i) * 1e-2, 1e-2).unwrap();
        }
        let descent = -s.get("floor_mid_uy").unwrap();
        peaks(&mut s, 0.5, &FLOOR);
        (descent, s.get("floor_stress_max").unwrap())
    };
    let ((kept, _), (stiffened, stress)) = (descent(false), descent(true));
    println!("floor descent at 0.3 s: {kept:.4} mm kept, {stiffened:.4} mm stiffened");
    assert!(kept > 0.0 && stiffened < kept, "{stiffened} vs {kept}");
    assert!(stiffened > kept / STIFFER, "{stiffened} vs {kept}");
    assert!(stress.is_finite() && stress > 0.0);
}

/// A step far below `max_step` — 1e-16 s, what a master's accumulated round-off leaves, and
/// 1e-10 s — only moves the time: it returns OK, and the next normal steps go on as the run
/// without it does (to 1e-12 of each output's size: the load's phase is 1e-16 s later).
#[test]
fn a_step_far_below_max_step_leaves_the_next_steps_as_they_were() {
    let outputs = ["floor_stress_max", "apex_uy", "floor_mid_uy"];
    let run = |tiny: Option<f64>| {
        let mut s = scene(&[], &[]);
        let mut t = 0.0;
        let mut rows = Vec::new();
        for i in 0..30 {
            if i == 15 {
                if let Some(h) = tiny {
                    s.do_step(t, h).unwrap();
                    t += h;
                }
            }
            s.do_step(t, 1e-2).unwrap();
            t += 1e-2;
            rows.push(outputs.map(|o| s.get(o).unwrap()));
        }
        (rows, s.time())
    };
    let (plain, end) = run(None);
    for h in [1e-16, 1e-10] {
        let (with, end_with) = run(Some(h));
        // The scene's clock took the tiny step: it ends at the sum of every step.
        let mut t = 0.0;
        for i in 0..30 {
            if i == 15 {
                t += h;
            }
            t += 1e-2;
        }
        assert_eq!(end_with, t, "{h}: {end_with} vs {end}");
        assert!(end_with > end, "{h}: {end_with} vs {end}");
        for (k, name) in outputs.iter().enumerate() {
            let size = plain.iter().fold(0.0_f64, |m, r| m.max(r[k].abs()));
            let gap = plain
                .iter()
                .zip(&with)
                .fold(0.0_f64, |m, (a, b)| m.max((a[k] - b[k]).abs()));
            assert!(
                gap <= 1e-12 * size,
                "{h} s: {name} off by {gap:e} of {size:e}"
            );
        }
    }
}

/// A parameter that cannot act under the present settings warns once, naming itself and
/// why: the wall's modulus with the wall held, set before initialization (warned there) and
/// after it (warned at the set); set again, no second warning. With the wall free it acts
/// and nothing is said.
#[test]
fn a_parameter_that_cannot_act_says_so_once() {
    let mut s = scene(&[], &[("wall_E", 0.03)]);
    let first = s.take_warnings();
    assert_eq!(first.len(), 1, "{first:?}");
    assert!(
        first[0].contains("wall_E = 0.03") && first[0].contains("abdominal_wall"),
        "{first:?}"
    );
    s.set("wall_E", 0.04).unwrap();
    s.set("wall_E", 0.05).unwrap();
    assert!(s.take_warnings().is_empty());
    let mut s = scene(&[], &[]);
    s.set("wall_E", 0.04).unwrap();
    let at_set = s.take_warnings();
    assert_eq!(at_set.len(), 1, "{at_set:?}");
    assert!(at_set[0].contains("wall_E = 0.04"), "{at_set:?}");
    let mut free = scene(&[("abdominal_wall", "free")], &[("wall_E", 0.03)]);
    free.set("wall_E", 0.04).unwrap();
    assert!(free.take_warnings().is_empty());
}

#[test]
fn hard_cases_stay_bounded() {
    // ν = 0.499 (finite strain), and line elements 1e6 times stiffer than the cavity.
    // The wall is held (the default), so its modulus would not act.
    let stiff = vec![("diaphragm_E", 5e3), ("floor_E", 5e3)];
    for (strings, reals) in [
        (vec![], vec![("cavity_nu", 0.499)]),
        (vec![("kinematics", "linear")], stiff.clone()),
    ] {
        let mut s = scene(&strings, &reals);
        let p = peaks(&mut s, 0.3, &["cavity_vm_max"]);
        assert!(p[0].is_finite(), "{strings:?} {reals:?}");
    }
    // At finite strain the stiff membranes' element forces, 10⁶ times the net ones, leave a
    // round-off in the residual that Newton's method cannot get below: it stops there
    // instead of wandering (before 2026-11-27 it wandered: 50–99 iterations per step on
    // 300 triangles, and on this mesh a step failed after the most iterations allowed).
    // At strains of 10⁻⁷ the finite-strain run is the linear one to far below 10⁻³ of its
    // motion, unless the stop accepted states short of equilibrium.
    let apex = |kinematics: &str| {
        let mut s = scene(&[("kinematics", kinematics)], &stiff);
        let mut most = 0;
        let history: Vec<f64> = (0..100)
            .map(|i| {
                s.do_step(f64::from(i) * 1e-3, 1e-3).unwrap();
                most = most.max(s.newton_iterations().unwrap());
                s.get("apex_uy").unwrap()
            })
            .collect();
        (history, most)
    };
    let (finite, most) = apex("finite");
    let (linear, _) = apex("linear");
    let peak = linear.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let gap = finite
        .iter()
        .zip(&linear)
        .fold(0.0_f64, |m, (a, b)| m.max((a - b).abs()))
        / peak;
    println!(
        "stiff membranes at finite strain: at most {most} Newton iterations per step, \
         apex within {gap:e} of the linear run's peak"
    );
    assert!(most <= 7, "{most} Newton iterations in a step");
    assert!(gap <= 1e-3, "{gap:e}");
    // Houbolt from dt = 1e-5 s to 0.1 s: bounded by the static response to the peak force.
    let bound = {
        let s = scene(&[], &[]);
        let u = s.static_displacement(0.8).unwrap();
        u.iter().fold(0.0f64, |a, b| a.max(b.abs()))
    };
    for dt in [1e-5, 1e-3, 0.1] {
        let mut s = scene(&[], &[("max_step", dt)]);
        let mut worst: f64 = 0.0;
        for i in 0..200 {
            s.do_step(i as f64 * dt, dt).unwrap();
            worst = worst.max(
                s.field()
                    .unwrap()
                    .u
                    .iter()
                    .fold(0.0f64, |a, b| a.max(b.abs())),
            );
        }
        println!("dt {dt:e}: max |u| {worst:.4e} (static peak {bound:.4e})");
        assert!(worst.is_finite() && worst < 2.0 * bound);
    }
}

#[test]
fn central_difference_above_its_limit_is_refused() {
    let explicit = [
        ("integrator", "central_difference"),
        ("kinematics", "linear"),
    ];
    let mut s = scene(&explicit, &[("max_step", 1e-3)]);
    let err = s.do_step(0.0, 1e-3).unwrap_err().to_string();
    assert!(
        err.contains("unstable") && err.contains("central_difference"),
        "{err}"
    );
    // Below the limit it runs.
    let mut s = scene(&explicit, &[("max_step", 1e-6)]);
    s.do_step(0.0, 1e-4).unwrap();
}

#[test]
fn bad_configurations_are_clear_errors() {
    let mut s = Abdomen::new();
    s.set_str("configuration", "no_such_pelvis").unwrap();
    let e = s.initialize(0.0).unwrap_err().to_string();
    assert!(e.contains("no_such_pelvis"), "{e}");
    let dir = std::env::temp_dir().join(format!("abdomen-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let open = dir.join("open.toml");
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../experiments/pelvis/normal.toml"
    ))
    .unwrap();
    std::fs::write(
        &open,
        text.replace("diaphragm = [[140.0, 260.0]", "diaphragm = [[141.0, 260.0]"),
    )
    .unwrap();
    let mut s = Abdomen::new();
    s.set_str("configuration", open.to_str().unwrap()).unwrap();
    let e = s.initialize(0.0).unwrap_err().to_string();
    assert!(e.contains("abdominal_wall") && e.contains("open"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
    let mut s = Abdomen::new();
    assert!(matches!(
        s.set_str("integrator", "euler"),
        Err(SceneError::Model(_))
    ));
    assert!(s
        .set("cavity_nu", 0.5)
        .unwrap_err()
        .to_string()
        .contains("cavity_nu"));
    assert!(s
        .set_str("abdominal_wall", "glued")
        .unwrap_err()
        .to_string()
        .contains("glued"));
    assert!(s
        .set_str("press_load", "push")
        .unwrap_err()
        .to_string()
        .contains("press_load"));
    // Seed 003's pressure over a passive diaphragm at finite strain (the default) is refused
    // by name; at small strain it runs.
    s.set_str("press_load", "pressure").unwrap();
    let e = s.initialize(0.0).unwrap_err().to_string();
    assert!(e.contains("press_load") && e.contains("linear"), "{e}");
    let mut s = Abdomen::new();
    s.set_str("press_load", "pressure").unwrap();
    s.set_str("kinematics", "linear").unwrap();
    s.initialize(0.0).unwrap();
    s.do_step(0.0, 0.01).unwrap();
    assert!(s.get("press_total").unwrap() > 0.0);
}

/// Time-dependent loads follow the caller's time: started at 2 s, one period of the default
/// press (0.8 N/mm at 0.5 Hz), the run is the start-at-0 run (to round-off), and
/// press_total is F(t) = 0.8 (1 − cos πt)/2 at the caller's time. Started at the peak
/// (t = 1 s) the scene starts in equilibrium with the press there: its first step is the
/// static displacement under the peak press, not the swing of a step load.
#[test]
fn a_start_time_shifts_the_load_phase_and_press_total_reports_the_applied_load() {
    let run = |t0: f64| {
        let mut s = Abdomen::new();
        s.set("target_triangles", 300.0).unwrap();
        s.initialize(t0).unwrap();
        let mut rows = Vec::new();
        for k in 0..50 {
            let t = t0 + k as f64 * 1e-2;
            s.do_step(t, 1e-2).unwrap();
            rows.push([s.get("apex_uy").unwrap(), s.get("press_total").unwrap()]);
            let press = 0.4 * (1.0 - (std::f64::consts::PI * (t + 1e-2)).cos());
            assert!((rows[k][1] - press).abs() < 1e-12, "{t}: {rows:?}");
        }
        rows
    };
    let (zero, two) = (run(0.0), run(2.0));
    let scale = zero.iter().fold(0.0f64, |a, r| a.max(r[0].abs()));
    for (a, b) in zero.iter().zip(&two) {
        // cos(π(2 + τ)) and cos(πτ) differ in the last bits.
        assert!((a[0] - b[0]).abs() <= 1e-9 * scale, "{a:?} {b:?}");
    }
    let at_peak = run(1.0);
    let s = scene(&[], &[("target_triangles", 300.0)]);
    let apex = s
        .evaluate(&s.static_displacement(0.8).unwrap(), 0.8)
        .unwrap()[APEX_UY];
    println!(
        "started at the peak: apex {:.5} mm, static {apex:.5} mm",
        at_peak[0][0]
    );
    assert!(
        (at_peak[0][0] / apex - 1.0).abs() < 1e-3,
        "{} {apex}",
        at_peak[0][0]
    );
}

#[test]
fn a_communication_step_of_too_many_substeps_is_refused_by_name() {
    let mut s = scene(&[], &[("target_triangles", 300.0), ("max_step", 1e-8)]);
    let e = s.do_step(0.0, 10.0).unwrap_err();
    // Refused before stepping: time and field are where they were.
    assert_eq!(s.time(), 0.0);
    assert_eq!(s.get("apex_uy").unwrap(), 0.0);
    assert!(matches!(e, SceneError::TooManySubsteps { .. }), "{e}");
    let text = e.to_string();
    assert!(
        text.contains("h = 10 s") && text.contains("max_step = 0.00000001 s"),
        "{text}"
    );
    // The scene is still usable with a step that fits (ten substeps).
    s.do_step(0.0, 1e-7).unwrap();
    assert_eq!(s.time(), 1e-7);
}

#[test]
fn a_model_above_the_memory_limit_is_refused_before_it_is_built() {
    let mut s = Abdomen::new();
    s.set("memory_limit", 100.0).unwrap();
    s.set("target_triangles", 500_000.0).unwrap();
    let e = s.initialize(0.0).unwrap_err().to_string();
    assert!(
        e.contains("the abdomen mesh and its sparse system") && e.contains("memory_limit = 100 MB"),
        "{e}"
    );
    // The default limit admits the default mesh; the limit also bounds the factorization.
    scene(&[], &[]);
    let mut s = Abdomen::new();
    s.set("memory_limit", 8.0).unwrap();
    let e = s.initialize(0.0).unwrap_err().to_string();
    assert!(
        e.contains("Cholesky factor") && e.contains("memory_limit = 8 MB"),
        "{e}"
    );
}

/// A change of `press_frequency` between steps goes on from the press's phase at that time
/// (issue 53): the press stays continuous, and the step after the change advances the phase
/// at the new frequency, F = A(1 − cos(2π(0.5 · 0.3 + 2 · 0.01)))/2; the phase 2πft of the
/// new frequency on the caller's time would have jumped the press from 0.16 to 0.69 N/mm.
/// A checkpoint taken after the change goes on the same, bit for bit.
#[test]
fn a_frequency_change_keeps_the_press_continuous() {
    let mut s = scene(&[("kinematics", "linear")], &[("target_triangles", 300.0)]);
    for i in 0..30 {
        s.do_step(f64::from(i) * 0.01, 0.01).unwrap();
    }
    let amplitude = 0.8;
    let press = |phase: f64| amplitude * 0.5 * (1.0 - phase.cos());
    let tau = 2.0 * std::f64::consts::PI;
    let before = s.get("press_total").unwrap();
    assert!((before - press(tau * 0.5 * 0.3)).abs() < 1e-12, "{before}");
    s.set("press_frequency", 2.0).unwrap();
    let saved = s.save();
    s.do_step(0.3, 0.01).unwrap();
    let after = s.get("press_total").unwrap();
    let expected = press(tau * (0.5 * 0.3 + 2.0 * 0.01));
    assert!((after - expected).abs() < 1e-12, "{after} vs {expected}");
    assert!((press(tau * 2.0 * 0.31) - expected).abs() > 0.25);
    let mut restored = Abdomen::new();
    restored.restore(&saved).unwrap();
    restored.do_step(0.3, 0.01).unwrap();
    assert_eq!(
        restored.get("press_total").unwrap().to_bits(),
        after.to_bits()
    );
    let floor = |s: &mut Abdomen| s.get("floor_stress_max").unwrap().to_bits();
    assert_eq!(floor(&mut restored), floor(&mut s));
}
