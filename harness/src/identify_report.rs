//! The identification report: E and ν of the cut block fitted to a measurement set (the
//! shipped set A by default), the profile deviations against seed 002's acceptance criterion,
//! the E–ν trade-off, and plots of forces and profiles, data against model.

use std::path::Path;

use anyhow::Result;
use harness::identify::{identify, response, Measurements};
use harness::plot::{self, Axis, Chart, Curve, Mark};
use harness::report::Report;
use models::scene::cutblock::PROFILE_STEP;

/// Adds the section to `report`.
pub fn run(report: &mut Report, dir: &Path, set: &str) -> Result<()> {
    report.heading(&format!(
        "Material identification, cut block, data set {set}"
    ));
    let m = Measurements::load(dir, set)?;
    let fit = identify(&m)?;
    let r = response(fit.nu, m.profile_pull)?;
    report.text(&format!(
        "Data: {} ({} force–displacement points, profiles at {} mm pull). ν from the profiles \
         (Brent's method, argmin): **{:.4}**; E from the forces at that ν: **{:.5} ± {:.5} MPa** \
         (standard error). Force RMS residual {:.4} N (largest measured force {:.3} N); profile \
         RMS {:.4} mm.",
        dir.display(),
        m.force.len(),
        m.profile_pull,
        fit.nu,
        fit.e,
        fit.e_std,
        fit.force_rms,
        m.force.iter().copied().fold(0.0, f64::max),
        fit.profile_rms
    ));
    if fit.nu > 0.498 {
        report.text(
            "ν sits at the upper end of the search interval: the profile misfit keeps falling \
             toward incompressibility, a sign of model-form error (the linear model overshoots the \
             rise near the cut), so this ν is not a trustworthy material value.",
        );
    }
    let rows: Vec<Vec<String>> = [25, 50, 75]
        .iter()
        .zip(&fit.lines)
        .map(|(x, d)| {
            vec![
                format!("x = {x} mm"),
                format!("{:.3}", d.rms),
                format!("{:.3}", d.max),
                d.points.to_string(),
                if d.max < 1.0 { "meets" } else { "misses" }.into(),
            ]
        })
        .collect();
    report.text(
        "Profile deviation per scan line; acceptance (seed 002 §3.5): below 1 % of the largest \
         block dimension = 1 mm.",
    );
    report.table(
        &["line", "RMS (mm)", "max (mm)", "points", "criterion"],
        &rows,
    );
    report.text(
        "E–ν trade-off: with the pull prescribed the force is E · c(ν) · d, so the forces alone \
         fit every ν equally well with its own E (their E–ν correlation is exact, −1 in the \
         linearized sense); only the profiles pin ν down. Profile misfit and force-only E over ν:",
    );
    let scan: Vec<Vec<String>> = fit
        .scan
        .iter()
        .map(|(nu, rms, e)| vec![nu.to_string(), format!("{rms:.4}"), format!("{e:.5}")])
        .collect();
    report.table(&["ν", "profile RMS (mm)", "E from forces (MPa)"], &scan);
    let data: Vec<(f64, f64)> = m
        .displacement
        .iter()
        .copied()
        .zip(m.force.clone())
        .collect();
    let model = m
        .displacement
        .iter()
        .map(|&d| (d, fit.e * r.force_per_e_mm * d))
        .collect();
    plot::chart(
        &report.path("force_displacement"),
        &Chart {
            title: format!("Cut block, set {set}: reaction force, data vs fit"),
            x: Axis::linear("pull displacement (mm)"),
            y: Axis::linear("reaction force (N)"),
            curves: vec![
                Curve::new("measured", data, Mark::Dots),
                Curve::new(
                    &format!("model, E = {:.4} MPa, ν = {:.3}", fit.e, fit.nu),
                    model,
                    Mark::Line,
                )
                .colour(1),
            ],
        },
    )?;
    report.figure(
        "Force–displacement: data and fitted model",
        "force_displacement",
    );
    let mut curves = Vec::new();
    for (k, x) in [25, 50, 75].iter().enumerate() {
        let data = m.profiles[k].clone();
        curves.push(Curve::new(&format!("scan x = {x} mm"), data, Mark::Dots).colour(k));
        let model = r.profiles[k]
            .iter()
            .enumerate()
            .filter(|(_, z)| z.is_finite())
            .map(|(i, &z)| (i as f64 * PROFILE_STEP, z))
            .collect();
        curves.push(Curve::new(&format!("model x = {x} mm"), model, Mark::Line).colour(k));
    }
    plot::chart(
        &report.path("profiles"),
        &Chart {
            title: format!(
                "Top-surface profiles at {} mm pull, data vs model",
                m.profile_pull
            ),
            x: Axis::linear("y along the pull (mm)"),
            y: Axis::linear("surface height z (mm)"),
            curves,
        },
    )?;
    report.figure("Laser profiles: scanner data and model", "profiles");
    Ok(())
}
