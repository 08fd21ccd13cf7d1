//! Designs of experiments: how a `[[sweep]]` block turns into cases.
//!
//! - `list`: the value lists are zipped — case i takes the i-th value of every list.
//! - `grid`: the Cartesian product of the value lists and of the ranges, each range
//!   sampled at `levels` evenly spaced points (in log space with `log = true`).
//! - `latin-hypercube`: `samples` points over the ranges; each range is cut into `samples`
//!   equal strata and every stratum is used exactly once per parameter (McKay, Beckman and
//!   Conover, Technometrics 21, 1979), with a random point inside it; `seed` makes the plan
//!   repeatable.

use std::collections::BTreeMap;

use anyhow::{bail, ensure, Result};
use rand::rngs::StdRng;
use rand::seq::SliceRandom;
use rand::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};

use super::simulate::Value;

/// One case of the plan: the values it varies (applied over the base parameters).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DesignPoint {
    /// The case's number, counted from 0 over all blocks.
    pub id: usize,
    /// The `[[sweep]]` block it comes from and that block's design.
    pub block: usize,
    /// The design of that block.
    pub design: Design,
    /// The values the case sets, by parameter name.
    pub values: BTreeMap<String, Value>,
}

/// The kind of a block.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Design {
    /// The value lists zipped: case i takes the i-th value of every list.
    List,
    /// The Cartesian product of the value lists and of the ranges at `levels` points each.
    Grid,
    /// `samples` points over the ranges, each range's `samples` strata used once per
    /// parameter; `seed` makes the plan repeatable.
    LatinHypercube,
}

/// A continuous parameter range.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Range {
    /// The smallest value, in the parameter's unit.
    pub min: f64,
    /// The largest value, in the parameter's unit.
    pub max: f64,
    /// Sample uniformly in log(x).
    #[serde(default)]
    pub log: bool,
    /// Grid points (grid design only).
    pub levels: Option<usize>,
}

impl Range {
    fn check(&self, key: &str) -> Result<()> {
        ensure!(
            self.min.is_finite() && self.max.is_finite() && self.min <= self.max,
            "`{key}`: need finite min ≤ max, got min = {}, max = {}",
            self.min,
            self.max
        );
        ensure!(
            !self.log || self.min > 0.0,
            "`{key}`: log = true needs min > 0, got {}",
            self.min
        );
        Ok(())
    }

    /// The point at fraction `f` ∈ [0, 1] of the range.
    fn at(&self, f: f64) -> f64 {
        if self.log {
            (self.min.ln() + f * (self.max.ln() - self.min.ln())).exp()
        } else {
            self.min + f * (self.max - self.min)
        }
    }
}

/// One `[[sweep]]` block.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Block {
    /// How the block turns into cases.
    pub design: Design,
    /// Value lists by parameter name (list and grid designs).
    #[serde(default)]
    pub values: BTreeMap<String, Vec<Value>>,
    /// Continuous ranges by parameter name (grid and Latin hypercube designs).
    #[serde(default)]
    pub ranges: BTreeMap<String, Range>,
    /// Points of a Latin hypercube (that design only).
    pub samples: Option<usize>,
    /// Seed of the Latin hypercube's random draws (that design only; 0 if not given).
    pub seed: Option<u64>,
}

/// All cases of all blocks, numbered from 0 in order. No blocks: one case with the base
/// parameters.
pub fn expand(blocks: &[Block]) -> Result<Vec<DesignPoint>> {
    if blocks.is_empty() {
        return Ok(vec![DesignPoint {
            id: 0,
            block: 0,
            design: Design::List,
            values: BTreeMap::new(),
        }]);
    }
    let mut cases = Vec::new();
    for (b, block) in blocks.iter().enumerate() {
        let key = format!("sweep[{b}]");
        for (name, range) in &block.ranges {
            range.check(&format!("{key}.ranges.{name}"))?;
            ensure!(
                !block.values.contains_key(name),
                "`{key}`: `{name}` is in both `values` and `ranges`"
            );
        }
        let points = match block.design {
            Design::List => list(block, &key)?,
            Design::Grid => grid(block, &key)?,
            Design::LatinHypercube => latin_hypercube(block, &key)?,
        };
        for values in points {
            cases.push(DesignPoint {
                id: cases.len(),
                block: b,
                design: block.design,
                values,
            });
        }
    }
    Ok(cases)
}

type Point = BTreeMap<String, Value>;

fn list(block: &Block, key: &str) -> Result<Vec<Point>> {
    ensure!(
        block.ranges.is_empty() && block.samples.is_none() && block.seed.is_none(),
        "`{key}`: a list takes `values` only"
    );
    let n = block.values.values().map(Vec::len).max().unwrap_or(0);
    ensure!(n > 0, "`{key}`: `values` is empty");
    for (name, v) in &block.values {
        ensure!(
            v.len() == n,
            "`{key}.values.{name}` has {} values, the longest list {n}: lists are zipped",
            v.len()
        );
    }
    Ok((0..n)
        .map(|i| {
            block
                .values
                .iter()
                .map(|(k, v)| (k.clone(), v[i].clone()))
                .collect()
        })
        .collect())
}

fn grid(block: &Block, key: &str) -> Result<Vec<Point>> {
    ensure!(
        block.samples.is_none() && block.seed.is_none(),
        "`{key}`: a grid takes no `samples` or `seed`"
    );
    let mut axes: Vec<(String, Vec<Value>)> = block
        .values
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    for (name, r) in &block.ranges {
        let Some(levels) = r.levels.filter(|&l| l > 0) else {
            bail!("`{key}.ranges.{name}`: a grid needs `levels` ≥ 1");
        };
        let f = |i: usize| {
            if levels == 1 {
                0.5
            } else {
                i as f64 / (levels - 1) as f64
            }
        };
        axes.push((
            name.clone(),
            (0..levels).map(|i| Value::Real(r.at(f(i)))).collect(),
        ));
    }
    ensure!(!axes.is_empty(), "`{key}`: the grid has no axes");
    let mut points = vec![Point::new()];
    for (name, values) in axes {
        ensure!(!values.is_empty(), "`{key}.values.{name}` is empty");
        points = points
            .into_iter()
            .flat_map(|p| {
                let name = &name;
                values.iter().map(move |v| {
                    let mut q = p.clone();
                    q.insert(name.clone(), v.clone());
                    q
                })
            })
            .collect();
    }
    Ok(points)
}

fn latin_hypercube(block: &Block, key: &str) -> Result<Vec<Point>> {
    ensure!(
        block.values.is_empty(),
        "`{key}`: a Latin hypercube samples `ranges` only"
    );
    ensure!(!block.ranges.is_empty(), "`{key}`: `ranges` is empty");
    let Some(n) = block.samples.filter(|&n| n > 0) else {
        bail!("`{key}`: a Latin hypercube needs `samples` ≥ 1");
    };
    if let Some((name, _)) = block.ranges.iter().find(|(_, r)| r.levels.is_some()) {
        bail!("`{key}.ranges.{name}`: `levels` is for grids");
    }
    let mut rng = StdRng::seed_from_u64(block.seed.unwrap_or(0));
    let mut points = vec![Point::new(); n];
    for (name, r) in &block.ranges {
        let mut strata: Vec<usize> = (0..n).collect();
        strata.shuffle(&mut rng);
        for (p, s) in points.iter_mut().zip(strata) {
            let f = (s as f64 + rng.random::<f64>()) / n as f64;
            p.insert(name.clone(), Value::Real(r.at(f)));
        }
    }
    Ok(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn block(text: &str) -> Block {
        toml::from_str(text).unwrap()
    }

    fn reals(cases: &[DesignPoint], name: &str) -> Vec<f64> {
        cases
            .iter()
            .map(|c| match c.values[name] {
                Value::Real(x) => x,
                Value::Text(_) => panic!("{name} is a number"),
            })
            .collect()
    }

    #[test]
    fn grid_is_the_cartesian_product_with_log_levels() {
        let b = block(
            r#"design = "grid"
values = { integrator = ["houbolt", "newmark"] }
ranges = { E = { min = 0.01, max = 1.0, log = true, levels = 3 } }"#,
        );
        let cases = expand(&[b]).unwrap();
        assert_eq!(cases.len(), 6);
        let e = reals(&cases, "E");
        for (got, want) in e.iter().zip([0.01, 0.1, 1.0, 0.01, 0.1, 1.0]) {
            assert!((got - want).abs() < 1e-12 * want, "{got} vs {want}");
        }
    }

    #[test]
    fn latin_hypercube_uses_every_stratum_once_per_parameter() {
        let b = block(
            r#"design = "latin-hypercube"
samples = 20
seed = 3
ranges = { a = { min = 0.0, max = 1.0 }, b = { min = 10.0, max = 30.0 } }"#,
        );
        let cases = expand(std::slice::from_ref(&b)).unwrap();
        assert_eq!(cases.len(), 20);
        for (name, lo, width) in [("a", 0.0, 1.0), ("b", 10.0, 20.0)] {
            let mut strata: Vec<usize> = reals(&cases, name)
                .iter()
                .map(|x| ((x - lo) / width * 20.0).floor() as usize)
                .collect();
            strata.sort();
            assert_eq!(strata, (0..20).collect::<Vec<_>>(), "{name}");
        }
        assert_eq!(expand(&[b]).unwrap(), cases, "the seed makes it repeatable");
    }

    #[test]
    fn lists_zip_and_blocks_concatenate() {
        let a = block(
            r#"design = "list"
values = { x = [1.0, 2.0], y = ["p", "q"] }"#,
        );
        let cases = expand(&[a.clone(), a]).unwrap();
        assert_eq!(cases.len(), 4);
        assert_eq!(cases[3].id, 3);
        assert_eq!(cases[3].values["y"], Value::Text("q".into()));
        let bad = block(
            r#"design = "list"
values = { x = [1.0, 2.0], y = ["p"] }"#,
        );
        let e = expand(&[bad]).unwrap_err().to_string();
        assert!(e.contains("sweep[0].values.y"), "{e}");
    }
}
