//! The main job: every section on built-in defaults, in one report folder.

use std::path::{Path, PathBuf};

use anyhow::Result;

use super::identification;
use super::{
    cut_speed_error, fields, model_order, speed_error, sweep, verification, Report, Section,
};

/// The default report's sections, in order.
pub const SECTIONS: [Section; 8] = [
    verification::section,
    identification::shipped,
    speed_error::section,
    cut_speed_error::section,
    |r| sweep::shipped(r, "pelvis_sweep", &["configuration", "anatomy.outlet"]),
    model_order::section,
    |r| sweep::shipped(r, "cutblock_sweep", &["cut_depth"]),
    fields::section,
];

/// Writes the default report into `out` and returns the path of its `report.md`.
pub fn run(out: &Path) -> Result<PathBuf> {
    let mut report = Report::create(out, "tissuefmu report on built-in defaults")?;
    for section in SECTIONS {
        section(&mut report)?;
    }
    report.finish()
}
