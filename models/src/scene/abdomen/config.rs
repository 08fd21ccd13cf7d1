//! Pelvis/spine configuration files (TOML): either explicit control points for the five
//! boundary parts, or anatomical parameters for the generator. Example:
//!
//! ```toml
//! name = "narrow"
//! description = "pelvic outlet 100 mm"
//! [control_points]
//! spine = [[-20.0, 260.0], [5.0, 117.0], [-45.0, 59.8], [0.0, 0.0]]
//! pelvic_floor = [[0.0, 0.0], [52.1, -7.1], [94.0, 34.2]]
//! # pelvic_bone, abdominal_wall, diaphragm likewise, each starting where the previous ends
//! ```
//!
//! or `[anatomy]` with any of `height`, `depth`, `dome`, `lordosis`, `outlet`, `pelvic_tilt`,
//! `floor_sag`, `symphysis`, `wall_bulge` (see [`Anatomy`]).

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::anatomy::Anatomy;
use super::geometry::ControlPoints;
use crate::scene::SceneError;

/// Prefix of the anatomy parameters that generate a configuration: `anatomy.outlet`, ….
pub const ANATOMY: &str = "anatomy.";

/// The shipped configurations by name (`experiments/pelvis/*.toml`, written by `cargo run -p
/// models --example pelvis_configs`), compiled into the library so that a copied binary or
/// FMU finds them without the source tree.
pub const SHIPPED: [(&str, &str); 5] = [
    (
        "normal",
        include_str!("../../../../experiments/pelvis/normal.toml"),
    ),
    (
        "narrow",
        include_str!("../../../../experiments/pelvis/narrow.toml"),
    ),
    (
        "wide",
        include_str!("../../../../experiments/pelvis/wide.toml"),
    ),
    (
        "lordotic",
        include_str!("../../../../experiments/pelvis/lordotic.toml"),
    ),
    (
        "tilted",
        include_str!("../../../../experiments/pelvis/tilted.toml"),
    ),
];

/// A configuration file's content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PelvisConfig {
    /// The configuration's name (`narrow`, …; empty if the file gives none).
    #[serde(default)]
    pub name: String,
    /// What the configuration describes, in words (empty if the file gives none).
    #[serde(default)]
    pub description: String,
    /// Explicit control points of the five boundary parts (mm); exactly one of these and
    /// [`anatomy`](Self::anatomy) is given.
    pub control_points: Option<ControlPoints>,
    /// Anatomical parameters (mm, degrees) from which the generator makes the control
    /// points; exactly one of these and [`control_points`](Self::control_points) is given.
    pub anatomy: Option<Anatomy>,
}

impl PelvisConfig {
    /// The built-in default: the generator's default anatomy.
    pub fn builtin() -> Self {
        Self {
            name: "default".into(),
            description: "built-in default anatomy".into(),
            control_points: None,
            anatomy: Some(Anatomy::default()),
        }
    }

    /// Parses TOML text; `origin` names the source in errors.
    pub fn parse(text: &str, origin: &str) -> Result<Self, SceneError> {
        let config: Self =
            toml::from_str(text).map_err(|e| SceneError::Config(format!("{origin}: {e}")))?;
        match (&config.control_points, &config.anatomy) {
            (Some(_), Some(_)) | (None, None) => Err(SceneError::Config(format!(
                "{origin}: give exactly one of [control_points] and [anatomy]"
            ))),
            _ => Ok(config),
        }
    }

    /// Reads a file.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            SceneError::Config(format!("configuration file {}: {e}", path.display()))
        })?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Resolves the `configuration` parameter: empty → built-in; a value containing a path
    /// separator or ending in `.toml` → that file; otherwise a shipped name ([`SHIPPED`]).
    pub fn resolve(value: &str) -> Result<Self, SceneError> {
        if value.is_empty() {
            return Ok(Self::builtin());
        }
        if value.contains('/') || value.contains('\\') || value.ends_with(".toml") {
            return Self::load(Path::new(value));
        }
        let text = crate::scene::shipped(&SHIPPED, value).map_err(|names| {
            SceneError::Config(format!(
                "configuration `{value}` is no shipped configuration ({names}) and no file \
                 path (a path contains `/` or ends in `.toml`)"
            ))
        })?;
        Self::parse(text, &format!("shipped configuration `{value}`"))
    }

    /// A configuration generated from anatomy fields (`anatomy.<field>` = value) over the
    /// default anatomy, as TOML text; errors name the bad field or value.
    pub fn generated(
        name: &str,
        description: &str,
        fields: &[(&str, f64)],
    ) -> Result<String, SceneError> {
        let mut anatomy = Anatomy::default();
        for (key, value) in fields {
            let field = key.strip_prefix(ANATOMY).ok_or_else(|| {
                SceneError::Config(format!(
                    "`{key}` is not an anatomy parameter ({ANATOMY}<field>)"
                ))
            })?;
            anatomy.set(field, *value).map_err(|e| match e {
                SceneError::Config(m) => SceneError::Config(format!("`{key}`: {m}")),
                other => other,
            })?;
        }
        anatomy.control_points()?;
        let config = Self {
            name: name.into(),
            description: description.into(),
            control_points: None,
            anatomy: Some(anatomy),
        };
        toml::to_string(&config)
            .map_err(|e| SceneError::Config(format!("writing configuration `{name}`: {e}")))
    }

    /// The control points, generating them from the anatomy if needed.
    pub fn control_points(&self) -> Result<ControlPoints, SceneError> {
        match (&self.control_points, &self.anatomy) {
            (Some(p), _) => Ok(p.clone()),
            (None, Some(a)) => a.control_points(),
            (None, None) => Err(SceneError::Config("configuration has no geometry".into())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every file in `experiments/pelvis` is compiled in, and each parses.
    #[test]
    fn every_shipped_configuration_is_compiled_in() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments/pelvis");
        let mut files: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        files.sort();
        let mut names: Vec<String> = SHIPPED.iter().map(|(n, _)| format!("{n}.toml")).collect();
        names.sort();
        assert_eq!(files, names);
        for (name, _) in SHIPPED {
            assert_eq!(PelvisConfig::resolve(name).unwrap().name, name);
        }
    }

    #[test]
    fn parse_errors_name_the_key() {
        let e = PelvisConfig::parse("[anatomy]\noutlett = 3.0\n", "x.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("x.toml") && e.contains("outlett"), "{e}");
        let e = PelvisConfig::parse("name = \"a\"\n", "y.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("exactly one"), "{e}");
        let c = PelvisConfig::parse("[anatomy]\noutlet = 100.0\n", "z.toml").unwrap();
        assert_eq!(c.anatomy.unwrap().outlet, 100.0);
        let e = PelvisConfig::resolve("nonexistent")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`nonexistent` is no shipped") && e.contains("tilted"),
            "{e}"
        );
        let e = PelvisConfig::resolve("/nowhere/x.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nowhere/x.toml"), "{e}");
    }
}
