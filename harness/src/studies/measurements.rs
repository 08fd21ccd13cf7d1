//! A measurement set of the cut block: the specimen it was taken on (`specimen_<S>.toml`:
//! block, cut, supports, mesh, scan lines, noise levels), its force–displacement points
//! (`force_displacement_<S>.csv`) and, if scanned, its laser profiles at the largest pull,
//! one file per scan line x = X mm (`profile_<S>_x<X>.csv`). The formats are documented in
//! `docs/reference/data-formats.md`; the shipped sets A and C and their provenance are in
//! `experiments/data/cutblock/` and compiled into the harness ([`Source::Shipped`]).
//!
//! Everything read is checked on the way in: a value that is not a finite number, a
//! missing or unknown column, a file without data rows, pulls that do not increase — each
//! error names the file, and the line and column where there is one.

use std::path::{Path, PathBuf};

use anyhow::{bail, ensure, Context, Result};
use serde::Deserialize;

use models::scene::cutblock::CutBlock;
use models::scene::Scene;

use crate::sweep::Value;

/// The shipped sets A and C (`experiments/data/cutblock`), compiled in so that a copied
/// binary identifies them without the source tree.
const SHIPPED: [(&str, &str); 10] = [
    (
        "specimen_A.toml",
        include_str!("../../../experiments/data/cutblock/specimen_A.toml"),
    ),
    (
        "force_displacement_A.csv",
        include_str!("../../../experiments/data/cutblock/force_displacement_A.csv"),
    ),
    (
        "profile_A_x25.csv",
        include_str!("../../../experiments/data/cutblock/profile_A_x25.csv"),
    ),
    (
        "profile_A_x50.csv",
        include_str!("../../../experiments/data/cutblock/profile_A_x50.csv"),
    ),
    (
        "profile_A_x75.csv",
        include_str!("../../../experiments/data/cutblock/profile_A_x75.csv"),
    ),
    (
        "specimen_C.toml",
        include_str!("../../../experiments/data/cutblock/specimen_C.toml"),
    ),
    (
        "force_displacement_C.csv",
        include_str!("../../../experiments/data/cutblock/force_displacement_C.csv"),
    ),
    (
        "profile_C_x25.csv",
        include_str!("../../../experiments/data/cutblock/profile_C_x25.csv"),
    ),
    (
        "profile_C_x50.csv",
        include_str!("../../../experiments/data/cutblock/profile_C_x50.csv"),
    ),
    (
        "profile_C_x75.csv",
        include_str!("../../../experiments/data/cutblock/profile_C_x75.csv"),
    ),
];

/// Where a set's files are: a folder, or the shipped sets compiled into the harness.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Source {
    /// A folder holding the set's files.
    Folder(PathBuf),
    /// The shipped sets A and C, compiled into the harness.
    Shipped,
}

impl Source {
    /// A file's text, `None` if there is no such file.
    fn read(&self, file: &str) -> Result<Option<String>> {
        match self {
            Self::Shipped => Ok(models::scene::shipped(&SHIPPED, file)
                .ok()
                .map(str::to_string)),
            Self::Folder(dir) => {
                let path = dir.join(file);
                if !path.is_file() {
                    return Ok(None);
                }
                let text = std::fs::read_to_string(&path)
                    .with_context(|| format!("reading {}", path.display()))?;
                Ok(Some(text))
            }
        }
    }

    /// A file's text, or an error naming it.
    fn require(&self, file: &str) -> Result<String> {
        self.read(file)?
            .with_context(|| format!("{}: no such file", self.name(file)))
    }

    /// Refuses a file named as a profile of set `set` that is none of the specimen's scan
    /// lines (a misnamed scan such as `profile_A_x25.0.csv` would be left out of the fit).
    fn refuse_unknown_profiles(&self, set: &str, specimen: &Specimen) -> Result<()> {
        let Self::Folder(dir) = self else {
            return Ok(());
        };
        let expected: Vec<String> = specimen
            .scan_lines
            .iter()
            .map(|&x| Specimen::profile_file(set, x))
            .collect();
        let entries =
            std::fs::read_dir(dir).with_context(|| format!("reading {}", dir.display()))?;
        for entry in entries {
            let name = entry?.file_name().to_string_lossy().into_owned();
            ensure!(
                !name.starts_with(&format!("profile_{set}_")) || expected.contains(&name),
                "{}: not a scan line of specimen_{set}.toml, whose scan_lines = {:?} are read \
                 from {}",
                self.name(&name),
                specimen.scan_lines,
                expected.join(", ")
            );
        }
        Ok(())
    }

    /// How errors name a file of this source.
    pub fn name(&self, file: &str) -> String {
        match self {
            Self::Shipped => format!("{file} (shipped set)"),
            Self::Folder(dir) => dir.join(file).display().to_string(),
        }
    }
}

impl std::fmt::Display for Source {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Shipped => write!(f, "the shipped sets (experiments/data/cutblock)"),
            Self::Folder(dir) => write!(f, "{}", dir.display()),
        }
    }
}

/// Standard deviations of the measurement noise.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Noise {
    /// Force noise (N).
    pub force: f64,
    /// Scanner height noise (mm).
    pub profile: f64,
}

/// The scan lines of seed 002's scanner (x, mm), the default of [`Specimen::scan_lines`].
fn seed_scan_lines() -> Vec<f64> {
    vec![25.0, 50.0, 75.0]
}

/// Uniform layers: the default [`Specimen::mesh_grading`].
pub(crate) fn uniform() -> f64 {
    1.0
}

/// The specimen a set was measured on: what the scene is built with to fit it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Specimen {
    /// Block lengths x, y, z (mm).
    pub size: [f64; 3],
    /// Cubes of the mirrored mesh along x, y, z.
    pub cells: [u32; 3],
    /// β of the layers' grading towards the cut plane, the crack front and the faces (the
    /// scene's `mesh_grading`; 1: uniform).
    #[serde(default = "uniform")]
    pub mesh_grading: f64,
    /// Cut plane (mm) and depth from the top (mm).
    pub y_cut: f64,
    /// Cut depth from the top (mm).
    pub cut_depth: f64,
    /// The incision runs in x from 0 to here (mm).
    pub cut_x: f64,
    /// The scene's `support` (`clamped`, `gripped` or `sliding`).
    pub support: String,
    /// The x (mm) of each laser scan line, each with its file `profile_<S>_x<X>.csv`
    /// (X as written here, e.g. 25 or 37.5).
    #[serde(default = "seed_scan_lines")]
    pub scan_lines: Vec<f64>,
    /// Standard deviations of the force and the profile noise.
    pub noise: Noise,
}

impl Specimen {
    /// Reads and checks a specimen file.
    pub fn parse(text: &str, origin: &str) -> Result<Self> {
        let s: Self = toml::from_str(text).with_context(|| format!("in {origin}"))?;
        for (name, value) in [
            ("noise.force", s.noise.force),
            ("noise.profile", s.noise.profile),
        ] {
            ensure!(
                value.is_finite() && value > 0.0,
                "{origin}: {name} = {value} must be a positive standard deviation"
            );
        }
        for (k, &x) in s.scan_lines.iter().enumerate() {
            ensure!(
                x.is_finite() && x > 0.0 && x < s.size[0],
                "{origin}: scan_lines[{k}] = {x} must lie inside the block, 0 < x < size[0] = {}",
                s.size[0]
            );
        }
        s.check_block(origin)?;
        Ok(s)
    }

    /// Checks the block, cut and supports as the cut block's scene does (its ranges, then
    /// the geometry they make together), naming this file's key and value.
    fn check_block(&self, origin: &str) -> Result<()> {
        let mut scene = CutBlock::new();
        let cut = ("scalpel_x".to_string(), Value::Real(self.cut_x));
        for (name, value) in self.settings().into_iter().chain([cut]) {
            let vr = scene.lookup(&name)?;
            match &value {
                Value::Real(x) => scene.set_real(vr, &[*x]),
                Value::Text(s) => scene.set_string(vr, s),
            }
            .with_context(|| format!("{origin}: {} = {value}", specimen_key(&name)))?;
        }
        ensure!(
            self.cut_depth < self.size[2] || self.cut_x < self.size[0],
            "{origin}: cut_depth = {} over the whole width (cut_x = {}) cuts the block of \
             height size[2] = {} in two: nothing would carry the pull",
            self.cut_depth,
            self.cut_x,
            self.size[2]
        );
        scene.check().with_context(|| {
            format!(
                "{origin}: size = {:?}, cells = {:?}, y_cut = {}, cut_depth = {} do not make a \
                 block the scene can build",
                self.size, self.cells, self.y_cut, self.cut_depth
            )
        })
    }

    /// The file of the scan line at `x`.
    pub fn profile_file(set: &str, x: f64) -> String {
        format!("profile_{set}_x{x}.csv")
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
        out.push(("mesh_grading".into(), Value::Real(self.mesh_grading)));
        out.push(("y_cut".into(), Value::Real(self.y_cut)));
        out.push(("cut_depth".into(), Value::Real(self.cut_depth)));
        out.push(("support".into(), Value::Text(self.support.clone())));
        out
    }
}

/// The specimen file's key of a cut-block variable that [`Specimen::settings`] sets (and
/// `scalpel_x`, which the identification holds at `cut_x`).
fn specimen_key(variable: &str) -> String {
    match variable {
        "scalpel_x" => "cut_x".into(),
        _ => match ["x", "y", "z"]
            .iter()
            .position(|a| variable.ends_with(&format!("_{a}")))
        {
            Some(k) if variable.starts_with("size_") => format!("size[{k}]"),
            Some(k) if variable.starts_with("cells_") => format!("cells[{k}]"),
            _ => variable.into(),
        },
    }
}

/// The points of one scan line.
#[derive(Debug, Clone, PartialEq)]
pub struct Scan {
    /// The line's x (mm).
    pub x: f64,
    /// (y, z) points in lab coordinates (mm).
    pub points: Vec<(f64, f64)>,
}

/// A measurement set.
#[derive(Debug, Clone, PartialEq)]
pub struct Measurements {
    /// The specimen the set was measured on.
    pub specimen: Specimen,
    /// Pulls (mm, increasing) and the reaction forces measured at them (N).
    pub displacement: Vec<f64>,
    /// The reaction force at each pull (N).
    pub force: Vec<f64>,
    /// One scan per line of the specimen at the largest pull; empty when the set has none.
    pub profiles: Vec<Scan>,
}

/// A row of a two-column CSV: its line in the file and its values.
struct Row {
    line: u64,
    values: (f64, f64),
}

/// The rows of a two-column CSV read by column name (any order, extra columns refused):
/// (`columns[0]`, `columns[1]`) per row, each a finite number.
fn read_pairs(text: &str, origin: &str, columns: [&str; 2]) -> Result<Vec<Row>> {
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader
        .headers()
        .with_context(|| format!("{origin}: reading the header"))?
        .clone();
    ensure!(
        !header.is_empty(),
        "{origin} is empty: expected a header `{},{}` and data rows",
        columns[0],
        columns[1]
    );
    let found: Vec<&str> = header.iter().collect();
    let position = |name: &str| found.iter().position(|h| *h == name);
    let (Some(a), Some(b), 2) = (position(columns[0]), position(columns[1]), found.len()) else {
        bail!(
            "{origin}, line 1: the header must name the columns `{}` and `{}` (in either \
             order); found {}",
            columns[0],
            columns[1],
            found
                .iter()
                .map(|h| format!("`{h}`"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    };
    let mut out = Vec::new();
    for record in reader.records() {
        // A row with another number of fields is refused by the reader, with its line.
        let record = record.with_context(|| origin.to_string())?;
        let line = record.position().map_or(0, |p| p.line());
        let value = |k: usize, name: &str| -> Result<f64> {
            let cell = &record[k];
            let x: f64 = cell.parse().map_err(|_| {
                anyhow::anyhow!("{origin}, line {line}, column `{name}`: `{cell}` is not a number")
            })?;
            ensure!(
                x.is_finite(),
                "{origin}, line {line}, column `{name}`: {cell} is not a finite number"
            );
            Ok(x)
        };
        out.push(Row {
            line,
            values: (value(a, columns[0])?, value(b, columns[1])?),
        });
    }
    ensure!(!out.is_empty(), "{origin} has no data rows");
    Ok(out)
}

impl Measurements {
    /// Reads set `set` from `source`: its specimen, forces and (if any scan file is there)
    /// one profile per scan line. The pulls must increase strictly from 0 or more.
    pub fn load(source: &Source, set: &str) -> Result<Self> {
        let file = format!("specimen_{set}.toml");
        let specimen = Specimen::parse(&source.require(&file)?, &source.name(&file))?;
        let file = format!("force_displacement_{set}.csv");
        let origin = source.name(&file);
        let fd = read_pairs(
            &source.require(&file)?,
            &origin,
            ["displacement_mm", "force_N"],
        )?;
        for w in fd.windows(2) {
            let (before, after) = (w[0].values.0, w[1].values.0);
            ensure!(
                after > before,
                "{origin}, line {}: the displacements must increase ({after} after {before})",
                w[1].line
            );
        }
        let (first, last) = (fd[0].values.0, fd[fd.len() - 1].values.0);
        ensure!(
            first >= 0.0,
            "{origin}, line {}: displacement {first} is negative (the fit is for pulls)",
            fd[0].line
        );
        ensure!(
            last <= specimen.size[1],
            "{origin}, line {}: a pull of {last} mm is longer than the block ({} mm): is the \
             column in mm?",
            fd[fd.len() - 1].line,
            specimen.size[1]
        );
        ensure!(
            last > 0.0,
            "{origin}: every displacement is {last}: E is fitted to forces at pulls above 0"
        );
        ensure!(
            fd.iter().any(|r| r.values.1 != 0.0),
            "{origin}: every force is 0: there is nothing to fit E to"
        );
        source.refuse_unknown_profiles(set, &specimen)?;
        let mut scans = Vec::new();
        for &x in &specimen.scan_lines {
            let file = Specimen::profile_file(set, x);
            scans.push((x, source.read(&file)?, file));
        }
        let mut profiles = Vec::new();
        if scans.iter().any(|(_, text, _)| text.is_some()) {
            for (x, text, file) in scans {
                let text = text.with_context(|| {
                    format!(
                        "{}: no such file, while the set has other scans (one per scan line)",
                        source.name(&file)
                    )
                })?;
                let rows = read_pairs(&text, &source.name(&file), ["y_mm", "z_mm"])?;
                let points = rows.into_iter().map(|r| r.values).collect();
                profiles.push(Scan { x, points });
            }
        }
        Ok(Self {
            specimen,
            displacement: fd.iter().map(|r| r.values.0).collect(),
            force: fd.iter().map(|r| r.values.1).collect(),
            profiles,
        })
    }

    /// Whether the set has scanner profiles.
    pub fn has_profiles(&self) -> bool {
        !self.profiles.is_empty()
    }

    /// The pull at which the profiles were taken: the largest one.
    pub fn profile_pull(&self) -> f64 {
        self.displacement.last().copied().unwrap_or(0.0)
    }
}

/// The folder of a `--data` argument, or the shipped sets without one.
pub fn source(data: Option<&Path>) -> Source {
    data.map_or(Source::Shipped, |d| Source::Folder(d.to_path_buf()))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every data file of the shipped folder is compiled in, and the sets load the same
    /// from either source.
    #[test]
    fn the_shipped_sets_load_with_their_specimens() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments/data/cutblock");
        let mut files: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|f| f != "README.md")
            .collect();
        files.sort();
        let mut shipped: Vec<&str> = SHIPPED.iter().map(|(f, _)| *f).collect();
        shipped.sort();
        assert_eq!(files, shipped);
        for (set, y_cut, depth, force_noise) in
            [("A", 45.0, 8.5, 0.0426), ("C", 50.0, 4.25, 0.0292)]
        {
            let m = Measurements::load(&Source::Shipped, set).unwrap();
            assert_eq!(
                m,
                Measurements::load(&Source::Folder(dir.clone()), set).unwrap()
            );
            assert_eq!((m.specimen.y_cut, m.specimen.cut_depth), (y_cut, depth));
            assert_eq!(m.specimen.noise.force, force_noise);
            assert_eq!(m.displacement.len(), 11);
            assert_eq!(m.profile_pull(), 10.0);
            let lines: Vec<f64> = m.profiles.iter().map(|s| s.x).collect();
            assert_eq!(lines, [25.0, 50.0, 75.0]);
            assert!(m.profiles.iter().all(|p| p.points.len() > 150));
        }
    }

    /// A folder with set A's specimen (with `replace` applied) and `files`.
    fn folder(replace: (&str, &str), files: &[(&str, &str)]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        let spec = Source::Shipped.require("specimen_A.toml").unwrap();
        std::fs::write(
            dir.path().join("specimen_A.toml"),
            spec.replace(replace.0, replace.1),
        )
        .unwrap();
        for (name, text) in files {
            std::fs::write(dir.path().join(name), text).unwrap();
        }
        dir
    }

    fn error(replace: (&str, &str), files: &[(&str, &str)]) -> String {
        let dir = folder(replace, files);
        let e = Measurements::load(&Source::Folder(dir.path().into()), "A").unwrap_err();
        format!("{e:#}")
    }

    const HEADER: &str = "displacement_mm,force_N\n";

    #[test]
    fn bad_files_are_named_with_line_and_column() {
        let e = format!(
            "{:#}",
            Measurements::load(&Source::Folder("/nowhere".into()), "A").unwrap_err()
        );
        assert!(e.contains("/nowhere/specimen_A.toml: no such file"), "{e}");
        let e = error(("force = 0.0426", "force = -1"), &[]);
        assert!(e.contains("noise.force = -1"), "{e}");
        let e = error(
            ("cut_x = 100.0", "cut_x = 100.0\nscan_lines = [50.0, 120.0]"),
            &[],
        );
        assert!(e.contains("scan_lines[1] = 120"), "{e}");
        let cases = [
            (
                "0,0\n2,1\n1,0.5\n",
                "line 4: the displacements must increase (1 after 2)",
            ),
            (
                "0,0\n90,1\n",
                "line 3: a pull of 90 mm is longer than the block (80 mm)",
            ),
            (
                "0,0\n1,NaN\n",
                "line 3, column `force_N`: NaN is not a finite number",
            ),
            (
                "0,0\ninf,1\n",
                "line 3, column `displacement_mm`: inf is not a finite number",
            ),
            ("0,0\n1,\n", "line 3, column `force_N`: `` is not a number"),
            (
                "0,0\n1\n",
                "(line: 3, byte: 28): found record with 1 fields",
            ),
            ("", "has no data rows"),
        ];
        for (rows, expected) in cases {
            let e = error(
                ("", ""),
                &[("force_displacement_A.csv", &format!("{HEADER}{rows}"))],
            );
            assert!(
                e.contains("force_displacement_A.csv") && e.contains(expected),
                "{rows:?}: {e}"
            );
        }
        let e = error(("", ""), &[("force_displacement_A.csv", "")]);
        assert!(e.contains("force_displacement_A.csv is empty"), "{e}");
        let e = error(
            ("", ""),
            &[("force_displacement_A.csv", "d,force_N\n0,0\n")],
        );
        assert!(
            e.contains("line 1: the header must name the columns `displacement_mm` and `force_N`")
                && e.contains("found `d`, `force_N`"),
            "{e}"
        );
        let forces = (
            "force_displacement_A.csv",
            "displacement_mm,force_N\n0,0\n1,0.5\n",
        );
        let e = error(("", ""), &[forces, ("profile_A_x25.csv", "y_mm,z_mm\n")]);
        assert!(e.contains("profile_A_x25.csv has no data rows"), "{e}");
        let e = error(
            ("", ""),
            &[forces, ("profile_A_x25.csv", "y_mm,z_mm\n1,17\n")],
        );
        assert!(
            e.contains("profile_A_x50.csv: no such file, while the set has other scans"),
            "{e}"
        );
    }

    /// The specimen's values are checked against the scene as the file is read, each error
    /// naming the file, the key and the value.
    #[test]
    fn specimen_values_are_checked_by_key_as_the_file_is_read() {
        let cases = [
            (("y_cut = 45.0", "y_cut = 95.0"), "y_cut = 95"),
            (("cut_x = 100.0", "cut_x = -5.0"), "cut_x = -5"),
            (
                ("cells = [6, 16, 14]", "cells = [6, 0, 14]"),
                "cells[1] = 0",
            ),
            (
                ("cut_depth = 8.5", "cut_depth = 17.0"),
                "cut_depth = 17 over the whole width",
            ),
            (
                ("size = [100.0, 80.0, 17.0]", "size = [100.0, -80.0, 17.0]"),
                "size[1] = -80",
            ),
            (("support = \"clamped\"", "support = \"glued\""), "glued"),
            (
                ("cut_x = 100.0", "cut_x = 100.0\nmesh_grading = 5.0"),
                "mesh_grading = 5",
            ),
        ];
        for (replace, expected) in cases {
            let e = error(replace, &[]);
            assert!(
                e.contains("specimen_A.toml") && e.contains(expected),
                "{replace:?}: {e}"
            );
        }
    }

    /// A file named as a profile of the set that is none of its scan lines is refused, and
    /// data that give no E (no pull above 0, no force) are errors, not NaN.
    #[test]
    fn misnamed_profiles_and_degenerate_forces_are_refused() {
        let forces = (
            "force_displacement_A.csv",
            "displacement_mm,force_N\n0,0\n1,0.5\n",
        );
        let e = error(
            ("", ""),
            &[forces, ("profile_A_x25.0.csv", "y_mm,z_mm\n1,17\n")],
        );
        assert!(
            e.contains("profile_A_x25.0.csv: not a scan line of specimen_A.toml")
                && e.contains("profile_A_x25.csv"),
            "{e}"
        );
        let e = error(
            ("", ""),
            &[("force_displacement_A.csv", &format!("{HEADER}0,1\n"))],
        );
        assert!(e.contains("every displacement is 0"), "{e}");
        let e = error(
            ("", ""),
            &[(
                "force_displacement_A.csv",
                &format!("{HEADER}0,0\n1,0\n2,0\n"),
            )],
        );
        assert!(e.contains("every force is 0"), "{e}");
    }

    /// Columns are read by name; scan lines anywhere the specimen names them; no scans
    /// at all is a set without profiles.
    #[test]
    fn columns_by_name_and_scan_lines_anywhere() {
        let swapped = (
            "force_displacement_A.csv",
            "force_N, displacement_mm\n0,0\n0.5,1\n",
        );
        let dir = folder(
            ("cut_x = 100.0", "cut_x = 100.0\nscan_lines = [37.5]"),
            &[
                swapped,
                ("profile_A_x37.5.csv", "z_mm,y_mm\n17,1\n16.5,2\n"),
            ],
        );
        let m = Measurements::load(&Source::Folder(dir.path().into()), "A").unwrap();
        assert_eq!(
            (m.displacement.clone(), m.force.clone()),
            (vec![0.0, 1.0], vec![0.0, 0.5])
        );
        assert_eq!(
            m.profiles,
            [Scan {
                x: 37.5,
                points: vec![(1.0, 17.0), (2.0, 16.5)]
            }]
        );
        let dir = folder(("", ""), &[swapped]);
        let m = Measurements::load(&Source::Folder(dir.path().into()), "A").unwrap();
        assert!(!m.has_profiles());
    }
}
