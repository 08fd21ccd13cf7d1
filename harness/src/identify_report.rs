//! The identification report: E and ν of the cut block fitted to the shipped measurement set
//! A, the profile deviations against seed 002's acceptance criterion, and the E–ν trade-off.

use std::path::PathBuf;

use anyhow::Result;
use harness::identify::{identify, Measurements};

/// Prints the report.
pub fn run() -> Result<()> {
    let dir = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../experiments/data/cutblock"
    ));
    let m = Measurements::load(&dir, "A")?;
    let fit = identify(&m)?;
    println!(
        "6. Material identification, cut block, data set A ({})",
        dir.display()
    );
    println!(
        "   ν from the profiles: {:.4}; E from the forces at that ν: {:.5} ± {:.5} MPa (standard error)",
        fit.nu, fit.e, fit.e_std
    );
    if fit.nu > 0.498 {
        println!(
            "   ν sits at the upper end of the search interval: the profile misfit keeps falling toward \
             incompressibility, a sign of model-form error (the linear model overshoots the rise \
             near the cut), so this ν is not a trustworthy material value"
        );
    }
    println!(
        "   residuals: force RMS {:.4} N (largest measured force {:.3} N), profile RMS {:.4} mm",
        fit.force_rms,
        m.force.iter().copied().fold(0.0, f64::max),
        fit.profile_rms
    );
    println!(
        "   profile deviation per line (acceptance: < 1 % of the largest block dimension = 1 mm):"
    );
    for (x, d) in [25, 50, 75].iter().zip(&fit.lines) {
        let verdict = if d.max < 1.0 { "meets" } else { "misses" };
        println!(
            "     x = {x} mm: RMS {:.3} mm, max {:.3} mm over {} points — {verdict} the criterion",
            d.rms, d.max, d.points
        );
    }
    println!("   E–ν trade-off (the forces alone fit every ν equally well with its own E):");
    println!(
        "     {:>6} {:>16} {:>18}",
        "ν", "profile RMS (mm)", "E from forces (MPa)"
    );
    for (nu, rms, e) in &fit.scan {
        println!("     {nu:>6} {rms:>16.4} {e:>18.5}");
    }
    Ok(())
}
