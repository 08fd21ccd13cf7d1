//! Material identification for the cut block (seed 002 ch. 4) from a measurement set
//! ([`Measurements`]): E and ν of a chosen model (material law and element), with intervals
//! and a model-form check.
//!
//! With the pull prescribed, the displacements of the linear and the hyperelastic models do
//! not depend on E (μ and λ both scale with it), so the reaction force is F = E · g(ν, d)
//! and the profiles depend on ν alone. The fit minimizes the misfit weighted by the stated
//! noise levels,
//!
//! χ²(E, ν) = Σᵢ ((Fᵢ − E g(ν, dᵢ)) / σ_F)² + Σⱼ ((zⱼ − hⱼ(ν)) / σ_P)²,
//!
//! by separation (variable projection, Golub and Pereyra 1973): for each ν, E is the linear
//! least-squares solution E(ν) = Σ F g / Σ g², and ν follows by Gauss–Newton on the
//! projected residuals r(ν) = ((F − E(ν) g(ν)) / σ_F, (z − h(ν)) / σ_P), whose Jacobian
//! comes with each run: one run of the scene per ν with E = 1 through the measured pulls (a
//! nonlinear solve at each for the finite-strain laws) gives g and, by direct
//! differentiation at each converged pull ([`CutBlock::poisson_sensitivity`]: one solve
//! with the tangent Newton has factorized), ∂g/∂ν, and at the largest pull the heights h
//! and ∂h/∂ν along each scan line the specimen names. A step that does not lower χ² is
//! halved; a step beyond an end of [`NU_RANGE`] goes half-way to it; the iteration starts
//! at [`NU_START`] and stops when a step is below [`STEP_FRACTION`] of ν's standard
//! deviation, or takes a last step below [`LINEAR_FRACTION`] of it along the derivatives
//! without another run where the steps' contraction says the one after would stop. The profiles carry nearly all the information on ν: the
//! forces alone fit almost any ν with its own E (the E–ν trade-off seed 002 ch. 4 found).
//! Without profiles ν must be given and only E is fitted.
//!
//! Uncertainty: the Gauss–Newton covariance (JᵀJ)⁻¹ of the weighted residuals in (E, ν) at
//! the optimum, from the same derivatives; intervals are ±1.96 σ under the stated noise.
//! That is the noise's share; the mesh's share is [`super::discretization`]'s.
//! Model-form check: the RMS force residual against σ_F (χ² per point) and the profile RMS
//! against σ_P; a fit is at the noise level within [`FORCE_LEVEL`] and [`PROFILE_LEVEL`]
//! of them.
//!
//! Profiles are compared in lab coordinates ([`super::profiles`]); points where the model
//! has no surface (the open cut) are skipped.

use models::assembly::tetrahedra::Tetrahedron;
use models::element::Law;
use std::collections::BTreeMap;

use anyhow::{bail, ensure, Context, Result};
use models::scene::cutblock::{CutBlock, PROFILE_STEP};
use models::scene::Scene;

use super::measurements::{Measurements, Specimen};
use super::profiles::{deviation, heights, Deviation};
use crate::sweep::{simulate_observed, InProcess, InputTable, Schedule, Value};

/// The interval ν is searched in.
pub const NU_RANGE: (f64, f64) = (0.05, 0.499);
/// Where the Gauss–Newton iteration on ν starts: mid-way in the range of soft silicones and
/// tissues (0.45–0.4999).
pub const NU_START: f64 = 0.45;
/// The iteration stops when its step in ν is below this fraction of ν's standard deviation
/// under the stated noise: what is left of the optimization then widens the interval by
/// less than 0.2 % (in quadrature), and the iteration converges quadratically, so the
/// error left is far smaller than the step.
pub const STEP_FRACTION: f64 = 0.05;
/// A step below this fraction of ν's standard deviation is taken without another run when
/// the contraction of the last two steps puts the next one below [`STEP_FRACTION`] of it
/// and χ² falls: the response at ν + δ is the run's moved along its derivatives,
/// g + δ ∂g/∂ν and h + δ ∂h/∂ν ([`Response::moved`]), to O(δ²). On set C the steps go
/// 0.0235, 2.8e-4: the next at that contraction 3.3e-6, a two-hundredth of σ. It saves the
/// run that would only confirm the step (set C: 3 runs to 2).
const LINEAR_FRACTION: f64 = 1.0;
/// Runs the iteration may make (halvings included).
const MAX_RUNS: usize = 30;
/// A step whose end lies beyond an end of [`NU_RANGE`] goes this fraction of the way to it
/// instead (the fraction-to-the-boundary rule of interior-point methods), so that a minimum
/// inside the range is not jumped: the linear tet4 model on set C, whose full first step
/// from 0.45 ended beyond 0.499, otherwise stopped at the bound with a profile RMS of
/// 14.08 σ_P against 13.81 σ_P at its interior minimum ν = 0.4952.
const BOUNDARY_FRACTION: f64 = 0.5;
/// A fit is at the noise level when its RMS force residual is within this factor of the
/// force noise and its profile RMS within [`PROFILE_LEVEL`] of the scanner noise.
pub const FORCE_LEVEL: f64 = 1.5;
/// A fit is at the noise level only when its profile RMS is within this factor of the
/// scanner noise (and its forces within [`FORCE_LEVEL`]).
pub const PROFILE_LEVEL: f64 = 3.0;

/// The model fitted: the cut block's material law and tetrahedron.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ModelForm {
    /// The material law.
    pub law: Law,
    /// The tetrahedron: tet4 or tet10.
    pub element: Tetrahedron,
}

impl ModelForm {
    /// The form of the scene's `material` and `element` values; an unknown one is refused
    /// by name.
    pub fn parse(material: &str, element: &str) -> Result<Self> {
        Ok(Self {
            law: Law::parse(material)?,
            element: Tetrahedron::parse(element)?,
        })
    }
}

impl std::fmt::Display for ModelForm {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{} {}", self.law.name(), self.element.name())
    }
}

/// The model's response for one ν with E = 1, and its derivatives in ν.
#[derive(Debug, Clone)]
pub struct Response {
    /// Poisson's ratio of the run.
    pub nu: f64,
    /// Reaction force per unit E at each measured pull: g(ν, d).
    pub force_per_e: Vec<f64>,
    /// ∂g/∂ν at each measured pull (empty if not asked for).
    pub force_slope: Vec<f64>,
    /// Heights at the model's stations (every [`PROFILE_STEP`] mm from y = 0) along each
    /// scan line at the largest pull (NaN where there is no surface); empty without
    /// profiles.
    pub profiles: Vec<Vec<f64>>,
    /// ∂h/∂ν at the same stations (empty if not asked for).
    pub profile_slopes: Vec<Vec<f64>>,
    /// The equilibrium u and its derivative du/dν at each measured pull (all dofs; empty
    /// unless the slopes were asked for): where a run at a nearby ν starts each pull.
    pub states: Vec<(Vec<f64>, Vec<f64>)>,
    /// What the scene warned about (e.g. the linear law beyond its strain).
    pub warnings: Vec<String>,
}

/// Runs the specimen of `m` with `model`, E = 1 and `nu` through the measured pulls, with
/// the profiles along its scan lines if `m` has scans, and the derivatives in ν if `slopes`;
/// each pull started from the run `from` at a nearby ν, if given (see [`run`]).
pub fn response(
    m: &Measurements,
    model: &ModelForm,
    nu: f64,
    slopes: bool,
    from: Option<&Response>,
) -> Result<Response> {
    let lines: Vec<f64> = m.profiles.iter().map(|s| s.x).collect();
    run(
        &m.specimen,
        &m.displacement,
        model,
        nu,
        &lines,
        slopes,
        from,
    )
}

impl Response {
    /// The response at ν + `step` to first order, from this one's slopes (which it keeps).
    fn moved(&self, step: f64) -> Self {
        let along = |x: &[f64], dx: &[f64]| -> Vec<f64> {
            x.iter().zip(dx).map(|(x, d)| x + step * d).collect()
        };
        Self {
            nu: self.nu + step,
            force_per_e: along(&self.force_per_e, &self.force_slope),
            force_slope: self.force_slope.clone(),
            profiles: (self.profiles.iter())
                .zip(&self.profile_slopes)
                .map(|(h, dh)| along(h, dh))
                .collect(),
            profile_slopes: self.profile_slopes.clone(),
            states: Vec::new(),
            warnings: self.warnings.clone(),
        }
    }
}

/// Runs `specimen` with `model`, E = 1 and `nu` through `pulls`; reads the profiles along
/// the scan `lines` (x, mm) at the last pull, at stations every [`PROFILE_STEP`] mm from
/// y = 0 to 10 mm beyond the pulled end; with `slopes`, the derivatives in ν of the forces
/// at every pull and of the heights at the last. With `from`, a run of the same pulls at
/// another ν with slopes, each pull's solve starts at that run's equilibrium moved along
/// its derivative, u + (ν − ν_from) du/dν ([`CutBlock::start_next_from`]: a continuation
/// in ν, a few iterations where the path from the last pull takes about ten).
pub fn run(
    specimen: &Specimen,
    pulls: &[f64],
    model: &ModelForm,
    nu: f64,
    lines: &[f64],
    slopes: bool,
    from: Option<&Response>,
) -> Result<Response> {
    let mut settings = specimen.settings();
    settings.extend([
        ("material".to_string(), Value::Text(model.law.name().into())),
        (
            "element".to_string(),
            Value::Text(model.element.name().into()),
        ),
        ("E".to_string(), Value::Real(1.0)),
        ("nu".to_string(), Value::Real(nu)),
    ]);
    let n = pulls.len();
    // The input rule: the output row k + 1 responds to the pull set at time k.
    let inputs = BTreeMap::from([
        (
            "scalpel_x".to_string(),
            InputTable::constant(specimen.cut_x),
        ),
        (
            "pull".to_string(),
            InputTable {
                time: (0..n).map(|k| k as f64).collect(),
                value: pulls.to_vec(),
            },
        ),
    ]);
    let record = vec!["reaction_force".to_string()];
    let schedule = Schedule {
        start_time: 0.0,
        stop_time: n as f64,
        step: 1.0,
        settings: &settings,
        inputs: &inputs,
        record: &record,
    };
    let end = specimen.size[1] + pulls.last().copied().unwrap_or(0.0) + 10.0;
    let stations: Vec<f64> = (0..=(end / PROFILE_STEP).ceil() as usize)
        .map(|i| i as f64 * PROFILE_STEP)
        .collect();
    let (mut force_slope, mut profile_slopes, mut states) = (Vec::new(), Vec::new(), Vec::new());
    let mut session = InProcess(Box::new(CutBlock::new()));
    let run = simulate_observed(&mut session, &schedule, |session, t| {
        let scene = &mut session.0;
        if slopes && t > 0.0 {
            let last = t == n as f64;
            let d = scene.poisson_sensitivity(if last { lines } else { &[] }, &stations)?;
            force_slope.push(d.reaction_force);
            if last {
                profile_slopes = d.profiles;
            }
            let u = scene
                .field()
                .context("the scene is initialized")?
                .1
                .to_vec();
            states.push((u, d.displacement));
        }
        // The state after the output row t starts the pull of index t.
        if let Some((u, du)) = from.and_then(|f| f.states.get(t as usize)) {
            let step = nu - from.map_or(nu, |f| f.nu);
            let start: Vec<f64> = u.iter().zip(du).map(|(u, d)| u + step * d).collect();
            scene.start_next_from(&start)?;
        }
        Ok(())
    })
    .with_context(|| format!("{model} at ν = {nu}"))?;
    let force = run.series.column("reaction_force").context("recorded")?;
    let profiles = lines
        .iter()
        .map(|&x| session.0.profile(x, &stations))
        .collect::<Result<_, _>>()?;
    Ok(Response {
        nu,
        force_per_e: force[1..].to_vec(),
        force_slope,
        profiles,
        profile_slopes,
        states,
        warnings: run.warnings,
    })
}

/// E by least squares on the forces: E = Σ F g / Σ g².
pub fn fit_e(g: &[f64], m: &Measurements) -> f64 {
    let gg: f64 = g.iter().map(|x| x * x).sum();
    g.iter().zip(&m.force).map(|(g, f)| g * f).sum::<f64>() / gg
}

/// Σ (F − E g)² over the measured pulls.
fn force_ssr(e: f64, g: &[f64], m: &Measurements) -> f64 {
    g.iter()
        .zip(&m.force)
        .map(|(g, f)| (f - e * g).powi(2))
        .sum()
}

/// The deviation of each scanned line.
fn lines(r: &Response, m: &Measurements) -> Vec<Deviation> {
    r.profiles
        .iter()
        .zip(&m.profiles)
        .map(|(model, scan)| deviation(model, &scan.points))
        .collect()
}

/// Σ (z − h)² over all compared profile points, and their number.
fn profile_ssr(r: &Response, m: &Measurements) -> (f64, usize) {
    lines(r, m).iter().fold((0.0, 0), |(s, n), d| {
        (s + d.rms * d.rms * d.points as f64, n + d.points)
    })
}

/// χ²(E(ν), ν): the misfit at the best E for this response.
fn chi2(r: &Response, m: &Measurements) -> f64 {
    let noise = m.specimen.noise;
    let e = fit_e(&r.force_per_e, m);
    let (profiles, _) = profile_ssr(r, m);
    force_ssr(e, &r.force_per_e, m) / noise.force.powi(2) + profiles / noise.profile.powi(2)
}

/// The identification result.
#[derive(Debug, Clone)]
pub struct Fit {
    /// The model fitted.
    pub model: ModelForm,
    /// Poisson's ratio: fitted, or as given.
    pub nu: f64,
    /// Young's modulus (MPa).
    pub e: f64,
    /// Standard deviations under the stated noise; ν's and the correlation only when ν was
    /// fitted.
    pub sigma_e: f64,
    /// Standard deviation of ν; `None` when ν was given.
    pub sigma_nu: Option<f64>,
    /// Correlation of the E and ν estimates; `None` when ν was given.
    pub correlation: Option<f64>,
    /// RMS force residual (N) and χ² per force point.
    pub force_rms: f64,
    /// χ² per force point: the mean squared force residual over σ_F².
    pub force_chi2: f64,
    /// RMS profile deviation (mm) over all compared points, and each scan line's deviation.
    pub profile_rms: f64,
    /// Each scan line's deviation, in the specimen's order.
    pub lines: Vec<Deviation>,
    /// Whether the fitted ν lies at an end of [`NU_RANGE`], the last step pointing beyond
    /// it: the model fits best with a ν outside what it can take, so ν (and E with it) is
    /// no material value.
    pub at_bound: bool,
    /// The model's response at the fitted ν.
    pub response: Response,
    /// Runs of the scene the fit needed.
    pub evaluations: usize,
}

impl Fit {
    /// Whether the residuals are at the stated noise level (see [`FORCE_LEVEL`]).
    pub fn at_noise_level(&self, m: &Measurements) -> bool {
        let noise = m.specimen.noise;
        self.force_rms <= FORCE_LEVEL * noise.force
            && (!m.has_profiles() || self.profile_rms <= PROFILE_LEVEL * noise.profile)
    }
}

/// The projected residuals r(ν) and their derivative ∂r/∂ν at a response with slopes:
/// the forces' rows (F − E(ν) g) / σ_F, E(ν) = Σ F g / Σ g² and
/// ∂E/∂ν = (Σ F g' − 2 E Σ g g') / Σ g², then the compared profile points' (z − h) / σ_P.
fn projected(r: &Response, m: &Measurements) -> Vec<(f64, f64)> {
    let noise = m.specimen.noise;
    let (g, dg) = (&r.force_per_e, &r.force_slope);
    let gg: f64 = g.iter().map(|x| x * x).sum();
    let e = fit_e(g, m);
    let de = (m.force.iter().zip(dg).map(|(f, d)| f * d).sum::<f64>()
        - 2.0 * e * g.iter().zip(dg).map(|(g, d)| g * d).sum::<f64>())
        / gg;
    let mut rows: Vec<(f64, f64)> = m
        .force
        .iter()
        .zip(g.iter().zip(dg))
        .map(|(f, (g, d))| ((f - e * g) / noise.force, -(de * g + e * d) / noise.force))
        .collect();
    rows.extend(
        profile_rows(r, m).map(|(z, h, dh)| ((z - h) / noise.profile, -dh / noise.profile)),
    );
    rows
}

/// Each compared profile point: (z, h, ∂h/∂ν), the model's values interpolated at the scan's
/// y (linear in the stations' values, so the slopes interpolate alike).
fn profile_rows<'a>(
    r: &'a Response,
    m: &'a Measurements,
) -> impl Iterator<Item = (f64, f64, f64)> + 'a {
    m.profiles.iter().enumerate().flat_map(move |(line, scan)| {
        let h = heights(&r.profiles[line], &scan.points);
        let dh = heights(&r.profile_slopes[line], &scan.points);
        scan.points
            .iter()
            .zip(h.into_iter().zip(dh))
            .filter_map(|(&(_, z), (h, dh))| Some((z, h?, dh?)))
    })
}

/// The Gauss–Newton step in ν, −Σ J r / Σ J² on the projected residuals, and ν's standard
/// deviation 1 / √(Σ J²) (the projection's: E's share of the information taken out).
fn gauss_newton_step(r: &Response, m: &Measurements) -> (f64, f64) {
    let (jr, jj) = projected(r, m)
        .iter()
        .fold((0.0, 0.0), |(jr, jj), (r, j)| (jr + j * r, jj + j * j));
    (-jr / jj, 1.0 / jj.sqrt())
}

/// ν by Gauss–Newton from `start` (see the module's text): the response at the
/// fitted ν (with slopes), the runs made, and whether the last step pointed beyond the end
/// of [`NU_RANGE`] (the model's best ν lies outside what it can take). `observe(ν, χ²)`
/// after each run.
fn fit_nu(
    m: &Measurements,
    model: &ModelForm,
    start: f64,
    observe: &(dyn Fn(f64, f64) + Sync),
) -> Result<(Response, usize, bool)> {
    let evaluate = |nu: f64, from: Option<&Response>| -> Result<(Response, f64)> {
        let r = response(m, model, nu, true, from)?;
        let chi = chi2(&r, m);
        observe(nu, chi);
        Ok((r, chi))
    };
    let (mut best, mut chi) = evaluate(start, None)?;
    let mut runs = 1;
    // The step from the run before `best` to it, once there is one.
    let mut last_step: Option<f64> = None;
    loop {
        let nu = best.nu;
        let (step, sigma) = gauss_newton_step(&best, m);
        if !step.is_finite() {
            bail!("E and ν cannot be told apart by these data (no slope in ν at ν = {nu})");
        }
        let bound = if step > 0.0 { NU_RANGE.1 } else { NU_RANGE.0 };
        let beyond = step.abs() > (bound - nu).abs();
        let mut next = if beyond {
            nu + BOUNDARY_FRACTION * (bound - nu)
        } else {
            nu + step
        };
        // The next step, at the contraction the last two showed.
        let after = last_step.map_or(f64::INFINITY, |last| step * step / last.abs());
        if !beyond && step.abs() <= LINEAR_FRACTION * sigma && after <= STEP_FRACTION * sigma {
            let moved = best.moved(step);
            let moved_chi = chi2(&moved, m);
            if moved_chi <= chi {
                observe(moved.nu, moved_chi);
                return Ok((moved, runs, false));
            }
        }
        loop {
            if (next - nu).abs() <= STEP_FRACTION * sigma {
                return Ok((best, runs, beyond));
            }
            if runs == MAX_RUNS {
                bail!(
                    "the ν fit did not converge in {MAX_RUNS} runs (last ν = {nu}, step \
                     {step:.2e})"
                );
            }
            let (trial, trial_chi) = evaluate(next, Some(&best))?;
            runs += 1;
            if trial_chi <= chi {
                last_step = Some(next - nu);
                (best, chi) = (trial, trial_chi);
                break;
            }
            next = nu + 0.5 * (next - nu);
        }
    }
}

/// Fits ν (unless `fixed_nu` is given) and E of `model` to `m`. `observe(ν, χ²)` is called
/// after each run of the scene (for progress).
pub fn identify(
    m: &Measurements,
    model: &ModelForm,
    fixed_nu: Option<f64>,
    observe: &(dyn Fn(f64, f64) + Sync),
) -> Result<Fit> {
    let (r, evaluations, at_bound) = match fixed_nu {
        Some(nu) => {
            let mut scene = CutBlock::new();
            let vr = scene.lookup("nu")?;
            scene.set_real(vr, &[nu]).context("--nu")?;
            let r = response(m, model, nu, false, None)?;
            observe(nu, chi2(&r, m));
            (r, 1, false)
        }
        None if !m.has_profiles() => {
            bail!("the set has no profiles to fit ν to: give ν (--nu) to fit E alone")
        }
        None => fit_nu(m, model, NU_START, observe)?,
    };
    finish(m, model, fixed_nu.is_none(), r, evaluations, at_bound)
}

/// Fits ν and E of `model` to `m` (which has profiles) with the iteration started at
/// `start`: a fit of the same data on another mesh ([`super::discretization`]).
pub fn refit(
    m: &Measurements,
    model: &ModelForm,
    start: f64,
    observe: &(dyn Fn(f64, f64) + Sync),
) -> Result<Fit> {
    ensure!(m.has_profiles(), "the set has no profiles to fit ν to");
    let (r, evaluations, at_bound) = fit_nu(m, model, start, observe)?;
    finish(m, model, true, r, evaluations, at_bound)
}

/// The fit at the response `r` at the final ν (fitted if `fitted`, else given): E, the
/// covariance and the residuals.
fn finish(
    m: &Measurements,
    model: &ModelForm,
    fitted: bool,
    r: Response,
    evaluations: usize,
    at_bound: bool,
) -> Result<Fit> {
    // The states served the iteration's starts: no part of the result.
    let r = Response {
        states: Vec::new(),
        ..r
    };
    let nu = r.nu;
    let e = fit_e(&r.force_per_e, m);
    let covariance = if fitted {
        Some(covariance(m, e, &r)?)
    } else {
        None
    };
    let gg: f64 = r.force_per_e.iter().map(|g| g * g).sum();
    let n = m.force.len() as f64;
    let ssr = force_ssr(e, &r.force_per_e, m);
    let (profiles, points) = profile_ssr(&r, m);
    if m.has_profiles() && points == 0 {
        bail!(
            "no profile point could be compared at ν = {nu}: the model has no top surface at \
             any scanned y (do the scans belong to this specimen?)"
        );
    }
    Ok(Fit {
        model: *model,
        nu,
        e,
        sigma_e: covariance.map_or(m.specimen.noise.force / gg.sqrt(), |c| c[0][0].sqrt()),
        sigma_nu: covariance.map(|c| c[1][1].sqrt()),
        correlation: covariance.map(|c| c[0][1] / (c[0][0] * c[1][1]).sqrt()),
        force_rms: (ssr / n).sqrt(),
        force_chi2: ssr / m.specimen.noise.force.powi(2) / n,
        profile_rms: if points == 0 {
            0.0
        } else {
            (profiles / points as f64).sqrt()
        },
        lines: lines(&r, m),
        at_bound,
        response: r,
        evaluations,
    })
}

/// (JᵀJ)⁻¹ for (E, ν) from the weighted residuals at the optimum and their derivatives
/// (∂F/∂E = g, ∂F/∂ν = E ∂g/∂ν, ∂h/∂ν; the heights do not depend on E).
fn covariance(m: &Measurements, e: f64, r: &Response) -> Result<[[f64; 2]; 2]> {
    let noise = m.specimen.noise;
    let mut jtj = [[0.0; 2]; 2];
    let mut add = |row: [f64; 2]| {
        for a in 0..2 {
            for b in 0..2 {
                jtj[a][b] += row[a] * row[b];
            }
        }
    };
    for (g, dg) in r.force_per_e.iter().zip(&r.force_slope) {
        add([g / noise.force, e * dg / noise.force]);
    }
    for (_, _, dh) in profile_rows(r, m) {
        add([0.0, dh / noise.profile]);
    }
    let det = jtj[0][0] * jtj[1][1] - jtj[0][1] * jtj[1][0];
    if det.is_nan() || det <= 0.0 {
        bail!("E and ν cannot be told apart by these data (singular information matrix)");
    }
    Ok([
        [jtj[1][1] / det, -jtj[0][1] / det],
        [-jtj[1][0] / det, jtj[0][0] / det],
    ])
}

/// Noise-free data for the tests of the fit and of its mesh's share.
#[cfg(test)]
pub(crate) mod fixtures {
    use super::*;
    use crate::studies::measurements::{Noise, Scan};

    /// A specimen other than the default: `cells`, cut at y = 35 mm, 6 mm deep, scanned
    /// along x = 30 and 60 mm.
    pub fn specimen(cells: [u32; 3]) -> Specimen {
        Specimen {
            size: [100.0, 80.0, 17.0],
            cells,
            mesh_grading: 1.0,
            y_cut: 35.0,
            cut_depth: 6.0,
            cut_x: 100.0,
            support: "clamped".into(),
            scan_lines: vec![30.0, 60.0],
            noise: Noise {
                force: 0.03,
                profile: 0.02,
            },
        }
    }

    /// Noise-free data of `model` with known E and ν made on [`specimen`]`(made_on)`, pulls
    /// 0, 2, …, 10 mm, for a specimen of `cells`.
    pub fn synthetic(
        model: &ModelForm,
        e: f64,
        nu: f64,
        made_on: [u32; 3],
        cells: [u32; 3],
    ) -> Measurements {
        let displacement: Vec<f64> = (0..=5).map(|k| 2.0 * f64::from(k)).collect();
        let made = specimen(made_on);
        let lines = made.scan_lines.clone();
        let r = run(&made, &displacement, model, nu, &lines, false, None).unwrap();
        Measurements {
            specimen: specimen(cells),
            force: r.force_per_e.iter().map(|g| e * g).collect(),
            displacement,
            profiles: lines
                .iter()
                .zip(&r.profiles)
                .map(|(&x, p)| Scan {
                    x,
                    points: p
                        .iter()
                        .enumerate()
                        .filter(|(_, z)| z.is_finite())
                        .map(|(i, z)| (i as f64 * PROFILE_STEP, *z))
                        .collect(),
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The cells of the tests' specimen.
    const CELLS: [u32; 3] = [4, 8, 6];

    fn synthetic(model: &ModelForm, e: f64, nu: f64) -> Measurements {
        fixtures::synthetic(model, e, nu, CELLS, CELLS)
    }

    /// On noise-free data along scan lines other than the seed's, the fit lands on the
    /// parameters the data were made with to within Brent's tolerance on ν (1e-4
    /// relative) and what follows from it for E.
    #[test]
    fn recovers_known_parameters_of_the_neo_hookean_tet10_model() {
        let model = ModelForm {
            law: Law::NeoHookean,
            element: Tetrahedron::Tet10,
        };
        let (e, nu) = (0.045, 0.42);
        let m = synthetic(&model, e, nu);
        let fit = identify(&m, &model, None, &|_, _| {}).unwrap();
        println!(
            "fit: E = {:.6} ± {:.2e} (true {e}), ν = {:.5} ± {:.2e} (true {nu}), \
             correlation {:.3}, {} runs",
            fit.e,
            fit.sigma_e,
            fit.nu,
            fit.sigma_nu.unwrap(),
            fit.correlation.unwrap(),
            fit.evaluations
        );
        assert!(((fit.e - e) / e).abs() < 2e-4, "{}", fit.e);
        assert!(((fit.nu - nu) / nu).abs() < 2e-4, "{}", fit.nu);
        assert!(fit.profile_rms < 1e-3 && fit.force_rms < 1e-4);
        assert!(fit.at_noise_level(&m));
    }

    #[test]
    fn forces_alone_give_e_at_a_given_nu_and_trade_e_against_nu() {
        let model = ModelForm {
            law: Law::Linear,
            element: Tetrahedron::Tet4,
        };
        let mut m = synthetic(&model, 0.05, 0.4);
        m.profiles = Default::default();
        let e = identify(&m, &model, None, &|_, _| {}).unwrap_err();
        assert!(e.to_string().contains("give ν (--nu)"), "{e}");
        let fit = identify(&m, &model, Some(0.4), &|_, _| {}).unwrap();
        assert!(((fit.e - 0.05) / 0.05).abs() < 1e-9, "{}", fit.e);
        assert!(fit.sigma_nu.is_none());
        // Another ν fits the (linear) forces exactly with another E.
        let other = identify(&m, &model, Some(0.3), &|_, _| {}).unwrap();
        assert!(other.force_rms < 1e-9 * m.force[5], "{}", other.force_rms);
        assert!((other.e - 0.05).abs() > 1e-4, "E should move with ν");
        // The range of --nu is the scene's (ν < 0.499999), named in the message.
        let e = identify(&m, &model, Some(0.4999995), &|_, _| {}).unwrap_err();
        assert!(
            format!("{e:#}").contains("--nu") && format!("{e:#}").contains("0.4999995"),
            "{e:#}"
        );
        assert!(identify(&m, &model, Some(0.49999), &|_, _| {}).is_ok());
    }

    /// Scans that lie off the block compare no point: an error, not a profile RMS of 0
    /// that would call the fit noise-level.
    #[test]
    fn scans_that_compare_no_point_are_an_error() {
        let model = ModelForm {
            law: Law::Linear,
            element: Tetrahedron::Tet4,
        };
        let mut m = synthetic(&model, 0.05, 0.4);
        for scan in &mut m.profiles {
            for p in &mut scan.points {
                p.0 += 1000.0;
            }
        }
        let e = identify(&m, &model, Some(0.4), &|_, _| {}).unwrap_err();
        assert!(
            e.to_string().contains("no profile point could be compared"),
            "{e}"
        );
    }
}
