//! The speed-versus-error report for the cut block: table, CSV and Pareto plot of every
//! model (law × element × mesh) against the reference, with a progress line per case.

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::{Depth, Report};
use crate::studies::cut_speed_error::{errors, measure, write_csv, Answer, Case, Study};
use crate::studies::speed_error::pareto;

/// Adds the section to `report`: the full study, or at [`Depth::Quick`] [`Study::quick`].
pub fn section(report: &mut Report, depth: Depth) -> Result<()> {
    let study = match depth {
        Depth::Quick => Study::quick(),
        Depth::Full => Study::default(),
    };
    let bar = ProgressBar::new(study.models.len() as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed_precise} {msg}")
            .expect("the template is valid"),
    );
    let (cases, reference) = measure(&study, &|k, _, model| {
        bar.set_position(k as u64);
        bar.set_message(format!("cut block speed–error: {model}"));
    })?;
    bar.finish_and_clear();
    let [cx, cy, cz] = study.cells;
    report.heading("Speed versus error, cut block");
    if depth == Depth::Quick {
        report.text(
            "Quick: tet4 with each law against neo-Hookean tet10 on the same mesh, which is \
             not mesh-converged itself (the lift under the crack front moves by a few per \
             cent with twice the cells); `--full` adds tet10 and twice the cells and measures \
             against neo-Hookean tet10 on twice the cells.",
        );
    }
    report.text(&format!(
        "Default block ({cx} × {cy} × {cz} cubes at ×1), full-width cut, 10 mm pull, E and ν \
         at their defaults. Reference: {} (reaction {:.4} N, bottom lift {:.3} mm, {:.0} s). \
         Errors: relative for the reaction and the bottom lift, largest deviation (mm) of the \
         top surface along x = 50 mm (seed 002's acceptance: 1 mm). Run time: set-up, cut \
         and pull, cases one after another on this machine; the Pareto front uses the larger \
         of the two relative errors.",
        study.reference, reference.reaction, reference.bottom_lift, reference.seconds
    ));
    table(report, &cases, &reference);
    write_csv(&cases, &reference, &report.path("cutblock_speed_error.csv"))?;
    report.file("measurements", "cutblock_speed_error.csv");
    pareto_plot(report, &cases, &reference)
}

fn table(report: &mut Report, cases: &[Case], reference: &Answer) {
    let rows: Vec<Vec<String>> = cases
        .iter()
        .map(|c| {
            let m = &c.model;
            let mut row = vec![
                m.material.into(),
                m.element.into(),
                format!("×{}", m.refine),
            ];
            match &c.outcome {
                Ok(a) => {
                    let e = errors(a, reference);
                    row.extend([
                        format!("{:.2}", a.seconds),
                        format!("{:.4}", a.reaction),
                        format!("{:.2e}", e.reaction),
                        format!("{:.3}", a.bottom_lift),
                        format!("{:.2e}", e.bottom_lift),
                        format!("{:.3}", e.profile),
                    ]);
                }
                Err(message) => {
                    row.extend(std::iter::repeat_n("–".to_string(), 5));
                    row.push(format!("failed: {message}"));
                }
            }
            row
        })
        .collect();
    report.table(
        &[
            "material",
            "element",
            "cells",
            "run (s)",
            "reaction (N)",
            "error",
            "bottom lift (mm)",
            "error",
            "profile x = 50 dev. (mm)",
        ],
        &rows,
    );
}

/// Combined error against run time, one colour per law and element (×1 and ×2 joined),
/// with the Pareto front.
fn pareto_plot(report: &mut Report, cases: &[Case], reference: &Answer) -> Result<()> {
    let labelled: Vec<(String, (f64, f64))> = cases
        .iter()
        .filter_map(|c| {
            let a = c.outcome.as_ref().ok()?;
            let error = errors(a, reference).combined();
            // The reference itself has no place on a log scale.
            let label = format!("{} {}", c.model.material, c.model.element);
            (error > 0.0).then_some((label, (a.seconds, error)))
        })
        .collect();
    let points: Vec<(f64, f64)> = labelled.iter().map(|(_, p)| *p).collect();
    let mut curves = plot::grouped(labelled);
    let colour = curves.len();
    curves.push(Curve::new("Pareto front", pareto(&points), Mark::Line).colour(colour));
    plot::chart(
        &report.path("cutblock_pareto"),
        &Chart {
            title: "Cut block: run time vs error at 10 mm pull".into(),
            x: Axis::log("run time: set-up, cut and pull (s)"),
            y: Axis::log("larger relative error of reaction and bottom lift (1)"),
            curves,
        },
    )?;
    report.figure(
        "Cut block speed versus error with the Pareto front",
        "cutblock_pareto",
    );
    Ok(())
}
