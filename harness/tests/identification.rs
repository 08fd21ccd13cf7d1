//! Identification on the shipped measurement set A (issue #11): the model the data were
//! generated with (neo-Hookean, tet10) fits it to the noise level with ν inside its search
//! interval; the linear model does not, and its fit says so. The same model on set C is the
//! quick report's identification, checked alike by `commands.rs`
//! (`the_quick_report_writes_every_section`).

use harness::studies::discretization::stored;
use harness::studies::identify::{identify, Fit, ModelForm, FORCE_LEVEL, PROFILE_LEVEL};
use harness::studies::measurements::{Measurements, Source};

fn fit(set: &str, material: &str, element: &str) -> (Measurements, Fit) {
    let m = Measurements::load(&Source::Shipped, set).unwrap();
    let model = ModelForm::parse(material, element).unwrap();
    let fit = identify(&m, &model, None, &|_, _| {}).unwrap();
    (m, fit)
}

fn assert_at_noise_level(set: &str) -> Fit {
    let (m, f) = fit(set, "neo-hookean", "tet10");
    let noise = m.specimen.noise;
    let (force, profile) = (f.force_rms / noise.force, f.profile_rms / noise.profile);
    assert!(force <= FORCE_LEVEL, "set {set}: force RMS {force:.3} σ_F");
    assert!(
        profile <= PROFILE_LEVEL,
        "set {set}: profile RMS {profile:.3} σ_P"
    );
    assert!(!f.at_bound, "set {set}: ν = {} at the search bound", f.nu);
    // ν is determined by the profiles: a 95 % interval narrower than ±0.01.
    let sigma_nu = f.sigma_nu.expect("ν was fitted");
    assert!(1.96 * sigma_nu < 0.01, "set {set}: σ_ν = {sigma_nu}");
    assert!(
        1.96 * f.sigma_e < 0.01 * f.e,
        "set {set}: σ_E = {}",
        f.sigma_e
    );
    assert!(f.at_noise_level(&m));
    f
}

/// And where the fit before the derivatives landed — Brent's method on ν, each trial a run,
/// 12 runs, to 1e-4 of ν (docs/results.md, d27ca4c): E = 0.04992 MPa, ν = 0.4531 to the
/// printed digits, in two runs.
///
/// The stored refits on × 1.5 and × 2 cells (experiments/references/identification.toml)
/// belong to this fit (an error otherwise), and give the mesh's share the docs quote
/// (docs/theory/cutblock.md, "Identification"; recomputed by hand from the stored fits:
/// ν's observed order 3.36, extrapolated at 3 to 0.4877): ν's 95 % half-width 0.0432 — 27
/// times the noise's, dominating the total 0.0433 — and E's 0.00045 (its changes grow: 3
/// times 0.05006 − 0.04992), 1.8 times the noise's.
#[test]
fn neo_hookean_tet10_fits_set_a_to_the_noise_level() {
    let f = assert_at_noise_level("A");
    assert_eq!(
        (format!("{:.5}", f.e), format!("{:.4}", f.nu)),
        ("0.04992".into(), "0.4531".into())
    );
    assert_eq!(f.evaluations, 2);
    let m = Measurements::load(&Source::Shipped, "A").unwrap();
    let (d, _) = stored("A", &f.model, &m.specimen, &f, 13.0)
        .unwrap()
        .expect("set A's refits are stored");
    assert_eq!(
        (d.meshes[0].e, d.meshes[0].nu),
        (f.e, f.nu),
        "the first is this fit"
    );
    assert!(!d.at_bound());
    let (noise_e, noise_nu) = (1.96 * f.sigma_e, 1.96 * f.sigma_nu.unwrap());
    assert!((d.nu.halfwidth - 0.0432).abs() < 0.0001, "{:?}", d.nu);
    assert!((d.nu.total(noise_nu) - 0.0433).abs() < 0.0001, "{:?}", d.nu);
    assert!((d.nu.halfwidth / noise_nu - 27.0).abs() < 0.5, "{noise_nu}");
    assert!((d.e.halfwidth - 0.00045).abs() < 0.000005, "{:?}", d.e);
    assert!((d.e.halfwidth / noise_e - 1.8).abs() < 0.05, "{noise_e}");
    // The converged mesh fits a larger ν: the specimens' cells are stiff in volume change.
    assert!(d.nu.limit > f.nu + 10.0 * f.sigma_nu.unwrap(), "{:?}", d.nu);
    // A fit a σ of E away from the stored one is a changed model: an error that names the
    // command to measure again; other cells or a given ν have no stored refits.
    let mut moved = f.clone();
    moved.e += f.sigma_e;
    let e = stored("A", &f.model, &m.specimen, &moved, 13.0).unwrap_err();
    assert!(e.to_string().contains("--discretization"), "{e}");
    let mut other = m.specimen.clone();
    other.cells[0] += 1;
    assert!(stored("A", &f.model, &other, &f, 13.0).unwrap().is_none());
    let given = Fit {
        sigma_nu: None,
        ..f.clone()
    };
    assert!(stored("A", &f.model, &m.specimen, &given, 13.0)
        .unwrap()
        .is_none());
}

#[test]
fn the_linear_model_misses_set_a_and_the_fit_says_so() {
    let (m, f) = fit("A", "linear", "tet4");
    assert!(!f.at_noise_level(&m));
    let profile = f.profile_rms / m.specimen.noise.profile;
    assert!(profile > 10.0, "profile RMS {profile:.2} σ_P");
    assert!(
        f.response.warnings.iter().any(|w| w.contains("strain")),
        "no strain warning: {:?}",
        f.response.warnings
    );
}
