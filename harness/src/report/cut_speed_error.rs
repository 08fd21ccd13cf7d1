//! The speed-versus-error report for the cut block: the Richardson reference with its
//! orders and error estimates, then table, CSV and Pareto plot of every model (law ×
//! element × mesh × grading) against it, with a progress line per case.

use anyhow::Result;
use indicatif::{ProgressBar, ProgressStyle};
use models::scene::cutblock::CutBlock;

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::{Depth, Report};
use crate::studies::cut_speed_error::{
    accurate, clamped_edge_order, cubes, errors, measure, write_csv, write_reference, Answer,
    BlockReference, BlockRun, Study, CELLS, FULL_CUT, MIN_ORDER, REACTION_ORDER, REFERENCE_CELLS,
};
use crate::studies::speed_error::pareto;

/// Adds the section to `report`: the full study, or at [`Depth::Quick`] [`Study::quick`].
pub fn section(report: &mut Report, depth: Depth) -> Result<()> {
    let study = match depth {
        Depth::Quick => Study::quick(),
        Depth::Full => Study::default(),
    };
    study_section(report, &study, depth)
}

/// Adds the section for `study` to `report` (at [`Depth::Full`] with the reference's
/// meshes written as `reference.toml`).
pub fn study_section(report: &mut Report, study: &Study, depth: Depth) -> Result<()> {
    let bar = ProgressBar::new((study.models.len() + study.reference.len()) as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed_precise} {msg}")
            .expect("the template is valid"),
    );
    let (cases, reference) = measure(study, &|k, _, model| {
        bar.set_position(k as u64);
        bar.set_message(format!("cut block speed–error: {model}"));
    })?;
    bar.finish_and_clear();
    report.heading("Speed versus error, cut block");
    if depth == Depth::Quick {
        report.text(
            "Quick: the three laws with tet4 on the default cells, uniform and graded, \
             against the full study's reference as stored in \
             `experiments/references/cutblock_full_cut.toml` (its 1× mesh run again here and \
             matched to its stored answer first; the reference meshes' run times are the full \
             study's); `--full` adds tet10, tet4 on twice the cells and the accurate setting \
             and measures the reference again.",
        );
    }
    let (cut, tip) = if study.front == FULL_CUT {
        ("full-width cut".to_string(), "the tip, here the far face")
    } else {
        (format!("cut from x = 0 to {} mm", study.front), "the tip")
    };
    let accurate_cells = if study.models.contains(&accurate()) {
        format!(", the accurate setting {}", accurate().cubes())
    } else {
        String::new()
    };
    report.text(&format!(
        "Default block ({} cubes at ×1{accurate_cells}), {cut}, 10 mm pull, E and ν \
         at their defaults; β is `mesh_grading` (1: uniform, 2: layers growing linearly \
         away from the cut plane, the crack front and the faces, x cells away from {tip}). \
         Errors: relative for the reaction \
         and the bottom lift, largest deviation (mm) of the top surface along x = 50 mm \
         (seed 002's acceptance: 1 mm). Run time: set-up, cut and pull, cases one after \
         another on this machine; the Pareto front uses the larger of the two relative \
         errors.",
        cubes(CELLS)
    ));
    reference_table(report, &reference)?;
    if depth == Depth::Full {
        let refine: Vec<String> = study
            .reference
            .iter()
            .map(|m| m.refine.to_string())
            .collect();
        let measured = format!(
            "`harness cut-speed-error --front {} --reference-refine {}` (harness {})",
            study.front,
            refine.join(","),
            env!("CARGO_PKG_VERSION")
        );
        write_reference(&reference, &measured, &report.path("reference.toml"))?;
        report.file("the reference's meshes", "reference.toml");
    }
    table(report, &cases, &reference.answer);
    write_csv(
        &cases,
        &reference.answer,
        &report.path("cutblock_speed_error.csv"),
    )?;
    report.file("measurements", "cutblock_speed_error.csv");
    pareto_plot(report, &cases, &reference.answer)
}

/// The reference: its meshes, and for three the extrapolation, orders and error estimates.
fn reference_table(report: &mut Report, reference: &BlockReference) -> Result<()> {
    let Some(x) = reference.extrapolation else {
        let (model, a) = &reference.meshes[0];
        report.text(&format!(
            "Reference: {model} (reaction {:.5} N, bottom lift {:.4} mm, {:.1} s).",
            a.reaction, a.bottom_lift, a.seconds
        ));
        return Ok(());
    };
    let order = |p: Option<f64>| {
        p.map_or(
            format!("none of at least {MIN_ORDER} (not extrapolated)"),
            |p| format!("{p:.2}"),
        )
    };
    let [p_reaction, p_lift, p_profile] = x.order.map(order);
    let finest: Vec<String> = [
        (x.order[0], x.finest[0], "reaction"),
        (x.order[1], x.finest[1], "lift"),
    ]
    .into_iter()
    .filter(|(p, _, _)| p.is_some())
    .map(|(_, f, name)| format!("{:.2} % ({name})", 100.0 * f))
    .collect();
    let nu = CutBlock::new().get("nu")?;
    let reference_cells = cubes(REFERENCE_CELLS);
    let mut text = format!(
        "Reference: neo-Hookean tet10 graded with β = 2 on {reference_cells} cubes × refine, \
         extrapolated by Richardson from \
         its finest three meshes (f(h) = f∞ + C h^p, h ∝ 1/refine, the order observed; an \
         output whose three values converge at an order below {MIN_ORDER} keeps the finest \
         mesh's value). Observed orders: reaction {p_reaction}, bottom lift {p_lift}, \
         profile along x = 50 mm {p_profile} (one order for every station, from the largest \
         differences between the meshes' profiles)."
    );
    if !finest.is_empty() {
        text += &format!(
            " The finest mesh is {} from the extrapolation.",
            finest.join(" and ")
        );
    }
    if let (Some(coarse), Some([s_reaction, s_lift])) = (x.coarse_order, x.spread) {
        let [c_reaction, c_lift, _] = coarse.map(order);
        text += &format!(
            " Made from the coarsest three instead (observed orders: reaction {c_reaction}, \
             lift {c_lift}) it differs by {:.3} % (reaction) and {:.3} % (lift; for an \
             output not extrapolated, at least its finest refinement's change): the \
             reference's error estimate. The reaction's expected order is that of tet10 \
             graded towards an r^½ crack front, {REACTION_ORDER}: the y and z layers are also \
             graded towards the faces, so the edges where the face clamped at y = 0 meets the \
             free ones (u ~ r^λ, Williams' λ for a clamped–free right angle), which ungraded \
             would limit it to 2λ = {:.2} at ν = {nu}, do not (docs/theory/cutblock.md).",
            100.0 * s_reaction,
            100.0 * s_lift,
            clamped_edge_order(nu)
        );
    }
    report.text(&text);
    let mut rows: Vec<Vec<String>> = reference
        .meshes
        .iter()
        .map(|(m, a)| {
            vec![
                format!("×{}: {}", m.refine, m.cubes()),
                format!("{:.2}", a.seconds),
                format!("{:.5}", a.reaction),
                format!("{:.4}", a.bottom_lift),
            ]
        })
        .collect();
    rows.push(vec![
        "reference".into(),
        format!("{:.2}", reference.answer.seconds),
        format!("{:.5}", reference.answer.reaction),
        format!("{:.4}", reference.answer.bottom_lift),
    ]);
    report.table(
        &[
            "reference mesh",
            "run (s)",
            "reaction (N)",
            "bottom lift (mm)",
        ],
        &rows,
    );
    Ok(())
}

fn table(report: &mut Report, cases: &[BlockRun], reference: &Answer) {
    let rows: Vec<Vec<String>> = cases
        .iter()
        .map(|c| {
            let m = &c.model;
            let mut row = vec![
                m.law.name().into(),
                m.element.name().into(),
                m.cubes(),
                format!("{}", m.grading),
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
            "β",
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

/// Combined error against run time, one colour per law, element and grading (its meshes joined),
/// with the Pareto front.
fn pareto_plot(report: &mut Report, cases: &[BlockRun], reference: &Answer) -> Result<()> {
    let labelled: Vec<(String, (f64, f64))> = cases
        .iter()
        .filter_map(|c| {
            let a = c.outcome.as_ref().ok()?;
            let error = errors(a, reference).combined();
            // The reference itself has no place on a log scale.
            let m = &c.model;
            let label = format!("{} {} β = {}", m.law.name(), m.element.name(), m.grading);
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
