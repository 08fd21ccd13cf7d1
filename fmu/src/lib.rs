//! The FMI layer: one model-independent instance core ([`instance`]) over the scene
//! interface, thin ABI files for FMI 2.0 ([`fmi2`]) and FMI 3.0 ([`fmi3`]) co-simulation,
//! `modelDescription.xml` generated from each scene's variable table ([`xml`]), and the
//! bundler that writes the `.fmu` archives ([`bundle`]).
//!
//! ```text
//! exports    the exported scenes: identifier, constructor, token
//! addressing value references of FMI 2 (scalars) and FMI 3 (arrays, `time`)
//! machine    the FMI state machine: phases, calls, and which call each phase allows
//! instance   the instance over a scene: value-reference addressing, error reporting
//! ffi        C strings and arrays, the panic guard around every entry point
//! fmi2, fmi3 the ABI: convert C arguments, call the instance
//! xml        modelDescription.xml from the scenes' variable tables
//! uri        resource locations as importers write them
//! bundle     the .fmu archives (bin `bundle`)
//! ```

pub mod addressing;
pub mod bundle;
pub mod exports;
mod ffi;
pub mod fmi2;
pub mod fmi3;
pub mod instance;
pub mod machine;
pub mod state;
pub mod uri;
pub mod xml;
