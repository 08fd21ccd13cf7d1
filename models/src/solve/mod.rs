//! The solvers: the linear static solve ([`statics`]), Newton's method — one executor for
//! the nonlinear statics and the implicit steps at finite strain ([`newton`]) — the
//! semi-discrete equation of motion ([`structure`]) and its factorized effective matrix,
//! the time integrators behind the [`Integrator`] trait (one file each: houbolt, newmark,
//! central_difference, rk4), eigenpairs by shift-invert Lanczos and modal reduction
//! ([`lanczos`], [`modal`]), the hyper-reduced finite-strain forces ([`pod`] basis,
//! [`ecsw`] weights), and the reduced models' error indicator ([`indicator`]).

pub mod central_difference;
pub mod ecsw;
mod effective;
pub mod houbolt;
pub mod indicator;
pub mod integrator;
pub mod lanczos;
pub mod modal;
pub mod newmark;
pub mod newton;
pub mod pod;
pub mod rk4;
pub mod spectrum;
pub mod statics;
pub mod structure;

pub use central_difference::CentralDifference;
pub use houbolt::Houbolt;
pub use indicator::{Indicator, Motion};
pub use integrator::{Checkpoint, Integrator, IntegratorKind, Load, State};
pub use modal::{Carried, ModalBasis, Reduction};
pub use newmark::Newmark;
pub use newton::Newton;
pub use rk4::Rk4;
pub use statics::Statics;
pub use structure::{Damping, History, Structure};
