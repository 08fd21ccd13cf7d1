//! Pelvis rankings with their confidence (issue 53, [`crate::studies::rankings`]): the
//! samples' inputs and outputs (`rankings_samples.csv`), the probabilities of each ordering
//! (`rankings.csv`: a, b, quantity, p), a plot of them and a table saying which orderings
//! are robust (p > 0.95 or < 0.05).

use std::fmt::Write as _;
use std::time::Instant;

use anyhow::{ensure, Result};
use indicatif::{ProgressBar, ProgressStyle};

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::{Depth, Report};
use crate::atomic::write_atomic;
use crate::studies::rankings::{
    plan, probabilities, run, Sample, CONFIGURATIONS, LOADS, QUANTITIES, UNCERTAIN, WALLS,
};

/// Samples of the quick report (a wall and load combination each, 6 in all, twice).
const QUICK_SAMPLES: usize = 12;

/// The Latin hypercube's seed.
const SEED: u64 = 53;

/// The section with [`QUICK_SAMPLES`] samples (quick) or 200 (full).
pub fn section(report: &mut Report, depth: Depth) -> Result<()> {
    let samples = match depth {
        Depth::Quick => QUICK_SAMPLES,
        Depth::Full => 200,
    };
    rankings(report, samples)
}

/// Runs `n` samples on the five configurations and writes the section.
pub fn rankings(report: &mut Report, n: usize) -> Result<()> {
    ensure!(n >= 1, "--samples must be at least 1 (got {n})");
    let mut samples = plan(n, SEED)?;
    let bar = ProgressBar::new((n * CONFIGURATIONS.len()) as u64).with_style(
        ProgressStyle::with_template("{bar:30} {pos}/{len} runs {elapsed_precise} rankings")
            .expect("the template is valid"),
    );
    let started = Instant::now();
    run(&mut samples, || bar.inc(1));
    let seconds = started.elapsed().as_secs_f64();
    bar.finish_and_clear();
    write_atomic(
        &report.path("rankings_samples.csv"),
        samples_csv(&samples).as_bytes(),
    )?;
    let rows = probabilities(&samples);
    let mut csv = String::from("a,b,quantity,p,samples\n");
    for &(a, b, q, p, count) in &rows {
        let (a, b) = (CONFIGURATIONS[a], CONFIGURATIONS[b]);
        let p = p.map_or(String::new(), |p| p.to_string());
        writeln!(csv, "{a},{b},{},{p},{count}", QUANTITIES[q])?;
    }
    write_atomic(&report.path("rankings.csv"), csv.as_bytes())?;
    let failed = samples
        .iter()
        .flat_map(|s| &s.runs)
        .filter(|r| r.is_err())
        .count();
    report.heading("Pelvis rankings with their confidence");
    report.text(&format!(
        "{n} samples of the uncertain inputs, each run on the five shipped configurations \
         ({} runs, {failed} without equilibrium; {seconds:.0} s wall time on this machine): a \
         static start at the sample's intra-abdominal pressure in the clinical settings (with \
         the sample's values) and the neo-Hookean sheets, full order at finite strain, 300 triangles. A sample uses \
         the same inputs on every configuration. p is the fraction of the samples run on both \
         configurations of a pair in which the first loads the floor more; an ordering is \
         robust where p > 0.95 or p < 0.05.",
        n * CONFIGURATIONS.len()
    ));
    report.table(
        &[
            "configurations",
            "by floor_stress_mean: p",
            "robust",
            "by floor_stress_max: p",
            "robust",
        ],
        &pair_rows(&rows),
    );
    report.text("The uncertain inputs:");
    report.table(&["input", "range", "source"], &input_rows());
    report.file(
        "the probabilities (a, b, quantity, p, samples)",
        "rankings.csv",
    );
    report.file(
        "every sample's inputs and floor stresses",
        "rankings_samples.csv",
    );
    plot_probabilities(report, &rows)
}

/// A row per pair: p by each quantity and whether the ordering is robust.
fn pair_rows(rows: &[(usize, usize, usize, Option<f64>, usize)]) -> Vec<Vec<String>> {
    rows.chunks(QUANTITIES.len())
        .map(|pair| {
            let mut row = vec![format!(
                "{} > {}",
                CONFIGURATIONS[pair[0].0], CONFIGURATIONS[pair[0].1]
            )];
            for &(_, _, _, p, count) in pair {
                match p {
                    Some(p) => {
                        row.push(format!("{p:.3} ({count})"));
                        row.push(robust(p).into());
                    }
                    None => row.extend(["–".into(), "no sample ran on both".into()]),
                }
            }
            row
        })
        .collect()
}

/// Whether an ordering of probability `p` is robust.
fn robust(p: f64) -> &'static str {
    if !(0.05..=0.95).contains(&p) {
        "robust"
    } else {
        "not robust"
    }
}

fn input_rows() -> Vec<Vec<String>> {
    let mut rows: Vec<Vec<String>> = UNCERTAIN
        .iter()
        .map(|u| {
            let scale = if u.log { ", log-uniform" } else { "" };
            vec![
                u.name.into(),
                format!("{} – {}{scale}", u.min, u.max),
                u.source.into(),
            ]
        })
        .collect();
    rows.push(vec![
        "abdominal_wall".into(),
        WALLS.join(", "),
        "taken in turn: the braced wall of straining or a passive one (seed 003 offered both)"
            .into(),
    ]);
    let loads: Vec<String> = LOADS.iter().map(|(n, p)| format!("{n} {p} kPa")).collect();
    rows.push(vec![
        "target_pressure".into(),
        loads.join(", "),
        "taken in turn: the clinical presets' peaks (experiments/clinical_*.toml)".into(),
    ]);
    rows
}

fn samples_csv(samples: &[Sample]) -> String {
    let mut out = String::from("sample,configuration,abdominal_wall,load,iap_kpa");
    for u in UNCERTAIN {
        let _ = write!(out, ",{}", u.name);
    }
    let _ = writeln!(out, ",{},{},error", QUANTITIES[0], QUANTITIES[1]);
    for (i, s) in samples.iter().enumerate() {
        for (c, run) in CONFIGURATIONS.iter().zip(&s.runs) {
            let _ = write!(out, "{i},{c},{},{},{}", s.wall, s.load.0, s.load.1);
            for u in UNCERTAIN {
                let _ = write!(out, ",{}", s.inputs[u.name]);
            }
            let _ = match run {
                Ok([mean, max]) => writeln!(out, ",{mean},{max},"),
                Err(e) => writeln!(out, ",,,\"{}\"", e.replace('"', "'")),
            };
        }
    }
    out
}

/// p of every pair by each quantity, with the robustness bounds.
fn plot_probabilities(
    report: &mut Report,
    rows: &[(usize, usize, usize, Option<f64>, usize)],
) -> Result<()> {
    let pairs: Vec<String> = rows
        .chunks(QUANTITIES.len())
        .map(|pair| {
            format!(
                "{}>{}",
                &CONFIGURATIONS[pair[0].0][..3],
                &CONFIGURATIONS[pair[0].1][..3]
            )
        })
        .collect();
    let mut curves: Vec<Curve> = (0..QUANTITIES.len())
        .map(|q| {
            let points = rows
                .iter()
                .filter(|r| r.2 == q)
                .enumerate()
                .filter_map(|(k, r)| Some((k as f64, r.3?)))
                .collect();
            Curve::new(&format!("p by {}", QUANTITIES[q]), points, Mark::Dots).colour(q)
        })
        .collect();
    let last = (pairs.len() - 1) as f64;
    for (k, bound) in [0.05, 0.95].into_iter().enumerate() {
        let label = format!("robust beyond {bound}");
        curves
            .push(Curve::new(&label, vec![(0.0, bound), (last, bound)], Mark::Line).colour(2 + k));
    }
    plot::chart(
        &report.path("rankings"),
        &Chart {
            title: "Pelvis rankings: p(a loads the floor more than b)".into(),
            x: Axis {
                categories: Some(pairs),
                ..Axis::linear("pair of configurations")
            },
            y: Axis::linear("p"),
            curves,
        },
    )?;
    report.figure(
        "The probability of each ordering of the shipped configurations",
        "rankings",
    );
    Ok(())
}
