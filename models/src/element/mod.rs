//! Elements and materials (seed 003 App. A and C): closed-form small-strain matrices of the
//! linear elements (tri3, line2, tet4), the quadratic triangle and tetrahedron (tri6,
//! tet10), the line elements at finite strain (membrane), the quadrature rules, the
//! material laws (linear, neo-Hookean, St. Venant–Kirchhoff), the one total Lagrangian
//! kernel (`total_lagrangian`) through which every solid element × law goes in 2D and 3D,
//! the 6-node triangle's mixed formulation (`mixed`) and its stresses at a point
//! (`recovery`).
//!
//! Every function here is pure: coordinates and material in, a small fixed-size `nalgebra`
//! matrix out. Degree-of-freedom order is node-major: `(u_x1, u_y1[, u_z1], u_x2, …)`.

pub mod line2;
pub mod line3;
pub mod material;
pub mod membrane;
pub mod mixed;
pub mod quadrature;
pub mod recovery;
pub mod tet10;
pub mod tet4;
pub mod total_lagrangian;
pub mod tri3;
pub mod tri6;

pub use material::{Elastic, Law, Material};
