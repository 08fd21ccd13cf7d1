//! tissuefmu harness. Until the scenes and the experiment runner land, the main job is the
//! FE-core verification report: convergence against analytical solutions, Houbolt's spectral
//! properties, and timings on the benchmark-sized problems.

mod core_report;

fn main() -> anyhow::Result<()> {
    core_report::run()
}
