//! The mesh's share of an identification's uncertainty (issue 55): the fit made again on
//! the specimen's cells × [`REFINE`] and extrapolated by Richardson
//! ([`models::verify::richardson`]) to the E and ν the converged model would fit, f∞. The
//! fit on the specimen's own cells, f₁, is off it by its discretization error; its interval
//! is Roache's grid convergence index (J. Fluids Eng. 116 (1994) 405),
//!
//! GCI = F_s |f₁ − f∞|,
//!
//! with F_s = [`SAFETY_OBSERVED`] when the three fits converge at an observed order of at
//! least [`MIN_ORDER`] (extrapolated at the smaller of it and [`MAX_ORDER`], as Roache
//! advises where the observed order exceeds the formal one), and otherwise f∞ taken as the
//! finest fit and F_s = [`SAFETY_UNOBSERVED`] (his factor where no order is observed). The
//! total interval adds it to the noise's ±1.96 σ in quadrature, the two taken as
//! independent 95 % half-widths.
//!
//! Each finer fit starts at the ν of the next coarser one. Mesh size h ∝ (n_x n_y
//! n_z)^(−1/3) of each fit's cells (the refined cells rounded to whole numbers).
//!
//! The shipped sets' refits are stored ([`STORED`]): the neo-Hookean tet10 fit on 12 × 32 ×
//! 28 cells takes about ten minutes and 3.4 GB, so the reports use the stored fits once the
//! fit on the specimen's cells has matched its stored value (to [`STORED_MATCH`] of its σ).

use std::path::Path;
use std::time::Instant;

use anyhow::{ensure, Context, Result};
use models::verify::richardson::{limit, observed_order};
use serde::{Deserialize, Serialize};

use super::identify::{refit, Fit, ModelForm};
use super::measurements::{Measurements, Specimen};

/// The refinements of the specimen's cells the fit is made again on, beyond its own (×1).
pub const REFINE: [f64; 2] = [1.5, 2.0];
/// Roache's safety factor for a three-mesh study at its observed order.
pub const SAFETY_OBSERVED: f64 = 1.25;
/// Roache's safety factor where the order is not observed.
pub const SAFETY_UNOBSERVED: f64 = 3.0;
/// The lowest observed order trusted for the extrapolation.
pub const MIN_ORDER: f64 = 0.5;
/// The highest order extrapolated at: a quadratic tetrahedron's outputs converge at most as
/// h³ (displacements in L², smooth fields); a higher observed order (the shipped sets' ν:
/// 3.4 and 4.3) is taken as 3, which extrapolates further.
pub const MAX_ORDER: f64 = 3.0;
/// How closely the fit on the specimen's cells must match a stored one, in its standard
/// deviations, for the stored refits to stand for it: the fit is deterministic, and a
/// model change that moves it by less is below what the noise can tell.
pub const STORED_MATCH: f64 = 0.1;

/// The shipped sets' refits as `harness identify --discretization` wrote them
/// (`discretization.toml` in its out folder).
pub const STORED: &str = include_str!("../../../experiments/references/identification.toml");
/// Where [`STORED`] lives, for messages.
pub const STORED_PATH: &str = "experiments/references/identification.toml";

/// The fit on one mesh.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MeshFit {
    /// Cells along x, y and z.
    pub cells: [u32; 3],
    /// Young's modulus fitted (MPa).
    pub e: f64,
    /// Poisson's ratio fitted.
    pub nu: f64,
    /// Runs of the scene the fit made.
    pub runs: usize,
    /// The fit's wall time (s).
    pub seconds: f64,
    /// Whether ν ran to an end of its search interval on this mesh.
    #[serde(default)]
    pub at_bound: bool,
}

impl MeshFit {
    /// The fit `fit` on `cells`, made in `seconds`.
    fn of(fit: &Fit, cells: [u32; 3], seconds: f64) -> Self {
        Self {
            cells,
            e: fit.e,
            nu: fit.nu,
            runs: fit.evaluations,
            seconds,
            at_bound: fit.at_bound,
        }
    }

    /// The mesh size relative to `base`'s: (Π base / Π cells)^(1/3).
    fn size(&self, base: [u32; 3]) -> f64 {
        let volume = |c: [u32; 3]| c.iter().map(|&n| f64::from(n)).product::<f64>();
        (volume(base) / volume(self.cells)).cbrt()
    }
}

/// What the refits say of one parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Share {
    /// The value the converged model would fit: extrapolated, or the finest fit's.
    pub limit: f64,
    /// The observed order, where it was at least [`MIN_ORDER`].
    pub observed: Option<f64>,
    /// The 95 % half-width of the discretization error of the fit on the specimen's cells
    /// (the GCI).
    pub halfwidth: f64,
}

impl Share {
    /// The GCI of the first of `f` on meshes of sizes `h` (coarse to fine).
    fn of(h: [f64; 3], f: [f64; 3]) -> Self {
        let observed = observed_order(h, f[0] - f[1], f[1] - f[2])
            .ok()
            .filter(|&p| p >= MIN_ORDER);
        match observed {
            Some(p) => {
                let limit = limit(h, f, p.min(MAX_ORDER));
                Self {
                    limit,
                    observed,
                    halfwidth: SAFETY_OBSERVED * (f[0] - limit).abs(),
                }
            }
            None => Self {
                limit: f[2],
                observed,
                halfwidth: SAFETY_UNOBSERVED * (f[0] - f[2]).abs(),
            },
        }
    }

    /// The order extrapolated at: the observed one, at most [`MAX_ORDER`].
    pub fn order(&self) -> Option<f64> {
        self.observed.map(|p| p.min(MAX_ORDER))
    }

    /// The total 95 % half-width with the statistical one `statistical`.
    pub fn total(&self, statistical: f64) -> f64 {
        statistical.hypot(self.halfwidth)
    }
}

/// The mesh's share of a fit: the fits on three meshes and what they say of E and ν.
#[derive(Debug, Clone, PartialEq)]
pub struct Discretization {
    /// The fits on the specimen's cells and on the refined ones, coarse to fine.
    pub meshes: [MeshFit; 3],
    /// The grading β of every mesh's layers (the specimen's `mesh_grading`).
    pub grading: f64,
    /// E's share.
    pub e: Share,
    /// ν's share.
    pub nu: Share,
}

impl Discretization {
    /// Whether ν ran to an end of its search interval on a finer mesh: the converged model
    /// then fits no admissible ν, and the share is at least what it says.
    pub fn at_bound(&self) -> bool {
        self.meshes.iter().any(|m| m.at_bound)
    }

    /// The shares from fits on three meshes, coarse to fine, graded with β = `grading`.
    pub fn of(meshes: [MeshFit; 3], grading: f64) -> Result<Self> {
        let h = meshes.each_ref().map(|m| m.size(meshes[0].cells));
        ensure!(
            h[0] > h[1] && h[1] > h[2],
            "the meshes {:?}, {:?}, {:?} are not ever finer",
            meshes[0].cells,
            meshes[1].cells,
            meshes[2].cells
        );
        Ok(Self {
            e: Share::of(h, meshes.each_ref().map(|m| m.e)),
            nu: Share::of(h, meshes.each_ref().map(|m| m.nu)),
            meshes,
            grading,
        })
    }

    /// Fits `model` to `m` again on the specimen's cells × each of [`REFINE`], each from the
    /// ν of the next coarser fit, beside `fit` (on the specimen's cells, made in
    /// `seconds`). `observe(cells, ν, χ²)` after each run.
    pub fn measure(
        m: &Measurements,
        model: &ModelForm,
        fit: &Fit,
        seconds: f64,
        observe: &(dyn Fn([u32; 3], f64, f64) + Sync),
    ) -> Result<Self> {
        let mut meshes = vec![MeshFit::of(fit, m.specimen.cells, seconds)];
        for refine in REFINE {
            let mut finer = m.clone();
            finer.specimen.cells = m
                .specimen
                .cells
                .map(|n| (f64::from(n) * refine).round() as u32);
            let cells = finer.specimen.cells;
            let start = Instant::now();
            let nu = meshes.last().map_or(fit.nu, |f| f.nu);
            let fit = refit(&finer, model, nu, &|nu, chi2| observe(cells, nu, chi2))
                .with_context(|| format!("the fit on {cells:?} cells"))?;
            meshes.push(MeshFit::of(&fit, cells, start.elapsed().as_secs_f64()));
        }
        let meshes: [MeshFit; 3] = meshes.try_into().expect("three meshes");
        Self::of(meshes, m.specimen.mesh_grading)
    }
}

/// Writes the refits of each (set, model, share) in `fits` to `path` (atomically) in
/// [`STORED`]'s format, `measured` saying how.
pub fn write(
    fits: &[(&str, ModelForm, &Discretization)],
    measured: &str,
    path: &Path,
) -> Result<()> {
    let stored = Stored {
        measured: measured.into(),
        fit: fits
            .iter()
            .map(|(set, model, d)| StoredFit {
                set: (*set).into(),
                material: model.law.name().into(),
                element: model.element.name().into(),
                mesh_grading: d.grading,
                mesh: d.meshes.to_vec(),
            })
            .collect(),
    };
    crate::atomic::write_atomic(path, toml::to_string(&stored)?.as_bytes())
}

/// The refits as [`STORED`] holds them.
#[derive(Debug, Serialize, Deserialize)]
struct Stored {
    /// How they were measured: the command and the harness version as written; the copy in
    /// `experiments/references` adds the date and the commit by hand.
    measured: String,
    fit: Vec<StoredFit>,
}

/// One set's refits.
#[derive(Debug, Serialize, Deserialize)]
struct StoredFit {
    set: String,
    material: String,
    element: String,
    /// The specimen's `mesh_grading`, which every refit keeps.
    #[serde(default = "super::measurements::uniform")]
    mesh_grading: f64,
    mesh: Vec<MeshFit>,
}

/// The stored refits of the shipped set `set` with `model` on the cells and grading of
/// `specimen`, and how they were measured: `Ok(None)` where none are stored; an error where
/// the stored fit on these cells differs from `fit` by more than [`STORED_MATCH`] of its σ
/// (the model changed since they were measured). The first mesh's fit is then `fit`, made
/// in `seconds`; `Ok(None)` too where ν was given.
pub fn stored(
    set: &str,
    model: &ModelForm,
    specimen: &Specimen,
    fit: &Fit,
    seconds: f64,
) -> Result<Option<(Discretization, String)>> {
    let cells = specimen.cells;
    let Stored {
        measured,
        fit: fits,
    } = toml::from_str(STORED).with_context(|| format!("reading {STORED_PATH}"))?;
    let Some(entry) = fits.into_iter().find(|f| {
        f.set == set
            && f.material == model.law.name()
            && f.element == model.element.name()
            && f.mesh_grading == specimen.mesh_grading
            && f.mesh.first().is_some_and(|m| m.cells == cells)
    }) else {
        return Ok(None);
    };
    let meshes: [MeshFit; 3] = entry.mesh.try_into().map_err(|m: Vec<MeshFit>| {
        anyhow::anyhow!("{STORED_PATH}: set {set} has {} meshes, not 3", m.len())
    })?;
    let first = &meshes[0];
    let Some(sigma_nu) = fit.sigma_nu else {
        return Ok(None);
    };
    ensure!(
        (first.e - fit.e).abs() <= STORED_MATCH * fit.sigma_e
            && (first.nu - fit.nu).abs() <= STORED_MATCH * sigma_nu,
        "set {set} with {model} now fits E = {} and ν = {} on {cells:?} cells, the stored \
         refits ({STORED_PATH}, {}) E = {} and ν = {}: the model changed since they were \
         measured; run `harness identify --set {set} --discretization` and copy its \
         discretization.toml there",
        fit.e,
        fit.nu,
        measured,
        first.e,
        first.nu
    );
    let [_, finer, finest] = meshes;
    let meshes = [MeshFit::of(fit, cells, seconds), finer, finest];
    Ok(Some((
        Discretization::of(meshes, specimen.mesh_grading)?,
        measured,
    )))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::studies::identify::{fixtures::synthetic, identify};
    use models::assembly::tetrahedra::Tetrahedron;
    use models::element::Law;

    fn mesh(cells: [u32; 3], e: f64, nu: f64) -> MeshFit {
        MeshFit {
            cells,
            e,
            nu,
            runs: 2,
            seconds: 1.0,
            at_bound: false,
        }
    }

    /// Fits that follow f(h) = f∞ + C h³ on cells × 1, 1.5, 2 give back f∞ and order 3, and
    /// the GCI 1.25 |f₁ − f∞|; fits that converge at order 6 are extrapolated at order 3;
    /// fits that change direction give the finest fit and three times the change to it.
    #[test]
    fn the_share_is_richardsons_limit_with_roaches_factors() {
        let cells = [[6, 16, 14], [9, 24, 21], [12, 32, 28]];
        let f = |h: f64| 0.48 - 0.05 * h.powi(3);
        let h = [1.0, 1.0 / 1.5, 0.5];
        let d = Discretization::of([0, 1, 2].map(|k| mesh(cells[k], 0.05, f(h[k]))), 1.0).unwrap();
        assert!((d.nu.observed.unwrap() - 3.0).abs() < 1e-9, "{:?}", d.nu);
        assert!((d.nu.limit - 0.48).abs() < 1e-12, "{:?}", d.nu);
        assert!((d.nu.halfwidth - 1.25 * 0.05).abs() < 1e-12, "{:?}", d.nu);
        // E does not change with the mesh: no order, no share.
        assert_eq!((d.e.observed, d.e.halfwidth), (None, 0.0));
        // Order 6 is extrapolated at 3: from the finest fit by its last change times
        // h₃³ / (h₂³ − h₃³) = 0.125 / (8/27 − 0.125) = 27/37.
        let steep = h.map(|h: f64| 0.48 - 0.05 * h.powi(6));
        let d = Discretization::of([0, 1, 2].map(|k| mesh(cells[k], 0.05, steep[k])), 1.0).unwrap();
        assert!((d.nu.observed.unwrap() - 6.0).abs() < 1e-9, "{:?}", d.nu);
        assert_eq!(d.nu.order(), Some(3.0));
        let limit = steep[2] + (steep[2] - steep[1]) * 27.0 / 37.0;
        assert!((d.nu.limit - limit).abs() < 1e-12, "{:?}", d.nu);
        // At the lower order the extrapolation goes beyond the true limit: the GCI errs wide.
        assert!(d.nu.limit > 0.48, "{:?}", d.nu);
        assert!((d.nu.halfwidth - 1.25 * (steep[0] - limit).abs()).abs() < 1e-12);
        let zigzag = [0.45, 0.47, 0.46];
        let d =
            Discretization::of([0, 1, 2].map(|k| mesh(cells[k], 0.05, zigzag[k])), 1.0).unwrap();
        assert_eq!(d.nu.observed, None);
        assert_eq!(d.nu.limit, 0.46);
        assert!((d.nu.halfwidth - 3.0 * 0.01).abs() < 1e-12, "{:?}", d.nu);
        assert!(!d.at_bound());
        let mut bound = [0, 1, 2].map(|k| mesh(cells[k], 0.05, zigzag[k]));
        bound[2].at_bound = true;
        assert!(Discretization::of(bound, 1.0).unwrap().at_bound());
        let coarser = [cells[0], cells[2], cells[1]].map(|c| mesh(c, 0.05, 0.45));
        let e = Discretization::of(coarser, 1.0).unwrap_err();
        assert!(e.to_string().contains("not ever finer"), "{e}");
    }

    /// Noise-free data of the neo-Hookean tet10 model with E = 0.05 MPa and ν = 0.45 on a
    /// mesh four times finer than the specimen's 2 × 4 × 4 cells stand for the converged
    /// model's: the fit on the specimen's cells is off by many σ, and the refits on × 1.5
    /// and × 2 say by how much — their limit lies nearer the data's values than the fit
    /// (measured: ν 0.320 → limit 0.473 against 0.45; E 0.04925 → 0.05028 against 0.05),
    /// and the GCI covers the fit's error. (The linear tet4 model's ν fits go 0.285, 0.208,
    /// 0.233 on 4 × 8 × 6 cells × 1, 1.5, 2 against 0.3 on × 4: no order, the finest fit
    /// and three times the change, which covers the error too.)
    #[test]
    fn the_refits_find_the_coarse_fits_error_against_a_fine_meshs_data() {
        let model = ModelForm {
            law: Law::NeoHookean,
            element: Tetrahedron::Tet10,
        };
        let (e, nu) = (0.05, 0.45);
        let coarse = [2, 4, 4];
        let m = synthetic(&model, e, nu, coarse.map(|n| 4 * n), coarse);
        let fit = identify(&m, &model, None, &|_, _| {}).unwrap();
        let d = Discretization::measure(&m, &model, &fit, 0.0, &|_, _, _| {}).unwrap();
        println!("{d:#?}");
        assert!(
            (fit.nu - nu).abs() > 10.0 * fit.sigma_nu.unwrap(),
            "the mesh must matter here"
        );
        for (name, fitted, truth, share) in [("E", fit.e, e, d.e), ("ν", fit.nu, nu, d.nu)] {
            let (error, left) = ((fitted - truth).abs(), (share.limit - truth).abs());
            println!(
                "{name}: error of the fit {error:.2e}, of the limit {left:.2e}, GCI {:.2e}",
                share.halfwidth
            );
            assert!(share.observed.is_some(), "{name}: {share:?}");
            assert!(left < 0.5 * error, "{name}: {share:?}");
            assert!(share.halfwidth > error, "{name}: {share:?}");
        }
    }
}
