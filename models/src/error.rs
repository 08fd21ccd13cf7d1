//! One error type for the finite-element core. Every variant names the offending value and
//! where it came from, so that a user (or an FMU importer reading the log) can act on it.

use thiserror::Error;

/// Errors raised while building meshes, materials, systems, or while solving them.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ModelError {
    /// A named choice (material law, element, integrator) that does not exist.
    #[error("unknown {what} `{value}`: use {choices}")]
    UnknownChoice {
        what: &'static str,
        value: String,
        choices: &'static str,
    },
    /// A scalar parameter is outside its admissible range (or not finite).
    #[error("invalid value {value} for `{name}`: {reason}")]
    InvalidParameter {
        name: String,
        value: f64,
        reason: &'static str,
    },
    /// An element has zero or negative signed area/volume.
    #[error(
        "{kind} element {index} is degenerate or inverted: signed {measure_name} = {measure:e}"
    )]
    DegenerateElement {
        kind: &'static str,
        index: usize,
        measure_name: &'static str,
        measure: f64,
    },
    /// An element refers to a node that does not exist.
    #[error("{kind} element {index} refers to node {node}, but the mesh has {n_nodes} nodes")]
    NodeOutOfRange {
        kind: &'static str,
        index: usize,
        node: usize,
        n_nodes: usize,
    },
    /// A node is not used by any element (it would have no stiffness).
    #[error("node {node} is not used by any element")]
    UnusedNode { node: usize },
    /// A named node set refers to a node that does not exist, or is missing.
    #[error("node set `{name}`: {reason}")]
    NodeSet { name: String, reason: String },
    /// Array sizes that must agree do not.
    #[error("size mismatch for `{name}`: expected {expected}, got {got}")]
    SizeMismatch {
        name: &'static str,
        expected: usize,
        got: usize,
    },
    /// The system matrix is singular or not positive definite (a floating body, a missing
    /// support, or a finite-strain tangent past a stability limit): the numerical pivot of
    /// equation `equation` fell to `ratio` times its diagonal entry (0: not positive).
    #[error(
        "singular or indefinite system (a floating body, a missing support, or at finite \
         strain an unstable state such as folding or buckling): pivot of equation {equation} \
         (global dof {dof}) is {ratio:e} times its diagonal entry"
    )]
    Singular {
        equation: usize,
        dof: usize,
        ratio: f64,
    },
    /// The time integration produced non-finite values.
    #[error("{integrator} diverged at t = {} s (step {step}): {reason}", crate::scene::seconds(*t))]
    Diverged {
        integrator: &'static str,
        t: f64,
        step: u64,
        reason: String,
    },
    /// A finite-strain element turned inside out: J = det F ≤ 0 at a quadrature point.
    #[error("element {element} is inverted (J = det F = {j:e} at a quadrature point)")]
    Inverted { element: usize, j: f64 },
    /// A nonlinear solve that stopped short of its load: `reached` is the fraction of the
    /// load change reached (0 … 1).
    #[error("no equilibrium beyond {:.1} % of the load change: {reason}", 100.0 * .reached)]
    NotConverged { reached: f64, reason: String },
    /// A build would need more memory than its limit allows (see [`crate::budget`]).
    #[error(
        "{what} would bring this build to {:.0} MB, above memory_limit = {:.0} MB: coarsen \
         the mesh or raise memory_limit",
        megabytes(*.needed),
        megabytes(*.limit)
    )]
    MemoryLimit {
        what: &'static str,
        needed: usize,
        limit: usize,
    },
    /// A method that needs the linear (small-strain) equation of motion was given a
    /// finite-strain structure.
    #[error(
        "{what} needs the linear equation of motion; finite strain runs with houbolt or \
         newmark in full order"
    )]
    LinearOnly { what: &'static str },
    /// Failure inside the sparse linear algebra that is not a singular matrix.
    #[error("sparse linear algebra failed: {0}")]
    LinearAlgebra(String),
}

fn megabytes(bytes: usize) -> f64 {
    bytes as f64 / 1e6
}

/// Returns `Ok(value)` when it is finite and strictly positive, else an error naming it.
pub fn positive(name: &str, value: f64) -> Result<f64, ModelError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ModelError::InvalidParameter {
            name: name.to_string(),
            value,
            reason: "must be finite and > 0",
        })
    }
}

/// Returns `Ok(value)` when it is finite and non-negative, else an error naming it.
pub fn non_negative(name: &str, value: f64) -> Result<f64, ModelError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(ModelError::InvalidParameter {
            name: name.to_string(),
            value,
            reason: "must be finite and >= 0",
        })
    }
}
