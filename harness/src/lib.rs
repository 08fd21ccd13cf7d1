//! tissuefmu harness library: everything the `harness` command runs, by role.
//!
//! ```text
//! sweep/      the engine: experiment files, designs, the one simulation loop
//!             (simulate), backends (in process, FMU), the parallel resumable runner
//! studies/    what is computed: identification, profile comparison, speed versus
//!             error, verification against analytical and seed results
//! report/     what is written: Markdown reports, plots, VTU fields, and one section
//!             per study or sweep; the commands the CLI dispatches to
//! atomic      every file goes through a temporary file and a rename
//! ```
//!
//! Dependencies run one way: `report` uses `studies` and `sweep`, `studies` uses `sweep`,
//! all use `atomic`.

pub mod atomic;
pub mod report;
pub mod studies;
pub mod sweep;
