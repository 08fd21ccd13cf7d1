//! A parametric midsagittal outline: a handful of anatomical parameters → control points for
//! the five boundary parts, so that sweeps can vary anatomy continuously.
//!
//! Coordinates: x anterior, y superior, origin at the coccyx tip (mm). The defaults describe
//! a plausible adult outline, not a measured subject. The pelvic outlet (coccyx–pubis
//! distance, the "narrow"/"wide" knob) defaults to 115 mm, inside the 11–12 cm
//! anteroposterior outlet diameter given in obstetric anatomy texts; a narrow pelvis is
//! represented by 100 mm and a wide one by 130 mm. The other defaults (height, depth, dome,
//! lordosis, tilt, sag, symphysis height, wall bulge) are round assumed values chosen to give
//! a cavity of about 300 × 160 mm, the order of an adult abdomen; they carry no citation.

use serde::{Deserialize, Serialize};

use super::geometry::ControlPoints;
use crate::scene::SceneError;

/// Anatomical parameters (mm, degrees).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Anatomy {
    /// Coccyx level to the top of the diaphragm dome.
    pub height: f64,
    /// Anteroposterior distance from the spine to the abdominal wall at the rib margin.
    pub depth: f64,
    /// Rise of the diaphragm dome above its ends.
    pub dome: f64,
    /// Anterior bulge of the lumbar spine into the cavity.
    pub lordosis: f64,
    /// Distance from the coccyx tip to the pubic bone (pelvic outlet).
    pub outlet: f64,
    /// Angle by which the coccyx–pubis line rises anteriorly (pelvic tilt).
    pub pelvic_tilt: f64,
    /// Sag of the pelvic floor below the coccyx–pubis line.
    pub floor_sag: f64,
    /// Height of the pubic symphysis.
    pub symphysis: f64,
    /// Anterior bulge of the abdominal wall at mid height.
    pub wall_bulge: f64,
}

impl Default for Anatomy {
    fn default() -> Self {
        Self {
            height: 300.0,
            depth: 160.0,
            dome: 40.0,
            lordosis: 25.0,
            outlet: 115.0,
            pelvic_tilt: 20.0,
            floor_sag: 15.0,
            symphysis: 45.0,
            wall_bulge: 25.0,
        }
    }
}

/// The generator's fields: name, unit, admissible range and meaning, in declaration order.
pub const FIELDS: [(&str, &str, f64, f64, &str); 9] = [
    (
        "height",
        "mm",
        100.0,
        600.0,
        "coccyx level to the top of the diaphragm dome",
    ),
    (
        "depth",
        "mm",
        60.0,
        400.0,
        "spine to abdominal wall at the rib margin",
    ),
    (
        "dome",
        "mm",
        0.0,
        150.0,
        "rise of the diaphragm dome above its ends",
    ),
    (
        "lordosis",
        "mm",
        -20.0,
        80.0,
        "anterior bulge of the lumbar spine",
    ),
    (
        "outlet",
        "mm",
        50.0,
        200.0,
        "coccyx tip to pubic bone (pelvic outlet)",
    ),
    (
        "pelvic_tilt",
        "°",
        -10.0,
        60.0,
        "rise of the coccyx–pubis line anteriorly",
    ),
    (
        "floor_sag",
        "mm",
        0.0,
        60.0,
        "sag of the pelvic floor below the coccyx–pubis line",
    ),
    (
        "symphysis",
        "mm",
        10.0,
        100.0,
        "height of the pubic symphysis",
    ),
    (
        "wall_bulge",
        "mm",
        -20.0,
        100.0,
        "anterior bulge of the abdominal wall at mid height",
    ),
];

impl Anatomy {
    /// The fields' values in the order of [`FIELDS`].
    fn values(&self) -> [f64; 9] {
        [
            self.height,
            self.depth,
            self.dome,
            self.lordosis,
            self.outlet,
            self.pelvic_tilt,
            self.floor_sag,
            self.symphysis,
            self.wall_bulge,
        ]
    }

    /// Sets one field by name; an unknown name is an error listing the fields.
    pub fn set(&mut self, field: &str, value: f64) -> Result<(), SceneError> {
        let slot = match field {
            "height" => &mut self.height,
            "depth" => &mut self.depth,
            "dome" => &mut self.dome,
            "lordosis" => &mut self.lordosis,
            "outlet" => &mut self.outlet,
            "pelvic_tilt" => &mut self.pelvic_tilt,
            "floor_sag" => &mut self.floor_sag,
            "symphysis" => &mut self.symphysis,
            "wall_bulge" => &mut self.wall_bulge,
            _ => {
                let names: Vec<&str> = FIELDS.iter().map(|f| f.0).collect();
                return Err(SceneError::Config(format!(
                    "the anatomy has no field `{field}` (fields: {})",
                    names.join(", ")
                )));
            }
        };
        *slot = value;
        Ok(())
    }

    /// Control points of the outline; errors name a parameter out of its range.
    pub fn control_points(&self) -> Result<ControlPoints, SceneError> {
        for ((name, _, lo, hi, _), value) in FIELDS.iter().zip(self.values()) {
            if !(value.is_finite() && value >= *lo && value <= *hi) {
                return Err(SceneError::Config(format!(
                    "anatomy.{name} = {value} is outside [{lo}, {hi}]"
                )));
            }
        }
        let tilt = self.pelvic_tilt.to_radians();
        let (c, s) = (tilt.cos(), tilt.sin());
        let coccyx = [0.0, 0.0];
        let pubis = [self.outlet * c, self.outlet * s];
        let floor_mid = [
            0.5 * pubis[0] + self.floor_sag * s,
            0.5 * pubis[1] - self.floor_sag * c,
        ];
        let symphysis_top = [pubis[0] + 0.3 * self.symphysis, pubis[1] + self.symphysis];
        let top = self.height - self.dome;
        let spine_top = [-20.0, top];
        let wall_top = [spine_top[0] + self.depth, top];
        let wall_mid = [
            0.5 * (symphysis_top[0] + wall_top[0]) + self.wall_bulge,
            0.5 * (symphysis_top[1] + wall_top[1]),
        ];
        let apex = [0.5 * (spine_top[0] + wall_top[0]), self.height];
        let lumbar = [-20.0 + self.lordosis, 0.45 * top];
        let sacrum = [-45.0, 0.23 * top];
        Ok(ControlPoints {
            spine: vec![spine_top, lumbar, sacrum, coccyx],
            pelvic_floor: vec![coccyx, floor_mid, pubis],
            pelvic_bone: vec![pubis, symphysis_top],
            abdominal_wall: vec![symphysis_top, wall_mid, wall_top],
            diaphragm: vec![wall_top, apex, spine_top],
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_field_is_set_by_its_name() {
        let mut a = Anatomy::default();
        for (i, (name, ..)) in FIELDS.iter().enumerate() {
            a.set(name, 1000.0 + i as f64).unwrap();
            assert_eq!(a.values()[i], 1000.0 + i as f64, "{name}");
        }
        let e = a.set("outlett", 1.0).unwrap_err().to_string();
        assert!(e.contains("outlett") && e.contains("outlet,"), "{e}");
    }

    #[test]
    fn out_of_range_fields_are_named() {
        let mut a = Anatomy::default();
        a.set("floor_sag", 61.0).unwrap();
        let e = a.control_points().unwrap_err().to_string();
        assert!(e.contains("anatomy.floor_sag = 61"), "{e}");
    }
}
