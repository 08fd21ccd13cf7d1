//! tissuefmu harness library: experiments and sweeps over the scenes (in process or as
//! FMUs), material identification, speed versus error, plots, fields for ParaView and
//! report folders. The command-line front end (`src/main.rs`) runs these.

pub mod backend;
pub mod design;
pub mod experiment;
pub mod fields;
#[cfg(feature = "fmu")]
pub mod fmu_backend;
pub mod identify;
pub mod plot;
pub mod profiles;
pub mod report;
pub mod speed_error;
pub mod sweep;
