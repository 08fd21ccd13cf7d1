//! The FMI layer: one model-independent instance core ([`instance`]) over the scene
//! interface, thin ABI files for FMI 2.0 ([`fmi2`]) and FMI 3.0 ([`fmi3`]) co-simulation,
//! `modelDescription.xml` generated from each scene's variable table ([`xml`]), and the
//! bundler that writes the `.fmu` archives ([`bundle`]).
//!
//! ```text
//! model      the exported scenes: identifier, constructor, token
//! instance   the FMI state machine, value-reference addressing, error reporting
//! ffi        C strings and arrays, the panic guard around every entry point
//! fmi2, fmi3 the ABI: convert C arguments, call the instance
//! xml        modelDescription.xml from the scenes' variable tables
//! uri        resource locations as importers write them
//! bundle     the .fmu archives (bin `bundle`)
//! ```

pub mod bundle;
mod ffi;
pub mod fmi2;
pub mod fmi3;
pub mod instance;
pub mod model;
pub mod state;
pub mod uri;
pub mod xml;
