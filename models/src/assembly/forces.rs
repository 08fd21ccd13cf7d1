//! The solver-facing interface of a body: its internal forces f_int(u) and their tangent
//! K_T(u) = ∂f_int/∂u on an assembler's pattern. Newton's method, the implicit time
//! integrators and the reduced models see a body through [`InternalForces`] only; the
//! hyper-reduction, which samples elements, through its element-by-element refinement
//! [`ElementForces`].

use crate::error::ModelError;

/// A body's internal forces and their tangent.
pub trait InternalForces: Send + Sync {
    /// Writes f_int(u) into `f` (u and f on all dofs) and, when `k` is given, the tangent's
    /// values on the body's pattern into `k`. An inverted element is an error
    /// ([`ModelError::Inverted`]): the solvers cut back or shorten their step.
    fn internal(&self, u: &[f64], f: &mut [f64], k: Option<&mut [f64]>) -> Result<(), ModelError>;

    /// Declares the load fraction s ∈ [0, 1] of a static solve's load change at which the
    /// next evaluations are made (0 the last equilibrium's load, 1 the target): for bodies
    /// whose own forces follow the load, such as an active tension. Others ignore it.
    fn at_load_fraction(&self, _s: f64) {}

    /// Whether the forces change along the load fraction ([`Self::at_load_fraction`]), so
    /// that a solve at unchanged prescribed values and external forces still changes its
    /// equations along its increments.
    fn follow_the_load(&self) -> bool {
        false
    }
}

/// Internal forces element by element: the sum over the elements, scattered to their dofs,
/// is [`InternalForces::internal`].
pub trait ElementForces: InternalForces {
    /// The number of elements.
    fn count(&self) -> usize;

    /// The dofs (all-dof numbering) of element `e` into `dofs`, replacing its content.
    fn dofs(&self, e: usize, dofs: &mut Vec<usize>);

    /// Element `e`'s internal force into `fe` and, when asked, its tangent into `ke`
    /// (column-major) at the displacement `ue` of its dofs; an inverted element is an error.
    fn evaluate(
        &self,
        e: usize,
        ue: &[f64],
        fe: &mut [f64],
        ke: Option<&mut [f64]>,
    ) -> Result<(), ModelError>;
}

/// Zeroes `f` and, when given, `k`: the start of an [`InternalForces::internal`] that adds
/// its parts.
pub fn clear(f: &mut [f64], k: Option<&mut [f64]>) {
    f.fill(0.0);
    if let Some(k) = k {
        k.fill(0.0);
    }
}
