//! The speed-versus-error report for the abdomen scene and the stability table.

use std::path::PathBuf;

use anyhow::Result;
use harness::speed_error::{measure, stability, write_csv, Study};

/// Prints the tables and writes the CSV.
pub fn run() -> Result<()> {
    let study = Study::default();
    println!(
        "7. Speed versus error, abdomen: peak-normalized max error of the pelvic-floor stress history over \
         {} s against Houbolt on {} triangles at dt = {} s",
        study.duration, study.reference.0, study.reference.1
    );
    let cases = measure(&study)?;
    println!(
        "   {:>9} {:>10} {:>8} {:>10} {:>10} {:>11}",
        "triangles", "integrator", "dt (s)", "set-up ms", "step ms", "rel. error"
    );
    for c in &cases {
        println!(
            "   {:>9} {:>10} {:>8} {:>10.1} {:>10.3} {:>11.3e}",
            c.triangles, c.integrator, c.dt, c.setup_ms, c.step_ms, c.error
        );
    }
    let path = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../target/report/speed_error.csv"
    ));
    println!("   written to {}", write_csv(&cases, &path)?.display());
    println!("   Stability on hard cases (800 triangles, 0.1 s):");
    for s in stability() {
        println!("   {:<34} {:<19} {}", s.case, s.integrator, s.outcome);
    }
    Ok(())
}
