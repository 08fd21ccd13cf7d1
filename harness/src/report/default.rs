//! The main job: every section on built-in defaults, in one report folder — quick (every
//! capability once, at settings chosen for time) or full (the converged studies).

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;

use super::identification;
use super::{
    blade_path, cut_speed_error, fields, findings, model_order, physiology, rankings, speed_error,
    sweep, verification, Depth, Report, Section,
};

/// The default report's sections with their names, in order.
pub const SECTIONS: [(&str, Section); 12] = [
    ("verification", verification::section),
    ("seed 003's findings", findings::section),
    ("the abdomen beside the body", physiology::section),
    ("pelvis rankings", rankings::section),
    ("identification", identification::shipped),
    ("speed versus error, abdomen", speed_error::section),
    ("speed versus error, cut block", cut_speed_error::section),
    ("blade path", blade_path::section),
    ("pelvis sweep", |r, depth| {
        let shown = ["configuration", "anatomy.outlet"];
        let thin = (depth == Depth::Quick).then_some(QUICK_SWEEP);
        sweep::shipped(r, "pelvis_sweep", &shown, thin)
    }),
    ("model orders", model_order::section),
    ("cut-block sweep", |r, _| {
        sweep::shipped(r, "cutblock_sweep", &["cut_depth"], None)
    }),
    ("fields", fields::section),
];

/// The quick report's pelvis sweep: its Latin hypercube drawn with this many samples and
/// its grids at this many levels (28 cases instead of 62; each takes seconds at finite
/// strain).
const QUICK_SWEEP: (usize, usize) = (8, 3);

/// What the quick report leaves to `--full`, said at its top.
const QUICK: &str = "Quick report: every capability once, at settings chosen for time; each \
section says what it ran and how accurate that is. `harness report --full` runs the converged \
studies instead: both measurement sets with two models each, the abdomen's speed–error front \
against a reference on 48,000 graded triangles, the cut block's against a Richardson reference \
on three graded neo-Hookean tet10 meshes, all 62 cases of the shipped pelvis sweep (quick: 28) and that sweep in four model forms (full and hyper-reduced finite strain, full and modal small strain).";

/// Writes the default report at `depth` into `out` and returns the path of its `report.md`.
pub fn run(out: &Path, depth: Depth) -> Result<PathBuf> {
    let title = match depth {
        Depth::Quick => "tissuefmu report on built-in defaults (quick)",
        Depth::Full => "tissuefmu report on built-in defaults (full)",
    };
    let mut report = Report::create(out, title)?;
    if depth == Depth::Quick {
        report.text(QUICK);
    }
    let mut times = Vec::new();
    for (name, section) in SECTIONS {
        let start = Instant::now();
        section(&mut report, depth)?;
        times.push(vec![
            name.to_string(),
            format!("{:.1}", start.elapsed().as_secs_f64()),
        ]);
    }
    report.heading("Wall time of each section");
    report.table(&["section", "wall time (s)"], &times);
    report.finish()
}
