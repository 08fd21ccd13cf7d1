//! The blade-path report (issue 27, item 3): reaction against the blade on the default
//! cells and on twice as many, side by side with their difference; opening and bottom
//! lift; the largest change of the reaction per step against the mean; CSV and plot.

use anyhow::{ensure, Result};
use indicatif::{ProgressBar, ProgressStyle};

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::{Depth, Report};
use crate::studies::blade_path::{run, write_csv, Crossing, Study};
use crate::studies::cut_speed_error::{cubes, CELLS};

/// Adds the section to `report`: 1 mm steps, or 20 mm at [`Depth::Quick`].
pub fn section(report: &mut Report, depth: Depth) -> Result<()> {
    let study = match depth {
        Depth::Quick => Study::quick(),
        Depth::Full => Study::default(),
    };
    let bar = ProgressBar::new(0).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} {elapsed_precise} blade path")
            .expect("the template is valid"),
    );
    let crossings = run(&study, &|k, n| {
        bar.set_length(n as u64);
        bar.set_position(k as u64);
    })?;
    bar.finish_and_clear();
    ensure!(
        crossings.len() == 2,
        "the blade-path report compares two meshes"
    );
    let (coarse, fine) = (&crossings[0], &crossings[1]);
    report.heading("Reaction against the blade, 1× and 2× cells");
    report.text(&format!(
        "The default cut block (neo-Hookean tet4) pulled {} mm while the blade crosses it in \
         {} mm steps, on the default {} cubes and on twice as many in each \
         direction. The crack front is a node plane at the blade, so the outputs change \
         smoothly with it; the last step cuts the ligament left at the far face, which a \
         cell at the tip does not resolve (it shrinks under refinement). Largest change of \
         the reaction per step over the mean change, last step left out: {:.2} (1×), {:.2} \
         (2×). Run time: {:.1} s (1×), {:.1} s (2×), each a warm-started Newton solve per \
         blade position.",
        study.pull,
        study.step,
        cubes(CELLS),
        coarse.largest_over_mean(),
        fine.largest_over_mean(),
        coarse.seconds,
        fine.seconds
    ));
    report.table(
        &[
            "blade (mm)",
            "reaction 1× (N)",
            "reaction 2× (N)",
            "2× − 1× (N)",
            "relative",
            "opening 1× / 2× (mm)",
            "bottom lift 1× / 2× (mm)",
        ],
        &rows(coarse, fine, study.step),
    );
    write_csv(&crossings, &report.path("blade_path.csv"))?;
    report.file("every blade position on both meshes", "blade_path.csv");
    plot_reactions(report, &crossings)
}

/// A row per 10 mm of blade travel (every row when the steps are longer).
fn rows(coarse: &Crossing, fine: &Crossing, step: f64) -> Vec<Vec<String>> {
    let every = (10.0 / step).round().max(1.0) as usize;
    coarse
        .points
        .iter()
        .zip(&fine.points)
        .enumerate()
        .filter(|(k, _)| k % every == 0 || *k == coarse.points.len() - 1)
        .map(|(_, (c, f))| {
            vec![
                format!("{}", c.blade),
                format!("{:.4}", c.reaction),
                format!("{:.4}", f.reaction),
                format!("{:+.4}", f.reaction - c.reaction),
                format!("{:+.2e}", (f.reaction - c.reaction) / f.reaction),
                format!("{:.3} / {:.3}", c.opening, f.opening),
                format!("{:.3} / {:.3}", c.bottom_lift, f.bottom_lift),
            ]
        })
        .collect()
}

fn plot_reactions(report: &mut Report, crossings: &[Crossing]) -> Result<()> {
    let curves = crossings
        .iter()
        .enumerate()
        .map(|(k, c)| {
            let points = c.points.iter().map(|p| (p.blade, p.reaction)).collect();
            Curve::new(&format!("{}× cells", c.refine), points, Mark::LineDots).colour(k)
        })
        .collect();
    plot::chart(
        &report.path("blade_path"),
        &Chart {
            title: "Cut block: reaction force as the blade crosses the pulled block".into(),
            x: Axis::linear("blade position scalpel_x (mm)"),
            y: Axis::linear("reaction force (N)"),
            curves,
        },
    )?;
    report.figure("Reaction force against the blade position", "blade_path");
    Ok(())
}
