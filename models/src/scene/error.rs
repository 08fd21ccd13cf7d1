//! Errors of a scene, in three kinds ([`ErrorKind`]): a call the scene cannot take (unknown
//! or wrong variable, value out of range, not initialized), an invalid configuration (bad
//! geometry, an unknown option), and a failure while running (an explicit integrator above
//! its stability limit, an iteration that does not converge, a cut that frees a body, a
//! singular or diverging system). Each message names the value and variable or the cause.

use thiserror::Error;

use crate::error::ModelError;

/// Errors of a scene.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SceneError {
    #[error("unknown value reference {0}")]
    UnknownVariable(u32),
    #[error("no variable named `{0}`")]
    UnknownName(String),
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
    /// Reading an output or stepping before the scene is initialized.
    #[error("`{name}` is not available: the scene is not initialized")]
    NotInitialized { name: String },
    /// A call argument that is not a variable (the step size).
    #[error("{name} = {value} {reason}")]
    InvalidArgument {
        name: &'static str,
        value: f64,
        reason: &'static str,
    },
    /// A communication step that would take more substeps than the scene allows.
    #[error(
        "a communication step of h = {h} s with max_step = {max_step} s needs {substeps:e} \
         substeps, more than the {limit:e} allowed per step: raise max_step or shorten the \
         communication step"
    )]
    TooManySubsteps {
        h: f64,
        max_step: f64,
        substeps: f64,
        limit: f64,
    },
    /// A change of a prescribed displacement that would take more Newton load increments
    /// than one step may.
    #[error(
        "the {input} changes by {change} mm in one step: with max_increment = {max_increment} \
         mm that is {increments} Newton load increments, more than the {limit} one step may \
         take; raise max_increment or spread the change over more steps"
    )]
    TooManyIncrements {
        input: &'static str,
        change: f64,
        max_increment: f64,
        increments: f64,
        limit: f64,
    },
    #[error("invalid configuration: {0}")]
    Config(String),
    /// An explicit integrator asked to step above its stability limit.
    #[error(
        "{integrator} is unstable at dt = {dt:e} s: its stability limit here is {limit:e} s; \
         lower max_step or use houbolt/newmark"
    )]
    Unstable {
        integrator: &'static str,
        dt: f64,
        limit: f64,
    },
    /// An iteration that did not settle.
    #[error("{what} did not settle in {iterations} iterations")]
    NotConverged {
        what: &'static str,
        iterations: usize,
    },
    /// The incision would cut a body free of its support.
    #[error(
        "the cut separates the block into {bodies} bodies; the body containing node {node} at \
         {at:?} mm does not touch the supported face y = 0 and would float"
    )]
    Separated {
        bodies: usize,
        node: usize,
        at: [f64; 3],
    },
    /// Cut flanks that slid or turned past each other further than the contact model's
    /// small-sliding range, so they pass through each other.
    #[error(
        "flank node {node} lies {depth:.4} mm behind the opposite flank, more than the {limit} \
         mm the contact accepts: the flanks slid or turned further than its small-sliding \
         range covers; lower press_force or the closing pull"
    )]
    Slid { node: usize, depth: f64, limit: f64 },
    #[error(transparent)]
    Model(#[from] ModelError),
}

/// What an error is about: how the scene was called, its configuration, or a failure while
/// it ran. The FMU layer and the harness name the kind in their messages.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// A call the scene cannot take: unknown or read-only variable, wrong kind or length,
    /// value out of range, not initialized, bad step size.
    Usage,
    /// Parameters or files that describe no valid model.
    Configuration,
    /// The model failed while running: unstable, not converged, separated, slid flanks,
    /// singular, diverged.
    Runtime,
}

impl SceneError {
    /// The kind of this error.
    pub fn kind(&self) -> ErrorKind {
        use ModelError as M;
        match self {
            Self::Config(_) => ErrorKind::Configuration,
            Self::Unstable { .. }
            | Self::NotConverged { .. }
            | Self::Separated { .. }
            | Self::Slid { .. } => ErrorKind::Runtime,
            Self::Model(
                M::Singular { .. }
                | M::Diverged { .. }
                | M::LinearAlgebra(_)
                | M::Inverted { .. }
                | M::NotConverged { .. },
            ) => ErrorKind::Runtime,
            Self::Model(_) => ErrorKind::Configuration,
            _ => ErrorKind::Usage,
        }
    }
}

impl std::fmt::Display for ErrorKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Self::Usage => "invalid call",
            Self::Configuration => "invalid configuration",
            Self::Runtime => "runtime failure",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn run_time_failures_are_not_configuration_errors() {
        let separated = SceneError::Separated {
            bodies: 2,
            node: 70,
            at: [0.0, 50.0, 0.0],
        };
        assert_eq!(separated.kind(), ErrorKind::Runtime);
        assert!(!separated.to_string().contains("configuration"));
        let singular = SceneError::Model(ModelError::Singular {
            equation: 3,
            dof: 3,
            ratio: 0.0,
        });
        assert_eq!(singular.kind(), ErrorKind::Runtime);
        assert_eq!(
            SceneError::Config("x".into()).kind(),
            ErrorKind::Configuration
        );
        let bad_e = SceneError::Model(ModelError::InvalidParameter {
            name: "E".into(),
            value: -1.0,
            reason: "must be finite and > 0",
        });
        assert_eq!(bad_e.kind(), ErrorKind::Configuration);
        let early = SceneError::NotInitialized {
            name: "floor_stress_max".into(),
        };
        assert_eq!(early.kind(), ErrorKind::Usage);
        assert!(early.to_string().contains("`floor_stress_max`"));
    }
}
