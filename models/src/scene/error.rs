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
    /// A value reference that is not a row of the variable table (the reference given).
    #[error("unknown value reference {0}")]
    UnknownVariable(u32),
    /// A name that no variable of the table has (the name given).
    #[error("no variable named `{0}`")]
    UnknownName(String),
    /// A real value for a string variable, or the other way round.
    #[error("variable `{name}` is {actual}, not {expected}")]
    WrongKind {
        /// The variable's name.
        name: String,
        /// The kind the call takes: `"real"` or `"string"`.
        expected: &'static str,
        /// The variable's own kind: `"real"` or `"string"`.
        actual: &'static str,
    },
    /// A number of values that is not the variable's number of elements.
    #[error("variable `{name}` expects {expected} values, got {got}")]
    WrongLength {
        /// The variable's name.
        name: String,
        /// The variable's number of elements.
        expected: usize,
        /// The number of values given (or of places to read them into).
        got: usize,
    },
    /// A real value that is not finite or lies outside the variable's range.
    #[error("value {value} for `{name}` is out of range [{min}, {max}]")]
    OutOfRange {
        /// The variable's name.
        name: String,
        /// The value given, in the variable's unit.
        value: f64,
        /// The smallest value the variable takes, in its unit.
        min: f64,
        /// The largest value the variable takes, in its unit.
        max: f64,
    },
    /// A set of an output, or of a fixed parameter after initialization.
    #[error("variable `{name}` cannot be set now: {reason}")]
    NotSettable {
        /// The variable's name.
        name: String,
        /// Why it cannot be set: it is an output, or it is fixed and the scene initialized.
        reason: &'static str,
    },
    /// Reading an output or stepping before the scene is initialized.
    #[error("`{name}` is not available: the scene is not initialized")]
    NotInitialized {
        /// The output variable's name, or the call that needs the built model (`do_step`,
        /// `restart`, `profile`, …).
        name: String,
    },
    /// A call argument that is not a variable (the step size).
    #[error("{name} = {value} {reason}")]
    InvalidArgument {
        /// What the argument is (`step size h`, `start time`, `displacement length`, …).
        name: &'static str,
        /// The value given (s for times, a count for lengths).
        value: f64,
        /// What the argument must be (`must be finite and > 0`, …).
        reason: &'static str,
    },
    /// A communication step that would take more substeps than the scene allows.
    #[error(
        "a communication step of h = {h} s with max_step = {max_step} s needs {substeps:e} \
         substeps, more than the {limit:e} allowed per step: raise max_step or shorten the \
         communication step"
    )]
    TooManySubsteps {
        /// The communication step size (s).
        h: f64,
        /// The largest internal time step, the `max_step` parameter (s).
        max_step: f64,
        /// The number of substeps the communication step would take.
        substeps: f64,
        /// The most substeps one communication step may take.
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
        /// The input whose change it is (`pull`).
        input: &'static str,
        /// The size of the change in one step (mm).
        change: f64,
        /// The largest change one Newton load increment takes, `max_increment` (mm).
        max_increment: f64,
        /// The number of load increments the change would take.
        increments: f64,
        /// The most load increments one step may take.
        limit: f64,
    },
    /// Parameters or configuration files that describe no valid model (the cause).
    #[error("invalid configuration: {0}")]
    Config(String),
    /// An explicit integrator asked to step above its stability limit.
    #[error(
        "{integrator} is unstable at dt = {dt:e} s: its stability limit here is {limit:e} s; \
         lower max_step or use houbolt/newmark"
    )]
    Unstable {
        /// The integrator's name.
        integrator: &'static str,
        /// The time step asked for (s).
        dt: f64,
        /// The integrator's critical time step for this model (s).
        limit: f64,
    },
    /// An iteration that did not settle.
    #[error("{what} did not settle in {iterations} iterations")]
    NotConverged {
        /// What did not settle (the flank contact's active set, …).
        what: &'static str,
        /// The number of iterations or solves taken before giving up.
        iterations: usize,
    },
    /// The incision would cut a body free of its support.
    #[error(
        "the cut separates the block into {bodies} bodies; the body containing node {node} at \
         {at:?} mm does not touch the supported face y = 0 and would float"
    )]
    Separated {
        /// The number of connected bodies the cut leaves.
        bodies: usize,
        /// A node of a body that does not touch the supported face (its index in the mesh).
        node: usize,
        /// That node's position (x, y, z; mm).
        at: [f64; 3],
    },
    /// Cut flanks that slid or turned past each other further than the contact model's
    /// small-sliding range, so they pass through each other.
    #[error(
        "flank node {node} lies {depth:.4} mm behind the opposite flank, more than the {limit} \
         mm the contact accepts: the flanks slid or turned further than its small-sliding \
         range covers; lower press_force or the closing pull"
    )]
    Slid {
        /// The flank node that lies deepest behind the opposite flank (its index in the
        /// mesh).
        node: usize,
        /// How deep it lies behind the opposite flank (mm).
        depth: f64,
        /// The deepest penetration the contact accepts (mm): the sliding limit times the y
        /// size of the cell in front of the cut.
        limit: f64,
    },
    /// An error of the model underneath: its parameters, assembly or solution.
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
