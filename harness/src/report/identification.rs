//! The identification report: E (and ν, when profiles are given) of the cut block fitted to a
//! measurement set (the shipped set A by default) or to a force–displacement CSV alone; the
//! profile deviations against seed 002's acceptance criterion; the E–ν trade-off; plots of
//! forces and profiles, data against model.

use std::path::Path;

use std::path::PathBuf;

use anyhow::Result;
use models::scene::cutblock::PROFILE_STEP;

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::Report;
use crate::studies::identify::{identify, response, Fit, Measurements, Response};
use crate::studies::profiles::align;
use crate::sweep::experiment::shipped_dir;

/// What to fit: a measurement set (forces and profiles) or a force–displacement CSV alone.
pub enum Data<'a> {
    Set { dir: &'a Path, set: &'a str },
    Forces(&'a Path),
}

/// The shipped measurement sets (`experiments/data/cutblock`).
pub fn shipped_data() -> PathBuf {
    shipped_dir().join("data/cutblock")
}

/// The `identify` command: a report in `out` on a measurement set in `data` (the shipped
/// sets by default) or on a force–displacement CSV alone.
pub fn command(
    data: Option<PathBuf>,
    set: &str,
    forces: Option<PathBuf>,
    nu: Option<f64>,
    out: &std::path::Path,
) -> Result<PathBuf> {
    let mut report = Report::create(out, "Material identification")?;
    let dir = data.unwrap_or_else(shipped_data);
    let what = match &forces {
        Some(path) => Data::Forces(path),
        None => Data::Set { dir: &dir, set },
    };
    section(&mut report, what, nu)?;
    report.finish()
}

/// Adds the section to `report`; `fixed_nu` skips the ν fit.
pub fn section(report: &mut Report, data: Data, fixed_nu: Option<f64>) -> Result<()> {
    let (m, name) = match data {
        Data::Set { dir, set } => (
            Measurements::load(dir, set)?,
            format!("set {set} in {}", dir.display()),
        ),
        Data::Forces(path) => (Measurements::load_forces(path)?, path.display().to_string()),
    };
    report.heading(&format!("Material identification, cut block, {name}"));
    let fit = identify(&m, fixed_nu)?;
    let r = response(fit.nu, m.profile_pull)?;
    let nu_source = if fixed_nu.is_some() {
        "given"
    } else {
        "from the profiles (Brent's method, argmin)"
    };
    report.text(&format!(
        "{} force–displacement points. ν {nu_source}: **{:.4}**; E from the forces at that ν: \
         **{:.5} ± {:.5} MPa** (standard error). Force RMS residual {:.4} N (largest measured \
         force {:.3} N).",
        m.force.len(),
        fit.nu,
        fit.e,
        fit.e_std,
        fit.force_rms,
        m.force.iter().copied().fold(0.0, f64::max),
    ));
    report.text(
        "E–ν trade-off: with the pull prescribed the force is E · c(ν) · d, so the forces alone \
         fit every ν equally well with its own E (their E–ν correlation is exact, −1 in the \
         linearized sense); only the profiles pin ν down.",
    );
    forces_plot(report, &m, &fit, &r)?;
    if m.has_profiles() {
        profiles_section(report, &m, &fit, &r, fixed_nu.is_none())?;
    }
    Ok(())
}

fn forces_plot(report: &mut Report, m: &Measurements, fit: &Fit, r: &Response) -> Result<()> {
    let data = m
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
    let label = format!("model, E = {:.4} MPa, ν = {:.3}", fit.e, fit.nu);
    plot::chart(
        &report.path("force_displacement"),
        &Chart {
            title: "Cut block: reaction force, data vs fit".into(),
            x: Axis::linear("pull displacement (mm)"),
            y: Axis::linear("reaction force (N)"),
            curves: vec![
                Curve::new("measured", data, Mark::Dots),
                Curve::new(&label, model, Mark::Line).colour(1),
            ],
        },
    )?;
    report.figure(
        "Force–displacement: data and fitted model",
        "force_displacement",
    );
    Ok(())
}

fn profiles_section(
    report: &mut Report,
    m: &Measurements,
    fit: &Fit,
    r: &Response,
    nu_fitted: bool,
) -> Result<()> {
    report.text(&format!("Profile RMS deviation {:.4} mm.", fit.profile_rms));
    if nu_fitted && fit.nu > 0.498 {
        report.text(
            "ν sits at the upper end of the search interval: the profile misfit keeps falling \
             toward incompressibility, a sign of model-form error (the linear model overshoots \
             the rise near the cut), so this ν is not a trustworthy material value.",
        );
    }
    report.text(
        "Profile deviation per scan line; acceptance (seed 002 §3.5): max below 1 % of the \
         largest block dimension = 1 mm. Lab frame: scanner and model share the clamped edge \
         y = 0, no offset. Aligned: the scan shifted rigidly by the (Δy, Δz) that minimizes its \
         RMS deviation (`harness/src/profiles.rs`), for scans whose registration is uncertain.",
    );
    let verdict = |max: f64| if max < 1.0 { "meets" } else { "misses" };
    let mut rows = Vec::new();
    for (k, x) in [25, 50, 75].iter().enumerate() {
        let lab = fit.lines[k];
        let a = align(&r.profiles[k], &m.profiles[k])?;
        rows.push(vec![
            format!("x = {x} mm"),
            lab.points.to_string(),
            format!("{:.3} / {:.3}", lab.rms, lab.max),
            verdict(lab.max).into(),
            format!("{:+.3} / {:+.3}", a.dy, a.dz),
            format!("{:.3} / {:.3}", a.deviation.rms, a.deviation.max),
            verdict(a.deviation.max).into(),
        ]);
    }
    report.table(
        &[
            "line",
            "points",
            "lab RMS / max (mm)",
            "lab",
            "fitted Δy / Δz (mm)",
            "aligned RMS / max (mm)",
            "aligned",
        ],
        &rows,
    );
    report.text("Profile misfit and the force-only E over ν:");
    let scan: Vec<Vec<String>> = fit
        .scan
        .iter()
        .map(|(nu, rms, e)| vec![nu.to_string(), format!("{rms:.4}"), format!("{e:.5}")])
        .collect();
    report.table(&["ν", "profile RMS (mm)", "E from forces (MPa)"], &scan);
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
