//! The speed-versus-error report for the abdomen scene: table, CSV, Pareto plot and the
//! stability table on the hard cases.

use anyhow::Result;

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::Report;
use crate::studies::speed_error::{measure, pareto, stability, write_csv, Case, Study};

/// Adds the section to `report`.
pub fn section(report: &mut Report) -> Result<()> {
    let study = Study::default();
    report.heading("Speed versus error, abdomen");
    report.text(&format!(
        "Error: peak-normalized max deviation of the pelvic-floor stress history over {} s from \
         Houbolt on {} triangles at dt = {} s. Run time: set-up plus the steps of {} s simulated.",
        study.duration, study.reference.0, study.reference.1, study.duration
    ));
    let cases = measure(&study)?;
    let cost = |c: &Case| c.setup_ms + c.step_ms * study.duration / c.dt;
    let rows: Vec<Vec<String>> = cases
        .iter()
        .map(|c| {
            vec![
                c.triangles.to_string(),
                c.integrator.clone(),
                c.dt.to_string(),
                format!("{:.1}", c.setup_ms),
                format!("{:.3}", c.step_ms),
                format!("{:.0}", cost(c)),
                format!("{:.3e}", c.error),
            ]
        })
        .collect();
    report.table(
        &[
            "triangles",
            "integrator",
            "dt (s)",
            "set-up (ms)",
            "step (ms)",
            "run (ms)",
            "rel. error",
        ],
        &rows,
    );
    write_csv(&cases, &report.path("speed_error.csv"))?;
    report.file("measurements", "speed_error.csv");
    let points: Vec<(f64, f64)> = cases.iter().map(|c| (cost(c), c.error)).collect();
    pareto_plot(report, &cases, &points, study.duration)?;
    report.text("Stability on hard cases (800 triangles, 0.1 s):");
    let rows: Vec<Vec<String>> = stability()
        .into_iter()
        .map(|s| vec![s.case.into(), s.integrator.into(), s.outcome])
        .collect();
    report.table(&["case", "integrator", "outcome"], &rows);
    Ok(())
}

/// Error against run time, one colour per mesh and integrator, with the Pareto front.
fn pareto_plot(
    report: &mut Report,
    cases: &[Case],
    points: &[(f64, f64)],
    duration: f64,
) -> Result<()> {
    let mut curves = plot::grouped(cases.iter().zip(points).map(|(c, &point)| {
        (
            format!("{} triangles, {}", c.triangles, c.integrator),
            point,
        )
    }));
    let colour = curves.len();
    curves.push(Curve::new("Pareto front", pareto(points), Mark::Line).colour(colour));
    plot::chart(
        &report.path("pareto"),
        &Chart {
            title: "Abdomen: run time vs error of the pelvic-floor stress".into(),
            x: Axis::log(&format!("run time for {duration} s simulated (ms)")),
            y: Axis::log("relative error of floor stress (1)"),
            curves,
        },
    )?;
    report.figure("Speed versus error with the Pareto front", "pareto");
    Ok(())
}
