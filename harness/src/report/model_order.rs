//! Model orders side by side. Every report: the shipped pelvis configurations in full-order
//! finite strain (the reference), the hyper-reduced finite-strain model and the modal model
//! of linear kinematics ([`model_orders`]) — set-up and stepping times, each order's error
//! in the peak floor stress against the reference, the ranking of the configurations and
//! the reduced model's error indicator. The full report adds the shipped pelvis sweep in
//! those three orders and in full order at small strain: the wall time of a fresh run of
//! each, its errors in the peak floor stress against full-order finite strain and the pairs
//! of cases it ranks the other way round.

use std::collections::BTreeMap;

use anyhow::{Context, Result};

use super::{Depth, Report};
use crate::atomic::write_atomic;
use crate::studies::model_orders::{self, Order, OrderRun, INDICATOR_EVERY, QUANTITIES};
use crate::sweep::experiment::Experiment;
use crate::sweep::runner::{self, Outcome, Sweep};
use crate::sweep::simulate::Value;

/// The shipped sweep compared.
const NAME: &str = "pelvis_sweep";

/// Runs the sweep fresh in `order` into `<report>/model_order/<order>_<kinematics>`.
fn fresh(report: &Report, e: &Experiment, order: Order) -> Result<Sweep> {
    let mut e = e.clone();
    e.parameters
        .insert("model_order".into(), Value::Text(order.model_order.into()));
    e.parameters
        .insert("kinematics".into(), Value::Text(order.kinematics.into()));
    let dir = report
        .path("model_order")
        .join(format!("{}_{}", order.model_order, order.kinematics));
    if dir.exists() {
        // A resumed sweep would not be timed: start over.
        std::fs::remove_dir_all(&dir).with_context(|| format!("clearing {}", dir.display()))?;
    }
    runner::run(&e, &dir)
}

/// Output `j`'s peak of every finished case, by case id.
fn peaks(s: &Sweep, j: usize) -> BTreeMap<usize, f64> {
    s.results
        .iter()
        .filter_map(|r| match &r.outcome {
            Outcome::Finished { peak, .. } => Some((r.id, peak[j])),
            Outcome::Failed(_) => None,
        })
        .collect()
}

/// The largest relative difference of `peaks` from `reference` over the cases both
/// finished, and the pairs of cases the two order differently.
fn compare(peaks: &BTreeMap<usize, f64>, reference: &BTreeMap<usize, f64>) -> (f64, usize) {
    let both: Vec<(f64, f64)> = reference
        .iter()
        .filter_map(|(id, x)| peaks.get(id).map(|y| (*x, *y)))
        .collect();
    let worst = model_orders::worst_relative(both.iter().copied());
    let mut swapped = 0;
    for (i, a) in both.iter().enumerate() {
        swapped += both[i + 1..]
            .iter()
            .filter(|b| (a.0 - b.0) * (a.1 - b.1) < 0.0)
            .count();
    }
    (worst, swapped)
}

/// The report section: the configurations in three orders; the shipped pelvis sweep in
/// them and in full order at small strain only in the full report.
pub fn section(report: &mut Report, depth: Depth) -> Result<()> {
    configurations(report)?;
    shipped_sweep(report, depth)
}

/// The shipped configurations in full, hyper-reduced and modal order.
fn configurations(report: &mut Report) -> Result<()> {
    report.heading("The shipped configurations in three model orders");
    let sweeps = model_orders::run()?;
    let reference = &sweeps[0];
    let n = reference.cases.len();
    report.text(&format!(
        "The {n} shipped pelvis configurations, one press of the default pressing force \
         (0.8 N/mm at 0.5 Hz, 2 s in 10 ms steps) from rest on the default model (braced \
         abdominal wall), in full-order finite strain — the reference, the right physics at \
         this load — in the hyper-reduced finite-strain order (`model_order = \"reduced\"`, \
         trained at initialization per configuration) and in the modal order of linear \
         kinematics; the cases of each order run {} at a time. Errors are of the peak over \
         the press, relative to the reference's, the worst over the configurations; the \
         error indicator (`error_indicator`, the full residual of the state in the energy \
         norm) is the largest read every {INDICATOR_EVERY} steps, outside the timed steps.",
        rayon::current_num_threads()
    ));
    let rows: Vec<Vec<String>> = sweeps.iter().map(|s| summary(s, reference)).collect();
    report.table(
        &[
            "model order",
            "kinematics",
            "set-up, sum (s)",
            "stepping, sum (s)",
            "wall time (s)",
            "floor stress mean, worst error",
            "floor stress max, worst error",
            "ranking as the reference (mean / max)",
            "largest error indicator",
        ],
        &rows,
    );
    let [_, reduced, modal] = &sweeps[..] else {
        anyhow::bail!("three model orders");
    };
    report.text(&format!(
        "Stepping alone, the reduced order is {:.1}× faster than full order and the modal \
         linear {:.0}×; with the set-up (the reduced model's training) full order's wall \
         time is {:.2}× the reduced order's (below 1: the training costs more than the one \
         press it serves) and {:.1}× the modal linear one's. The modal linear errors are the model-form error of \
         linear kinematics at this load, which its error indicator (the residual of its own \
         linear equations) does not see.",
        stepping(reference) / stepping(reduced),
        stepping(reference) / stepping(modal),
        reference.seconds / reduced.seconds,
        reference.seconds / modal.seconds,
    ));
    for s in &sweeps {
        let warned: Vec<&model_orders::ConfigurationRun> =
            s.cases.iter().filter(|c| !c.warnings.is_empty()).collect();
        if let Some(first) = warned.first() {
            report.text(&format!(
                "Validity warnings in {} order at {} kinematics: {} of {n} configurations; \
                 the first ({}): {}",
                s.order.model_order,
                s.order.kinematics,
                warned.len(),
                first.configuration,
                first.warnings[0]
            ));
        }
    }
    let csv = report.path("model_orders.csv");
    write_atomic(&csv, &table_csv(&sweeps)?)?;
    report.file("Every case", "model_orders.csv");
    Ok(())
}

/// A summary row of one order against the reference.
fn summary(s: &OrderRun, reference: &OrderRun) -> Vec<String> {
    let sum = |f: fn(&model_orders::ConfigurationRun) -> f64| s.cases.iter().map(f).sum::<f64>();
    let same = |j: usize| {
        if model_orders::ranking(s, j) == model_orders::ranking(reference, j) {
            "yes"
        } else {
            "no"
        }
    };
    let indicator = s.cases.iter().map(|c| c.indicator).fold(0.0, f64::max);
    vec![
        s.order.model_order.to_string(),
        s.order.kinematics.to_string(),
        format!("{:.3}", sum(|c| c.setup)),
        format!("{:.3}", sum(|c| c.stepping)),
        format!("{:.3}", s.seconds),
        format!(
            "{:.3} %",
            100.0 * model_orders::worst_error(s, reference, 0)
        ),
        format!(
            "{:.3} %",
            100.0 * model_orders::worst_error(s, reference, 1)
        ),
        format!("{} / {}", same(0), same(1)),
        format!("{indicator:.2e}"),
    ]
}

/// The stepping time of all cases of a sweep (s).
fn stepping(s: &OrderRun) -> f64 {
    s.cases.iter().map(|c| c.stepping).sum()
}

/// Every case of every order as CSV.
fn table_csv(sweeps: &[OrderRun]) -> Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec![
        "model_order",
        "kinematics",
        "configuration",
        "setup_s",
        "stepping_s",
    ];
    header.extend(QUANTITIES);
    header.push("error_indicator_max");
    w.write_record(&header)?;
    for s in sweeps {
        for c in &s.cases {
            let mut row = vec![
                s.order.model_order.to_string(),
                s.order.kinematics.to_string(),
                c.configuration.to_string(),
                format!("{:?}", c.setup),
                format!("{:?}", c.stepping),
            ];
            row.extend(c.peaks.iter().map(|p| format!("{p:?}")));
            row.push(format!("{:?}", c.indicator));
            w.write_record(&row)?;
        }
    }
    Ok(w.into_inner()?)
}

/// The shipped pelvis sweep in the three orders of [`model_orders::ORDERS`] and in full
/// order at small strain (what the modal order reduces); the quick report only says where
/// it is.
fn shipped_sweep(report: &mut Report, depth: Depth) -> Result<()> {
    let e = Experiment::shipped(NAME)?;
    if depth == Depth::Quick {
        report.heading(&format!("Sweep `{NAME}` in four model forms"));
        report.text(&format!(
            "Not run in the quick report: the {} cases take minutes in each model form. \
             Run `harness model-order` or `harness report --full`; the last measured figures \
             are in docs/results.md.",
            e.cases.len()
        ));
        return Ok(());
    }
    report.heading(&format!(
        "Sweep `{NAME}` in four model forms ({} cases, {} s of pressing each)",
        e.cases.len(),
        e.stop_time - e.start_time
    ));
    let column = |name: &str| {
        e.record
            .iter()
            .position(|r| r == name)
            .with_context(|| format!("`{name}` is recorded"))
    };
    let metrics = [column("floor_stress_mean")?, column("floor_stress_max")?];
    let linear = Order {
        model_order: "full",
        kinematics: "linear",
    };
    let mut runs = Vec::new();
    for order in model_orders::ORDERS.into_iter().chain([linear]) {
        runs.push((order, fresh(report, &e, order)?));
    }
    let reference = &runs[0].1;
    let jobs = e.threads();
    report.text(&format!(
        "Every run from scratch on this machine ({jobs} cases at a time); the reduced and \
         modal models are trained or built for every case. Errors are of each case's peak \
         against full-order finite strain (the worst over the cases), with the pairs of \
         cases ranked the other way round (of {} pairs).",
        e.cases.len() * e.cases.len().saturating_sub(1) / 2
    ));
    let rows: Vec<Vec<String>> = runs
        .iter()
        .map(|(order, s)| {
            let mut row = vec![
                format!("{} {}", order.model_order, order.kinematics),
                format!("{}/{}", peaks(s, metrics[0]).len(), s.results.len()),
                format!("{:.1}", s.seconds),
                format!("{:.2}", reference.seconds / s.seconds),
            ];
            for &j in &metrics {
                let (worst, swapped) = compare(&peaks(s, j), &peaks(reference, j));
                row.push(format!("{:.3} % / {swapped}", 100.0 * worst));
            }
            row
        })
        .collect();
    report.table(
        &[
            "model form",
            "cases finished",
            "wall time (s)",
            "speed-up",
            "floor stress mean: worst error / pairs swapped",
            "floor stress max: worst error / pairs swapped",
        ],
        &rows,
    );
    Ok(())
}
