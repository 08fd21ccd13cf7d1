//! tissuefmu finite-element core: meshes, elements, sparse assembly, static and dynamic
//! solvers, stress recovery. Units throughout: mm, N, s, t (tonne); stress in MPa.

pub mod assembly;
pub mod contact;
pub mod element;
pub mod error;
pub mod mesh;
pub mod scene;
pub mod solve;
pub mod stress;
pub mod verify;

pub use error::ModelError;
