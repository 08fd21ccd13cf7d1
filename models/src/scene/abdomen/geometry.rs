//! The boundary of the midsagittal cavity (seed 003 §5.4): five parts given by control
//! points, joined end to start in counter-clockwise order (x anterior, y superior, mm):
//! spine (posterior, top → coccyx), pelvic floor (coccyx → pubic bone), pelvic bone
//! (→ top of the pubic symphysis), abdominal wall (anterior, → lower rib margin), diaphragm
//! (→ back to the spine). Each part is an interpolating centripetal Catmull–Rom spline
//! (Yuksel, Schaefer & Keyser 2011) through its control points — seed 003 §5.3 uses
//! Catmull–Rom curves; the centripetal variant cannot form cusps or loops within a segment.

use serde::{Deserialize, Serialize};

use crate::scene::SceneError;

/// The boundary parts in boundary order.
pub const PARTS: [&str; 5] = [
    "spine",
    "pelvic_floor",
    "pelvic_bone",
    "abdominal_wall",
    "diaphragm",
];

/// Control points of the five parts (mm).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlPoints {
    /// The spine, posterior, from the top down to the coccyx ([x, y], mm).
    pub spine: Vec<[f64; 2]>,
    /// The pelvic floor, from the coccyx to the pubic bone ([x, y], mm).
    pub pelvic_floor: Vec<[f64; 2]>,
    /// The pelvic bone, up to the top of the pubic symphysis ([x, y], mm).
    pub pelvic_bone: Vec<[f64; 2]>,
    /// The abdominal wall, anterior, up to the lower rib margin ([x, y], mm).
    pub abdominal_wall: Vec<[f64; 2]>,
    /// The diaphragm, from the rib margin back to the top of the spine ([x, y], mm).
    pub diaphragm: Vec<[f64; 2]>,
}

impl ControlPoints {
    /// The parts in boundary order.
    pub fn parts(&self) -> [&[[f64; 2]]; 5] {
        [
            &self.spine,
            &self.pelvic_floor,
            &self.pelvic_bone,
            &self.abdominal_wall,
            &self.diaphragm,
        ]
    }
}

/// A sampled closed boundary: vertices in counter-clockwise order and, for each segment
/// (vertex i → i + 1, wrapping), the part it belongs to.
#[derive(Debug, Clone)]
pub struct Boundary {
    /// The vertices in counter-clockwise order ([x, y], mm); the last joins the first.
    pub vertices: Vec<[f64; 2]>,
    /// For each segment (vertex i → i + 1, wrapping), the index of its part in [`PARTS`].
    pub segment_part: Vec<usize>,
    /// The vertex of each of the [`LANDMARKS`], in their order.
    pub landmarks: [usize; 3],
}

fn geometry_error(part: &str, what: String) -> SceneError {
    SceneError::Config(format!("geometry, part `{part}`: {what}"))
}

/// Point on the centripetal Catmull–Rom segment between p1 and p2 at local parameter s ∈ [0, 1]
/// (Barry–Goldman pyramidal form with knot spacing |Δp|^½).
fn catmull_rom(p: [[f64; 2]; 4], s: f64) -> [f64; 2] {
    let dist = |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).hypot(a[1] - b[1])).sqrt().max(1e-12);
    let t0 = 0.0;
    let t1 = t0 + dist(p[0], p[1]);
    let t2 = t1 + dist(p[1], p[2]);
    let t3 = t2 + dist(p[2], p[3]);
    let t = t1 + s * (t2 - t1);
    let lerp = |a: [f64; 2], b: [f64; 2], ta: f64, tb: f64| {
        let w = (t - ta) / (tb - ta);
        [a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1])]
    };
    let a1 = lerp(p[0], p[1], t0, t1);
    let a2 = lerp(p[1], p[2], t1, t2);
    let a3 = lerp(p[2], p[3], t2, t3);
    let b1 = lerp(a1, a2, t0, t2);
    let b2 = lerp(a2, a3, t1, t3);
    lerp(b1, b2, t1, t2)
}

/// A dense polyline through the control points (end segments use mirrored phantom points).
/// 2,048 points per span: fine enough that samplings graded down to ~0.01 mm
/// ([`Spacing`]) still lie on the spline rather than on a polyline's corners.
fn dense_curve(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = points.len();
    let mirror = |a: [f64; 2], b: [f64; 2]| [2.0 * a[0] - b[0], 2.0 * a[1] - b[1]];
    let get = |i: isize| -> [f64; 2] {
        if i < 0 {
            mirror(points[0], points[1])
        } else if i as usize >= n {
            mirror(points[n - 1], points[n - 2])
        } else {
            points[i as usize]
        }
    };
    let mut out = vec![points[0]];
    const PER_SEGMENT: usize = 2048;
    for i in 0..n - 1 {
        let quad = [
            get(i as isize - 1),
            get(i as isize),
            get(i as isize + 1),
            get(i as isize + 2),
        ];
        for k in 1..=PER_SEGMENT {
            out.push(catmull_rom(quad, k as f64 / PER_SEGMENT as f64));
        }
    }
    out
}

/// How a part's boundary is sampled: spacing `h` along its length, refined towards both of
/// its ends — where a membrane meets bone or another membrane and the stresses are singular
/// (a fixed–free transition: r^-½, Szabó & Babuška 1991 §10) — as h·(s/R)^β within
/// R = min([`GRADING_RADIUS`], L/2) of an end, s the arc length from it. β = `grading` = 0 is
/// uniform. Against an r^λ displacement singularity a mesh graded as r^β converges in energy
/// as H^(λ/(1−β)) up to the element's H^p (Babuška, Kellogg & Pitkäranta, Numer. Math. 33
/// (1979) 447), and mean outputs such as a mean stress at twice that rate. The uniform
/// meshes' order near 1 in the mean outputs says λ ≈ ½ here; β = ½ then gives those outputs
/// order 2, the 6-node element's stress order (measured: 1.96 against 1.40 uniform,
/// `tests/scenes/abdomen.rs`). Full energy order would need β ≥ 1 − λ/p = ¾, where the mesher
/// makes degenerate triangles at fine targets, so `mesh_grading` stops at ½.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spacing {
    /// The spacing along a part away from its ends (mm).
    pub h: f64,
    /// The grading exponent β towards the ends (0: uniform).
    pub grading: f64,
}

/// Radius of the graded zone at each end of a part (mm).
pub const GRADING_RADIUS: f64 = 60.0;

impl Spacing {
    /// Spacing `h` everywhere.
    pub fn uniform(h: f64) -> Self {
        Self { h, grading: 0.0 }
    }

    /// Number of segments up to arc length `s` on a part of length `l` — the integral of
    /// 1/spacing, a strictly increasing map from [0, l] onto [0, count(l, l)].
    fn count(&self, s: f64, l: f64) -> f64 {
        let r = GRADING_RADIUS.min(0.5 * l);
        let b = self.grading;
        let end = |s: f64| r / (self.h * (1.0 - b)) * (s / r).powf(1.0 - b);
        let zone = end(r);
        if s <= r {
            end(s)
        } else if s <= l - r {
            zone + (s - r) / self.h
        } else {
            2.0 * zone + (l - 2.0 * r) / self.h - end(l - s)
        }
    }

    /// The arc length at which [`count`](Self::count) reaches `n`.
    fn arc_length(&self, n: f64, l: f64) -> f64 {
        let r = GRADING_RADIUS.min(0.5 * l);
        let b = self.grading;
        let end_inverse = |n: f64| r * (n.max(0.0) * self.h * (1.0 - b) / r).powf(1.0 / (1.0 - b));
        let zone = self.count(r, l);
        let total = self.count(l, l);
        if n <= zone {
            end_inverse(n)
        } else if n <= total - zone {
            r + (n - zone) * self.h
        } else {
            l - end_inverse(total - n)
        }
    }
}

/// Arc length at each point of a polyline.
fn arc_lengths(curve: &[[f64; 2]]) -> Vec<f64> {
    let mut cumulative = vec![0.0];
    for w in curve.windows(2) {
        let l = (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]);
        cumulative.push(cumulative.last().unwrap() + l);
    }
    cumulative
}

/// Resamples a polyline at steps of about `spacing` along its arc length (at least one
/// segment), each step then split into 2^`subdivisions` (equal steps of the segment count,
/// so that vertex k · 2^subdivisions is vertex k of the unsplit sampling). With a `mark` (an
/// arc length), the vertex nearest to it in segment count is moved onto it, the steps on
/// either side evened out. Returns the vertices and the index of the vertex at the mark.
fn resample(
    curve: &[[f64; 2]],
    spacing: Spacing,
    subdivisions: u32,
    mark: Option<f64>,
) -> (Vec<[f64; 2]>, Option<usize>) {
    let cumulative = arc_lengths(curve);
    let total = *cumulative.last().unwrap();
    let n_total = spacing.count(total, total);
    let unsplit = (n_total.round() as usize).max(1);
    let segments = unsplit << subdivisions;
    // The mark's vertex and its segment count; at an end, the end itself.
    let (at, n_at) = match mark {
        Some(s) => {
            let n = spacing.count(s, total);
            let m = ((n / n_total * unsplit as f64).round() as usize).min(unsplit);
            match m {
                0 => (0, 0.0),
                m if m == unsplit => (segments, n_total),
                m => (m << subdivisions, n),
            }
        }
        None => (0, 0.0),
    };
    let count_at = |k: usize| match k <= at {
        true if at > 0 => n_at * k as f64 / at as f64,
        true => 0.0,
        false => n_at + (n_total - n_at) * (k - at) as f64 / (segments - at) as f64,
    };
    let mut out = Vec::with_capacity(segments + 1);
    let mut j = 0;
    for k in 0..=segments {
        let s = spacing.arc_length(count_at(k), total);
        while j + 2 < cumulative.len() && cumulative[j + 1] < s {
            j += 1;
        }
        let span = cumulative[j + 1] - cumulative[j];
        let w = if span > 0.0 {
            ((s - cumulative[j]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push([
            curve[j][0] + w * (curve[j + 1][0] - curve[j][0]),
            curve[j][1] + w * (curve[j + 1][1] - curve[j][1]),
        ]);
    }
    *out.last_mut().unwrap() = *curve.last().unwrap();
    (out, mark.map(|_| at))
}

/// The landmarks (output points, [`super::outputs`]): the arc-length middle of the pelvic
/// floor and of the abdominal wall, and the highest point of the diaphragm — named points of
/// the curve, vertices of every sampling, so that meshes of any resolution report the same
/// material points.
pub const LANDMARKS: [(&str, usize); 3] =
    [("floor_mid", 1), ("wall_mid", 3), ("diaphragm_apex", 4)];

/// Arc length of landmark `name` on its part's dense curve.
fn landmark_arc_length(name: &str, curve: &[[f64; 2]]) -> f64 {
    let cumulative = arc_lengths(curve);
    let total = *cumulative.last().unwrap();
    match name {
        "diaphragm_apex" => {
            let highest = (0..curve.len())
                .max_by(|&a, &b| curve[a][1].total_cmp(&curve[b][1]))
                .unwrap();
            cumulative[highest]
        }
        _ => 0.5 * total,
    }
}

fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let orient = |p: [f64; 2], q: [f64; 2], r: [f64; 2]| {
        (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])
    };
    let (d1, d2) = (orient(a, b, c), orient(a, b, d));
    let (d3, d4) = (orient(c, d, a), orient(c, d, b));
    d1 * d2 < 0.0 && d3 * d4 < 0.0
}

impl Boundary {
    /// Checks the parts (at least two points each, each part starting where the previous
    /// one ends, the last ending where the first starts), samples each spline at
    /// `spacing` and checks that the closed curve neither crosses itself nor runs clockwise.
    pub fn new(points: &ControlPoints, spacing: Spacing) -> Result<Self, SceneError> {
        Self::subdivided(points, spacing, 0)
    }

    /// The boundary of [`new`](Self::new) with each segment split into 2^`subdivisions`
    /// pieces of equal spacing count on the curve (equal arc length where the spacing is
    /// uniform): vertex k · 2^subdivisions is vertex k of `new`.
    pub fn subdivided(
        points: &ControlPoints,
        spacing: Spacing,
        subdivisions: u32,
    ) -> Result<Self, SceneError> {
        let parts = points.parts();
        let scale = parts
            .iter()
            .flat_map(|p| p.iter())
            .fold(0.0f64, |m, q| m.max(q[0].abs()).max(q[1].abs()));
        let tol = 1e-6 * scale.max(1.0);
        for (i, part) in parts.iter().enumerate() {
            if part.len() < 2 {
                return Err(geometry_error(
                    PARTS[i],
                    format!("needs at least 2 control points, has {}", part.len()),
                ));
            }
            if let Some(p) = part
                .iter()
                .find(|p| !(p[0].is_finite() && p[1].is_finite()))
            {
                return Err(geometry_error(
                    PARTS[i],
                    format!("control point {p:?} is not finite"),
                ));
            }
            let next = (i + 1) % parts.len();
            let (end, start) = (part[part.len() - 1], parts[next][0]);
            if (end[0] - start[0]).hypot(end[1] - start[1]) > tol {
                return Err(geometry_error(
                    PARTS[i],
                    format!(
                        "ends at {end:?} but `{}` starts at {start:?}: the boundary is open",
                        PARTS[next]
                    ),
                ));
            }
        }
        let mut vertices = Vec::new();
        let mut segment_part = Vec::new();
        let mut landmarks = [0; 3];
        for (i, part) in parts.iter().enumerate() {
            let curve = dense_curve(part);
            let mark = LANDMARKS.iter().position(|&(_, p)| p == i);
            let at = mark.map(|m| landmark_arc_length(LANDMARKS[m].0, &curve));
            let (sampled, at_vertex) = resample(&curve, spacing, subdivisions, at);
            if let (Some(m), Some(v)) = (mark, at_vertex) {
                landmarks[m] = vertices.len() + v;
            }
            vertices.extend_from_slice(&sampled[..sampled.len() - 1]);
            segment_part.extend(std::iter::repeat_n(i, sampled.len() - 1));
        }
        let n = vertices.len();
        landmarks.iter_mut().for_each(|v| *v %= n);
        let b = Self {
            vertices,
            segment_part,
            landmarks,
        };
        b.check_simple()?;
        if b.signed_area() <= 0.0 {
            return Err(SceneError::Config(
                "geometry: the parts run clockwise (spine → pelvic floor → pelvic bone → abdominal wall → \
                 diaphragm must go counter-clockwise with x anterior, y superior)"
                    .into(),
            ));
        }
        Ok(b)
    }

    fn segment(&self, i: usize) -> ([f64; 2], [f64; 2]) {
        (
            self.vertices[i],
            self.vertices[(i + 1) % self.vertices.len()],
        )
    }

    fn check_simple(&self) -> Result<(), SceneError> {
        let n = self.vertices.len();
        for i in 0..n {
            for j in i + 2..n {
                if i == 0 && j == n - 1 {
                    continue;
                }
                let ((a, b), (c, d)) = (self.segment(i), self.segment(j));
                if segments_cross(a, b, c, d) {
                    let (pi, pj) = (PARTS[self.segment_part[i]], PARTS[self.segment_part[j]]);
                    return Err(SceneError::Config(format!(
                        "geometry: the curve of `{pi}` crosses the curve of `{pj}` near {a:?}"
                    )));
                }
            }
        }
        Ok(())
    }

    /// Signed area (positive for counter-clockwise).
    pub fn signed_area(&self) -> f64 {
        let n = self.vertices.len();
        0.5 * (0..n)
            .map(|i| {
                let (a, b) = self.segment(i);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> ControlPoints {
        ControlPoints {
            spine: vec![[0.0, 100.0], [0.0, 0.0]],
            pelvic_floor: vec![[0.0, 0.0], [50.0, 0.0]],
            pelvic_bone: vec![[50.0, 0.0], [100.0, 0.0]],
            abdominal_wall: vec![[100.0, 0.0], [100.0, 100.0]],
            diaphragm: vec![[100.0, 100.0], [0.0, 100.0]],
        }
    }

    #[test]
    fn catmull_rom_interpolates_its_control_points() {
        let pts = vec![[0.0, 0.0], [10.0, 5.0], [20.0, -3.0], [35.0, 0.0]];
        let dense = dense_curve(&pts);
        for p in &pts {
            assert!(dense
                .iter()
                .any(|q| (q[0] - p[0]).abs() < 1e-9 && (q[1] - p[1]).abs() < 1e-9));
        }
        // Straight control points give a straight curve.
        let line = dense_curve(&[[0.0, 0.0], [1.0, 1.0], [3.0, 3.0]]);
        assert!(line.iter().all(|q| (q[0] - q[1]).abs() < 1e-9));
    }

    #[test]
    fn square_boundary_samples_and_orients() {
        let b = Boundary::new(&square(), Spacing::uniform(10.0)).unwrap();
        assert_eq!(b.vertices.len(), 40);
        assert!((b.signed_area() - 10_000.0).abs() < 1e-6);
        assert_eq!(b.segment_part.iter().filter(|&&p| p == 1).count(), 5);
    }

    #[test]
    fn bad_boundaries_name_the_part() {
        let mut open = square();
        open.pelvic_bone[1] = [90.0, 0.0];
        let e = Boundary::new(&open, Spacing::uniform(10.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("pelvic_bone") && e.contains("open"), "{e}");
        let mut few = square();
        few.spine = vec![[0.0, 100.0]];
        let e = Boundary::new(&few, Spacing::uniform(10.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("spine") && e.contains("at least 2"), "{e}");
        let mut crossing = square();
        crossing.abdominal_wall = vec![[100.0, 0.0], [-20.0, 50.0], [100.0, 100.0]];
        let e = Boundary::new(&crossing, Spacing::uniform(10.0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("crosses"), "{e}");
        let cw = ControlPoints {
            spine: vec![[0.0, 0.0], [0.0, 100.0]],
            pelvic_floor: vec![[0.0, 100.0], [100.0, 100.0]],
            pelvic_bone: vec![[100.0, 100.0], [100.0, 50.0]],
            abdominal_wall: vec![[100.0, 50.0], [100.0, 0.0]],
            diaphragm: vec![[100.0, 0.0], [0.0, 0.0]],
        };
        assert!(Boundary::new(&cw, Spacing::uniform(10.0))
            .unwrap_err()
            .to_string()
            .contains("clockwise"));
    }

    #[test]
    fn spacing_count_and_arc_length_invert_each_other() {
        for grading in [0.0, 0.5, 0.7] {
            for l in [80.0, 300.0] {
                let sp = Spacing { h: 3.0, grading };
                let total = sp.count(l, l);
                for i in 0..=100 {
                    let s = l * f64::from(i) / 100.0;
                    let n = sp.count(s, l);
                    assert!(
                        (sp.arc_length(n, l) - s).abs() < 1e-9 * l,
                        "{grading} {l} {s}"
                    );
                    // Graded alike at both ends.
                    assert!((total - sp.count(l - s, l) - n).abs() < 1e-9 * total);
                }
                if grading == 0.0 {
                    assert!((total - l / 3.0).abs() < 1e-12);
                }
            }
        }
    }

    #[test]
    fn graded_sampling_follows_the_spacing_function() {
        // A straight part 300 mm long: segment lengths h·(s/R)^β within R = 60 mm of its
        // ends (s at the segment's middle), h beyond.
        let line: Vec<[f64; 2]> = (0..=3000).map(|i| [0.1 * f64::from(i), 0.0]).collect();
        let sp = Spacing {
            h: 4.0,
            grading: 0.5,
        };
        let (v, _) = resample(&line, sp, 0, None);
        for w in v.windows(2) {
            let (a, b) = (w[0][0], w[1][0]);
            let s = (0.5 * (a + b)).min(300.0 - 0.5 * (a + b));
            let expected = 4.0 * (s / GRADING_RADIUS).min(1.0).sqrt();
            if s > 5.0 {
                assert!(((b - a) / expected - 1.0).abs() < 0.02, "at {s}: {}", b - a);
            }
        }
        assert!(v[1][0] < 0.2, "first segment {}", v[1][0]);
    }

    #[test]
    fn a_mark_becomes_a_vertex_and_subdivision_keeps_the_vertices() {
        let line: Vec<[f64; 2]> = (0..=1000).map(|i| [0.1 * f64::from(i), 0.0]).collect();
        let sp = Spacing {
            h: 7.0,
            grading: 0.5,
        };
        let (coarse, at) = resample(&line, sp, 0, Some(37.0));
        let at = at.unwrap();
        assert!((coarse[at][0] - 37.0).abs() < 1e-9);
        let (fine, fine_at) = resample(&line, sp, 2, Some(37.0));
        assert_eq!(fine_at, Some(4 * at));
        for (k, p) in coarse.iter().enumerate() {
            assert!((fine[4 * k][0] - p[0]).abs() < 1e-9);
        }
        // A mark within half a segment of an end is that end.
        assert_eq!(resample(&line, sp, 0, Some(0.001)).1, Some(0));
    }
}
