//! tissuefmu harness. Until the experiment runner lands, the main job is the verification
//! report: the FE core (convergence against analytical solutions, Houbolt's spectral
//! properties, timings), the cut-block scene (seed comparison, refinement, hard cases) and the
//! abdomen scene (mesh quality, the seed's findings, convergence, timings), and the cut
//! block's material identification on the shipped measurement set, and the abdomen's speed
//! versus error with a stability table.

mod abdomen_report;
mod core_report;
mod cutblock_report;
mod identify_report;
mod speed_error_report;

fn main() -> anyhow::Result<()> {
    core_report::run()?;
    println!();
    cutblock_report::run()?;
    println!();
    abdomen_report::run()?;
    println!();
    identify_report::run()?;
    println!();
    speed_error_report::run()
}
