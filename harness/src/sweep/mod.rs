//! The sweep engine: experiment files, the designs that turn them into cases, the one
//! simulation loop and the backends it drives, and the runner that executes a plan in
//! parallel, resumably.
//!
//! ```text
//! experiment ──▶ design (cases) ──▶ runner ──▶ backend ──▶ simulate (the loop)
//!   TOML file     list/grid/LHS     rayon,      in process      inputs held over
//!   checked                         resume      or FMU (fmu)    each step
//! ```

pub mod backend;
pub mod design;
pub mod experiment;
#[cfg(feature = "fmu")]
pub mod fmu;
pub mod runner;
pub mod simulate;

pub use backend::{Backend, BackendKind, InProcess};
pub use design::{Design, DesignPoint};
pub use experiment::Experiment;
pub use runner::{prepare, run, CaseResult, Outcome, Sweep};
pub use simulate::{
    simulate, simulate_observed, InputTable, Run, Schedule, Series, Session, Value, VariableRef,
};
