//! What the harness writes: report folders (Markdown linking CSVs, PNG + SVG plots and VTU
//! files), one section per study or sweep, and the commands the CLI dispatches to.
//!
//! ```text
//! markdown      Report: a folder and its report.md
//! plot          charts and mesh maps (plotters)
//! vtu           fields for ParaView (vtkio)
//! sections      verification, findings, physiology, identification, speed_error,
//!               cut_speed_error, blade_path, sweep, model_order, fields: each adds itself
//!               to a Report at a Depth
//! default       the main job: every section on built-in defaults, listed once
//! series        one run of a scene as a time-series CSV (`harness simulate`)
//! variables     the variable reference of a scene (`harness describe`)
//! ```

pub mod blade_path;
pub mod cut_speed_error;
pub mod default;
/// The fields section: the pressed abdomen's stress map and the VTU files of both scenes.
pub mod fields;
pub mod findings;
pub mod identification;
pub mod markdown;
pub mod model_order;
pub mod physiology;
pub mod plot;
pub mod rankings;
pub mod results;
pub mod series;
pub mod speed_error;
pub mod sweep;
pub mod variables;
pub mod verification;
pub mod vtu;

use std::path::{Path, PathBuf};

use anyhow::Result;

pub use markdown::Report;

/// How far a section goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Depth {
    /// Every capability once, at settings chosen for time, each labelled with the accuracy
    /// it has (the main job, `harness report`).
    Quick,
    /// The converged studies: references, full speed–error fronts, every identification,
    /// full against reduced order (`harness report --full` and the single-study commands).
    Full,
}

/// A report section: adds its headings, tables, figures and files to a report.
pub type Section = fn(&mut Report, Depth) -> Result<()>;

/// Writes a report in `out` with one section at `depth` and returns the path of its
/// `report.md`.
pub fn write(out: &Path, title: &str, section: Section, depth: Depth) -> Result<PathBuf> {
    let mut report = Report::create(out, title)?;
    section(&mut report, depth)?;
    report.finish()
}
