//! One error type for the finite-element core. Every variant names the offending value and
//! where it came from, so that a user (or an FMU importer reading the log) can act on it.

use thiserror::Error;

/// Errors raised while building meshes, materials, systems, or while solving them.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ModelError {
    /// A named choice (material law, element, integrator) that does not exist.
    #[error("unknown {what} `{value}`: use {choices}")]
    UnknownChoice {
        /// What was chosen (e.g. `material`, `element`, `integrator`).
        what: &'static str,
        /// The name given.
        value: String,
        /// The names that exist, as the message lists them.
        choices: &'static str,
    },
    /// A scalar parameter is outside its admissible range (or not finite).
    #[error("invalid value {value} for `{name}`: {reason}")]
    InvalidParameter {
        /// The parameter's name (e.g. `cavity.E`).
        name: String,
        /// The value given.
        value: f64,
        /// Why it is refused (the range it must lie in).
        reason: &'static str,
    },
    /// An element has zero or negative signed area/volume.
    #[error(
        "{kind} element {index} is degenerate or inverted: signed {measure_name} = {measure:e}"
    )]
    DegenerateElement {
        /// The kind of element (`triangle`, `line` or `tetrahedron`).
        kind: &'static str,
        /// The index of the element among those of its kind.
        index: usize,
        /// The name of the measure (`area`, `length` or `volume`).
        measure_name: &'static str,
        /// The signed measure (mm², mm or mm³).
        measure: f64,
    },
    /// An element refers to a node that does not exist.
    #[error("{kind} element {index} refers to node {node}, but the mesh has {n_nodes} nodes")]
    NodeOutOfRange {
        /// The kind of element (e.g. `triangle`).
        kind: &'static str,
        /// The index of the element among those of its kind.
        index: usize,
        /// The node it refers to.
        node: usize,
        /// Number of nodes of the mesh.
        n_nodes: usize,
    },
    /// A node is not used by any element (it would have no stiffness).
    #[error("node {node} is not used by any element")]
    UnusedNode {
        /// The index of the unused node.
        node: usize,
    },
    /// A named node set refers to a node that does not exist, or is missing.
    #[error("node set `{name}`: {reason}")]
    NodeSet {
        /// The name of the node set.
        name: String,
        /// What is wrong with it.
        reason: String,
    },
    /// Array sizes that must agree do not.
    #[error("size mismatch for `{name}`: expected {expected}, got {got}")]
    SizeMismatch {
        /// The name of the array.
        name: &'static str,
        /// The length it must have.
        expected: usize,
        /// The length it has.
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
        /// The equation whose pivot failed.
        equation: usize,
        /// The global dof of that equation (the factorization, which has no dof map,
        /// reports the equation number).
        dof: usize,
        /// The pivot L_jj² over its diagonal entry A_jj (0: not positive).
        ratio: f64,
    },
    /// The time integration produced non-finite values.
    #[error("{integrator} diverged at t = {} s (step {step}): {reason}", seconds(*t))]
    Diverged {
        /// The name of the integrator (e.g. `houbolt`).
        integrator: &'static str,
        /// The time reached (s).
        t: f64,
        /// Steps taken since the start.
        step: u64,
        /// What was not finite.
        reason: String,
    },
    /// A finite-strain element turned inside out: J = det F ≤ 0 at a quadrature point.
    #[error("element {element} is inverted (J = det F = {j:e} at a quadrature point)")]
    Inverted {
        /// The index of the element among those of its kind.
        element: usize,
        /// The offending J ≤ 0: det F at a quadrature point (for a membrane line, its
        /// stretch λ).
        j: f64,
    },
    /// A nonlinear solve that stopped short of its load: `reached` is the fraction of the
    /// load change reached (0 … 1).
    #[error("no equilibrium beyond {:.1} % of the load change: {reason}", 100.0 * .reached)]
    NotConverged {
        /// The fraction of the load change reached (0 … 1).
        reached: f64,
        /// Why the solve stopped.
        reason: String,
    },
    /// A build would need more memory than its limit allows (the scene's `memory_limit`).
    #[error(
        "{what} would bring this build to {:.0} MB, above memory_limit = {:.0} MB: coarsen \
         the mesh or raise memory_limit",
        megabytes(*.needed),
        megabytes(*.limit)
    )]
    MemoryLimit {
        /// What the claim was for.
        what: &'static str,
        /// Bytes the build would have claimed in all, with this claim.
        needed: usize,
        /// The limit (bytes).
        limit: usize,
    },
    /// A method that needs the linear (small-strain) equation of motion was given a
    /// finite-strain structure.
    #[error(
        "{what} needs the linear equation of motion; finite strain runs with houbolt or \
         newmark in full order"
    )]
    LinearOnly {
        /// The method that needs it.
        what: &'static str,
    },
    /// Failure inside the sparse linear algebra that is not a singular matrix.
    #[error("sparse linear algebra failed: {0}")]
    LinearAlgebra(String),
}

/// A time (s) as messages print it: rounded to 12 significant digits, so that a sum of steps
/// reads `0.3`, not `0.30000000000000004`.
pub fn seconds(t: f64) -> String {
    let rounded: f64 = format!("{t:.11e}").parse().unwrap_or(t);
    format!("{rounded}")
}

fn megabytes(bytes: usize) -> f64 {
    bytes as f64 / 1e6
}

impl ModelError {
    /// The error for `value` of the choice `what`, which must be one of `choices`.
    pub fn unknown(what: &'static str, value: &str, choices: &'static str) -> Self {
        Self::UnknownChoice {
            what,
            value: value.to_string(),
            choices,
        }
    }
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
