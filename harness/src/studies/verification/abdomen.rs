//! The abdomen against seed 003: mesh quality, the seed-003 findings with numbers, mesh convergence,
//! timings.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::time::Instant;

use anyhow::{Context, Result};
use models::scene::abdomen::Abdomen;
use models::scene::Scene;

use crate::sweep::{simulate, InProcess, Schedule, Value};

fn scene(strings: &[(&str, &str)], reals: &[(&str, f64)]) -> Result<Abdomen> {
    let mut s = Abdomen::new();
    for (k, v) in strings {
        s.set_str(k, v)?;
    }
    for (k, v) in reals {
        s.set(k, *v)?;
    }
    s.initialize(0.0)?;
    Ok(s)
}

/// Peak pelvic-floor stress (mean, max) over 1 s of the default pressing at dt = 1 ms, for
/// a scene with `settings`.
fn floor_peaks(settings: &[(&str, Value)]) -> Result<[f64; 2]> {
    let settings: Vec<(String, Value)> = settings
        .iter()
        .map(|(k, v)| (k.to_string(), v.clone()))
        .collect();
    let record = [
        "floor_stress_mean".to_string(),
        "floor_stress_max".to_string(),
    ];
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: 1.0,
        step: 1e-3,
        settings: &settings,
        inputs: &BTreeMap::new(),
        record: &record,
    };
    let series = simulate(&mut InProcess(Box::new(Abdomen::new())), &schedule)?.series;
    let peak = |name: &str| -> Result<f64> {
        let column = series.column(name).context("recorded")?;
        Ok(column[1..]
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max))
    };
    Ok([peak("floor_stress_mean")?, peak("floor_stress_max")?])
}

/// Writes the section's tables to `out`.
pub fn run(out: &mut String) -> Result<()> {
    writeln!(
        out,"5. Abdomen (seed 003 §5.4): default pressing 0.8 N/mm at 0.5 Hz on the diaphragm, Houbolt, dt = 1 ms")?;
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
    row("wall E = 225 kPa (10×)", &[("wall_E", Value::Real(0.225))])?;
    row(
        "abdominal wall fixed",
        &[("abdominal_wall", Value::Text("fixed".into()))],
    )?;
    writeln!(out)?;

    writeln!(
        out,
        "   static pelvic-floor stress under 0.8 N/mm vs mesh size:"
    )?;
    for n in [1500.0, 6000.0, 24000.0] {
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

    let start = Instant::now();
    let _ = scene(&[], &[])?;
    let setup = start.elapsed().as_secs_f64() * 1e3;
    let mut times = Vec::new();
    for i in 0..300 {
        let t0 = Instant::now();
        s.do_step(i as f64 * 1e-3, 1e-3)?;
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
