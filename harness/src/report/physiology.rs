//! The abdomen beside the body: the static response over the press range people reach, on
//! the defaults and with the wall free, beside published figures; what a 2D plane-strain
//! slice can and cannot match.

use anyhow::Result;

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::{Depth, Report};
use crate::studies::physiology::{run, Point, Response, PRESSES, PUBLISHED};

/// What the comparison can and cannot show, and what was (not) tuned, with the model's
/// figures at the default press (`at`) and its highest mean pressure (`top`, kPa).
fn limits(at: Option<&Point>, top: f64) -> String {
    let (floor, apex) = at.map_or((f64::NAN, f64::NAN), |p| (p.floor_descent, p.apex_descent));
    format!(
        "What a 2D midsagittal plane-strain slice can match, and what not. Nothing in the \
         defaults was tuned to the figures above: the tissue moduli come from elastography \
         and in-vivo measurement, the braced wall from dynamic MRI of straining, the press \
         from a bear-down pressure (docs/theory/abdomen.md), and the comparison was made \
         after. The slice has no lateral extent: the contents cannot move sideways, and the \
         abdominal wall has no transverse (hoop) curvature, which in the body carries much of \
         the pressure; a passive wall in the slice can only bulge, where the contracted wall \
         of a person straining is drawn in, so the defaults brace it. The diaphragm alone \
         raises the contents' pressure: as its dome flattens it presses less for the same \
         effort, and the model's mean pressure reaches {top:.1} kPa at the highest press \
         where people reach 4–7 kPa with the abdominal wall contracting too. At the default \
         press (0.8 N/mm) the floor descends {floor:.1} mm (measured in women straining: \
         17–19 mm; Noakes' model: 27 mm at 4 kPa) and the apex {apex:.1} mm (the dome's \
         measured excursion: 32 ± 13 mm). With the wall free the wall takes most of the \
         volume the diaphragm displaces and the floor is barely loaded."
    )
}

/// Adds the section to `report` (the same at either depth: a static solve per point).
pub fn section(report: &mut Report, _depth: Depth) -> Result<()> {
    let responses = run()?;
    report.heading("The abdomen beside the body");
    let length = responses[0].diaphragm;
    let nominal = |press: f64| 1e3 * press / length;
    report.text(&format!(
        "Static response to the press on the defaults (finite strain) and with the \
         abdominal wall free, over a nominal {:.1}–{:.1} kPa (the press over the \
         diaphragm's {length:.0} mm); the model's intra-abdominal pressure is the contents' \
         mean pressure.",
        nominal(PRESSES[0]),
        nominal(PRESSES[PRESSES.len() - 1]),
    ));
    for r in &responses {
        table(report, r);
    }
    report.text("Published figures:");
    let rows: Vec<Vec<String>> = PUBLISHED
        .iter()
        .map(|f| {
            vec![
                f.quantity.into(),
                f.value.into(),
                f.condition.into(),
                f.source.into(),
            ]
        })
        .collect();
    report.table(&["quantity", "value", "condition", "source"], &rows);
    let defaults = responses[0].points.iter().filter_map(|p| p.as_ref().ok());
    let at = defaults.clone().find(|p| p.press == 0.8);
    let top = defaults.map(|p| p.pressure).fold(0.0, f64::max);
    report.text(&limits(at, top));
    descent_plot(report, &responses)?;
    Ok(())
}

fn table(report: &mut Report, r: &Response) {
    report.text(&format!("{}:", r.label));
    let rows: Vec<Vec<String>> = r
        .points
        .iter()
        .map(|p| match p {
            Ok(p) => vec![
                format!("{:.1}", p.press),
                format!("{:.1}", p.nominal),
                format!("{:.2}", p.pressure),
                format!("{:.1}", p.floor_descent),
                format!("{:.1}", p.apex_descent),
                format!("{:.1}", p.wall_bulge),
                format!("{:.2}", p.floor_mean),
                format!("{:.2}", p.floor_max),
            ],
            Err(why) => vec![why.clone(); 1],
        })
        .collect();
    report.table(
        &[
            "press (N/mm)",
            "nominal (kPa)",
            "mean pressure (kPa)",
            "floor descent (mm)",
            "apex descent (mm)",
            "wall bulge (mm)",
            "floor stress mean (kPa)",
            "max (kPa)",
        ],
        &rows,
    );
}

/// Floor descent against the model's intra-abdominal pressure, with the published descents
/// as marks.
fn descent_plot(report: &mut Report, responses: &[Response]) -> Result<()> {
    let mut curves: Vec<Curve> = responses
        .iter()
        .enumerate()
        .map(|(k, r)| {
            let points: Vec<(f64, f64)> = r
                .points
                .iter()
                .filter_map(|p| p.as_ref().ok())
                .map(|p: &Point| (p.pressure, p.floor_descent))
                .collect();
            Curve::new(r.label, points, Mark::LineDots).colour(k)
        })
        .collect();
    let published = [
        ("Dietz 2004 (Valsalva, pressure not measured)", 17.4),
        ("upright MRI 2001 (straining)", 19.1),
    ];
    for (k, (label, descent)) in published.iter().enumerate() {
        let line = vec![(1.0, *descent), (7.0, *descent)];
        curves.push(Curve::new(label, line, Mark::Line).colour(responses.len() + k));
    }
    curves.push(
        Curve::new("Noakes 2008 model at 4 kPa", vec![(4.0, 27.2)], Mark::Dots)
            .colour(responses.len() + published.len()),
    );
    plot::chart(
        &report.path("physiology"),
        &Chart {
            title: "Abdomen: pelvic-floor descent against intra-abdominal pressure".into(),
            x: Axis::linear("mean pressure of the contents (kPa)"),
            y: Axis::linear("pelvic-floor descent (mm)"),
            curves,
        },
    )?;
    report.figure(
        "Pelvic-floor descent beside published figures",
        "physiology",
    );
    Ok(())
}
