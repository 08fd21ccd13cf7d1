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

impl Anatomy {
    /// Control points of the outline; errors name a parameter out of its range.
    pub fn control_points(&self) -> Result<ControlPoints, SceneError> {
        let checks = [
            ("height", self.height, 100.0, 600.0),
            ("depth", self.depth, 60.0, 400.0),
            ("dome", self.dome, 0.0, 150.0),
            ("lordosis", self.lordosis, -20.0, 80.0),
            ("outlet", self.outlet, 50.0, 200.0),
            ("pelvic_tilt", self.pelvic_tilt, -10.0, 60.0),
            ("floor_sag", self.floor_sag, 0.0, 60.0),
            ("symphysis", self.symphysis, 10.0, 100.0),
            ("wall_bulge", self.wall_bulge, -20.0, 100.0),
        ];
        for (name, value, lo, hi) in checks {
            if !(value.is_finite() && value >= lo && value <= hi) {
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
