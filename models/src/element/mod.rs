//! Element matrices for linear elasticity, small strain (seed 003 App. A and C).
//!
//! Every function here is pure: coordinates and material in, a small fixed-size `nalgebra`
//! matrix out. Degree-of-freedom order is node-major: `(u_x1, u_y1[, u_z1], u_x2, …)`.

pub mod line2;
pub mod material;
pub mod tet4;
pub mod tri3;

pub use material::Elastic;
