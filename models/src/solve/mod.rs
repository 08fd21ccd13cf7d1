//! Linear solvers: sparse Cholesky, the static solve, Newton's method (with Anderson
//! acceleration of its iterations on a kept factorization, [`anderson`]), eigenpairs by shift-invert Lanczos and
//! modal reduction ([`lanczos`], [`modal`]), the hyper-reduced finite-strain forces
//! ([`pod`] basis, [`ecsw`] weights), and the time integrators behind the
//! [`Integrator`] trait (one file each: houbolt, newmark, central_difference, rk4).

pub mod anderson;
pub mod central_difference;
pub mod cholesky;
pub mod ecsw;
pub mod houbolt;
pub mod indicator;
pub mod integrator;
pub mod lanczos;
pub mod modal;
pub mod newmark;
pub mod newton;
pub mod ordering;
pub mod pod;
mod product;
pub mod rk4;
pub mod spectrum;
pub mod statics;
pub mod structure;
mod sweeps;
pub(crate) mod vector_state;

pub use central_difference::CentralDifference;
pub use cholesky::{Cholesky, Factorization, Ordering};
pub use houbolt::Houbolt;
pub use indicator::{Indicator, Motion};
pub use integrator::{Checkpoint, Integrator, IntegratorKind, Load, State};
pub use modal::{ModalBasis, Reduction};
pub use newmark::Newmark;
pub use newton::Newton;
pub use rk4::Rk4;
pub use statics::Statics;
pub use structure::{Damping, History, Structure};
