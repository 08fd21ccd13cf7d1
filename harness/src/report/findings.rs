//! Seed 003's findings on both kinematics: the configuration table at small strain beside
//! finite strain, each kinematics' ranking of the configurations with the differences
//! marked, and what a stiffer free wall does at each.

use anyhow::Result;

use super::{Depth, Report};
use crate::studies::findings::{ranks, run, Row, CONFIGURATIONS, KINEMATICS};

/// Adds the section to `report` (the same at either depth).
pub fn section(report: &mut Report, _depth: Depth) -> Result<()> {
    let rows = run()?;
    report.heading("Seed 003's findings on both kinematics");
    report.text(
        "Peak pelvic-floor stress over the first press (1 s, 10 ms steps, kPa), on the \
         defaults but the kinematics. Ranks count from the lowest among the five \
         configurations; ≠ marks a configuration the two kinematics rank differently. Seed \
         003: a narrower pelvis and a stiffer abdominal wall lower the floor stress.",
    );
    let value = |r: &Row, k: usize, q: usize| r.peaks[k].as_ref().map_or(f64::NAN, |p| p[q]);
    let configurations = &rows[..CONFIGURATIONS.len()];
    let rank = |k: usize, q: usize| -> Vec<usize> {
        ranks(
            &configurations
                .iter()
                .map(|r| value(r, k, q))
                .collect::<Vec<_>>(),
        )
    };
    let (linear, finite) = ([rank(0, 0), rank(0, 1)], [rank(1, 0), rank(1, 1)]);
    let table: Vec<Vec<String>> = rows
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let mut row = vec![r.label.to_string()];
            for k in 0..KINEMATICS.len() {
                match &r.peaks[k] {
                    Ok(p) => row.extend(p.map(|x| format!("{:.3}", 1e3 * x))),
                    Err(why) => row.extend([why.clone(), String::new()]),
                }
            }
            for q in 0..2 {
                let change = value(r, 1, q) / value(r, 0, q) - 1.0;
                row.push(format!("{:+.0} %", 100.0 * change));
            }
            for q in 0..2 {
                row.push(match i < CONFIGURATIONS.len() {
                    true => {
                        let (a, b) = (linear[q][i], finite[q][i]);
                        format!("{a} → {b}{}", if a == b { "" } else { " ≠" })
                    }
                    false => String::new(),
                });
            }
            row
        })
        .collect();
    report.table(
        &[
            "case",
            "linear mean",
            "linear max",
            "finite mean",
            "finite max",
            "finite − linear, mean",
            "max",
            "rank by mean, linear → finite",
            "by max",
        ],
        &table,
    );
    let n = CONFIGURATIONS.len();
    let verdicts: Vec<String> = KINEMATICS
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let narrow = value(&rows[0], k, 0) < value(&rows[1], k, 0);
            let stiffer = value(&rows[n + 1], k, 0) < value(&rows[n], k, 0);
            format!(
                "{name} strain: a narrower pelvis {} the mean floor stress; a stiffer free \
                 wall {} it",
                if narrow { "lowers" } else { "raises" },
                if stiffer { "lowers" } else { "raises" }
            )
        })
        .collect();
    report.text(&format!("{}.", verdicts.join("; ")));
    Ok(())
}
