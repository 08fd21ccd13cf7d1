//! The scene interface (DESIGN.md "One interface, two doors"): a scene is built from a
//! configuration, exposes a table of variables, accepts `set`/`get`, and advances with
//! `do_step(t, h)`. The FMU layer and the harness drive every scene through this trait only;
//! `modelDescription.xml` is generated from the same table.

pub mod abdomen;
pub mod cutblock;
mod variables;

pub use variables::{Causality, Start, Values, Variability, Variable, VariableKind};

use thiserror::Error;

use crate::error::ModelError;

/// Errors of a scene: bad variable access, bad values, or a failure of the model.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SceneError {
    #[error("unknown value reference {0}")]
    UnknownVariable(u32),
    #[error("variable `{name}` is {actual}, not {expected}")]
    WrongKind {
        name: String,
        expected: &'static str,
        actual: &'static str,
    },
    #[error("variable `{name}` expects {expected} values, got {got}")]
    WrongLength {
        name: String,
        expected: usize,
        got: usize,
    },
    #[error("value {value} for `{name}` is out of range [{min}, {max}]")]
    OutOfRange {
        name: String,
        value: f64,
        min: f64,
        max: f64,
    },
    #[error("variable `{name}` cannot be set now: {reason}")]
    NotSettable { name: String, reason: &'static str },
    #[error("invalid configuration: {0}")]
    Config(String),
    #[error(transparent)]
    Model(#[from] ModelError),
}

/// The scenes by name (the FMI model identifiers): `abdomen` and `cutblock`.
pub const SCENES: [&str; 2] = ["abdomen", "cutblock"];

/// A new scene with default parameters, by name.
pub fn create(name: &str) -> Result<Box<dyn Scene>, SceneError> {
    match name {
        "abdomen" => Ok(Box::new(abdomen::Abdomen::new())),
        "cutblock" => Ok(Box::new(cutblock::CutBlock::new())),
        _ => Err(SceneError::Config(format!(
            "unknown scene `{name}` (known: {})",
            SCENES.join(", ")
        ))),
    }
}

/// A simulation scene. All methods return errors instead of panicking.
pub trait Scene: Send {
    /// The variable table; value references are indices into it.
    fn variables(&self) -> &[Variable];

    /// Sets a real variable (a scalar, or all elements of an array).
    fn set_real(&mut self, vr: u32, values: &[f64]) -> Result<(), SceneError>;

    /// Reads a real variable into `out` (its length must match). Outputs are computed on
    /// first request after a step.
    fn get_real(&mut self, vr: u32, out: &mut [f64]) -> Result<(), SceneError>;

    /// Sets a string parameter.
    fn set_string(&mut self, vr: u32, value: &str) -> Result<(), SceneError>;

    /// Reads a string variable.
    fn get_string(&self, vr: u32) -> Result<String, SceneError>;

    /// Builds everything the configuration needs (mesh, matrices, factorization) and solves
    /// the initial state. Fixed parameters cannot change afterwards.
    fn initialize(&mut self) -> Result<(), SceneError>;

    /// Advances from `t` to `t + h` with the current inputs.
    fn do_step(&mut self, t: f64, h: f64) -> Result<(), SceneError>;

    /// Tells the scene where its resources (shipped configuration files) are; scenes that
    /// read none ignore it.
    fn set_resource_dir(&mut self, _dir: &std::path::Path) {}

    /// Looks a variable up by name.
    fn lookup(&self, name: &str) -> Result<u32, SceneError> {
        self.variables()
            .iter()
            .find(|v| v.name == name)
            .map(|v| v.vr)
            .ok_or_else(|| SceneError::Config(format!("no variable named `{name}`")))
    }
}
