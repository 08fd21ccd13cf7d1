//! Material identification for the cut block (seed 002 ch. 4) and comparison with laser
//! profiles (seed 002 §3.5).
//!
//! With the pull prescribed, the linear model's displacements do not depend on E, and its
//! reaction force is F = E · d · c(ν). So the force–displacement curve alone fixes only the
//! product E · c(ν) — E and ν trade off exactly, as seed 002 ch. 4 found — while the profiles
//! fix ν alone. The fit therefore takes ν from the profiles (Brent's method from argmin on the
//! RMS profile deviation) and then E from the forces by linear least squares, with its
//! standard error; a scan over ν shows how the force-only estimate of E moves with ν. This
//! two-stage fit is the joint least-squares fit of forces and profiles: for every ν the force
//! residual at its best E is the same, so the joint minimum over (E, ν) lies at the ν that
//! minimizes the profile misfit. With `fixed_nu` (or without profiles) only E is fitted.
//!
//! Profiles are compared in lab coordinates (`crate::profiles`), the frame both the scanner
//! data and the model's stations use (clamped edge at y = 0); points where the model has no
//! surface (the open cut) are skipped.

use std::path::Path;

use std::collections::BTreeMap;

use anyhow::{bail, Context, Result};
use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::brent::BrentOpt;
use models::scene::cutblock::{CutBlock, PROFILE_LINES};

use super::profiles::{deviation, Deviation};
use crate::sweep::{simulate, InProcess, InputTable, Schedule, Value};

/// A measurement set: force–displacement points and the top profiles at the largest pull.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurements {
    pub displacement: Vec<f64>,
    pub force: Vec<f64>,
    /// (y, z) points along x = 25, 50, 75 mm.
    pub profiles: [Vec<(f64, f64)>; 3],
    /// The pull at which the profiles were taken (mm).
    pub profile_pull: f64,
}

fn read_pairs(path: &Path) -> Result<Vec<(f64, f64)>> {
    let mut reader =
        csv::Reader::from_path(path).with_context(|| format!("opening {}", path.display()))?;
    let mut out = Vec::new();
    for (i, row) in reader.deserialize::<(f64, f64)>().enumerate() {
        out.push(row.with_context(|| format!("{}: data row {}", path.display(), i + 1))?);
    }
    if out.is_empty() {
        bail!("{} has no data rows", path.display());
    }
    Ok(out)
}

impl Measurements {
    /// Reads `force_displacement_<set>.csv` and `profile_<set>_x25/50/75.csv` from `dir`;
    /// the profiles are taken at the largest displacement.
    pub fn load(dir: &Path, set: &str) -> Result<Self> {
        let forces = Self::load_forces(&dir.join(format!("force_displacement_{set}.csv")))?;
        let [a, b, c] =
            [25, 50, 75].map(|x| read_pairs(&dir.join(format!("profile_{set}_x{x}.csv"))));
        Ok(Self {
            profiles: [a?, b?, c?],
            ..forces
        })
    }

    /// Reads a force–displacement CSV alone (no profiles: ν must then be given).
    pub fn load_forces(path: &Path) -> Result<Self> {
        let fd = read_pairs(path)?;
        Ok(Self {
            profile_pull: fd.iter().map(|p| p.0).fold(f64::MIN, f64::max),
            displacement: fd.iter().map(|p| p.0).collect(),
            force: fd.iter().map(|p| p.1).collect(),
            profiles: Default::default(),
        })
    }

    /// Whether scanner profiles were given.
    pub fn has_profiles(&self) -> bool {
        self.profiles.iter().any(|p| !p.is_empty())
    }
}

/// The model's response for ν: reaction force per unit E and unit pull, and the three
/// profiles at `pull` (heights at the model's stations, NaN where there is no surface).
#[derive(Debug, Clone)]
pub struct Response {
    pub force_per_e_mm: f64,
    pub profiles: [Vec<f64>; 3],
}

/// Runs the default cut block (full-width cut) with E = 1 and Poisson's ratio `nu`: pulled
/// 1 mm over the first second, `pull` over the second.
pub fn response(nu: f64, pull: f64) -> Result<Response> {
    let settings = [
        ("E".to_string(), Value::Real(1.0)),
        ("nu".to_string(), Value::Real(nu)),
    ];
    let inputs = BTreeMap::from([
        ("scalpel_x".to_string(), InputTable::constant(100.0)),
        (
            "pull".to_string(),
            InputTable {
                time: vec![0.0, 1.0],
                value: vec![1.0, pull],
            },
        ),
    ]);
    let profiles = PROFILE_LINES.map(|x| format!("profile_x{x:.0}"));
    let mut record = vec!["reaction_force".to_string()];
    record.extend(profiles.iter().cloned());
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: 2.0,
        step: 1.0,
        settings: &settings,
        inputs: &inputs,
        record: &record,
    };
    let series = simulate(&mut InProcess(Box::new(CutBlock::new())), &schedule)?.series;
    let force = series.column("reaction_force").context("recorded")?;
    let profile = |name: &String| series.array(name, 2).context("recorded");
    let [a, b, c] = profiles.each_ref().map(profile);
    Ok(Response {
        force_per_e_mm: force[1],
        profiles: [a?, b?, c?],
    })
}

fn profile_rms(r: &Response, m: &Measurements) -> f64 {
    let (mut sum, mut n) = (0.0, 0);
    for (model, data) in r.profiles.iter().zip(&m.profiles) {
        let d = deviation(model, data);
        sum += d.rms * d.rms * d.points as f64;
        n += d.points;
    }
    (sum / n.max(1) as f64).sqrt()
}

/// E by least squares on the forces for a model force per unit E and pull: E = Σ F g / Σ g²
/// with g = d · force_per_e_mm; returns (E, standard error, RMS force residual).
pub fn fit_e(force_per_e_mm: f64, m: &Measurements) -> (f64, f64, f64) {
    let g: Vec<f64> = m.displacement.iter().map(|d| d * force_per_e_mm).collect();
    let gg: f64 = g.iter().map(|x| x * x).sum();
    let e = g.iter().zip(&m.force).map(|(g, f)| g * f).sum::<f64>() / gg;
    let ssr: f64 = g
        .iter()
        .zip(&m.force)
        .map(|(g, f)| (f - e * g).powi(2))
        .sum();
    let n = m.force.len();
    let std = (ssr / (n.saturating_sub(1).max(1)) as f64 / gg).sqrt();
    (e, std, (ssr / n as f64).sqrt())
}

struct ProfileCost<'a>(&'a Measurements);

impl CostFunction for ProfileCost<'_> {
    type Param = f64;
    type Output = f64;

    fn cost(&self, nu: &f64) -> Result<f64, ArgminError> {
        let r = response(*nu, self.0.profile_pull).map_err(|e| ArgminError::msg(e.to_string()))?;
        Ok(profile_rms(&r, self.0))
    }
}

/// The identification result.
#[derive(Debug, Clone)]
pub struct Fit {
    pub nu: f64,
    pub e: f64,
    pub e_std: f64,
    pub force_rms: f64,
    pub profile_rms: f64,
    pub lines: [Deviation; 3],
    /// (ν, profile RMS, E fitted to the forces alone at that ν).
    pub scan: Vec<(f64, f64, f64)>,
}

/// Fits ν to the profiles (ν ∈ [0.05, 0.499]) unless `fixed_nu` is given, then E to the
/// forces.
pub fn identify(m: &Measurements, fixed_nu: Option<f64>) -> Result<Fit> {
    let nu = match fixed_nu {
        Some(nu) if (0.0..0.5).contains(&nu) => nu,
        Some(nu) => bail!("ν = {nu} is outside [0, 0.5)"),
        None if !m.has_profiles() => {
            bail!("no profiles to fit ν to: give ν to fit E alone from the forces")
        }
        None => Executor::new(ProfileCost(m), BrentOpt::new(0.05, 0.499))
            .configure(|s| s.max_iters(40))
            .run()
            .map_err(|e| anyhow::anyhow!("ν fit: {e}"))?
            .state()
            .best_param
            .context("ν fit returned no parameter")?,
    };
    let r = response(nu, m.profile_pull)?;
    let (e, e_std, force_rms) = fit_e(r.force_per_e_mm, m);
    let lines = [0, 1, 2].map(|k| deviation(&r.profiles[k], &m.profiles[k]));
    let mut scan = Vec::new();
    for v in [0.3, 0.4, 0.43, 0.45, 0.47, 0.49] {
        let rv = response(v, m.profile_pull)?;
        scan.push((v, profile_rms(&rv, m), fit_e(rv.force_per_e_mm, m).0));
    }
    Ok(Fit {
        nu,
        e,
        e_std,
        force_rms,
        profile_rms: profile_rms(&r, m),
        lines,
        scan,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Data generated by the model itself with known E and ν.
    fn synthetic(e: f64, nu: f64) -> Measurements {
        let r = response(nu, 10.0).unwrap();
        let displacement: Vec<f64> = (0..=10).map(f64::from).collect();
        let force = displacement
            .iter()
            .map(|d| e * d * r.force_per_e_mm)
            .collect();
        let profiles = r.profiles.clone().map(|p| {
            p.iter()
                .enumerate()
                .filter(|(_, z)| z.is_finite())
                .map(|(i, z)| (i as f64 * models::scene::cutblock::PROFILE_STEP, *z))
                .collect()
        });
        Measurements {
            displacement,
            force,
            profiles,
            profile_pull: 10.0,
        }
    }

    #[test]
    fn recovers_known_parameters_within_one_percent() {
        let (e, nu) = (0.05, 0.4);
        let fit = identify(&synthetic(e, nu), None).unwrap();
        println!(
            "fit: E = {:.6} (true {e}), ν = {:.5} (true {nu})",
            fit.e, fit.nu
        );
        assert!(((fit.e - e) / e).abs() < 0.01, "{}", fit.e);
        assert!(((fit.nu - nu) / nu).abs() < 0.01, "{}", fit.nu);
        assert!(fit.profile_rms < 1e-3);
    }

    #[test]
    fn forces_alone_trade_e_against_nu() {
        let m = synthetic(0.05, 0.4);
        // Any ν fits the forces exactly with its own E: the residual does not tell them apart.
        for nu in [0.3, 0.45] {
            let r = response(nu, 10.0).unwrap();
            let (e, _, rms) = fit_e(r.force_per_e_mm, &m);
            assert!(rms < 1e-9 * m.force[10], "{rms}");
            assert!((e - 0.05).abs() > 1e-4, "E should move with ν: {e}");
        }
    }

    #[test]
    fn forces_alone_give_e_at_a_given_nu() {
        let mut m = synthetic(0.05, 0.4);
        m.profiles = Default::default();
        let e = identify(&m, None).unwrap_err().to_string();
        assert!(e.contains("give ν"), "{e}");
        let fit = identify(&m, Some(0.4)).unwrap();
        assert!(((fit.e - 0.05) / 0.05).abs() < 1e-9, "{}", fit.e);
        assert!(identify(&m, Some(0.5)).is_err());
    }

    #[test]
    fn missing_files_name_the_path() {
        let e = Measurements::load(Path::new("/nonexistent"), "A")
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/force_displacement_A.csv"), "{e}");
    }
}
