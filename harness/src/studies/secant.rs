//! Seed 002's own identification (ch. 4.1), applied to a measurement set beside the FE fit:
//! the block taken as a bar in uniaxial tension,
//!
//! E = (f₂ − f₁) / (l₂ − l₁) · l₀ / A (eq. 4.1, the secant of force against length over the
//! gross section A = width · thickness and the length l₀ between the grips; the thesis
//! prints the factor garbled as 1 / (A l₀), which is not a modulus),
//!
//! ν = (b₀ − b₁) / b₁ · l₀ / (l₁ − l₀) (eq. 4.2, the lateral strain over the axial strain at
//! the largest pull).
//!
//! What the data allow, and what is assumed: f₁, f₂ are the forces at the first and the last
//! pull (the whole curve's secant); A is the uncut section (the seed's bars had no cut); the
//! lateral dimension b is the block's thickness, read as the mean scanned height over the
//! segment between the cut (10 mm clear of it) and the pulled face — the bottom taken to stay
//! at z = 0, since the scans see only the top. The seed measured the width of uncut bars
//! with calipers.

use super::measurements::Measurements;

/// The distance (mm) from the cut plane inside which scanned heights are left out of the
/// thickness: the flanks' opening tilts the surface there.
const CLEAR_OF_CUT: f64 = 10.0;

/// What seed 002's eqs. 4.1 and 4.2 give for a set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SeedMethod {
    /// E by eq. 4.1 (MPa).
    pub e: f64,
    /// The gross section A (mm²) and the length l₀ (mm) it used.
    pub section: f64,
    /// The length between the grips (mm).
    pub length: f64,
    /// The mean scanned height b₁ (mm) over the segment between the cut and the pulled
    /// face at the largest pull, and ν by eq. 4.2 from it; `None` without scans there.
    pub thickness: Option<f64>,
    /// ν by eq. 4.2 (a material value only inside (0, 0.5)).
    pub nu: Option<f64>,
}

impl SeedMethod {
    /// Eqs. 4.1 and 4.2 on the set `m` (at least two pulls, the set's loader checks).
    pub fn of(m: &Measurements) -> Self {
        let s = &m.specimen;
        let (section, length) = (s.size[0] * s.size[2], s.size[1]);
        let (first, last) = (0, m.force.len() - 1);
        let e = (m.force[last] - m.force[first]) / (m.displacement[last] - m.displacement[first])
            * length
            / section;
        let pull = m.displacement[last];
        let heights: Vec<f64> = m
            .profiles
            .iter()
            .flat_map(|scan| &scan.points)
            .filter(|(y, _)| *y >= s.y_cut + CLEAR_OF_CUT && *y <= s.size[1] + pull)
            .map(|(_, z)| *z)
            .collect();
        let thickness =
            (!heights.is_empty()).then(|| heights.iter().sum::<f64>() / heights.len() as f64);
        let nu = thickness
            .filter(|_| pull > 0.0)
            .map(|b1| (s.size[2] - b1) / b1 * length / pull);
        Self {
            e,
            section,
            length,
            thickness,
            nu,
        }
    }

    /// Whether eq. 4.2's ν is a material value (inside (0, 0.5)).
    pub fn nu_admissible(&self) -> bool {
        self.nu.is_some_and(|nu| nu > 0.0 && nu < 0.5)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::studies::measurements::{Noise, Scan, Specimen};

    /// A uniform bar 10 × 100 × 5 mm of E = 0.05 MPa and ν = 0.4 in uniaxial tension, by
    /// hand: F = E A d / l₀, thickness b₁ = b₀ (1 − ν d / l₀); the equations give E and ν
    /// back.
    #[test]
    fn a_bar_in_uniaxial_tension_gives_its_e_and_nu_back() {
        let (e, nu, l0, b0, a) = (0.05, 0.4, 100.0, 5.0, 10.0 * 5.0);
        let displacement = vec![0.0, 1.0, 2.0];
        let force = displacement.iter().map(|d| e * a * d / l0).collect();
        let b1 = b0 * (1.0 - nu * 2.0 / l0);
        let m = Measurements {
            specimen: Specimen {
                size: [10.0, l0, b0],
                cells: [1, 1, 1],
                mesh_grading: 1.0,
                y_cut: 0.0,
                cut_depth: 0.0,
                cut_x: 0.0,
                support: "sliding".into(),
                scan_lines: vec![5.0],
                noise: Noise {
                    force: 0.01,
                    profile: 0.01,
                },
            },
            displacement,
            force,
            profiles: vec![Scan {
                x: 5.0,
                points: (0..=100).map(|y| (f64::from(y), b1)).collect(),
            }],
        };
        let s = SeedMethod::of(&m);
        assert!((s.e - e).abs() < 1e-12 * e, "{}", s.e);
        // Eq. 4.2 divides the lateral change by b₁, the deformed width: ν / (1 − ν d/l₀),
        // 0.4 · 1.008 here, equal to ν to first order in the strain.
        let nu_42 = s.nu.unwrap();
        assert!(
            (nu_42 - nu / (1.0 - nu * 2.0 / l0)).abs() < 1e-12,
            "{nu_42}"
        );
        assert!(s.nu_admissible());
    }
}
