//! The abdomen scene's discretizations (issue 12): `element` tri3 | tri6, `formulation`
//! displacement | mixed, `kinematics` linear | finite — checked choices, supports on the
//! mid-edge nodes, locking, finite strain against small strain at small loads, and the
//! reduced order on 6-node triangles.

use models::scene::abdomen::Abdomen;
use models::scene::Scene;

/// The static outputs (table order, from `floor_stress_mean`) under a press of `press`.
fn static_outputs(s: &Abdomen, press: f64) -> Vec<f64> {
    let u = s.static_displacement(press).unwrap();
    s.evaluate(&u, press).unwrap()
}

/// Indices into [`static_outputs`].
const FLOOR_MEAN: usize = 0;
const APEX_UY: usize = 7;

#[test]
fn element_choices_are_checked_with_clear_errors() {
    let mut s = Abdomen::new();
    for (name, bad) in [
        ("element", "tri4"),
        ("formulation", "hybrid"),
        ("kinematics", "large"),
    ] {
        let e = s.set_str(name, bad).unwrap_err().to_string();
        assert!(e.contains(name) && e.contains(bad), "{e}");
    }
    let refused = [
        (
            vec![("element", "tri3"), ("formulation", "mixed")],
            "needs element = `tri6`",
        ),
        (
            vec![("element", "tri3"), ("kinematics", "finite")],
            "needs element = `tri6`",
        ),
        (
            vec![
                ("element", "tri6"),
                ("kinematics", "finite"),
                ("model_order", "modal"),
            ],
            "finite strain",
        ),
    ];
    for (strings, expected) in refused {
        let e = Abdomen::initialized(&strings, &[("target_triangles", 300.0)])
            .unwrap_err()
            .to_string();
        assert!(e.contains(expected), "{strings:?}: {e}");
    }
    // Finite strain on the mixed element is offered (issue 26).
    Abdomen::initialized(
        &[("formulation", "mixed"), ("kinematics", "finite")],
        &[("target_triangles", 300.0)],
    )
    .unwrap();
    let e = s.set_str("costal_margin", "loose").unwrap_err().to_string();
    assert!(e.contains("costal_margin") && e.contains("loose"), "{e}");
    // An explicit scheme cannot step finite strain; the error says so at the first step.
    let mut s = Abdomen::initialized(
        &[
            ("element", "tri6"),
            ("kinematics", "finite"),
            ("integrator", "central_difference"),
        ],
        &[("target_triangles", 300.0), ("max_step", 1e-5)],
    );
    let e = match &mut s {
        Ok(s) => s.do_step(0.0, 1e-5).unwrap_err().to_string(),
        Err(e) => e.to_string(),
    };
    assert!(e.contains("finite strain"), "{e}");
}

/// Spine and pelvic bone are polylines of n corners each: with 6-node triangles their n − 1
/// edges' mid-edge nodes are held too, and nothing else is; a fixed costal margin holds one
/// node more (the corner where wall and diaphragm meet).
#[test]
fn supports_hold_the_mid_edge_nodes_of_supported_edges() {
    let held = |margin: &str| {
        let s = Abdomen::initialized(
            &[
                ("abdominal_wall", "free"),
                ("costal_margin", margin),
                ("kinematics", "linear"),
            ],
            &[("target_triangles", 1500.0)],
        )
        .unwrap();
        let u = s.static_displacement(0.8).unwrap();
        let sets = s.meshed().unwrap().mesh.node_sets();
        let corners = sets.get("spine").unwrap().len() + sets.get("pelvic_bone").unwrap().len();
        let held = u.chunks(2).filter(|d| d[0] == 0.0 && d[1] == 0.0).count();
        (held, corners)
    };
    let (free, corners) = held("free");
    assert_eq!(free, corners + corners - 2);
    let (fixed, corners) = held("fixed");
    assert_eq!(fixed, corners + corners - 2 + 1);
}

/// At ν → 0.5 the 3-node triangles lock (the apex barely moves), the mixed 6-node ones do
/// not: their displacement hardly changes from ν = 0.49 to 0.4999 (small strain; at finite
/// strain: `tests/elements/plane_finite_strain.rs`).
#[test]
fn the_mixed_element_does_not_lock_where_linear_triangles_do() {
    let apex = |element: &str, formulation: &str, nu: f64| {
        let s = Abdomen::initialized(
            &[
                ("element", element),
                ("formulation", formulation),
                ("kinematics", "linear"),
                ("abdominal_wall", "free"),
            ],
            &[("target_triangles", 1500.0), ("cavity_nu", nu)],
        )
        .unwrap();
        static_outputs(&s, 0.8)[APEX_UY]
    };
    let mixed = [apex("tri6", "mixed", 0.49), apex("tri6", "mixed", 0.4999)];
    let tri3 = [
        apex("tri3", "displacement", 0.49),
        apex("tri3", "displacement", 0.4999),
    ];
    println!("apex u_y at nu 0.49, 0.4999: mixed {mixed:?}, tri3 {tri3:?}");
    // Between ν = 0.49 and 0.4999 the bulk modulus grows 100-fold but is already 50 times the
    // shear modulus: the compliance changes by a few per cent of its volumetric part at most.
    assert!((mixed[1] / mixed[0] - 1.0).abs() < 0.02, "{mixed:?}");
    assert!(tri3[1] / tri3[0] < 0.9, "{tri3:?}");
}

/// Finite strain departs from small strain in proportion to the load (the kinematics'
/// first neglected term), below 1e-3 relative at 10⁻⁵ of the default load, in the static
/// solution and in Houbolt steps. (The membranes' slack law leaves E ε at compressive
/// strains near δ = 10⁻³ (`element::membrane`): at 0.1 % of the load the compressed
/// diaphragm reaches 0.4 δ and the gap is 5 %; at 10⁻⁵ of it 0.004 δ.)
#[test]
fn finite_strain_departs_from_small_strain_in_proportion_to_the_load() {
    let tri6 = |kinematics: &str, amplitude: f64| {
        Abdomen::initialized(
            &[("element", "tri6"), ("kinematics", kinematics)],
            &[
                ("target_triangles", 600.0),
                ("press_amplitude", amplitude),
                ("press_frequency", 2.0),
            ],
        )
        .unwrap()
    };
    let (linear, finite) = (tri6("linear", 0.8), tri6("finite", 0.8));
    let gaps: Vec<[f64; 2]> = [0.8e-5, 1.6e-5, 0.8]
        .iter()
        .map(|&press| {
            let (a, b) = (
                static_outputs(&linear, press),
                static_outputs(&finite, press),
            );
            let gap = [APEX_UY, FLOOR_MEAN].map(|k| (b[k] / a[k] - 1.0).abs());
            println!(
                "static press {press} N/mm: relative gap apex u_y, floor stress {:.2e}, {:.2e}",
                gap[0], gap[1]
            );
            gap
        })
        .collect();
    for k in 0..2 {
        assert!(gaps[0][k] < 1e-3, "{gaps:?}");
        assert!((gaps[1][k] / gaps[0][k] - 2.0).abs() < 0.1, "{gaps:?}");
    }
    let (mut linear, mut finite) = (tri6("linear", 0.8e-5), tri6("finite", 0.8e-5));
    let mut worst: f64 = 0.0;
    for i in 0..100 {
        let t = i as f64 * 1e-3;
        linear.do_step(t, 1e-3).unwrap();
        finite.do_step(t, 1e-3).unwrap();
        let (a, b) = (
            linear.get("apex_uy").unwrap(),
            finite.get("apex_uy").unwrap(),
        );
        worst = worst.max((a - b).abs() / a.abs().max(1e-12));
    }
    println!("Houbolt, 100 steps at 10⁻⁵ of the load: worst relative gap {worst:.2e}");
    assert!(worst < 1e-3, "{worst}");
}

/// The reduced order works on 6-node triangles: 80 Ritz vectors of the mixed model follow
/// the full mixed model within 1 % over the first 0.3 s.
#[test]
fn modal_order_follows_the_full_order_on_mixed_triangles() {
    let run = |order: &str| {
        let mut s = Abdomen::initialized(
            &[
                ("element", "tri6"),
                ("formulation", "mixed"),
                ("kinematics", "linear"),
                ("model_order", order),
            ],
            &[("target_triangles", 600.0), ("cavity_nu", 0.4999)],
        )
        .unwrap();
        (0..300)
            .map(|i| {
                s.do_step(i as f64 * 1e-3, 1e-3).unwrap();
                s.get("apex_uy").unwrap()
            })
            .collect::<Vec<_>>()
    };
    let (full, modal) = (run("full"), run("modal"));
    let peak = full.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let worst = full
        .iter()
        .zip(&modal)
        .fold(0.0f64, |a, (f, m)| a.max((f - m).abs()));
    println!(
        "modal vs full, mixed tri6: {:.2e} of the peak",
        worst / peak
    );
    // Measured 1.03e-5 (2026-11-25); the 80-vector basis holds the static response exactly.
    assert!(worst < 3e-5 * peak, "{worst} of {peak}");
}

/// `mesh_subdivisions` nests the meshes: each split quadruples the triangles and keeps the
/// landmarks (the outputs' points) where they were; new boundary nodes lie on the curve,
/// between their neighbours.
#[test]
fn subdivided_meshes_are_nested_and_keep_their_landmarks() {
    let meshes: Vec<_> = (0..3)
        .map(|n| {
            Abdomen::initialized(
                &[],
                &[
                    ("target_triangles", 300.0),
                    ("mesh_grading", 0.0),
                    ("mesh_subdivisions", f64::from(n)),
                ],
            )
            .unwrap()
            .meshed()
            .unwrap()
            .clone()
        })
        .collect();
    let landmark = |m: &models::scene::abdomen::mesher::Meshed, set: &str| {
        m.mesh.nodes()[m.mesh.node_sets().get(set).unwrap()[0]]
    };
    for pair in meshes.windows(2) {
        let (coarse, fine) = (&pair[0].mesh, &pair[1].mesh);
        assert_eq!(fine.triangles().len(), 4 * coarse.triangles().len());
        assert_eq!(fine.lines().len(), 2 * coarse.lines().len());
        for set in ["diaphragm_apex", "floor_mid", "wall_mid"] {
            assert_eq!(landmark(&pair[0], set), landmark(&pair[1], set), "{set}");
        }
        // Splitting keeps the angles; moving boundary nodes onto the curve changes them a
        // little.
        assert!(pair[1].min_angle > pair[0].min_angle - 5.0);
    }
    let e = Abdomen::initialized(&[], &[("mesh_subdivisions", 1.5)])
        .unwrap_err()
        .to_string();
    assert!(e.contains("mesh_subdivisions"), "{e}");
}

#[test]
fn the_largest_strain_of_a_uniform_strain_field_is_its_principal_strain() {
    // u = H x: ε = sym H = [[0.02, 0.02], [0.02, −0.01]], principal strains
    // 0.005 ± 0.025, the larger magnitude 0.03 — on every triangle of either element.
    let h = [[0.02, 0.01], [0.03, -0.01]];
    for element in ["tri3", "tri6"] {
        let strings = [("element", element), ("kinematics", "linear")];
        let s = Abdomen::initialized(&strings, &[("target_triangles", 300.0)]).unwrap();
        let zero = s.static_displacement(0.0).unwrap();
        let view = s.view(&zero).unwrap();
        let nodes = view.quadratic.map_or(view.mesh.nodes(), |q| q.nodes());
        let u: Vec<f64> = nodes
            .iter()
            .flat_map(|x| h.map(|row| row[0] * x[0] + row[1] * x[1]))
            .collect();
        let strain = s.view(&u).unwrap().largest_strain();
        assert!((strain - 0.03).abs() < 1e-12, "{element}: {strain}");
    }
}

/// The contents' mean pressure (`cavity_pressure`) of a uniform plane-strain compression
/// u = −ε x, on every triangle of either element (area-weighted mean of equal values), is
/// the law's closed form. Linear, Hooke's: σ_xx = σ_yy = −2(λ + μ)ε, σ_zz = −2λε,
/// p = (4μ + 6λ)ε/3. Finite (neo-Hookean, F = diag(s, s, 1), s = 1 − ε, J = s²):
/// σ = J⁻¹(μ FFᵀ + (λ ln J − μ) I), so σ_xx = σ_yy = (μ(s² − 1) + λ ln J)/J and
/// σ_zz = λ ln J / J — the plane-strain σ_zz is in the trace, and at ε = 5 % the two
/// laws differ by 5 %.
#[test]
fn the_mean_pressure_of_a_uniform_compression_is_the_laws() {
    let (e, nu) = (0.005, 0.45);
    let (lambda, mu) = (
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        e / (2.0 * (1.0 + nu)),
    );
    let hooke = |eps: f64| (4.0 * mu + 6.0 * lambda) * eps / 3.0;
    let neo_hooke = |eps: f64| {
        let (s, j) = (1.0 - eps, (1.0 - eps).powi(2));
        let (inplane, zz) = (
            (mu * (s * s - 1.0) + lambda * j.ln()) / j,
            lambda * j.ln() / j,
        );
        -(2.0 * inplane + zz) / 3.0
    };
    let cases = [
        ("tri3", "displacement", "linear", 1e-3),
        ("tri6", "displacement", "linear", 1e-3),
        ("tri6", "displacement", "finite", 0.05),
        ("tri6", "mixed", "finite", 0.05),
    ];
    for (element, formulation, kinematics, eps) in cases {
        let strings = [
            ("element", element),
            ("formulation", formulation),
            ("kinematics", kinematics),
        ];
        let reals = [
            ("target_triangles", 300.0),
            ("cavity_E", e),
            ("cavity_nu", nu),
        ];
        let s = Abdomen::initialized(&strings, &reals).unwrap();
        let zero = s.static_displacement(0.0).unwrap();
        let view = s.view(&zero).unwrap();
        let nodes = view.quadratic.map_or(view.mesh.nodes(), |q| q.nodes());
        let u: Vec<f64> = nodes.iter().flat_map(|x| x.map(|c| -eps * c)).collect();
        let pressure = s.evaluate(&u, 0.0).unwrap()[13];
        let expected = match kinematics {
            "linear" => hooke(eps),
            _ => neo_hooke(eps),
        };
        assert!(
            (pressure / expected - 1.0).abs() < 1e-10,
            "{element} {formulation} {kinematics}: {pressure} vs {expected}"
        );
    }
    assert!((neo_hooke(0.05) / hooke(0.05) - 1.0).abs() > 0.03);
}

#[test]
fn the_scene_warns_once_where_it_leaves_its_validity() {
    let strain = |w: &[String]| w.iter().any(|m| m.contains("principal strain"));
    let locking = |w: &[String]| w.iter().any(|m| m.contains("free of locking"));
    // The default press strains the linear model beyond 5 % within half a period: one
    // warning.
    let linear = [("kinematics", "linear")];
    let mut s = Abdomen::initialized(&linear, &[]).unwrap();
    assert!(s.take_warnings().is_empty());
    let mut warnings = Vec::new();
    for i in 0..50 {
        s.do_step(i as f64 * 1e-2, 1e-2).unwrap();
        warnings.extend(s.take_warnings());
    }
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(strain(&warnings) && warnings[0].contains("kinematics = \"finite\""));
    // The modal order (which checks a bound before it expands its field) warns at the same
    // step; under a press a hundred times smaller neither warns.
    for (amplitude, expected) in [(0.8, &warnings), (0.008, &Vec::new())] {
        for order in ["full", "modal"] {
            let strings = [linear[0], ("model_order", order)];
            let mut s = Abdomen::initialized(&strings, &[("press_amplitude", amplitude)]).unwrap();
            let mut seen = Vec::new();
            for i in 0..50 {
                s.do_step(i as f64 * 1e-2, 1e-2).unwrap();
                seen.extend(s.take_warnings());
            }
            assert_eq!(&seen, expected, "{order} at {amplitude} N/mm");
        }
    }
    // At finite strain (the default) the same load is no reason to warn.
    let mut s = Abdomen::initialized(&[], &[("target_triangles", 300.0)]).unwrap();
    for i in 0..50 {
        s.do_step(i as f64 * 1e-2, 1e-2).unwrap();
    }
    assert!(s.take_warnings().is_empty());
    // Linear triangles lock beyond ν = 0.45 (the default is 0.49); the 6-node displacement element beyond
    // 0.499, also when ν is raised at run time; the mixed element does not.
    let tri3 = [("element", "tri3"), linear[0]];
    let mut s = Abdomen::initialized(&tri3, &[("press_amplitude", 0.0)]).unwrap();
    assert!(locking(&s.take_warnings()));
    let mut s = Abdomen::initialized(&[], &[("press_amplitude", 0.0)]).unwrap();
    assert!(s.take_warnings().is_empty());
    s.set("cavity_nu", 0.4999).unwrap();
    s.do_step(0.0, 1e-3).unwrap();
    assert!(locking(&s.take_warnings()));
    let mut s =
        Abdomen::initialized(&[("formulation", "mixed")], &[("cavity_nu", 0.4999)]).unwrap();
    assert!(s.take_warnings().is_empty());
}
