//! The abdomen beside the body (issue 26): the static response to the press over the
//! range of intra-abdominal pressures people reach — floor descent, apex and wall
//! displacement, pelvic-floor stress, and the mean pressure of the contents, the model's
//! intra-abdominal pressure — on the defaults (the wall braced) and with the wall free,
//! beside published figures ([`PUBLISHED`]).

use anyhow::Result;
use models::scene::abdomen::Abdomen;
use models::scene::Scene;

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
