//! The abdomen against seed 003: mesh quality, the seed-003 findings with numbers, mesh
//! convergence, the defaults before and after issue 26, linear against finite strain,
//! timings.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Result;
use models::scene::abdomen::Abdomen;
use models::scene::Scene;

use crate::studies::findings;
use crate::sweep::Value;

fn scene(strings: &[(&str, &str)], reals: &[(&str, f64)]) -> Result<Abdomen> {
    Ok(Abdomen::initialized(strings, reals)?)
}

/// Peak pelvic-floor stress (mean, max) over the first press, for a scene with `settings`
/// ([`findings::peaks`]).
fn floor_peaks(settings: &[(&str, Value)]) -> Result<[f64; 2]> {
    let settings: Vec<(String, Value)> = settings
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
    findings::peaks(&settings)
}

/// Writes the section's tables to `out`.
pub fn run(out: &mut String) -> Result<()> {
    writeln!(
        out,
        "5. Abdomen (seed 003 §5.4): the default press (peak 0.8 N/mm at 1 s, 0.5 Hz) by the \
         contracting diaphragm, finite strain, Houbolt, dt = 10 ms"
    )?;
    let mut s = scene(&[], &[])?;
    if let Some(m) = s.meshed() {
        writeln!(
            out,
            "   default mesh: {} triangles, {} line elements, {} nodes; smallest angle {:.1}°",
            m.mesh.triangles().len(),
            m.mesh.lines().len(),
            m.mesh.nodes().len(),
            m.min_angle
        )?;
        let bins: Vec<String> = m
            .angle_histogram
            .iter()
            .enumerate()
            .filter(|(_, &c)| c > 0)
            .map(|(i, c)| format!("{}–{}°: {c}", 5 * i, 5 * i + 5))
            .collect();
        writeln!(out, "   triangles by smallest angle: {}", bins.join(", "))?;
    }
    writeln!(
        out,
        "   peak pelvic-floor stress over the first second (MPa):"
    )?;
    writeln!(out, "   {:<28} {:>10} {:>10}", "case", "mean", "max")?;
    let mut row = |label: &str, settings: &[(&str, Value)]| -> Result<()> {
        let p = floor_peaks(settings)?;
        writeln!(out, "   {label:<28} {:>10.5} {:>10.5}", p[0], p[1])?;
        Ok(())
    };
    for cfg in ["narrow", "normal", "wide", "lordotic", "tilted"] {
        row(
            &format!("configuration {cfg}"),
            &[("configuration", Value::Text(cfg.into()))],
        )?;
    }
    let free = ("abdominal_wall", Value::Text("free".into()));
    row("abdominal wall free", std::slice::from_ref(&free))?;
    row(
        "wall free, E = 225 kPa (10×)",
        &[free, ("wall_E", Value::Real(0.225))],
    )?;
    writeln!(out)?;

    writeln!(
        out,
        "   static pelvic-floor stress under 0.8 N/mm vs mesh size (graded):"
    )?;
    for n in [750.0, 3000.0] {
        let s = scene(&[], &[("target_triangles", n)])?;
        let u = s.static_displacement(0.8)?;
        let stress = s.evaluate(&u, 0.8)?;
        let tris = s.meshed().map_or(0, |m| m.mesh.triangles().len());
        writeln!(
            out,
            "   {tris:>6} triangles: mean {:.6} MPa, max {:.6} MPa",
            stress[0], stress[1]
        )?;
    }

    defaults_before_and_after(out)?;
    linear_and_finite(out)?;

    let start = Instant::now();
    let _ = scene(&[], &[])?;
    let setup = start.elapsed().as_secs_f64() * 1e3;
    let mut times = Vec::new();
    for i in 0..100 {
        let t0 = Instant::now();
        s.do_step(i as f64 * 1e-2, 1e-2)?;
        times.push(t0.elapsed().as_secs_f64() * 1e3);
    }
    times.sort_by(f64::total_cmp);
    writeln!(
        out,
        "   timings: set-up (configuration → mesh → factorization) {setup:.1} ms, Houbolt step median {:.3} ms",
        times[times.len() / 2]
    )?;
    Ok(())
}

/// Issue 26: the static solution at the default press on the defaults before (issue 12:
/// small strain, uniform 1,500-triangle mesh, the abdominal wall and its junction with the
/// diaphragm free, pelvic floor 0.1 MPa, the press a uniform pressure) and now.
fn defaults_before_and_after(out: &mut String) -> Result<()> {
    writeln!(
        out,
        "   static solution under the default press (0.8 N/mm), defaults before and after issue 26:"
    )?;
    let before = scene(
        &[
            ("kinematics", "linear"),
            ("abdominal_wall", "free"),
            ("costal_margin", "free"),
        ],
        &[
            ("target_triangles", 1500.0),
            ("mesh_grading", 0.0),
            ("floor_E", 0.1),
        ],
    )?;
    for (label, s) in [
        ("before (press as a contraction)", before),
        ("now", scene(&[], &[])?),
    ] {
        let u = s.static_displacement(0.8)?;
        let o = s.evaluate(&u, 0.8)?;
        writeln!(
            out,
            "   {label:<32} floor stress {:.2}/{:.2} kPa, apex {:6.1} mm, floor midpoint {:6.1} mm, \
             wall midpoint {:5.1} mm",
            1e3 * o[0],
            1e3 * o[1],
            o[7],
            o[9],
            o[10]
        )?;
    }
    Ok(())
}

/// Issue 12: when linear kinematics suffice — static floor stress and apex displacement,
/// linear against finite strain, at 0.25, 1 and 2 times the default press; then the cost of
/// finite strain in Houbolt steps at the default press.
fn linear_and_finite(out: &mut String) -> Result<()> {
    writeln!(
        out,
        "   linear vs finite strain (default mesh, static): floor stress mean, max (MPa), apex u_y (mm)"
    )?;
    let linear = scene(&[("kinematics", "linear")], &[])?;
    let finite = scene(&[], &[])?;
    for factor in [0.25, 1.0, 2.0] {
        let press = 0.8 * factor;
        let outputs = |s: &Abdomen| -> Result<[f64; 3]> {
            let o = s.evaluate(&s.static_displacement(press)?, press)?;
            Ok([o[0], o[1], o[7]])
        };
        let l = outputs(&linear)?;
        let finite = match outputs(&finite) {
            Ok(f) => {
                let change: Vec<String> = (0..3)
                    .map(|k| format!("{:+.1} %", 100.0 * (f[k] - l[k]) / l[k].abs()))
                    .collect();
                format!(
                    "finite {:.5} {:.5} {:7.2} | change {}",
                    f[0],
                    f[1],
                    f[2],
                    change.join(", ")
                )
            }
            Err(e) => format!("finite: {e:#}"),
        };
        writeln!(
            out,
            "   {factor:>4} × press: linear {:.5} {:.5} {:7.2} | {finite}",
            l[0], l[1], l[2]
        )?;
    }
    writeln!(
        out,
        "   Houbolt, dt = 10 ms, one press (2 s) on the default mesh: time, Newton iterations \
         and tangent factorizations per step"
    )?;
    let mixed = [("formulation", "mixed")];
    for (label, strings, nu) in [
        ("finite, displacement", &[][..], 0.49),
        ("finite, mixed, ν = 0.4999", &mixed[..], 0.4999),
        ("linear", &[("kinematics", "linear")][..], 0.49),
    ] {
        let (step_ms, iterations, factorizations) = stepping_cost(strings, nu)?;
        writeln!(
            out,
            "   {label:<27} {step_ms:6.2} ms, {iterations:5.2} iterations, \
             {factorizations:4.2} factorizations"
        )?;
    }
    Ok(())
}

/// Mean step time (ms), Newton iterations and tangent factorizations per step over one press
/// (2 s) at dt = 10 ms on the default mesh with `strings` and the contents' ν = `nu`.
fn stepping_cost(strings: &[(&str, &str)], nu: f64) -> Result<(f64, f64, f64)> {
    let mut s = scene(strings, &[("cavity_nu", nu)])?;
    let (steps, mut iterations, mut factorizations) = (200, 0, 0);
    let start = Instant::now();
    for i in 0..steps {
        s.do_step(f64::from(i) * 1e-2, 1e-2)?;
        iterations += s.newton_iterations().unwrap_or(0);
        factorizations += s.newton_factorizations().unwrap_or(0);
    }
    let per_step = |n: usize| n as f64 / f64::from(steps);
    let ms = start.elapsed().as_secs_f64() * 1e3 / f64::from(steps);
    Ok((ms, per_step(iterations), per_step(factorizations)))
}
