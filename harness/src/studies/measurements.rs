//! A measurement set of the cut block: the specimen it was taken on (`specimen_<S>.toml`:
//! block, cut, supports, mesh, noise levels), its force–displacement points
//! (`force_displacement_<S>.csv`) and, if scanned, its laser profiles along x = 25, 50,
//! 75 mm at the largest pull (`profile_<S>_x25.csv`, …). The shipped sets and their
//! provenance are in `experiments/data/cutblock/`.

use std::path::Path;

use anyhow::{bail, ensure, Context, Result};
use models::scene::cutblock::PROFILE_LINES;
use serde::Deserialize;

use crate::sweep::Value;

/// Standard deviations of the measurement noise.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Noise {
    /// Force noise (N).
    pub force: f64,
    /// Scanner height noise (mm).
    pub profile: f64,
}

/// The specimen a set was measured on: what the scene is built with to fit it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Specimen {
    /// Block lengths x, y, z (mm).
    pub size: [f64; 3],
    /// Cubes of the mirrored mesh along x, y, z.
    pub cells: [u32; 3],
    /// Cut plane (mm) and depth from the top (mm).
    pub y_cut: f64,
    pub cut_depth: f64,
    /// The incision runs in x from 0 to here (mm).
    pub cut_x: f64,
    /// The scene's `support` (`clamped`, `gripped` or `sliding`).
    pub support: String,
    pub noise: Noise,
}

impl Specimen {
    /// Reads and checks a specimen file.
    pub fn load(path: &Path) -> Result<Self> {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("opening the specimen file {}", path.display()))?;
        let s: Self = toml::from_str(&text).with_context(|| format!("in {}", path.display()))?;
        for (name, value) in [
            ("noise.force", s.noise.force),
            ("noise.profile", s.noise.profile),
        ] {
            ensure!(
                value.is_finite() && value > 0.0,
                "{}: {name} = {value} must be a positive standard deviation",
                path.display()
            );
        }
        Ok(s)
    }

    /// The scene settings that build this specimen (the scene checks the values).
    pub fn settings(&self) -> Vec<(String, Value)> {
        let mut out = Vec::new();
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            out.push((format!("size_{axis}"), Value::Real(self.size[k])));
            out.push((
                format!("cells_{axis}"),
                Value::Real(f64::from(self.cells[k])),
            ));
        }
        out.push(("y_cut".into(), Value::Real(self.y_cut)));
        out.push(("cut_depth".into(), Value::Real(self.cut_depth)));
        out.push(("support".into(), Value::Text(self.support.clone())));
        out
    }
}

/// A measurement set.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurements {
    pub specimen: Specimen,
    /// Pulls (mm, increasing) and the reaction forces measured at them (N).
    pub displacement: Vec<f64>,
    pub force: Vec<f64>,
    /// (y, z) points along x = 25, 50, 75 mm; empty when the set has no scans.
    pub profiles: [Vec<(f64, f64)>; 3],
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
    /// Reads set `set` from `dir`: its specimen, forces and (if all three are there) its
    /// profiles. The pulls must increase strictly from 0 or more.
    pub fn load(dir: &Path, set: &str) -> Result<Self> {
        let specimen = Specimen::load(&dir.join(format!("specimen_{set}.toml")))?;
        let path = dir.join(format!("force_displacement_{set}.csv"));
        let fd = read_pairs(&path)?;
        for (k, w) in fd.windows(2).enumerate() {
            ensure!(
                w[1].0 > w[0].0,
                "{}: the displacements must increase (row {}: {} after {})",
                path.display(),
                k + 2,
                w[1].0,
                w[0].0
            );
        }
        ensure!(
            fd[0].0 >= 0.0,
            "{}: displacement {} is negative (the fit is for pulls)",
            path.display(),
            fd[0].0
        );
        let scans = PROFILE_LINES.map(|x| dir.join(format!("profile_{set}_x{x:.0}.csv")));
        let profiles = if scans.iter().any(|p| p.is_file()) {
            let [a, b, c] = scans.each_ref().map(|p| read_pairs(p));
            [a?, b?, c?]
        } else {
            Default::default()
        };
        Ok(Self {
            specimen,
            displacement: fd.iter().map(|p| p.0).collect(),
            force: fd.iter().map(|p| p.1).collect(),
            profiles,
        })
    }

    /// Whether the set has scanner profiles.
    pub fn has_profiles(&self) -> bool {
        self.profiles.iter().any(|p| !p.is_empty())
    }

    /// The pull at which the profiles were taken: the largest one.
    pub fn profile_pull(&self) -> f64 {
        self.displacement.last().copied().unwrap_or(0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_sets_load_with_their_specimens() {
        let dir = crate::sweep::experiment::shipped_dir().join("data/cutblock");
        for (set, y_cut, depth, force_noise) in
            [("A", 45.0, 8.5, 0.0426), ("C", 50.0, 4.25, 0.0292)]
        {
            let m = Measurements::load(&dir, set).unwrap();
            assert_eq!((m.specimen.y_cut, m.specimen.cut_depth), (y_cut, depth));
            assert_eq!(m.specimen.noise.force, force_noise);
            assert_eq!(m.displacement.len(), 11);
            assert_eq!(m.profile_pull(), 10.0);
            assert!(m.profiles.iter().all(|p| p.len() > 150));
        }
    }

    #[test]
    fn bad_files_are_named() {
        let dir = tempfile::tempdir().unwrap();
        let e = Measurements::load(dir.path(), "A").unwrap_err();
        assert!(format!("{e:#}").contains("specimen_A.toml"), "{e:#}");
        let spec = crate::sweep::experiment::shipped_dir().join("data/cutblock/specimen_A.toml");
        let text = std::fs::read_to_string(spec).unwrap();
        std::fs::write(
            dir.path().join("specimen_A.toml"),
            text.replace("force = 0.0426", "force = -1"),
        )
        .unwrap();
        let e = Measurements::load(dir.path(), "A").unwrap_err();
        assert!(format!("{e:#}").contains("noise.force = -1"), "{e:#}");
        std::fs::write(dir.path().join("specimen_A.toml"), text).unwrap();
        std::fs::write(
            dir.path().join("force_displacement_A.csv"),
            "displacement_mm,force_N\n0,0\n2,1\n1,0.5\n",
        )
        .unwrap();
        let e = Measurements::load(dir.path(), "A").unwrap_err();
        assert!(
            format!("{e:#}").contains("must increase (row 3: 1 after 2)"),
            "{e:#}"
        );
        std::fs::write(
            dir.path().join("force_displacement_A.csv"),
            "displacement_mm,force_N\n0,0\n1,0.5\n",
        )
        .unwrap();
        let m = Measurements::load(dir.path(), "A").unwrap();
        assert!(!m.has_profiles());
    }
}
