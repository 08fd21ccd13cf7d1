//! Comparison of scanner profiles with the model (seed 002 §3.5): a profile is a list of
//! (y, z) points along one scan line; the model gives heights at stations every
//! `PROFILE_STEP` mm from y = 0 (NaN where there is no surface, e.g. in the open cut), read
//! between stations by linear interpolation.
//!
//! Two frames: the lab frame, where scanner data and model share the clamped edge y = 0 (no
//! offset), and an aligned frame for scans whose registration is uncertain. The seed aligns by
//! the block's edges found from steep gradients; scans of the top surface alone (like the
//! shipped set) have no edges, so the alignment here is a documented fit instead: the rigid
//! shift (Δy, Δz) of the scan that minimizes the RMS deviation — Δz in closed form (the mean
//! residual) for each Δy, Δy by Brent's method (argmin) within ±`MAX_SHIFT` mm.

use anyhow::{anyhow, Result};
use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::brent::BrentOpt;
use models::scene::cutblock::PROFILE_STEP;

/// Largest |Δy| the alignment considers (mm).
pub const MAX_SHIFT: f64 = 3.0;

/// Deviation of one profile line from the data: RMS, largest |Δz|, points compared.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Deviation {
    /// RMS of the residuals data − model (mm).
    pub rms: f64,
    /// Largest |data − model| (mm).
    pub max: f64,
    /// Points compared: those where the model has a surface.
    pub points: usize,
}

/// The model height at `y` by linear interpolation between stations; None outside the
/// stations or next to a station without surface.
fn height(model: &[f64], y: f64) -> Option<f64> {
    let s = y / PROFILE_STEP;
    if s < 0.0 {
        return None;
    }
    let i = s.floor() as usize;
    let w = s - i as f64;
    let a = *model.get(i)?;
    if w < 1e-9 {
        return a.is_finite().then_some(a);
    }
    let b = *model.get(i + 1)?;
    (a.is_finite() && b.is_finite()).then_some(a + w * (b - a))
}

/// The model's height at each data point's y (None where it has no surface there).
pub fn heights(model: &[f64], data: &[(f64, f64)]) -> Vec<Option<f64>> {
    data.iter().map(|&(y, _)| height(model, y)).collect()
}

/// Residuals data − model for the data shifted by (dy, dz), where the model has a surface.
fn residuals(model: &[f64], data: &[(f64, f64)], dy: f64, dz: f64) -> Vec<f64> {
    data.iter()
        .filter_map(|&(y, z)| height(model, y + dy).map(|m| z + dz - m))
        .collect()
}

fn summarize(r: &[f64]) -> Deviation {
    Deviation {
        rms: (r.iter().map(|x| x * x).sum::<f64>() / r.len().max(1) as f64).sqrt(),
        max: r.iter().fold(0.0, |a, x| a.max(x.abs())),
        points: r.len(),
    }
}

/// Deviation in the lab frame (no shift).
pub fn deviation(model: &[f64], data: &[(f64, f64)]) -> Deviation {
    summarize(&residuals(model, data, 0.0, 0.0))
}

/// A fitted rigid shift of the scan and the deviation after it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Alignment {
    /// Shift of the scan in y (mm).
    pub dy: f64,
    /// Shift of the scan in z (mm): minus the mean residual at `dy`.
    pub dz: f64,
    /// The deviation of the shifted scan.
    pub deviation: Deviation,
}

/// The best Δz for a Δy: minus the mean residual.
fn best_dz(model: &[f64], data: &[(f64, f64)], dy: f64) -> f64 {
    let r = residuals(model, data, dy, 0.0);
    -r.iter().sum::<f64>() / r.len().max(1) as f64
}

struct ShiftCost<'a>(&'a [f64], &'a [(f64, f64)]);

impl CostFunction for ShiftCost<'_> {
    type Param = f64;
    type Output = f64;

    fn cost(&self, dy: &f64) -> Result<f64, ArgminError> {
        let dz = best_dz(self.0, self.1, *dy);
        Ok(summarize(&residuals(self.0, self.1, *dy, dz)).rms)
    }
}

/// Fits the shift (Δy, Δz) that brings the scan closest to the model.
pub fn align(model: &[f64], data: &[(f64, f64)]) -> Result<Alignment> {
    let dy = Executor::new(ShiftCost(model, data), BrentOpt::new(-MAX_SHIFT, MAX_SHIFT))
        .configure(|s| s.max_iters(60))
        .run()
        .map_err(|e| anyhow!("profile alignment: {e}"))?
        .state()
        .best_param
        .ok_or_else(|| anyhow!("profile alignment returned no shift"))?;
    let dz = best_dz(model, data, dy);
    Ok(Alignment {
        dy,
        dz,
        deviation: summarize(&residuals(model, data, dy, dz)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth model profile with a gap (the cut).
    fn model() -> Vec<f64> {
        (0..181)
            .map(|i| {
                let y = i as f64 * PROFILE_STEP;
                if (45.5..46.5).contains(&y) {
                    f64::NAN
                } else {
                    17.0 + 2.0 * (-(y - 45.0).powi(2) / 200.0).exp()
                }
            })
            .collect()
    }

    #[test]
    fn on_station_data_compare_exactly_and_gaps_are_skipped() {
        let m = model();
        let data: Vec<(f64, f64)> = (0..181)
            .map(|i| (i as f64 * PROFILE_STEP, m[i] + 0.1))
            .filter(|p| p.1.is_finite())
            .collect();
        let d = deviation(&m, &data);
        assert!((d.rms - 0.1).abs() < 1e-12 && (d.max - 0.1).abs() < 1e-12);
        // Stations 91 and 92 have no surface (and no data): the other 179 points compare.
        assert_eq!(d.points, 179);
    }

    #[test]
    fn alignment_recovers_a_known_shift() {
        let m = model();
        let (dy, dz) = (0.8, -0.35);
        // The scan is the model seen in a frame shifted by (−dy, −dz), off the stations.
        let data: Vec<(f64, f64)> = (10..160)
            .map(|k| {
                let y = k as f64 * 0.5 + 0.13;
                (y - dy, height(&m, y).unwrap_or(f64::NAN) - dz)
            })
            .filter(|p| p.1.is_finite())
            .collect();
        let a = align(&m, &data).unwrap();
        assert!((a.dy - dy).abs() < 1e-3, "Δy = {}", a.dy);
        assert!((a.dz - dz).abs() < 1e-3, "Δz = {}", a.dz);
        assert!(a.deviation.rms < 1e-3, "{:?}", a.deviation);
        assert!(deviation(&m, &data).rms > 0.3, "unaligned, the shift shows");
    }
}
