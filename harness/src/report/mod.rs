//! What the harness writes: report folders (Markdown linking CSVs, PNG + SVG plots and VTU
//! files), one section per study or sweep, and the commands the CLI dispatches to.
//!
//! ```text
//! markdown      Report: a folder and its report.md
//! plot          charts and mesh maps (plotters)
//! vtu           fields for ParaView (vtkio)
//! sections      verification, identification, speed_error, sweep, fields:
//!               each adds itself to a Report
//! default       the main job: every section on built-in defaults, listed once
//! series        one run of a scene as a time-series CSV (`harness simulate`)
//! ```

pub mod cut_speed_error;
pub mod default;
pub mod fields;
pub mod identification;
pub mod markdown;
pub mod model_order;
pub mod plot;
pub mod series;
pub mod speed_error;
pub mod sweep;
pub mod verification;
pub mod vtu;

use std::path::{Path, PathBuf};

use anyhow::Result;

pub use markdown::Report;

/// A report section: adds its headings, tables, figures and files to a report.
pub type Section = fn(&mut Report) -> Result<()>;

/// Writes a report in `out` with one section and returns the path of its `report.md`.
pub fn write(out: &Path, title: &str, section: Section) -> Result<PathBuf> {
    let mut report = Report::create(out, title)?;
    section(&mut report)?;
    report.finish()
}
