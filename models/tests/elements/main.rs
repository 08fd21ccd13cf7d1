//! Tests of the finite-element core below the scenes: elements and materials (patch tests,
//! convergence rates, locking, tangents), finite-strain statics, the membrane lines, hard
//! geometries and the self-contact search. One module per file, linked as one binary.

mod common;

mod contact;
mod convergence;
mod finite_strain;
mod hard_cases;
mod locking;
mod membrane;
mod patch;
mod plane_finite_strain;
mod tet10;
