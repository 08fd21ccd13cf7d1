//! The abdomen beside the body (issue 26): the static response to the press over the
//! range of intra-abdominal pressures people reach — floor descent, apex and wall
//! displacement, pelvic-floor stress, and the mean pressure of the contents, the model's
//! intra-abdominal pressure — on the defaults (the wall braced) and with the wall free,
//! beside published figures ([`PUBLISHED`]); and at the clinical pressures themselves
//! (issue 53), driven by the contents' pressure in the clinical settings ([`clinical`]).

use anyhow::Result;
use models::scene::abdomen::Abdomen;
use models::scene::Scene;
use rayon::prelude::*;

/// The presses (N per mm of depth) the study solves for: 0.2 to 1.4 N/mm over the default
/// diaphragm of 181 mm (its line elements' length), a nominal 1.1 to 7.7 kPa.
pub const PRESSES: [f64; 7] = [0.2, 0.4, 0.6, 0.8, 1.0, 1.2, 1.4];

/// The static response at one press.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// The press (N/mm) and the press over the diaphragm's length (kPa).
    pub press: f64,
    /// The nominal pressure: the press over the diaphragm's length (kPa).
    pub nominal: f64,
    /// The contents' area-weighted mean pressure, −tr σ / 3 (kPa).
    pub pressure: f64,
    /// Downward displacement of the pelvic-floor midpoint and the diaphragm apex, outward
    /// displacement of the abdominal-wall midpoint (mm).
    pub floor_descent: f64,
    /// Downward displacement of the diaphragm apex (mm).
    pub apex_descent: f64,
    /// Outward displacement of the abdominal-wall midpoint (mm).
    pub wall_bulge: f64,
    /// Pelvic-floor stress, mean and max (kPa).
    pub floor_mean: f64,
    /// Pelvic-floor stress, max (kPa).
    pub floor_max: f64,
}

/// The response of one variant of the scene at every press: a point, or why the static
/// solve found none.
#[derive(Debug, Clone)]
pub struct Response {
    /// The variant's name.
    pub label: &'static str,
    /// The diaphragm's length (mm), over which the press makes its nominal pressure.
    pub diaphragm: f64,
    /// The response at each of [`PRESSES`], or why the static solve found none.
    pub points: Vec<Result<Point, String>>,
}

/// The two variants: the defaults, and the abdominal wall free (a passive membrane).
pub const VARIANTS: [(&str, &str); 2] = [
    ("defaults (wall braced)", "fixed"),
    ("abdominal wall free", "free"),
];

/// Solves every press on both variants.
pub fn run() -> Result<Vec<Response>> {
    VARIANTS
        .iter()
        .map(|&(label, wall)| {
            let mut s = Abdomen::new();
            s.set_str("abdominal_wall", wall)?;
            s.initialize(0.0)?;
            let length = diaphragm_length(&s);
            let points = PRESSES
                .iter()
                .map(|&press| point(&s, press, length).map_err(|e| format!("{press} N/mm: {e:#}")))
                .collect();
            Ok(Response {
                label,
                diaphragm: length,
                points,
            })
        })
        .collect()
}

/// The diaphragm's length along its line elements (mm).
fn diaphragm_length(s: &Abdomen) -> f64 {
    let Some(m) = s.meshed() else {
        return f64::NAN;
    };
    let mesh = &m.mesh;
    (0..mesh.lines().len())
        .filter(|&i| mesh.line_regions()[i] == 0)
        .map(|i| {
            let [a, b] = mesh.line(i);
            (b[0] - a[0]).hypot(b[1] - a[1])
        })
        .sum()
}

fn point(s: &Abdomen, press: f64, length: f64) -> Result<Point> {
    let u = s.static_displacement(press)?;
    let o = s.evaluate(&u, press)?;
    Ok(Point {
        press,
        nominal: 1e3 * press / length,
        pressure: 1e3 * o[13],
        floor_descent: -o[9],
        apex_descent: -o[7],
        wall_bulge: o[10],
        floor_mean: 1e3 * o[0],
        floor_max: 1e3 * o[1],
    })
}

/// The shipped pelvis configurations.
pub const CONFIGURATIONS: [&str; 5] = ["normal", "narrow", "wide", "lordotic", "tilted"];

/// The clinical pressures of the side-by-side (kPa): about sitting, a light effort, a
/// Valsalva manoeuvre (median 7.9 kPa) and bearing down (9.9 kPa; Neurourol Urodyn 40
/// (2021) 783–790).
pub const CLINICAL_PRESSURES: [f64; 4] = [2.0, 4.0, 8.0, 10.0];

/// The clinical settings (docs/theory/abdomen.md) with the neo-Hookean sheets, which hold
/// bearing down: the text settings.
pub const CLINICAL_STRINGS: [(&str, &str); 3] = [
    ("press_mode", "pressure"),
    ("formulation", "mixed"),
    ("membrane_law", "neo-hookean"),
];

/// The clinical settings' numbers (on the 300-triangle mesh of the FMU tests).
pub const CLINICAL_REALS: [(&str, f64); 4] = [
    ("cavity_nu", 0.4999),
    ("diaphragm_transverse_curvature", 0.01),
    ("floor_transverse_curvature", 1.0 / 60.0),
    ("target_triangles", 300.0),
];

/// The static response of `configuration` with `changes` to the clinical settings at each
/// of [`CLINICAL_PRESSURES`]: a start in equilibrium at the target pressure (the force
/// found is the point's press; its nominal pressure is not defined and left NaN).
pub fn clinical(configuration: &str, changes: &[(&str, f64)]) -> Vec<Result<Point, String>> {
    CLINICAL_PRESSURES
        .par_iter()
        .map(|&kpa| {
            clinical_point(configuration, changes, kpa).map_err(|e| format!("{kpa} kPa: {e:#}"))
        })
        .collect()
}

fn clinical_point(configuration: &str, changes: &[(&str, f64)], kpa: f64) -> Result<Point> {
    let mut s = clinical_abdomen(configuration, &[], changes, kpa)?;
    let mut get = |name: &str| s.get(name);
    Ok(Point {
        press: get("press_total")?,
        nominal: f64::NAN,
        pressure: 1e3 * get("cavity_pressure")?,
        floor_descent: -get("floor_mid_uy")?,
        apex_descent: -get("apex_uy")?,
        wall_bulge: get("wall_mid_ux")?,
        floor_mean: 1e3 * get("floor_stress_mean")?,
        floor_max: 1e3 * get("floor_stress_max")?,
    })
}

/// The abdomen of `configuration` in the clinical settings with `strings` and `reals`
/// changed, started in equilibrium at `kpa` kPa.
pub fn clinical_abdomen(
    configuration: &str,
    strings: &[(&str, &str)],
    reals: &[(&str, f64)],
    kpa: f64,
) -> Result<Abdomen> {
    let mut all_strings = CLINICAL_STRINGS.to_vec();
    all_strings.push(("configuration", configuration));
    all_strings.extend_from_slice(strings);
    let mut all_reals = CLINICAL_REALS.to_vec();
    all_reals.extend_from_slice(reals);
    all_reals.push(("target_pressure", 1e-3 * kpa));
    Ok(Abdomen::initialized(&all_strings, &all_reals)?)
}

/// A published figure: what was measured, the value, on whom and how, the source.
#[derive(Debug, Clone, Copy)]
pub struct Figure {
    /// What was measured.
    pub quantity: &'static str,
    /// The value as the source gives it, with its unit.
    pub value: &'static str,
    /// On whom and how it was measured.
    pub condition: &'static str,
    /// The publication.
    pub source: &'static str,
}

/// Published figures to set the model beside (the values as the sources' abstracts give
/// them; kPa from mmHg and cmH₂O by 0.1333 and 0.0981).
pub const PUBLISHED: [Figure; 7] = [
    Figure {
        quantity: "pelvic-floor (bladder-neck) descent",
        value: "17.4 mm (1.2–40.2)",
        condition: "maximal Valsalva, supine; 118 nulligravid women, translabial ultrasound; pressure not measured",
        source: "Dietz et al., Am J Obstet Gynecol 191 (2004) 95–99",
    },
    Figure {
        quantity: "pelvic-floor descent",
        value: "19.1 ± 7.4 mm",
        condition: "straining, sitting upright; 16 women, open MRI",
        source: "Neurourol Urodyn 20 (2001) 167–174",
    },
    Figure {
        quantity: "levator descent",
        value: "27.2 mm",
        condition: "4 kPa bear-down in a subject-specific model checked against one volunteer's dynamic MRI",
        source: "Noakes et al., J Biomech 41 (2008)",
    },
    Figure {
        quantity: "diaphragm dome excursion (right dome)",
        value: "32 ± 15 mm, 32 ± 13 mm",
        condition: "forced breathing, coughing; 8 nulliparous women, real-time MRI",
        source: "Talasz et al., Int Urogynecol J 22 (2011) 61–68",
    },
    Figure {
        quantity: "abdominal wall",
        value: "drawn in: the muscles thicken, the abdominal diameter decreases",
        condition: "straining and Valsalva; 4 women, dynamic MRI",
        source: "Talasz et al., Eur J Obstet Gynecol Reprod Biol 164 (2012) 227–233",
    },
    Figure {
        quantity: "intra-abdominal pressure",
        value: "2.2 sitting, 2.7 standing, 14.3 coughing kPa",
        condition: "20 healthy adults, bladder catheter",
        source: "Cobb et al., J Surg Res 129 (2005) 231–235",
    },
    Figure {
        quantity: "intra-abdominal pressure",
        value: "3.4–7.0 kPa lifting 13.6–20.4 kg, 4.8 kPa plank",
        condition: "women, vaginal sensors (review, Table 2)",
        source: "Sports Med 50 (2020) 471–484",
    },
];
