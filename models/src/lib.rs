//! tissuefmu finite-element core: meshes, elements, sparse assembly, static and dynamic
//! solvers, stress recovery, self-contact, and the scenes built from them. Units
//! throughout: mm, N, s, t (tonne); stress in MPa.
//!
//! ```text
//! mesh/      2D meshes (tri3 + line2), quadratic ones (tri6 + line3, tet10) from linear
//!            ones, tet meshes, generators, cuts by node duplication
//! element/   tri3, tri6 (displacement and mixed P2/P0), line2, line3, tet4, tet10,
//!            quadrature, material laws (linear, neo-Hookean, St. Venant–Kirchhoff) and
//!            the total Lagrangian kernel: small fixed-size matrices
//! assembly/  sparse pattern once + scatter, Dirichlet by elimination, loads, plane and
//!            solid bodies (linear and finite strain)
//! solve/     Cholesky (faer), statics, Newton, the dynamic structure, integrators
//!            (houbolt, newmark, central_difference, rk4), spectrum, Lanczos, modal
//!            reduction
//! stress     element and nodal stresses, von Mises, axial stress
//! contact/   the self-contact search of seed 001 (BV tree, curvature, pairs)
//! scene/     the scene interface (variable table, set/get, do_step) and the
//!            abdomen and cutblock scenes the FMUs and the harness drive
//! verify/    analytical reference problems and Richardson extrapolation, which the
//!            tests and the harness check against
//! budget     the memory limit of a build: large allocations are claimed first
//! error      ModelError: what went wrong, with the value and the variable
//! ```

pub mod assembly;
pub mod budget;
pub mod contact;
pub mod element;
pub mod error;
pub mod mesh;
pub mod scene;
pub mod solve;
pub mod stress;
pub mod verify;

pub use error::ModelError;
