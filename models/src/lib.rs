//! tissuefmu finite-element core: meshes, elements, sparse assembly, static and dynamic
//! solvers, stress recovery, self-contact, and the scenes built from them. Units
//! throughout: mm, N, s, t (tonne); stress in MPa.
//!
//! ```text
//! mesh/      2D (tri3 + line2) and tet meshes, generators, cuts by node duplication
//! element/   tri3, line2, tet4, the linear material: small fixed-size matrices
//! assembly/  sparse pattern once + scatter, Dirichlet by elimination, loads
//! solve/     Cholesky (faer), statics, the dynamic structure, integrators
//!            (houbolt, newmark, central_difference, rk4), spectrum
//! stress     element and nodal stresses, von Mises, axial stress
//! contact/   the self-contact search of seed 001 (BV tree, curvature, pairs)
//! scene/     the scene interface (variable table, set/get, do_step) and the
//!            abdomen and cutblock scenes the FMUs and the harness drive
//! verify/    analytical reference problems the tests and the harness check against
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
