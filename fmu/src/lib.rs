//! The FMI layer: one model-independent instance core ([`instance`]) over the scene
//! interface, thin ABI files for FMI 2.0 ([`fmi2`]) and FMI 3.0 ([`fmi3`]) co-simulation,
//! `modelDescription.xml` generated from each scene's variable table ([`xml`]), and the
//! bundler that writes the `.fmu` archives ([`bundle`]).

pub mod bundle;
mod ffi;
pub mod fmi2;
pub mod fmi3;
pub mod instance;
pub mod model;
pub mod uri;
pub mod xml;
