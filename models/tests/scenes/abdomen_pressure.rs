//! The abdomen driven by the contents' pressure (`press_mode = "pressure"`, issue 53) and the
//! muscle sheets' curvature across the slice.

use models::scene::abdomen::Abdomen;
use models::scene::Scene;

const PRESSURE: [(&str, &str); 1] = [("press_mode", "pressure")];

/// A ramp of the target to 2 kPa over 0.3 s in 50 ms communication steps (10 ms steps
/// inside) ends every step within 10⁻⁶ of the target, the force rising with it; held there
/// until the motion has died down, the force found is the one whose static equilibrium has
/// the target pressure (within 0.1 %: the static solve is an independent path).
#[test]
fn a_pressure_driven_press_holds_the_target_at_every_step() {
    let mut s = Abdomen::initialized(&PRESSURE, &[("target_triangles", 300.0)]).unwrap();
    let mut force = 0.0;
    for i in 0..40 {
        let t = f64::from(i) * 0.05;
        let target = 0.002 * ((t + 0.05) / 0.3).min(1.0);
        s.set("target_pressure", target).unwrap();
        s.do_step(t, 0.05).unwrap();
        let p = s.get("cavity_pressure").unwrap();
        assert!(
            (p - target).abs() <= 1e-6 * target,
            "t = {t}: {p} vs {target}"
        );
        let f = s.get("press_total").unwrap();
        assert!(f >= force || t > 0.3, "the force rises with the target");
        force = f;
    }
    let u = s.static_displacement(force).unwrap();
    let p = s.evaluate(&u, force).unwrap()[13];
    assert!(
        (p / 0.002 - 1.0).abs() < 1e-3,
        "static at {force} N/mm: {p}"
    );
}

/// At linear kinematics the pressure is linear in the force: the force found at the start
/// is the target over the pressure of a unit force's static solution (to 10⁻⁶).
#[test]
fn at_linear_kinematics_the_force_found_is_the_target_over_the_unit_pressure() {
    let linear = [("kinematics", "linear"), PRESSURE[0]];
    let s = Abdomen::initialized(&linear, &[("target_triangles", 300.0)]).unwrap();
    let unit = s.static_displacement(1.0).unwrap();
    let per_force = s.evaluate(&unit, 1.0).unwrap()[13];
    let mut s = Abdomen::initialized(
        &linear,
        &[("target_triangles", 300.0), ("target_pressure", 0.0015)],
    )
    .unwrap();
    let found = s.get("press_total").unwrap();
    let expected = 0.0015 / per_force;
    assert!(
        (found / expected - 1.0).abs() < 1e-6,
        "{found} vs {expected}"
    );
    let p = s.get("cavity_pressure").unwrap();
    assert!((p / 0.0015 - 1.0).abs() < 1e-6, "{p}");
}

/// A state saved in a pressure-driven run continues bit for bit in a new instance.
#[test]
fn a_pressure_driven_run_continues_bit_for_bit_from_a_saved_state() {
    let mut s = Abdomen::initialized(&PRESSURE, &[("target_triangles", 300.0)]).unwrap();
    let step = |s: &mut Abdomen, i: u32| {
        s.set("target_pressure", 0.0005 * f64::from(i)).unwrap();
        s.do_step(f64::from(i) * 0.02, 0.02).unwrap();
    };
    for i in 0..3 {
        step(&mut s, i);
    }
    let saved = s.save();
    let mut restored = Abdomen::new();
    restored.restore(&saved).unwrap();
    for i in 3..6 {
        step(&mut s, i);
        step(&mut restored, i);
    }
    for name in ["cavity_pressure", "press_total", "floor_stress_max"] {
        let bits = |s: &mut Abdomen| s.get(name).unwrap().to_bits();
        assert_eq!(bits(&mut restored), bits(&mut s), "{name}");
    }
}

/// What cannot work is refused before any work, by name; the press of the mode not chosen
/// and the membranes' law at linear kinematics are warned of.
#[test]
fn pressure_mode_settings_that_cannot_work_are_refused_by_name() {
    let explicit = [PRESSURE[0], ("kinematics", "linear")];
    let e = Abdomen::initialized(
        &[
            explicit[0],
            explicit[1],
            ("integrator", "central_difference"),
        ],
        &[],
    )
    .unwrap_err();
    assert!(e.to_string().contains("press_mode"), "{e}");
    let e = Abdomen::initialized(&[("press_muscles", "diaphragm_and_wall")], &[]).unwrap_err();
    assert!(e.to_string().contains("abdominal_wall"), "{e}");
    let e = Abdomen::initialized(
        &[("element", "tri3"), ("kinematics", "linear")],
        &[("floor_transverse_curvature", 0.01)],
    )
    .unwrap_err();
    assert!(e.to_string().contains("floor_transverse_curvature"), "{e}");
    let mut s = Abdomen::new();
    let e = s.set_str("press_mode", "iap").unwrap_err();
    assert!(
        e.to_string().contains("press_mode") && e.to_string().contains("iap"),
        "{e}"
    );
    let e = Abdomen::initialized(
        &[
            PRESSURE[0],
            ("kinematics", "linear"),
            ("model_order", "modal"),
        ],
        &[],
    )
    .unwrap_err();
    assert!(e.to_string().contains("model_order"), "{e}");
    let mut s = Abdomen::initialized(&[], &[("target_triangles", 300.0)]).unwrap();
    s.take_warnings();
    s.set("target_pressure", 0.004).unwrap();
    s.do_step(0.0, 0.01).unwrap();
    let warnings = s.take_warnings();
    assert!(
        warnings.iter().any(|w| w.contains("target_pressure")),
        "{warnings:?}"
    );
    let e = s.set_str("membrane_law", "ogden").unwrap_err();
    assert!(e.to_string().contains("membrane_law") && e.to_string().contains("ogden"));
    let linear = [("kinematics", "linear"), ("membrane_law", "neo-hookean")];
    let mut s = Abdomen::initialized(&linear, &[("target_triangles", 300.0)]).unwrap();
    let warnings = s.take_warnings();
    assert!(
        warnings.iter().any(|w| w.contains("membrane_law")),
        "{warnings:?}"
    );
}

/// The pelvic floor's curvature across the slice holds it as a bowl: at 3 kPa it descends
/// less, as its in-plane support and the foundation E A κ₂² of its transverse tension in
/// parallel predict, 1/w = 1/w₀ + E A κ₂² / p (within 15 %: the contents carry shear too).
#[test]
fn the_floors_transverse_curvature_holds_it_as_a_bowl() {
    let (kappa, p) = (1.0 / 60.0, 0.003);
    let descent = |k: f64| {
        let mut s = Abdomen::initialized(
            &PRESSURE,
            &[
                ("target_triangles", 300.0),
                ("target_pressure", p),
                ("floor_transverse_curvature", k),
            ],
        )
        .unwrap();
        -s.get("floor_mid_uy").unwrap()
    };
    let (flat, bowl) = (descent(0.0), descent(kappa));
    let foundation = 0.05 * 8.0 * kappa * kappa;
    let predicted = 1.0 / (1.0 / flat + foundation / p);
    assert!(bowl < flat, "{bowl} vs {flat}");
    assert!(
        (bowl / predicted - 1.0).abs() < 0.15,
        "{bowl} mm vs {predicted} mm predicted ({flat} mm flat)"
    );
}

/// The clinical settings of the pressure-driven press: contents of ν = 0.4999 on the mixed
/// element, a diaphragm curved across at a radius of 100 mm, a floor at 60 mm.
const CLINICAL: [(&str, f64); 4] = [
    ("cavity_nu", 0.4999),
    ("diaphragm_transverse_curvature", 0.01),
    ("floor_transverse_curvature", 1.0 / 60.0),
    ("target_triangles", 300.0),
];

/// A press that stretches the pelvic floor beyond the membranes' limit (1.5) warns once,
/// naming the floor: in the clinical settings 2.5 N/mm (7.3 kPa; the floor's largest
/// stress 15 kPa, beyond the law's 13.5 kPa at λ = 1.5) does, 1 N/mm (4.4 kPa, 9 kPa)
/// does not.
#[test]
fn a_membrane_stretched_beyond_its_law_warns() {
    let warnings = |force: f64| {
        let mut reals = CLINICAL.to_vec();
        reals.extend([("press_force", force), ("press_amplitude", 0.0)]);
        let mut s = Abdomen::initialized(&[("formulation", "mixed")], &reals).unwrap();
        s.take_warnings()
    };
    let within = warnings(1.0);
    assert!(within.is_empty(), "{within:?}");
    let beyond = warnings(2.5);
    assert_eq!(beyond.len(), 1, "{beyond:?}");
    assert!(
        beyond[0].contains("floor is stretched beyond 1.5"),
        "{beyond:?}"
    );
}

/// The first steps at the default 10 ms, one step per communication step, while Houbolt's
/// starter runs, the target rising 4 kPa/s: each trial retakes the starter's step too, on
/// the factorization in use (a kept tangent of another trial's tension made the second step
/// singular).
#[test]
fn the_starter_steps_are_taken_again_at_each_trial() {
    let mut s = Abdomen::initialized(&PRESSURE, &[]).unwrap();
    for k in 1..=5 {
        let target = 0.00004 * f64::from(k);
        s.set("target_pressure", target).unwrap();
        s.do_step(0.01 * f64::from(k - 1), 0.01).unwrap();
        let p = s.get("cavity_pressure").unwrap();
        assert!(
            (p - target).abs() <= 1e-6 * target,
            "step {k}: {p} vs {target}"
        );
    }
}

/// The pelvic floor's law is why Hencky's floor necks below the pressure of bearing down
/// (10 kPa, Neurourol Urodyn 40 (2021) 783: median 101 cmH₂O): at the press that gives it
/// with neo-Hookean sheets (6.2 N/mm, static, clinical settings; measured 10.00 kPa)
/// Hencky's floor stands at its peak stress E/e (measured 0.98 of it) and the contents'
/// pressure falls short (measured 9.44 kPa, 5.6 % short); the neo-Hookean floor carries
/// 1.16 E/e. Asserted: Hencky's floor within 2.5 % of its peak and below it, the pressure
/// 4.5–7 % short, the neo-Hookean floor more than 10 % beyond E/e.
#[test]
fn hencky_s_floor_necks_at_its_peak_stress_where_the_neo_hookean_one_holds() {
    let press = |law: &str| {
        let mut s = Abdomen::initialized(
            &[("formulation", "mixed"), ("membrane_law", law)],
            &CLINICAL,
        )
        .unwrap();
        let u = s.static_displacement(6.2).unwrap();
        let outputs = s.evaluate(&u, 6.2).unwrap();
        let peak = s.get("floor_E").unwrap() / std::f64::consts::E;
        (outputs[13], outputs[1] / peak)
    };
    let (hencky, hencky_peak) = press("hencky");
    let (neo_hookean, neo_hookean_peak) = press("neo-hookean");
    assert!((0.975..1.0).contains(&hencky_peak), "{hencky_peak}");
    assert!(neo_hookean_peak > 1.1, "{neo_hookean_peak}");
    assert!((neo_hookean - 0.01).abs() < 2e-4, "{neo_hookean}");
    let short = 1.0 - hencky / neo_hookean;
    assert!((0.045..0.07).contains(&short), "{hencky} vs {neo_hookean}");
}

/// Why the floor descends more at a Valsalva manoeuvre's pressure (8 kPa) than women
/// straining are measured to (19.1 ± 7.4 mm, open MRI, Neurourol Urodyn 20 (2001) 167–174):
/// the default floor has the levator's stiffness at rest (shear-wave elastography μ = 16–17
/// kPa, E = 3μ ≈ 50 kPa; Gachon et al., Int Urogynecol J 30 (2019)), which rises to μ =
/// 35–38 kPa during a Valsalva manoeuvre. Statically at 8 kPa in the clinical settings with
/// neo-Hookean sheets, the resting floor descends beyond the measured scatter (more than
/// 26.5 mm), the floor of the Valsalva stiffness (E = 105 kPa) inside it and at least 30 %
/// less.
#[test]
fn at_valsalva_the_floor_s_stiffness_during_the_manoeuvre_brings_its_descent_into_the_measured_scatter(
) {
    let descent = |floor_e: f64| {
        let mut reals = CLINICAL.to_vec();
        reals.extend([("target_pressure", 0.008), ("floor_E", floor_e)]);
        let strings = [
            PRESSURE[0],
            ("formulation", "mixed"),
            ("membrane_law", "neo-hookean"),
        ];
        let mut s = Abdomen::initialized(&strings, &reals).unwrap();
        -s.get("floor_mid_uy").unwrap()
    };
    let (rest, valsalva) = (descent(0.05), descent(0.105));
    assert!(rest > 19.1 + 7.4, "{rest} mm");
    assert!(
        (19.1 - 7.4..19.1 + 7.4).contains(&valsalva),
        "{valsalva} mm"
    );
    assert!(valsalva < 0.7 * rest, "{valsalva} vs {rest} mm");
}

/// A target that falls faster than the contents recoil leaves the muscles relaxed and the
/// pressure above it — said once, by a warning naming both: from 2 kPa to 0 in one 10 ms
/// step the pressure stays above it by more than 0.1 kPa (measured 1.51 kPa), and later
/// steps do not warn again. The same release over 1 s in 50 ms steps is followed within
/// 10⁻⁶ of 2 kPa at every step but the last, which ends 1.6 Pa above 0 with the muscles
/// relaxed (measured), below the warning's 0.1 kPa: no warning.
#[test]
fn a_target_falling_faster_than_the_contents_recoil_warns_once() {
    let start = [("target_triangles", 300.0), ("target_pressure", 0.002)];
    let mut s = Abdomen::initialized(&PRESSURE, &start).unwrap();
    assert!(s.take_warnings().is_empty());
    s.set("target_pressure", 0.0).unwrap();
    s.do_step(0.0, 0.01).unwrap();
    let (p, f) = (
        s.get("cavity_pressure").unwrap(),
        s.get("press_total").unwrap(),
    );
    assert!(p > 1e-4 && f == 0.0, "{p} MPa at {f} N/mm");
    let warnings = s.take_warnings();
    assert!(
        warnings.len() == 1
            && warnings[0].contains("above target_pressure")
            && warnings[0].contains("relaxed"),
        "{warnings:?}"
    );
    s.do_step(0.01, 0.01).unwrap();
    let (p, f) = (
        s.get("cavity_pressure").unwrap(),
        s.get("press_total").unwrap(),
    );
    assert!(p > 1e-4 && f == 0.0, "still above: {p} MPa at {f} N/mm");
    assert!(s.take_warnings().is_empty());

    let mut s = Abdomen::initialized(&PRESSURE, &start).unwrap();
    for i in 0..20 {
        let t = f64::from(i) * 0.05;
        let target = 0.002 * (1.0 - (t + 0.05)).max(0.0);
        s.set("target_pressure", target).unwrap();
        s.do_step(t, 0.05).unwrap();
        let p = s.get("cavity_pressure").unwrap();
        let tolerance = if i < 19 { 1e-6 * 0.002 } else { 1e-5 };
        assert!((p - target).abs() <= tolerance, "t = {t}: {p} vs {target}");
    }
    assert!(s.take_warnings().is_empty());
}
