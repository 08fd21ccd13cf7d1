//! The abdomen report: mesh quality, the seed-003 findings with numbers, mesh convergence,
//! timings.

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::Result;
use models::scene::abdomen::Abdomen;
use models::scene::Scene;

fn scene(strings: &[(&str, &str)], reals: &[(&str, f64)]) -> Result<Abdomen> {
    let mut s = Abdomen::new();
    for (k, v) in strings {
        s.set_str(k, v)?;
    }
    for (k, v) in reals {
        s.set(k, *v)?;
    }
    s.initialize()?;
    Ok(s)
}

/// Peak pelvic-floor stress (mean, max) over 1 s of pressing at dt = 1 ms.
fn floor_peaks(s: &mut Abdomen) -> Result<[f64; 2]> {
    let mut peak = [f64::NEG_INFINITY; 2];
    for i in 0..1000 {
        s.do_step(i as f64 * 1e-3, 1e-3)?;
        peak[0] = peak[0].max(s.get("floor_stress_mean")?);
        peak[1] = peak[1].max(s.get("floor_stress_max")?);
    }
    Ok(peak)
}

/// Prints the report.
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
    let mut row = |label: &str, s: &mut Abdomen| -> Result<()> {
        let p = floor_peaks(s)?;
        writeln!(out, "   {label:<28} {:>10.5} {:>10.5}", p[0], p[1])?;
        Ok(())
    };
    for cfg in ["narrow", "normal", "wide", "lordotic", "tilted"] {
        row(
            &format!("configuration {cfg}"),
            &mut scene(&[("configuration", cfg)], &[])?,
        )?;
    }
    row(
        "wall E = 225 kPa (10×)",
        &mut scene(&[], &[("wall_E", 0.225)])?,
    )?;
    row(
        "abdominal wall fixed",
        &mut scene(&[("abdominal_wall", "fixed")], &[])?,
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
