//! The shipped pelvis sweep in both model orders at small strain (the modal order reduces
//! the linear equation of motion), side by side: the wall time of a fresh run of each and
//! the largest difference in the peak of the sweep's metric (the pelvic-floor stress)
//! between them — what a sweep gains from `model_order = "modal"`, and what it costs in
//! accuracy against full order of the same kinematics.

use std::collections::BTreeMap;

use anyhow::{Context, Result};

use super::{Depth, Report};
use crate::sweep::experiment::Experiment;
use crate::sweep::runner::{self, Outcome, Sweep};
use crate::sweep::simulate::Value;

/// The shipped sweep compared.
const NAME: &str = "pelvis_sweep";

/// Runs the sweep fresh in `order` into `<report>/model_order/<order>`.
fn fresh(report: &Report, e: &Experiment, order: &str) -> Result<Sweep> {
    let mut e = e.clone();
    e.parameters
        .insert("model_order".into(), Value::Text(order.into()));
    e.parameters
        .insert("kinematics".into(), Value::Text("linear".into()));
    let dir = report.path("model_order").join(order);
    if dir.exists() {
        // A resumed sweep would not be timed: start over.
        std::fs::remove_dir_all(&dir).with_context(|| format!("clearing {}", dir.display()))?;
    }
    runner::run(&e, &dir)
}

/// The metric's peak of every finished case, by case id.
fn peaks(s: &Sweep, metric: usize) -> BTreeMap<usize, f64> {
    s.results
        .iter()
        .filter_map(|r| match &r.outcome {
            Outcome::Finished { peak, .. } => Some((r.id, peak[metric])),
            Outcome::Failed(_) => None,
        })
        .collect()
}

/// The report section; the quick report only says where it is.
pub fn section(report: &mut Report, depth: Depth) -> Result<()> {
    let e = Experiment::shipped(NAME)?;
    if depth == Depth::Quick {
        report.heading(&format!("Sweep `{NAME}` in full and modal order"));
        report.text(&format!(
            "Not run in the quick report: the full-order half of the {} cases takes minutes. \
             Run `harness model-order` or `harness report --full`; the last measured figures \
             are in docs/results.md.",
            e.cases.len()
        ));
        return Ok(());
    }
    report.heading(&format!(
        "Sweep `{NAME}` in full and modal order, small strain ({} cases, {} s of pressing each)",
        e.cases.len(),
        e.stop_time - e.start_time
    ));
    let metric = e
        .record
        .iter()
        .position(|r| *r == e.metric)
        .context("the metric is recorded")?;
    let full = fresh(report, &e, "full")?;
    let modal = fresh(report, &e, "modal")?;
    let (pf, pm) = (peaks(&full, metric), peaks(&modal, metric));
    let worst = pf
        .iter()
        .filter_map(|(id, x)| pm.get(id).map(|y| (x - y).abs() / x.abs()))
        .fold(0.0f64, f64::max);
    let jobs = e.threads();
    report.text(&format!(
        "Both runs from scratch on this machine ({jobs} cases at a time). The modal order \
         uses the default 80 load-dependent Ritz vectors; its basis is rebuilt for every case."
    ));
    let row = |order: &str, s: &Sweep, peaks: &BTreeMap<usize, f64>| {
        vec![
            order.to_string(),
            format!("{}/{}", peaks.len(), s.results.len()),
            format!("{:.1}", s.seconds),
        ]
    };
    report.table(
        &["model order", "cases finished", "wall time (s)"],
        &[row("full", &full, &pf), row("modal", &modal, &pm)],
    );
    report.text(&format!(
        "Modal is {:.1}× faster; the largest difference in the peak `{}` over the cases is \
         {:.3} % of the full-order peak.",
        full.seconds / modal.seconds,
        e.metric,
        100.0 * worst
    ));
    Ok(())
}
