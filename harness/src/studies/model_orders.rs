//! The shipped pelvis configurations in three model orders (issue 29): full-order finite
//! strain — the right physics at the scene's load, the reference — the hyper-reduced
//! finite-strain model (`model_order = "reduced"`) and the modal model of linear kinematics,
//! each over one press of the default pressing force from rest on the default model (the
//! braced wall). For each case: the set-up time (a reduced
//! model's training included), the stepping time, the peaks of the floor stress mean and
//! max, and the largest error indicator (read every [`INDICATOR_EVERY`] steps, outside the
//! timed steps).

use std::collections::BTreeMap;
use std::time::Instant;

use anyhow::{Context, Result};
use models::scene::abdomen::config::SHIPPED;
use models::scene::abdomen::Abdomen;
use rayon::prelude::*;

use crate::sweep::{simulate_observed, InProcess, Schedule, Session, Value};

/// The outputs whose peaks are compared.
pub const QUANTITIES: [&str; 2] = ["floor_stress_mean", "floor_stress_max"];

/// One press of the default pressing force (0.8 N/mm at 0.5 Hz) takes 2 s; the shipped
/// pelvis sweep's communication step.
const DURATION: f64 = 2.0;
const STEP: f64 = 0.01;

/// Steps between two reads of the error indicator.
pub const INDICATOR_EVERY: usize = 10;

/// A model order and the kinematics it runs at.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Order {
    /// The scene's `model_order`: `full`, `reduced` or `modal`.
    pub model_order: &'static str,
    /// The scene's `kinematics`: `finite` or `linear`.
    pub kinematics: &'static str,
}

/// The orders compared, the reference first.
pub const ORDERS: [Order; 3] = [
    Order {
        model_order: "full",
        kinematics: "finite",
    },
    Order {
        model_order: "reduced",
        kinematics: "finite",
    },
    Order {
        model_order: "modal",
        kinematics: "linear",
    },
];

/// One configuration run in one order.
#[derive(Debug, Clone)]
pub struct ConfigurationRun {
    /// The shipped configuration's name.
    pub configuration: &'static str,
    /// Build and initialization (s; a reduced model's training included).
    pub setup: f64,
    /// All steps (s; without the output and indicator reads).
    pub stepping: f64,
    /// Peaks of |[`QUANTITIES`]| over the press.
    pub peaks: [f64; 2],
    /// The largest error indicator read.
    pub indicator: f64,
    /// What the scene warned about during the run.
    pub warnings: Vec<String>,
}

/// One order over every shipped configuration, the cases run at a time by rayon's pool,
/// with the wall time of the whole.
#[derive(Debug, Clone)]
pub struct OrderRun {
    /// The model order and its kinematics.
    pub order: Order,
    /// One run per shipped configuration.
    pub cases: Vec<ConfigurationRun>,
    /// Wall time of all the cases together (s).
    pub seconds: f64,
}

/// Runs every order over the shipped configurations.
pub fn run() -> Result<Vec<OrderRun>> {
    ORDERS.iter().map(|&order| sweep(order)).collect()
}

/// One order over the shipped configurations.
pub fn sweep(order: Order) -> Result<OrderRun> {
    let clock = Instant::now();
    let cases = SHIPPED
        .par_iter()
        .map(|&(configuration, _)| case(order, configuration))
        .collect::<Result<Vec<_>>>()?;
    Ok(OrderRun {
        order,
        cases,
        seconds: clock.elapsed().as_secs_f64(),
    })
}

/// One configuration in `order`.
fn case(order: Order, configuration: &'static str) -> Result<ConfigurationRun> {
    let settings = vec![
        ("configuration".into(), Value::Text(configuration.into())),
        ("model_order".into(), Value::Text(order.model_order.into())),
        ("kinematics".into(), Value::Text(order.kinematics.into())),
    ];
    let record = QUANTITIES.map(str::to_string);
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: DURATION,
        step: STEP,
        settings: &settings,
        inputs: &BTreeMap::new(),
        record: &record,
    };
    let mut session = InProcess(Box::new(Abdomen::new()));
    let eta = session.reference("error_indicator")?;
    let (mut indicator, mut reads) = (0.0_f64, 0);
    let run = simulate_observed(&mut session, &schedule, |s, _| {
        if reads % INDICATOR_EVERY == 0 {
            let mut x = [0.0];
            s.get(eta, &mut x)?;
            indicator = indicator.max(x[0]);
        }
        reads += 1;
        Ok(())
    })
    .with_context(|| format!("{configuration} in {order:?}"))?;
    let mut peaks = [0.0; 2];
    for (peak, name) in peaks.iter_mut().zip(QUANTITIES) {
        let column = run.series.column(name).context("recorded")?;
        *peak = column.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    }
    Ok(ConfigurationRun {
        configuration,
        setup: run.setup.as_secs_f64(),
        stepping: run.stepping.as_secs_f64(),
        peaks,
        indicator,
        warnings: run.warnings,
    })
}

/// The largest relative error of quantity `j`'s peak in `s` against `reference`, case by
/// case (the same configurations in the same order).
pub fn worst_error(s: &OrderRun, reference: &OrderRun, j: usize) -> f64 {
    worst_relative(
        reference
            .cases
            .iter()
            .zip(&s.cases)
            .map(|(b, a)| (b.peaks[j], a.peaks[j])),
    )
}

/// The largest |y − x| / |x| over pairs (reference x, value y).
pub fn worst_relative(pairs: impl IntoIterator<Item = (f64, f64)>) -> f64 {
    pairs
        .into_iter()
        .map(|(x, y)| (y - x).abs() / x.abs())
        .fold(0.0, f64::max)
}

/// The configurations' order by quantity `j`'s peak, highest first.
pub fn ranking(s: &OrderRun, j: usize) -> Vec<&'static str> {
    let mut cases: Vec<&ConfigurationRun> = s.cases.iter().collect();
    cases.sort_by(|a, b| b.peaks[j].total_cmp(&a.peaks[j]));
    cases.iter().map(|c| c.configuration).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sweep_of(peaks: &[(&'static str, f64)]) -> OrderRun {
        OrderRun {
            order: ORDERS[0],
            cases: peaks
                .iter()
                .map(|&(configuration, p)| ConfigurationRun {
                    configuration,
                    setup: 0.0,
                    stepping: 0.0,
                    peaks: [p, 2.0 * p],
                    indicator: 0.0,
                    warnings: Vec::new(),
                })
                .collect(),
            seconds: 0.0,
        }
    }

    #[test]
    fn errors_are_relative_to_the_reference_case_by_case_and_rankings_sort_down() {
        let reference = sweep_of(&[("a", 1.0), ("b", 4.0), ("c", 2.0)]);
        let other = sweep_of(&[("a", 1.1), ("b", 3.0), ("c", 2.0)]);
        assert!((worst_error(&other, &reference, 0) - 0.25).abs() < 1e-15);
        assert!((worst_error(&other, &reference, 1) - 0.25).abs() < 1e-15);
        assert_eq!(ranking(&reference, 0), ["b", "c", "a"]);
        assert_eq!(ranking(&other, 0), ["b", "c", "a"]);
        let swapped = sweep_of(&[("a", 2.5), ("b", 4.0), ("c", 2.0)]);
        assert_eq!(ranking(&swapped, 0), ["b", "a", "c"]);
    }
}
