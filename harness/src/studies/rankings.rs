//! Pelvis rankings with their confidence (issue 53): the uncertain inputs of the abdomen
//! sampled ([`UNCERTAIN`], [`WALLS`], [`LOADS`]), every sample run on each shipped
//! configuration, and for every pair of configurations the fraction of samples in which the
//! first loads the pelvic floor more than the second.
//!
//! Each run is a static start in equilibrium at the sample's intra-abdominal pressure in the
//! clinical settings with the neo-Hookean sheets ([`physiology::CLINICAL_STRINGS`]), full
//! order at finite strain on the 300-triangle mesh: the pressure search continues each trial
//! from the nearest equilibrium below. A sample uses the same inputs on every configuration
//! (common random numbers), so that a pair's difference is the configurations' own.

use std::collections::BTreeMap;

use anyhow::Result;
use rayon::prelude::*;

use super::physiology;
use crate::sweep::design::{self, Block, Design, Range};
use crate::sweep::simulate::Value;

pub use super::physiology::CONFIGURATIONS;

/// The floor-load quantities compared.
pub const QUANTITIES: [&str; 2] = ["floor_stress_mean", "floor_stress_max"];

/// An uncertain input: its variable, range (sampled log-uniformly where `log`) and source.
#[derive(Debug, Clone, Copy)]
pub struct Uncertain {
    /// The abdomen's variable.
    pub name: &'static str,
    /// The least value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// Sampled uniformly in log(x).
    pub log: bool,
    /// Where the range comes from.
    pub source: &'static str,
}

/// The continuous uncertain inputs, sampled by a Latin hypercube.
pub const UNCERTAIN: [Uncertain; 7] = [
    Uncertain {
        name: "cavity_E",
        min: 0.0042,
        max: 0.0069,
        log: false,
        source: "3μ, μ from 1.4 kPa (bowel) to 2.3 kPa (liver, 2.1 ± 0.2) by MR elastography (docs/theory/abdomen.md)",
    },
    Uncertain {
        name: "cavity_nu",
        min: 0.49,
        max: 0.4999,
        log: false,
        source: "soft tissue is mostly water: nearly incompressible (Fung 1993); the mixed element holds 0.4999",
    },
    Uncertain {
        name: "diaphragm_E",
        min: 0.1,
        max: 0.4,
        log: true,
        source: "assumed: the default 0.2 MPa halved and doubled (its passive stiffness matters little once it contracts)",
    },
    Uncertain {
        name: "diaphragm_area",
        min: 2.6,
        max: 6.5,
        log: false,
        source: "the contracted diaphragm's thickness by ultrasound, 2.6–6.5 mm (Boussuges et al. 2020)",
    },
    Uncertain {
        name: "wall_E",
        min: 0.01,
        max: 0.2,
        log: true,
        source: "the shipped pelvis sweep's range about the relaxed in-vivo 22.5 kPa (Song et al. 2006); acts with the wall free",
    },
    Uncertain {
        name: "floor_E",
        min: 0.048,
        max: 0.114,
        log: true,
        source: "3μ, the levator's μ by shear-wave elastography from 16 kPa at rest to 38 kPa in a Valsalva manoeuvre (Gachon et al. 2019)",
    },
    Uncertain {
        name: "floor_area",
        min: 6.0,
        max: 10.0,
        log: false,
        source: "assumed: the default 8 mm²/mm ± 25 %",
    },
];

/// The wall's settings, alternated between samples: braced (the default) or free. A free
/// wall contracts with the diaphragm (`press_muscles = "diaphragm_and_wall"`, as the
/// abdominal muscles do in a Valsalva manoeuvre; a passive free wall bulges and the
/// diaphragm alone does not reach 7.9 kPa) and is curved round the waist at
/// [`WAIST_CURVATURE`].
pub const WALLS: [&str; 2] = ["fixed", "free"];

/// The free wall's curvature across the slice (1/mm): 1/150 mm, about the radius of the
/// mean waist of NHANES 1999–2000 (147–157 mm; docs/theory/abdomen.md).
pub const WAIST_CURVATURE: f64 = 1.0 / 150.0;

/// The loads, the clinical presets' peaks (kPa), cycled between samples: standing at rest
/// (Cobb et al. 2005), a Valsalva manoeuvre and bearing down (medians; Neurourol Urodyn 40
/// (2021) 783–790). A cough (14.3 kPa) is left out: the model does not follow it on the
/// normal and wide pelvises (docs/theory/abdomen.md).
pub const LOADS: [(&str, f64); 3] = [("rest", 2.67), ("Valsalva", 7.88), ("bear-down", 9.91)];

/// One sample: its inputs, and per configuration the quantities or why the run failed.
#[derive(Debug, Clone)]
pub struct Sample {
    /// The continuous inputs by name.
    pub inputs: BTreeMap<String, f64>,
    /// The wall's setting.
    pub wall: &'static str,
    /// The load's name and pressure (kPa).
    pub load: (&'static str, f64),
    /// Per configuration ([`CONFIGURATIONS`] order): the [`QUANTITIES`] (MPa) or the error.
    pub runs: Vec<Result<[f64; 2], String>>,
}

/// The sample plan: `n` Latin-hypercube points over [`UNCERTAIN`] (seeded), each with a wall
/// and a load taken in turn.
pub fn plan(n: usize, seed: u64) -> Result<Vec<Sample>> {
    let block = Block {
        design: Design::LatinHypercube,
        values: BTreeMap::new(),
        ranges: UNCERTAIN
            .iter()
            .map(|u| {
                let range = Range {
                    min: u.min,
                    max: u.max,
                    log: u.log,
                    levels: None,
                };
                (u.name.to_string(), range)
            })
            .collect(),
        samples: Some(n),
        seed: Some(seed),
    };
    Ok(design::expand(&[block])?
        .into_iter()
        .enumerate()
        .map(|(i, point)| Sample {
            inputs: point
                .values
                .into_iter()
                .filter_map(|(k, v)| match v {
                    Value::Real(x) => Some((k, x)),
                    Value::Text(_) => None,
                })
                .collect(),
            wall: WALLS[i % WALLS.len()],
            load: LOADS[(i / WALLS.len()) % LOADS.len()],
            runs: Vec::new(),
        })
        .collect())
}

/// Runs every sample on every configuration (in parallel), calling `done` after each run.
pub fn run(samples: &mut [Sample], done: impl Fn() + Sync) {
    let jobs: Vec<(usize, usize)> = (0..samples.len())
        .flat_map(|s| (0..CONFIGURATIONS.len()).map(move |c| (s, c)))
        .collect();
    let results: Vec<Result<[f64; 2], String>> = jobs
        .par_iter()
        .map(|&(s, c)| {
            let result = one(&samples[s], CONFIGURATIONS[c]).map_err(|e| format!("{e:#}"));
            done();
            result
        })
        .collect();
    for ((s, _), result) in jobs.into_iter().zip(results) {
        samples[s].runs.push(result);
    }
}

/// The floor's quantities of `sample` on `configuration`: the clinical settings with the
/// sample's values (its `cavity_nu` in place of theirs).
fn one(sample: &Sample, configuration: &str) -> Result<[f64; 2]> {
    let mut strings = vec![("abdominal_wall", sample.wall)];
    let mut reals: Vec<(&str, f64)> = sample
        .inputs
        .iter()
        .map(|(k, v)| (k.as_str(), *v))
        .collect();
    if sample.wall == "free" {
        strings.push(("press_muscles", "diaphragm_and_wall"));
        reals.push(("wall_transverse_curvature", WAIST_CURVATURE));
    }
    let mut s = physiology::clinical_abdomen(configuration, &strings, &reals, sample.load.1)?;
    Ok([s.get(QUANTITIES[0])?, s.get(QUANTITIES[1])?])
}

/// For each pair (a, b) of configurations (a before b in [`CONFIGURATIONS`]) and each
/// quantity: the fraction of the samples run on both in which a's quantity exceeds b's
/// (none where no sample ran on both), and that count of samples.
pub fn probabilities(samples: &[Sample]) -> Vec<(usize, usize, usize, Option<f64>, usize)> {
    let mut rows = Vec::new();
    for a in 0..CONFIGURATIONS.len() {
        for b in a + 1..CONFIGURATIONS.len() {
            for q in 0..QUANTITIES.len() {
                let both: Vec<bool> = samples
                    .iter()
                    .filter_map(|s| match (&s.runs[a], &s.runs[b]) {
                        (Ok(x), Ok(y)) => Some(x[q] > y[q]),
                        _ => None,
                    })
                    .collect();
                let n = both.len();
                let more = both.iter().filter(|&&more| more).count();
                let p = (n > 0).then(|| more as f64 / n as f64);
                rows.push((a, b, q, p, n));
            }
        }
    }
    rows
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(values: &[[f64; 2]]) -> Sample {
        Sample {
            inputs: BTreeMap::new(),
            wall: "fixed",
            load: LOADS[0],
            runs: values.iter().map(|v| Ok(*v)).collect(),
        }
    }

    /// The probabilities count the samples in which a exceeds b, over the samples run on
    /// both: a failed run drops its sample from its pairs only.
    #[test]
    fn a_pair_s_probability_is_the_share_of_samples_in_which_a_exceeds_b() {
        let mut samples = vec![
            sample(&[[3.0, 1.0], [2.0, 2.0], [1.0, 3.0], [0.0, 0.0], [0.0, 0.0]]),
            sample(&[[3.0, 1.0], [4.0, 0.5], [1.0, 3.0], [0.0, 0.0], [0.0, 0.0]]),
            sample(&[[3.0, 1.0], [2.0, 2.0], [1.0, 3.0], [0.0, 0.0], [0.0, 0.0]]),
        ];
        samples[2].runs[2] = Err("no equilibrium".into());
        let rows = probabilities(&samples);
        let find = |a, b, q| rows.iter().find(|r| (r.0, r.1, r.2) == (a, b, q)).unwrap();
        // normal vs narrow: mean 3 > 2, 3 < 4, 3 > 2: 2 of 3; max 1 < 2, 1 > 0.5, 1 < 2.
        assert_eq!((find(0, 1, 0).3, find(0, 1, 0).4), (Some(2.0 / 3.0), 3));
        assert_eq!((find(0, 1, 1).3, find(0, 1, 1).4), (Some(1.0 / 3.0), 3));
        // normal vs wide: the third sample failed on wide.
        assert_eq!((find(0, 2, 0).3, find(0, 2, 0).4), (Some(1.0), 2));
        assert_eq!(find(0, 2, 1).3, Some(0.0));
        // Ties are not "more": lordotic vs tilted.
        assert_eq!(find(3, 4, 0).3, Some(0.0));
        assert_eq!(rows.len(), 10 * 2);
        // Where no sample ran on both, there is no probability.
        for s in &mut samples {
            s.runs[4] = Err("no equilibrium".into());
        }
        assert_eq!(probabilities(&samples)[19], (3, 4, 1, None, 0));
    }

    /// The plan is repeatable, covers each range's strata once, and cycles walls and loads
    /// so that every combination appears equally often in 12 samples.
    #[test]
    fn the_plan_is_repeatable_and_balanced() {
        let a = plan(12, 7).unwrap();
        let b = plan(12, 7).unwrap();
        assert_eq!(a.len(), 12);
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.inputs, y.inputs);
        }
        for u in UNCERTAIN {
            let inside = a
                .iter()
                .all(|s| (u.min..=u.max).contains(&s.inputs[u.name]));
            assert!(inside, "{}", u.name);
        }
        for wall in WALLS {
            for load in LOADS {
                let n = a
                    .iter()
                    .filter(|s| s.wall == wall && s.load == load)
                    .count();
                assert_eq!(n, 2, "{wall} {}", load.0);
            }
        }
    }
}
