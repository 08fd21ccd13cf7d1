//! tissuefmu harness library: what the command-line front end runs.

pub mod identify;
pub mod speed_error;
