//! Seed 003's findings on both kinematics: the configuration table at small strain beside
//! finite strain, each kinematics' ranking of the configurations with the differences
//! marked, and what a stiffer free wall does at each; then the walk from seed 003's own
//! model form to the default, one change at a time, naming the change that reverses each
//! finding.

use anyhow::Result;

use super::{Depth, Report};
use crate::studies::findings::{
    ranks, run, walk, Row, Stage, CONFIGURATIONS, KINEMATICS, SEED_FORM, STIFF_WALL_E,
};

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
    walk_section(report);
    Ok(())
}

/// The walk's table and which change reverses each finding.
fn walk_section(report: &mut Report) {
    let stages = walk();
    report.heading("From seed 003's model form to the default, one change at a time");
    let form: Vec<String> = SEED_FORM
        .iter()
        .map(|(n, v)| format!("{n} = {v}"))
        .collect();
    report.text(&format!(
        "Seed 003's form: {} (the press the seed's force on the diaphragm, a uniform \
         pressure over it as a dead load, with the default time course; the floor's modulus \
         that of this project's first rendering of the seed, whose own tissue values are not \
         legible in its text). Each row makes one more change towards the default. Peak mean floor stress over the first press \
         (kPa); the findings: a narrower pelvis lowers it (narrow < normal), a stiffer free \
         wall lowers it (wall_E = {STIFF_WALL_E} MPa, ten times the default, < the default).",
        form.join(", ")
    ));
    let cell = |p: &Option<Result<[f64; 2], String>>| match p {
        Some(Ok(p)) => format!("{:.3}", 1e3 * p[0]),
        Some(Err(why)) => why.clone(),
        None => "– (wall braced)".into(),
    };
    let verdict = |holds: Option<bool>| match holds {
        Some(true) => "holds",
        Some(false) => "reversed",
        None => "–",
    };
    let rows: Vec<Vec<String>> = stages
        .iter()
        .map(|s| {
            let [narrow, wall] = s.findings();
            vec![
                s.label.into(),
                cell(&s.peaks[0]),
                cell(&s.peaks[1]),
                verdict(narrow).into(),
                cell(&s.peaks[2]),
                verdict(wall).into(),
            ]
        })
        .collect();
    report.table(
        &[
            "stage",
            "narrow",
            "normal",
            "narrower pelvis lowers it",
            "normal, stiffer free wall",
            "stiffer wall lowers it",
        ],
        &rows,
    );
    let names = ["narrower pelvis", "stiffer free wall"];
    let lines: Vec<String> = (0..2)
        .map(|f| format!("the {} finding {}", names[f], reversal(&stages, f)))
        .collect();
    report.text(&format!("{}.", lines.join("; ")));
}

/// Where finding `f` changes along the walk: the change after which it first differs from
/// the seed form's verdict.
fn reversal(stages: &[Stage], f: usize) -> String {
    let verdicts: Vec<Option<bool>> = stages.iter().map(|s| s.findings()[f]).collect();
    match verdicts[0] {
        None => "cannot be judged on the seed's form (a run failed)".into(),
        Some(seed) => match verdicts.iter().position(|v| v.is_some_and(|v| v != seed)) {
            Some(k) => format!(
                "{} on the seed's form and turns with \"{}\"",
                if seed { "holds" } else { "does not hold" },
                stages[k].label
            ),
            None if seed => "holds on the seed's form and at every stage of the walk".into(),
            None => "holds neither on the seed's form nor at any stage of the walk".into(),
        },
    }
}
