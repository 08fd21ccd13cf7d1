//! The speed-versus-error report for the abdomen scene: the reference and its own error
//! estimates, the table, CSV and Pareto plot of every case, the cheapest setting for 5 %,
//! 1 % and 0.1 %, and the stability table on the hard cases.

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::{Depth, Report};
use crate::studies::speed_error::{
    cheapest, measure, pareto, reference, write_csv, AbdomenReference, AbdomenRun, Study,
    QUANTITIES,
};
use crate::studies::stability::stability;
use models::verify::richardson::RichardsonEstimate;

/// The tolerances the report recommends a setting for.
const TOLERANCES: [f64; 3] = [0.05, 0.01, 0.001];

/// Adds the section to `report`: the full study, or at [`Depth::Quick`] [`Study::quick`].
pub fn section(report: &mut Report, depth: Depth) -> Result<()> {
    let study = match depth {
        Depth::Quick => Study::quick(),
        Depth::Full => Study::default(),
    };
    let total = study.case_count();
    let bar = ProgressBar::new(total as u64 + 1).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed_precise} {msg}")
            .expect("the template is valid"),
    );
    bar.set_message("abdomen speed–error: reference");
    let reference = reference(study.reference, study.duration)?;
    bar.inc(1);
    let cases = measure(&study, &reference, |c| {
        bar.inc(1);
        bar.set_message(format!(
            "abdomen speed–error: {} {} {} {} triangles {}",
            c.kinematics, c.element, c.formulation, c.triangles, c.order
        ));
    })?;
    bar.finish_and_clear();
    report.heading("Speed versus error, abdomen");
    if depth == Depth::Quick {
        report.text(
            "Quick: the coarsest mesh of each model form against a finite-strain reference on \
             12,000 graded triangles, whose own estimated error (below) bounds what this table \
             can resolve; `--full` measures more meshes and steps against 48,000 graded \
             triangles.",
        );
    }
    describe_reference(report, &study, &reference);
    table(report, &cases);
    write_csv(&cases, &report.path("speed_error.csv"))?;
    report.file("measurements", "speed_error.csv");
    recommendations(report, &cases, &reference);
    pareto_plot(report, &cases)?;
    report.text("Stability on hard cases (300 triangles, 0.1 s):");
    let rows: Vec<Vec<String>> = stability()
        .into_iter()
        .map(|s| vec![s.case.into(), s.integrator.into(), s.outcome])
        .collect();
    report.table(&["case", "integrator", "outcome"], &rows);
    Ok(())
}

fn describe_reference(report: &mut Report, study: &Study, reference: &AbdomenReference) {
    let r = study.reference;
    let e = &reference.error;
    report.text(&format!(
        "Errors: max over the first {} s (the rise of the default press to its peak, sampled \
         every 20 ms) of the deviation of each history from the reference, relative to the \
         reference's peak; a case's error is the largest of the four. The apex and the floor \
         midpoint are fixed points of every mesh; the wall midpoint, braced by default, does not \
         move and is not compared. Reference — the right physics at this load: \
         finite strain, tri6 displacement on {} triangles (target {}, mesh_grading {}), Houbolt \
         at dt = {} s. Its own errors, estimated from the static outputs at the peak press: \
         mesh — the larger of the Richardson error on its graded family (targets {}, {}, {}) \
         and its distance from the Richardson extrapolation of uniform nested meshes (target {} \
         split into four 1–3 times); time step — halving dt on the graded target-{} mesh \
         (× 4/3, second order):",
        study.duration,
        e.triangles,
        r.target,
        r.grading,
        r.dt,
        r.target / 16,
        r.target / 4,
        r.target,
        r.target / 64,
        r.target / 16,
    ));
    let fit = |f: &Result<RichardsonEstimate, String>| match f {
        Ok(f) => format!("order {:.2}, {:.6e}", f.order, f.value),
        Err(why) => why.clone(),
    };
    let rows: Vec<Vec<String>> = (0..QUANTITIES.len())
        .map(|k| {
            let [a, b, c] = e.graded_values[k];
            vec![
                QUANTITIES[k].into(),
                format!("{a:.6e}, {b:.6e}, {c:.6e}"),
                fit(&e.graded[k]),
                fit(&e.uniform[k]),
                format!("{:.2e}", e.mesh_error[k]),
                format!("{:.2e}", e.time_error[k]),
            ]
        })
        .collect();
    report.table(
        &[
            "quantity",
            "graded family (static, peak press)",
            "graded family: Richardson",
            "uniform nested: Richardson",
            "mesh error",
            "time-step error",
        ],
        &rows,
    );
}

fn table(report: &mut Report, cases: &[AbdomenRun]) {
    let rows: Vec<Vec<String>> = cases
        .iter()
        .map(|c| {
            vec![
                c.kinematics.into(),
                c.element.into(),
                c.formulation.into(),
                c.grading.to_string(),
                c.triangles.to_string(),
                c.order.into(),
                c.integrator.clone(),
                c.dt.to_string(),
                format!("{:.1}", c.setup_ms),
                format!("{:.3}", c.step_ms),
                format!("{:.0}", c.ms_per_second()),
                format!("{:.2e}", c.errors[0]),
                format!("{:.2e}", c.errors[1]),
                format!("{:.2e}", c.errors[2]),
                format!("{:.2e}", c.errors[3]),
            ]
        })
        .collect();
    report.table(
        &[
            "kinematics",
            "element",
            "formulation",
            "grading",
            "triangles",
            "order",
            "integrator",
            "dt (s)",
            "set-up (ms)",
            "step (ms)",
            "ms per simulated s",
            "error floor stress mean",
            "error floor stress max",
            "error apex",
            "error floor midpoint",
        ],
        &rows,
    );
}

/// The cheapest case for each tolerance, or why there is none: a tolerance below twice the
/// reference's own estimated error is not resolvable.
fn recommendations(report: &mut Report, cases: &[AbdomenRun], reference: &AbdomenReference) {
    let e = &reference.error;
    // An error that could not be estimated (NaN) resolves nothing.
    let resolvable = (0..QUANTITIES.len())
        .map(|k| 2.0 * (e.mesh_error[k] + e.time_error[k]))
        .map(|x| if x.is_nan() { f64::INFINITY } else { x })
        .fold(0.0, f64::max);
    let rows: Vec<Vec<String>> = TOLERANCES
        .iter()
        .map(|&tol| {
            let answer = if tol < resolvable {
                format!(
                    "not resolvable: twice the reference's own estimated error is {:.2} %",
                    100.0 * resolvable
                )
            } else {
                cheapest(cases, tol).map_or("no case of the study".into(), |c| {
                    format!(
                        "{} strain, {} {} on {} triangles (mesh_grading {}), {} order, {} at \
                         dt = {} s: {:.0} ms per simulated s (set-up {:.0} ms), error {:.2} %",
                        c.kinematics,
                        c.element,
                        c.formulation,
                        c.triangles,
                        c.grading,
                        c.order,
                        c.integrator,
                        c.dt,
                        c.ms_per_second(),
                        c.setup_ms,
                        100.0 * c.error()
                    )
                })
            };
            vec![format!("{} %", 100.0 * tol), answer]
        })
        .collect();
    report.text("The cheapest setting (stepping time per simulated second) for each error:");
    report.table(&["error at most", "setting"], &rows);
}

/// Error against stepping time per simulated second, one colour per discretization and
/// integrator, with the Pareto front.
fn pareto_plot(report: &mut Report, cases: &[AbdomenRun]) -> Result<()> {
    let points: Vec<(f64, f64)> = cases
        .iter()
        .map(|c| (c.ms_per_second(), c.error()))
        .collect();
    let mut curves = plot::grouped(cases.iter().zip(&points).map(|(c, &point)| {
        (
            format!(
                "{} {} {}{}, {}, {}",
                c.kinematics,
                c.element,
                c.formulation,
                if c.grading > 0.0 { " graded" } else { "" },
                c.order,
                c.integrator
            ),
            point,
        )
    }));
    let colour = curves.len();
    curves.push(Curve::new("Pareto front", pareto(&points), Mark::Line).colour(colour));
    plot::chart(
        &report.path("pareto"),
        &Chart {
            title: "Abdomen: stepping time vs error".into(),
            x: Axis::log("stepping time per simulated second (ms)"),
            y: Axis::log("relative error against finite strain (1)"),
            curves,
        },
    )?;
    report.figure("Speed versus error with the Pareto front", "pareto");
    Ok(())
}
