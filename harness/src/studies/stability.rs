//! The abdomen's integrators on hard cases (issue 12): each run for 0.1 s on a small mesh
//! with what the scene says of it — bounded, or the error it reported (an explicit scheme
//! above its stability limit, a step without equilibrium) — for the speed–error report's
//! stability table.

use std::collections::BTreeMap;

use models::scene::abdomen::Abdomen;

use rayon::prelude::*;

use super::speed_error::Setting;
use crate::sweep::{simulate_observed, InProcess, Schedule, Value};

/// What an integrator did on a hard case.
#[derive(Debug, Clone, PartialEq)]
pub struct Stability {
    /// The hard case's label.
    pub case: &'static str,
    /// The integrator's name.
    pub integrator: &'static str,
    /// `bounded (peak |u| … mm)`, or `refused:` and the scene's error.
    pub outcome: String,
}

/// A hard case: label, parameter settings, step.
type HardCase = (&'static str, Vec<(&'static str, Value)>, f64);

/// Runs each integrator on the hard cases for 0.1 s on a small mesh and says what happened:
/// "bounded (peak |u| …)", or the error the scene reported.
pub fn stability() -> Vec<Stability> {
    let mixed = [
        ("formulation", Value::Text("mixed".into())),
        ("cavity_nu", Value::Real(0.4999)),
    ];
    let finite = [("kinematics", Value::Text("finite".into()))];
    // The line elements that act (the default wall is held: its modulus cannot act).
    let stiff = [
        ("diaphragm_E", Value::Real(5e3)),
        ("floor_E", Value::Real(5e3)),
    ];
    let cases: [HardCase; 6] = [
        ("ν = 0.4999 (mixed)", mixed.to_vec(), 1e-3),
        (
            "ν = 0.4999, finite strain",
            [finite.to_vec(), vec![("cavity_nu", Value::Real(0.4999))]].concat(),
            1e-3,
        ),
        ("line elements 1e6 × stiffer", stiff.to_vec(), 1e-3),
        (
            "1e6 × stiffer, finite strain",
            [finite.to_vec(), stiff.to_vec()].concat(),
            1e-3,
        ),
        ("huge dt (0.1 s), finite strain", finite.to_vec(), 0.1),
        ("dt = 1 ms (above explicit limits)", vec![], 1e-3),
    ];
    let runs: Vec<_> = cases
        .iter()
        .flat_map(|case| {
            ["houbolt", "newmark", "central_difference", "rk4"].map(|integrator| (case, integrator))
        })
        .collect();
    // Nothing here is timed: the cases run side by side.
    runs.into_par_iter()
        .map(|((case, extra, dt), integrator)| {
            let mut settings = Setting {
                kinematics: "linear",
                element: "tri6",
                formulation: "displacement",
                grading: 0.0,
                triangles: 300,
                subdivisions: 0,
                order: "full",
                integrator,
                dt: *dt,
            }
            .values();
            settings.extend(extra.iter().map(|(k, v)| (k.to_string(), v.clone())));
            Stability {
                case,
                integrator,
                outcome: hard_run(&settings, *dt),
            }
        })
        .collect()
}

/// 0.1 s of `settings` at step `dt`: "bounded (peak |u| …)" or the scene's error.
fn hard_run(settings: &[(String, Value)], dt: f64) -> String {
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: ((0.1 / dt).round()).max(1.0) * dt,
        step: dt,
        settings,
        inputs: &BTreeMap::new(),
        record: &[],
    };
    let mut peak: f64 = 0.0;
    let observe = |s: &mut InProcess<Abdomen>, _| {
        let u =
            s.0.field()
                .map_or(0.0, |f| f.u.iter().fold(0.0f64, |a, b| a.max(b.abs())));
        peak = peak.max(u);
        Ok(())
    };
    match simulate_observed(&mut InProcess(Box::new(Abdomen::new())), &schedule, observe) {
        Ok(_) => format!("bounded (peak |u| {peak:.3e} mm)"),
        Err(e) => format!(
            "refused: {}",
            e.root_cause()
                .to_string()
                .split(';')
                .next()
                .unwrap_or_default()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn explicit_schemes_above_their_limit_are_refused_and_implicit_ones_stay_bounded() {
        let table = stability();
        let outcome = |case: &str, integ: &str| {
            table
                .iter()
                .find(|s| s.case == case && s.integrator == integ)
                .unwrap()
                .outcome
                .clone()
        };
        for integ in ["central_difference", "rk4"] {
            let o = outcome("dt = 1 ms (above explicit limits)", integ);
            assert!(
                o.starts_with("refused") && o.contains("unstable"),
                "{integ}: {o}"
            );
        }
        for integ in ["houbolt", "newmark"] {
            for case in [
                "ν = 0.4999 (mixed)",
                "ν = 0.4999, finite strain",
                "line elements 1e6 × stiffer",
                "1e6 × stiffer, finite strain",
                "huge dt (0.1 s), finite strain",
            ] {
                assert!(
                    outcome(case, integ).starts_with("bounded"),
                    "{integ} {case}: {}",
                    outcome(case, integ)
                );
            }
        }
    }
}
