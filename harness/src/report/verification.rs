//! The verification section: the FE core, the cut block and the abdomen against analytical
//! and seed results ([`crate::studies::verification`]), as preformatted tables.

use anyhow::Result;

use super::{Depth, Report};
use crate::studies::verification::TABLES;

/// Adds the section to `report` (the same at every depth).
pub fn section(report: &mut Report, _: Depth) -> Result<()> {
    report.heading("Verification");
    for table in TABLES {
        let mut text = String::new();
        table(&mut text)?;
        report.verbatim(&text);
    }
    Ok(())
}
