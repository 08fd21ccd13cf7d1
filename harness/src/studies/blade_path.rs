//! The blade crossing the pulled block (issue 27, item 3): reaction, opening and bottom lift
//! against the blade position on the default cells and on twice as many, and the largest
//! change of the reaction per step against the mean change.

use std::path::{Path, PathBuf};

use anyhow::{ensure, Context, Result};
use models::scene::cutblock::CutBlock;
use models::scene::Scene;

use super::cut_speed_error::CELLS;

/// The study: the block pulled `pull` mm with the default law, the blade advanced from 0
/// to 100 mm in `step` mm steps, on the default cells times each of `refine`.
#[derive(Debug, Clone)]
pub struct Study {
    /// The pull of the face y = L (mm), held while the blade advances.
    pub pull: f64,
    /// The blade's advance per step (mm).
    pub step: f64,
    /// Factors on the default cells ([`CELLS`]), one crossing per factor.
    pub refine: Vec<f64>,
}

impl Study {
    /// The quick report's: 20 mm steps at the seed's 10 mm pull (its last step, 80 → 100 mm,
    /// holds the far-face ligament).
    pub fn quick() -> Self {
        Self {
            step: 20.0,
            ..Self::default()
        }
    }
}

impl Default for Study {
    /// 1 mm steps at the seed's 10 mm pull, 1× and 2× cells.
    fn default() -> Self {
        Self {
            pull: 10.0,
            step: 1.0,
            refine: vec![1.0, 2.0],
        }
    }
}

/// The outputs at one blade position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// The blade position `scalpel_x` (mm).
    pub blade: f64,
    /// The reaction force on the pulled face (N).
    pub reaction: f64,
    /// The cut opening: the largest gap between the flanks on the top surface (mm).
    pub opening: f64,
    /// The largest upward displacement of the bottom surface under the cut plane (mm).
    pub bottom_lift: f64,
}

/// One mesh's crossing: a point per blade position, the first uncut.
#[derive(Debug, Clone)]
pub struct Crossing {
    /// The factor on the default cells.
    pub refine: f64,
    /// The outputs at each blade position, from 0 mm.
    pub points: Vec<Point>,
    /// Wall time of the crossing, set-up included (s).
    pub seconds: f64,
}

impl Crossing {
    /// The largest change of the reaction between neighbouring positions, over the mean
    /// change |R(first) − R(last)| / steps, leaving out the last step (the ligament at the
    /// far face: `docs/theory/cutblock.md`).
    pub fn largest_over_mean(&self) -> f64 {
        let r: Vec<f64> = self.points.iter().map(|p| p.reaction).collect();
        let inner = &r[..r.len() - 1];
        let steps = inner.len() - 1;
        let mean = (inner[0] - inner[steps]).abs() / steps as f64;
        let largest = inner
            .windows(2)
            .map(|w| (w[1] - w[0]).abs())
            .fold(0.0, f64::max);
        largest / mean
    }
}

/// Runs the study; `progress(k, n)` after each of the n blade positions of all meshes.
pub fn run(study: &Study, progress: &dyn Fn(usize, usize)) -> Result<Vec<Crossing>> {
    let positions = (100.0 / study.step).round() as usize;
    ensure!(
        positions >= 3,
        "blade step {} mm: the blade path needs at least three steps across the 100 mm block",
        study.step
    );
    let total = (positions + 1) * study.refine.len();
    let mut done = 0;
    study
        .refine
        .iter()
        .map(|&refine| {
            let start = std::time::Instant::now();
            let mut s = CutBlock::new();
            for (name, cells) in ["cells_x", "cells_y", "cells_z"].into_iter().zip(CELLS) {
                s.set(name, cells * refine)?;
            }
            s.initialize(0.0)?;
            s.set("pull", study.pull)?;
            let mut points = Vec::with_capacity(positions + 1);
            for k in 0..=positions {
                let blade = k as f64 * study.step;
                s.set("scalpel_x", blade)?;
                s.do_step(k as f64, 1.0)
                    .with_context(|| format!("{refine}× cells, blade at {blade} mm"))?;
                points.push(Point {
                    blade,
                    reaction: s.get("reaction_force")?,
                    opening: s.get("cut_opening")?,
                    bottom_lift: s.get("bottom_lift")?,
                });
                done += 1;
                progress(done, total);
            }
            Ok(Crossing {
                refine,
                points,
                seconds: start.elapsed().as_secs_f64(),
            })
        })
        .collect()
}

/// Writes every mesh's points as CSV (one row per mesh and blade position), atomically.
pub fn write_csv(paths: &[Crossing], path: &Path) -> Result<PathBuf> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "cells",
        "blade_mm",
        "reaction_N",
        "cut_opening_mm",
        "bottom_lift_mm",
    ])?;
    for p in paths {
        for q in &p.points {
            w.write_record([
                p.refine.to_string(),
                q.blade.to_string(),
                format!("{:.6}", q.reaction),
                format!("{:.5}", q.opening),
                format!("{:.5}", q.bottom_lift),
            ])?;
        }
    }
    crate::atomic::write_atomic(path, &w.into_inner()?)?;
    Ok(path.to_path_buf())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn crossing(reactions: &[f64]) -> Crossing {
        Crossing {
            refine: 1.0,
            points: reactions
                .iter()
                .enumerate()
                .map(|(k, &reaction)| Point {
                    blade: k as f64,
                    reaction,
                    opening: 0.0,
                    bottom_lift: 0.0,
                })
                .collect(),
            seconds: 0.0,
        }
    }

    /// A steady fall is 1 × its mean step; one jump of 3 in a fall of 6 over 4 steps is
    /// 2 × the mean of 1.5; the last step (the far-face ligament) is left out.
    #[test]
    fn the_largest_step_is_measured_against_the_mean_without_the_last() {
        assert!((crossing(&[8.0, 7.0, 6.0, 5.0, 0.0]).largest_over_mean() - 1.0).abs() < 1e-12);
        let jump = crossing(&[8.0, 7.0, 4.0, 3.0, 2.0, -10.0]);
        assert!((jump.largest_over_mean() - 2.0).abs() < 1e-12);
    }
}
