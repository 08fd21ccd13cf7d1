//! The identification report: E and ν of a cut-block model fitted to a measurement set, with
//! intervals, correlation and the model-form check (residuals against the stated noise);
//! the profile deviations against seed 002's acceptance criterion; plots of forces and
//! profiles, data against model; the same as JSON for scripts. The full default report fits
//! the shipped sets A and C with the matching model (neo-Hookean tet10) and with the linear
//! one, the quick one set C with the matching model.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::Result;
use indicatif::{MultiProgress, ProgressBar, ProgressStyle};
use models::scene::cutblock::PROFILE_STEP;
use rayon::prelude::*;

use super::plot::{self, Axis, Chart, Curve, Mark};
use super::{Depth, Report};
use crate::studies::cut_speed_error::cubes;
use crate::studies::discretization::{
    self, Discretization, Share, SAFETY_OBSERVED, SAFETY_UNOBSERVED, STORED_PATH,
};
use crate::studies::identify::{identify, Fit, ModelForm, FORCE_LEVEL, NU_RANGE, PROFILE_LEVEL};
use crate::studies::measurements::{Measurements, Source};
use crate::studies::profiles::align;
use crate::studies::secant::SeedMethod;
use models::assembly::tetrahedra::Tetrahedron;
use models::element::Law;

/// One fit to make: a set in a folder (or a shipped one), a model, and ν if it is given.
#[derive(Debug, Clone)]
pub struct Job {
    /// Where the set's files are.
    pub data: Source,
    /// The set's name, `<S>` in its file names (e.g. `A`).
    pub set: String,
    /// The model fitted: material law and tetrahedron.
    pub model: ModelForm,
    /// Poisson's ratio held fixed, so that E alone is fitted; `None` fits ν as well.
    pub nu: Option<f64>,
    /// Whether to measure the mesh's share of the intervals by fitting again on finer
    /// meshes ([`Discretization::measure`]); without, the shipped sets use the stored
    /// refits.
    pub discretization: bool,
}

/// The mesh's share of a fit and where it comes from.
struct MeshShare {
    share: Discretization,
    /// "measured here", or the stored file and how it was measured.
    source: String,
}

/// A finished fit with its data and how long it took.
struct Done {
    job: Job,
    data: Measurements,
    fit: Fit,
    time: Duration,
    /// The mesh's share, where it was measured or stored (only for a fitted ν inside its
    /// range).
    mesh: Option<MeshShare>,
}

/// The `identify` command: one fit per job (a batch when several, run side by side),
/// reported in `out` (`report.md` with one summary table, plots, and for scripts
/// `identify.json` — in a batch `identify_<set>_<law>_<element>.json` per fit).
pub fn command(jobs: Vec<Job>, out: &Path) -> Result<PathBuf> {
    anyhow::ensure!(!jobs.is_empty(), "no measurement set to fit (--set)");
    if let Some(nu) = jobs.iter().find(|j| j.discretization).and_then(|j| j.nu) {
        anyhow::bail!(
            "--discretization fits ν again on finer meshes: it needs ν fitted, not given \
             (--nu {nu})"
        );
    }
    let mut report = Report::create(out, "Material identification")?;
    let done = run(jobs)?;
    summary(&mut report, &done);
    write_measured(&mut report, &done)?;
    for d in &done {
        let json = match done.len() {
            1 => "identify.json".to_string(),
            _ => format!("{}.json", stem(d)),
        };
        fit_section(&mut report, d, &json)?;
    }
    report.finish()
}

/// The default report's section. Full: sets A and C with the neo-Hookean tet10 model (the
/// law and element the data were made with) and the linear tet4 one. Quick: set C with
/// neo-Hookean tet10 (the faster set; the model at the noise level).
pub fn shipped(report: &mut Report, depth: Depth) -> Result<()> {
    let generated = ModelForm {
        law: Law::NeoHookean,
        element: Tetrahedron::Tet10,
    };
    let linear = ModelForm {
        law: Law::Linear,
        element: Tetrahedron::Tet4,
    };
    let (sets, models): (&[&str], &[ModelForm]) = match depth {
        Depth::Quick => (&["C"], &[generated]),
        Depth::Full => (&["A", "C"], &[generated, linear]),
    };
    let mut jobs = Vec::new();
    for &set in sets {
        for &model in models {
            jobs.push(Job {
                data: Source::Shipped,
                set: set.into(),
                model,
                nu: None,
                discretization: false,
            });
        }
    }
    let done = run(jobs)?;
    report.heading(&format!(
        "Material identification on the shipped set{} {}",
        if sets.len() > 1 { "s" } else { "" },
        sets.join(" and ")
    ));
    if depth == Depth::Quick {
        report.text(
            "Quick: set C with the model its data were made with (neo-Hookean tet10); the \
             intervals below are the fit's accuracy under the stated noise. `--full` adds set \
             A and the linear tet4 model on both (which is not at the noise level: \
             model-form error).",
        );
    }
    summary(report, &done);
    for d in &done {
        let json = format!("{}.json", stem(d));
        fit_section(report, d, &json)?;
    }
    Ok(())
}

/// Runs the fits in parallel, each with a progress line.
fn run(jobs: Vec<Job>) -> Result<Vec<Done>> {
    let bars = MultiProgress::new();
    let style = ProgressStyle::with_template("{spinner} {elapsed_precise} {msg}")
        .expect("the template is valid");
    jobs.into_par_iter()
        .map(|job| {
            let data = Measurements::load(&job.data, &job.set)?;
            let bar = bars.add(ProgressBar::new_spinner().with_style(style.clone()));
            let name = format!("set {} with {}", job.set, job.model);
            bar.set_message(format!("{name}: first run"));
            let runs = std::sync::atomic::AtomicUsize::new(0);
            let observe = |nu: f64, chi2: f64| {
                let k = runs.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
                bar.set_message(format!("{name}: run {k}, ν = {nu:.5}, χ² = {chi2:.4e}"));
                bar.tick();
            };
            let start = Instant::now();
            let fit = identify(&data, &job.model, job.nu, &observe)?;
            let time = start.elapsed();
            let observe = |cells: [u32; 3], nu: f64, chi2: f64| {
                bar.set_message(format!(
                    "{name} on {} cells: ν = {nu:.5}, χ² = {chi2:.4e}",
                    cubes(cells.map(f64::from))
                ));
                bar.tick();
            };
            let mesh = mesh_share(&job, &data, &fit, time, &observe)?;
            bar.finish_and_clear();
            Ok(Done {
                job,
                data,
                fit,
                time,
                mesh,
            })
        })
        .collect()
}

/// The mesh's share of a fit of ν inside its range: measured if the job asks, else the
/// stored one of a shipped set, if any.
fn mesh_share(
    job: &Job,
    data: &Measurements,
    fit: &Fit,
    time: Duration,
    observe: &(dyn Fn([u32; 3], f64, f64) + Sync),
) -> Result<Option<MeshShare>> {
    if fit.sigma_nu.is_none() || fit.at_bound {
        return Ok(None);
    }
    if job.discretization {
        let share = Discretization::measure(data, &job.model, fit, time.as_secs_f64(), observe)?;
        return Ok(Some(MeshShare {
            share,
            source: "measured here".into(),
        }));
    }
    if job.data != Source::Shipped {
        return Ok(None);
    }
    let seconds = time.as_secs_f64();
    let stored = discretization::stored(&job.set, &job.model, &data.specimen, fit, seconds)?;
    Ok(stored.map(|(share, measured)| MeshShare {
        share,
        source: format!("stored in `{STORED_PATH}`, measured {measured}"),
    }))
}

/// Writes the refits measured here to `discretization.toml` in the format of
/// [`STORED_PATH`] (the file to copy there when the model changes).
fn write_measured(report: &mut Report, done: &[Done]) -> Result<()> {
    let measured: Vec<(&str, ModelForm, &Discretization)> = done
        .iter()
        .filter(|d| d.job.discretization)
        .filter_map(|d| Some((d.job.set.as_str(), d.fit.model, &d.mesh.as_ref()?.share)))
        .collect();
    if measured.is_empty() {
        return Ok(());
    }
    let sets: Vec<&str> = measured.iter().map(|(set, ..)| *set).collect();
    let how = format!(
        "`harness identify --set {} --material {} --element {} --discretization` (harness {})",
        sets.join(","),
        done[0].fit.model.law.name(),
        done[0].fit.model.element.name(),
        env!("CARGO_PKG_VERSION")
    );
    discretization::write(&measured, &how, &report.path("discretization.toml"))?;
    report.file(
        &format!("the refits, in the format of `{STORED_PATH}`"),
        "discretization.toml",
    );
    Ok(())
}

/// Whether the fit is at the noise level, in words.
fn verdict(d: &Done) -> &'static str {
    match (d.fit.at_noise_level(&d.data), d.fit.at_bound) {
        (true, false) => "at the noise level",
        (true, true) => "at the noise level, but ν at the end of its search interval",
        (false, false) => "**not** at the noise level: model-form error",
        (false, true) => {
            "**not** at the noise level, ν at the end of its search interval: model-form error"
        }
    }
}

fn summary(report: &mut Report, done: &[Done]) {
    report.text(&format!(
        "E and ν with 95 % intervals: the noise's (±1.96 σ from the derivatives in ν and the \
         stated noise), the mesh's (the grid convergence index of the same fit on finer \
         meshes, `harness identify --discretization`; stored for the shipped sets) and the \
         total (the two in quadrature), and which of the two dominates; none where ν ran to \
         its bound. Then the correlation of E and ν and the residuals against the noise: a \
         model that matches the experiment gives force RMS / σ_F ≤ {FORCE_LEVEL} and profile \
         RMS / σ_P ≤ {PROFILE_LEVEL}."
    ));
    let rows: Vec<Vec<String>> = done
        .iter()
        .map(|d| {
            let f = &d.fit;
            let noise = d.data.specimen.noise;
            let [e, nu] = intervals(d);
            vec![
                d.job.set.clone(),
                f.model.to_string(),
                e.estimate(),
                nu.estimate(),
                format!("{} / {}", e.noise(), nu.noise()),
                format!("{} / {}", e.mesh(), nu.mesh()),
                format!("{} / {}", e.total(), nu.total()),
                dominant(&[e, nu]),
                f.correlation
                    .filter(|_| !f.at_bound)
                    .map_or("–".into(), |c| format!("{c:+.2}")),
                format!("{:.2}", f.force_rms / noise.force),
                format!("{:.2}", f.profile_rms / noise.profile),
                verdict(d).into(),
                format!("{:.0}", d.time.as_secs_f64()),
            ]
        })
        .collect();
    report.table(
        &[
            "set",
            "model",
            "E (MPa)",
            "ν",
            "noise ± E / ν",
            "mesh ± E / ν",
            "total ± E / ν",
            "dominates",
            "corr.",
            "force RMS / σ_F",
            "profile RMS / σ_P",
            "verdict",
            "time (s)",
        ],
        &rows,
    );
}

/// One parameter's estimate and 95 % half-widths, as printed.
#[derive(Debug, Clone, Copy)]
struct Interval {
    name: &'static str,
    value: f64,
    /// Decimals printed.
    digits: usize,
    /// The noise's half-width; `None` where there is none (ν given, or at its bound).
    noise: Option<f64>,
    /// The mesh's share, where measured or stored.
    mesh: Option<Share>,
    /// Whether the value is given rather than fitted.
    given: bool,
    /// Whether ν ran to its bound (no material values, no intervals).
    at_bound: bool,
}

impl Interval {
    fn number(&self, x: f64) -> String {
        format!("{x:.*}", self.digits)
    }

    fn estimate(&self) -> String {
        let value = self.number(self.value);
        match (self.given, self.at_bound) {
            (true, _) => format!("{value} (given)"),
            (false, true) => format!("{value} (bound)"),
            _ => value,
        }
    }

    fn noise(&self) -> String {
        self.noise
            .map_or("–".into(), |h| format!("±{}", self.number(h)))
    }

    fn mesh(&self) -> String {
        match (self.noise, self.mesh) {
            (Some(_), Some(m)) => format!("±{}", self.number(m.halfwidth)),
            _ => "–".into(),
        }
    }

    /// The total half-width: the noise's alone where the mesh's is not known.
    fn total_halfwidth(&self) -> Option<f64> {
        let noise = self.noise?;
        Some(self.mesh.map_or(noise, |m| m.total(noise)))
    }

    fn total(&self) -> String {
        match (self.total_halfwidth(), self.mesh) {
            (Some(t), Some(_)) => format!("±{}", self.number(t)),
            (Some(t), None) => format!("±{} (noise only)", self.number(t)),
            (None, _) => "–".into(),
        }
    }

    /// "mesh" or "noise", whichever half-width is the larger; `None` without both.
    fn dominant(&self) -> Option<&'static str> {
        let (noise, mesh) = (self.noise?, self.mesh?.halfwidth);
        Some(if mesh > noise { "mesh" } else { "noise" })
    }
}

/// E's and ν's intervals of a fit.
fn intervals(d: &Done) -> [Interval; 2] {
    let f = &d.fit;
    let fitted = |sigma: Option<f64>| sigma.filter(|_| !f.at_bound).map(|s| 1.96 * s);
    let share = |get: fn(&Discretization) -> Share| d.mesh.as_ref().map(|m| get(&m.share));
    [
        Interval {
            name: "E (MPa)",
            value: f.e,
            digits: 5,
            noise: fitted(Some(f.sigma_e)),
            mesh: share(|s| s.e),
            given: false,
            at_bound: f.at_bound,
        },
        Interval {
            name: "ν",
            value: f.nu,
            digits: 4,
            noise: fitted(f.sigma_nu),
            mesh: share(|s| s.nu),
            given: f.sigma_nu.is_none(),
            at_bound: f.at_bound,
        },
    ]
}

/// Which share dominates each parameter's interval, e.g. "mesh (E, ν)".
fn dominant(intervals: &[Interval]) -> String {
    let mut by: Vec<(&str, Vec<&str>)> = Vec::new();
    for i in intervals {
        let Some(d) = i.dominant() else { continue };
        let name = i.name.split(' ').next().unwrap_or(i.name);
        match by.iter_mut().find(|(k, _)| *k == d) {
            Some((_, names)) => names.push(name),
            None => by.push((d, vec![name])),
        }
    }
    if by.is_empty() {
        return "–".into();
    }
    by.iter()
        .map(|(d, names)| format!("{d} ({})", names.join(", ")))
        .collect::<Vec<_>>()
        .join("; ")
}

/// Seed 002's eqs. 4.1 and 4.2 on the same data, with their bias against the fit and what
/// the seed's E makes of the measured force.
fn seed_method(m: &Measurements, f: &Fit) -> String {
    let s = SeedMethod::of(m);
    let (last, pull) = (m.force.len() - 1, m.displacement[m.force.len() - 1]);
    let predicted = s.e * f.response.force_per_e[last];
    let mut text = format!(
        "Seed 002's method on the same data (ch. 4.1; `harness/src/studies/secant.rs` says what \
         it assumes): the block as a bar in uniaxial tension, E = ΔF / Δl · l₀ / A (eq. 4.1) \
         over the pulls {} to {pull} mm with l₀ = {} mm and the uncut section A = {} mm², \
         gives E = {:.5} MPa, {:+.1} % against the fit; the fitted model with that E would \
         pull {predicted:.3} N at {pull} mm against the {:.3} N measured ({:+.1} %; the seed \
         found its simulated forces about 20 % low, its Table 4.1).",
        m.displacement[0],
        s.length,
        s.section,
        s.e,
        100.0 * (s.e / f.e - 1.0),
        m.force[last],
        100.0 * (predicted / m.force[last] - 1.0),
    );
    text.push_str(&match (s.thickness, s.nu) {
        (Some(b1), Some(nu)) if s.nu_admissible() => format!(
            " Eq. 4.2 on the scanned thickness ({b1:.3} mm from {} mm) gives ν = {nu:.4}, \
             {:+.4} against the fit (the scanned height mixes the contraction with the \
             bending the cut's opening causes).",
            m.specimen.size[2],
            nu - f.nu
        ),
        (Some(b1), Some(nu)) => format!(
            " Eq. 4.2 needs the lateral contraction, which these scans do not show: the \
             mean height between the cut and the pulled face is {b1:.3} mm against {} mm \
             at rest (the cut's opening bends the segments up), and gives ν = {nu:.3}, no \
             material value.",
            m.specimen.size[2]
        ),
        _ => " Eq. 4.2 needs a lateral dimension; the set has no scans beside the cut.".into(),
    });
    text
}

/// The file stem of a fit's plots and results.
fn stem(d: &Done) -> String {
    format!("identify_{}_{}", d.job.set, d.fit.model).replace([' ', '-'], "_")
}

/// One fit: parameters, residuals, warnings, plots and the profile table; the results as
/// JSON in `json`.
fn fit_section(report: &mut Report, d: &Done, json: &str) -> Result<()> {
    let (f, m) = (&d.fit, &d.data);
    let s = &m.specimen;
    let noise = s.noise;
    report.heading(&format!(
        "Identification: set {} in {}, {} model",
        d.job.set, d.job.data, f.model
    ));
    report.text(&format!(
        "Specimen: {} × {} × {} mm, cut at y = {} mm, {} mm deep, x from 0 to {} mm, {} \
         supports, {} × {} × {} cells ({}). {} force points (σ_F = {} N), {} profile \
         points (σ_P = {} mm). {} runs of the scene, {:.0} s.",
        s.size[0],
        s.size[1],
        s.size[2],
        s.y_cut,
        s.cut_depth,
        s.cut_x,
        s.support,
        s.cells[0],
        s.cells[1],
        s.cells[2],
        if s.mesh_grading == 1.0 {
            "uniform layers".to_string()
        } else {
            format!("layers graded with β = {}", s.mesh_grading)
        },
        m.force.len(),
        noise.force,
        m.profiles.iter().map(|s| s.points.len()).sum::<usize>(),
        noise.profile,
        f.evaluations,
        d.time.as_secs_f64()
    ));
    parameters(report, d);
    if f.at_bound {
        report.text(&format!(
            "ν ran to the end of the search interval [{}, {}]: no admissible ν fits the \
             profiles, so this ν and the E that goes with it are not material properties, \
             and their intervals mean nothing.",
            NU_RANGE.0, NU_RANGE.1
        ));
    }
    if let Some(c) = f.correlation.filter(|_| !f.at_bound) {
        report.text(&format!(
            "Correlation of E and ν: {c:+.3}. ν comes from the profiles; the forces alone \
             would trade E against ν along F = E · g(ν, d)."
        ));
    }
    report.text(&format!(
        "Model-form check: force RMS residual {:.4} N = {:.2} σ_F (χ² per point {:.2}); \
         profile RMS {:.4} mm = {:.2} σ_P. The fit is {}.",
        f.force_rms,
        f.force_rms / noise.force,
        f.force_chi2,
        f.profile_rms,
        f.profile_rms / noise.profile,
        verdict(d)
    ));
    if !f.response.warnings.is_empty() {
        report.text(&format!(
            "The scene warned: {}",
            f.response.warnings.join("; ")
        ));
    }
    report.text(&seed_method(m, f));
    let stem = stem(d);
    forces_plot(report, m, f, &stem)?;
    if m.has_profiles() {
        profiles_section(report, m, f, &stem)?;
    }
    let results = serde_json::to_vec_pretty(&results(d))?;
    crate::atomic::write_atomic(&report.path(json), &results)?;
    report.file("the results for scripts (JSON)", json);
    Ok(())
}

/// The parameters' table: estimate, σ, the three 95 % intervals and the converged mesh's
/// value; then the mesh's share: its fits, which share dominates.
fn parameters(report: &mut Report, d: &Done) {
    let f = &d.fit;
    let rows: Vec<Vec<String>> = intervals(d)
        .iter()
        .zip([Some(f.sigma_e), f.sigma_nu])
        .map(|(i, sigma)| {
            let around = |h: Option<f64>| {
                h.map_or("–".into(), |h| {
                    format!("[{}, {}]", i.number(i.value - h), i.number(i.value + h))
                })
            };
            vec![
                i.name.into(),
                i.estimate(),
                sigma.map_or("–".into(), |s| format!("{s:.2e}")),
                around(i.noise),
                around(i.noise.and(i.mesh.map(|m| m.halfwidth))),
                around(i.total_halfwidth()),
                i.mesh.map_or("–".into(), |m| i.number(m.limit)),
            ]
        })
        .collect();
    report.table(
        &[
            "parameter",
            "estimate",
            "σ",
            "noise 95 %",
            "mesh 95 %",
            "total 95 %",
            "converged mesh",
        ],
        &rows,
    );
    match &d.mesh {
        Some(m) => mesh_text(report, d, m),
        None if f.sigma_nu.is_some() && !f.at_bound => report.text(
            "The mesh's share is not known for this set: `--discretization` measures it \
             (the same fit on the specimen's cells × 1.5 and × 2), and the total is the \
             noise's alone until then.",
        ),
        None => {}
    }
}

/// The mesh's share: the fits on three meshes, the orders and which share dominates.
fn mesh_text(report: &mut Report, d: &Done, m: &MeshShare) {
    let share = &m.share;
    let order = |s: &Share| match (s.observed, s.order()) {
        (Some(seen), Some(p)) if seen > p => format!(
            "order {seen:.2} observed, extrapolated at {p}; ×{SAFETY_OBSERVED} the change to \
             the limit"
        ),
        (_, Some(p)) => format!("order {p:.2}, ×{SAFETY_OBSERVED} the change to the limit"),
        _ => format!("no order observed: the finest fit, ×{SAFETY_UNOBSERVED} the change to it"),
    };
    report.text(&format!(
        "The mesh's share: the same fit on finer meshes, extrapolated by Richardson to the \
         converged mesh; its 95 % half-width is Roache's grid convergence index of the fit on \
         the specimen's cells (E: {}; ν: {}); `harness/src/studies/discretization.rs` says \
         how. The fits, {}:",
        order(&share.e),
        order(&share.nu),
        m.source,
    ));
    let rows: Vec<Vec<String>> = share
        .meshes
        .iter()
        .map(|f| {
            vec![
                cubes(f.cells.map(f64::from)),
                format!("{:.5}", f.e),
                format!("{:.4}", f.nu),
                f.runs.to_string(),
                format!("{:.0}", f.seconds),
            ]
        })
        .collect();
    report.table(&["cells", "E (MPa)", "ν", "runs", "time (s)"], &rows);
    if share.at_bound() {
        report.text(&format!(
            "On a finer mesh ν ran to the end of its search interval [{}, {}]: the converged \
             model fits no admissible ν to these data, and the mesh's share is at least the \
             interval above.",
            NU_RANGE.0, NU_RANGE.1
        ));
    }
    let [e, nu] = intervals(d);
    let ratio = |i: &Interval| match (i.noise, i.mesh) {
        (Some(n), Some(m)) => format!("{:.1}", m.halfwidth / n),
        _ => "–".into(),
    };
    report.text(&format!(
        "The interval is dominated by {}: the mesh's half-width is {} times the noise's for \
         E and {} times for ν.",
        dominant(&[e, nu]),
        ratio(&e),
        ratio(&nu)
    ));
}

/// The fit as JSON: values, 95 % intervals, correlation, residuals against the noise, each
/// scan line's deviation, the verdict (`docs/reference/data-formats.md`).
fn results(d: &Done) -> serde_json::Value {
    let (f, m) = (&d.fit, &d.data);
    let noise = m.specimen.noise;
    // No interval where ν ran to its bound: those values are not material values.
    let interval = |value: f64, sigma: f64| {
        (!f.at_bound).then_some([value - 1.96 * sigma, value + 1.96 * sigma])
    };
    let scanned = |x: f64| m.has_profiles().then_some(x);
    let seed = SeedMethod::of(m);
    serde_json::json!({
        "set": d.job.set,
        "data": d.job.data.to_string(),
        "model": { "material": f.model.law.name(), "element": f.model.element.name() },
        "E_MPa": {
            "value": f.e,
            "sigma": f.sigma_e,
            "interval95": interval(f.e, f.sigma_e),
        },
        "nu": {
            "value": f.nu,
            "given": d.job.nu.is_some(),
            "sigma": f.sigma_nu,
            "interval95": f.sigma_nu.and_then(|s| interval(f.nu, s)),
            "at_bound": f.at_bound,
            "search_interval": [NU_RANGE.0, NU_RANGE.1],
        },
        "correlation": f.correlation,
        "discretization": d.mesh.as_ref().map(|m| discretization_json(d, m)),
        "seed_method": {
            "E_MPa": seed.e,
            "section_mm2": seed.section,
            "length_mm": seed.length,
            "thickness_mm": seed.thickness,
            "nu": seed.nu,
            "nu_admissible": seed.nu_admissible(),
        },
        "forces": {
            "points": m.force.len(),
            "rms_N": f.force_rms,
            "noise_N": noise.force,
            "rms_over_noise": f.force_rms / noise.force,
            "chi2_per_point": f.force_chi2,
            "limit_rms_over_noise": FORCE_LEVEL,
        },
        "profiles": {
            "pull_mm": m.profile_pull(),
            "rms_mm": scanned(f.profile_rms),
            "noise_mm": noise.profile,
            "rms_over_noise": scanned(f.profile_rms / noise.profile),
            "limit_rms_over_noise": PROFILE_LEVEL,
            "lines": m.profiles.iter().zip(&f.lines).map(|(s, l)| serde_json::json!({
                "x_mm": s.x,
                "points_compared": l.points,
                "rms_mm": l.rms,
                "max_mm": l.max,
            })).collect::<Vec<_>>(),
        },
        "at_noise_level": f.at_noise_level(m),
        "verdict": verdict(d).replace("**", ""),
        "warnings": f.response.warnings,
        "runs": f.evaluations,
        "seconds": d.time.as_secs_f64(),
    })
}

/// The mesh's share as JSON: its fits, and for E and ν the converged mesh's value, the
/// order, the mesh's and the total 95 % half-widths and which dominates.
fn discretization_json(d: &Done, m: &MeshShare) -> serde_json::Value {
    let [e, nu] = intervals(d);
    let parameter = |i: &Interval, s: &Share| {
        serde_json::json!({
            "limit": s.limit,
            "observed_order": s.observed,
            "order": s.order(),
            "halfwidth95": s.halfwidth,
            "total_halfwidth95": i.total_halfwidth(),
            "dominant": i.dominant(),
        })
    };
    serde_json::json!({
        "source": m.source,
        "meshes": m.share.meshes,
        "at_bound": m.share.at_bound(),
        "E_MPa": parameter(&e, &m.share.e),
        "nu": parameter(&nu, &m.share.nu),
    })
}

fn forces_plot(report: &mut Report, m: &Measurements, f: &Fit, stem: &str) -> Result<()> {
    let data = m
        .displacement
        .iter()
        .copied()
        .zip(m.force.clone())
        .collect();
    let model = m
        .displacement
        .iter()
        .zip(&f.response.force_per_e)
        .map(|(&d, g)| (d, f.e * g))
        .collect();
    let label = format!("{}, E = {:.4} MPa, ν = {:.3}", f.model, f.e, f.nu);
    let name = format!("{stem}_forces");
    plot::chart(
        &report.path(&name),
        &Chart {
            title: "Cut block: reaction force, data vs fit".into(),
            x: Axis::linear("pull displacement (mm)"),
            y: Axis::linear("reaction force (N)"),
            curves: vec![
                Curve::new("measured", data, Mark::Dots),
                Curve::new(&label, model, Mark::Line).colour(1),
            ],
        },
    )?;
    report.figure("Force–displacement: data and fitted model", &name);
    Ok(())
}

fn profiles_section(report: &mut Report, m: &Measurements, f: &Fit, stem: &str) -> Result<()> {
    report.text(
        "Profile deviation per scan line; acceptance (seed 002 §3.5): max below 1 % of the \
         largest block dimension. Lab frame: scanner and model share the clamped edge y = 0, \
         no offset. Aligned: the scan shifted rigidly by the (Δy, Δz) that minimizes its RMS \
         deviation (`harness/src/studies/profiles.rs`), for scans whose registration is \
         uncertain.",
    );
    let limit = 0.01 * m.specimen.size.iter().copied().fold(0.0, f64::max);
    let verdict = |max: f64| if max < limit { "meets" } else { "misses" };
    let mut rows = Vec::new();
    for (k, scan) in m.profiles.iter().enumerate() {
        let lab = f.lines[k];
        let a = align(&f.response.profiles[k], &scan.points)?;
        rows.push(vec![
            format!("x = {} mm", scan.x),
            lab.points.to_string(),
            format!("{:.3} / {:.3}", lab.rms, lab.max),
            verdict(lab.max).into(),
            format!("{:+.3} / {:+.3}", a.dy, a.dz),
            format!("{:.3} / {:.3}", a.deviation.rms, a.deviation.max),
            verdict(a.deviation.max).into(),
        ]);
    }
    report.table(
        &[
            "line",
            "points",
            "lab RMS / max (mm)",
            "lab",
            "fitted Δy / Δz (mm)",
            "aligned RMS / max (mm)",
            "aligned",
        ],
        &rows,
    );
    let mut curves = Vec::new();
    for (k, scan) in m.profiles.iter().enumerate() {
        let x = scan.x;
        let data = scan.points.clone();
        curves.push(Curve::new(&format!("scan x = {x} mm"), data, Mark::Dots).colour(k));
        let model = f.response.profiles[k]
            .iter()
            .enumerate()
            .filter(|(_, z)| z.is_finite())
            .map(|(i, &z)| (i as f64 * PROFILE_STEP, z))
            .collect();
        curves.push(Curve::new(&format!("model x = {x} mm"), model, Mark::Line).colour(k));
    }
    let name = format!("{stem}_profiles");
    plot::chart(
        &report.path(&name),
        &Chart {
            title: format!(
                "Top-surface profiles at {} mm pull, data vs {}",
                m.profile_pull(),
                f.model
            ),
            x: Axis::linear("y along the pull (mm)"),
            y: Axis::linear("surface height z (mm)"),
            curves,
        },
    )?;
    report.figure("Laser profiles: scanner data and model", &name);
    Ok(())
}
