//! Verification problems with independent (analytical) references, shared by the test suite,
//! the benchmarks and the harness's verification report: the Lamé thick-walled cylinder, the
//! single-degree-of-freedom oscillator with Houbolt's characteristic equation, the two
//! benchmark-sized meshes, and Richardson extrapolation for outputs without one.

pub mod lame;
pub mod oscillator;
pub mod problems;
pub mod richardson;
