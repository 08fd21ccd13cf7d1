//! tissuefmu finite-element core: meshes, elements, sparse assembly, static and dynamic
//! solvers, stress recovery, self-contact, and the scenes built from them. Units
//! throughout: mm, N, s, t (tonne); stress in MPa.
//!
//! The modules are layers, lowest first; each imports only from the layers below it, and no
//! two files import each other (`../shared/tools/layers.py` checks both):
//!
//! ```text
//! error      ModelError: what went wrong, with the value and the variable
//! budget     the memory limit of a build: large allocations are claimed first
//! element/   tri3, tri6, line2, line3, tet4, tet10, the membranes at finite strain, the
//!            quadrature rules, the material laws, the one total Lagrangian kernel (2D and
//!            3D), the 6-node triangle's mixed formulation and its stresses at a point:
//!            small fixed-size matrices
//! linalg/    sparse Cholesky (faer) with its orderings (AMD, METIS), the symmetric sparse
//!            products, the vector-register reset
//! mesh/      2D meshes (tri3 + line2), quadratic ones (tri6 + line3, tet10) from linear
//!            ones, tet meshes, generators, cuts by node duplication
//! contact/   the self-contact search of seed 001 (BV tree, curvature, pairs)
//! assembly/  sparse pattern once + scatter, Dirichlet by elimination, loads, plane and
//!            solid bodies (linear and finite strain), and the solver-facing interface of a
//!            body: its internal forces and their tangent (`forces`)
//! solve/     the linear static solve, Newton's method (one executor for statics and the
//!            implicit steps), the equation of motion and its effective matrix, the
//!            integrators (houbolt, newmark, central_difference, rk4), spectrum, Lanczos,
//!            modal and hyper-reduced orders
//! stress     element and nodal stresses, von Mises, axial stress
//! scene/     the scene interface (variable table, set/get, do_step) and the abdomen and
//!            cutblock scenes the FMUs and the harness drive
//! verify/    analytical reference problems and Richardson extrapolation, which the tests
//!            and the harness check against
//! ```

pub mod assembly;
pub mod budget;
pub mod contact;
pub mod element;
pub mod error;
pub mod linalg;
pub mod mesh;
pub mod scene;
pub mod solve;
pub mod stress;
pub mod verify;

pub use error::ModelError;
