//! Seed 003's findings on both kinematics (issue 26): the peak pelvic-floor stress over the
//! first press (1 s, its peak) for the shipped configurations and the wall variants, at
//! small strain beside finite strain, and each kinematics' ranking of the configurations.

use std::collections::BTreeMap;

use anyhow::{Context, Result};
use models::scene::abdomen::Abdomen;

use crate::sweep::{simulate, InProcess, Schedule, Value};

/// A case: its label and its settings beside the defaults.
pub struct Variant {
    /// The case's name in the tables.
    pub label: &'static str,
    /// The scene parameters the case sets, by name.
    pub settings: Vec<(&'static str, Value)>,
}

/// The cases: the five shipped configurations (the wall braced, the default), then the
/// normal pelvis with the wall free, and free and ten times stiffer.
pub fn cases() -> Vec<Variant> {
    let text = |s: &str| Value::Text(s.into());
    let mut cases: Vec<Variant> = CONFIGURATIONS
        .iter()
        .map(|&c| Variant {
            label: c,
            settings: vec![("configuration", text(c))],
        })
        .collect();
    cases.push(Variant {
        label: "normal, wall free",
        settings: vec![("abdominal_wall", text("free"))],
    });
    cases.push(Variant {
        label: "normal, wall free, 10× stiffer",
        settings: vec![
            ("abdominal_wall", text("free")),
            ("wall_E", Value::Real(0.225)),
        ],
    });
    cases
}

/// The shipped configurations, in the seed's order of interest.
pub const CONFIGURATIONS: [&str; 5] = ["narrow", "normal", "wide", "lordotic", "tilted"];

/// The kinematics compared.
pub const KINEMATICS: [&str; 2] = ["linear", "finite"];

/// Peak floor stress (mean, max; MPa) of a case at each kinematics, or why the run failed.
pub struct Row {
    /// The case's label.
    pub label: &'static str,
    /// Per kinematics, in [`KINEMATICS`] order: the peaks (mean, max; MPa), or the error of
    /// the run.
    pub peaks: [Result<[f64; 2], String>; 2],
}

/// Runs every case at both kinematics: 1 s of the default press at 10 ms steps.
pub fn run() -> Result<Vec<Row>> {
    cases()
        .into_iter()
        .map(|case| {
            let peaks = KINEMATICS.map(|k| {
                let mut settings: Vec<(String, Value)> = case
                    .settings
                    .iter()
                    .map(|(n, v)| (n.to_string(), v.clone()))
                    .collect();
                settings.push(("kinematics".into(), Value::Text(k.into())));
                peaks(&settings).map_err(|e| format!("{e:#}"))
            });
            Ok(Row {
                label: case.label,
                peaks,
            })
        })
        .collect()
}

/// The peak pelvic-floor stress (mean, max) over the first second of the default pressing
/// (its peak) at 10 ms steps, for a scene with `settings`.
pub fn peaks(settings: &[(String, Value)]) -> Result<[f64; 2]> {
    let record = [
        "floor_stress_mean".to_string(),
        "floor_stress_max".to_string(),
    ];
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: 1.0,
        step: 1e-2,
        settings,
        inputs: &BTreeMap::new(),
        record: &record,
    };
    let series = simulate(&mut InProcess(Box::new(Abdomen::new())), &schedule)?.series;
    let peak = |name: &str| -> Result<f64> {
        let column = series.column(name).context("recorded")?;
        Ok(column[1..]
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max))
    };
    Ok([peak(&record[0])?, peak(&record[1])?])
}

/// The rank (1 = lowest) of each of `values` among them; NaN ranks last.
pub fn ranks(values: &[f64]) -> Vec<usize> {
    let mut order: Vec<usize> = (0..values.len()).collect();
    order.sort_by(|&a, &b| values[a].total_cmp(&values[b]));
    let mut rank = vec![0; values.len()];
    for (r, &i) in order.iter().enumerate() {
        rank[i] = r + 1;
    }
    rank
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranks_count_from_the_lowest() {
        assert_eq!(ranks(&[4.7, 5.1, 4.2, 3.8, 3.9]), [4, 5, 3, 1, 2]);
        assert_eq!(ranks(&[]), Vec::<usize>::new());
    }
}
