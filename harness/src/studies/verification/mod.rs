//! Verification against analytical and seed results: the FE core (Lamé convergence, Houbolt
//! against its characteristic equation, timings), the cut block against seed 002 and the
//! abdomen against seed 003. Each writes its tables as preformatted text.

pub mod abdomen;
pub mod core;
pub mod cutblock;

use anyhow::Result;

/// The verification tables, in report order.
pub const TABLES: [fn(&mut String) -> Result<()>; 3] = [core::run, cutblock::run, abdomen::run];
