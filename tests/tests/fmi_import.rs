//! The packaged FMUs (`target/fmu/*.fmu`, written by the bundler) loaded through the `fmi`
//! crate — the importer the harness uses — give the in-process scene's numbers bit for bit.

use std::path::PathBuf;

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation as _, Common as _};
use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::{CoSimulation as _, Common as _, Fmi3Model as _, GetSet as _};
use fmi::import;
use models::scene::cutblock::CutBlock;
use models::scene::Scene;

fn fmu(name: &str) -> PathBuf {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../target/fmu")
        .join(name);
    assert!(p.is_file(), "{} missing: build and bundle first (cargo build --release -p fmu && target/release/bundle)", p.display());
    p
}

/// One test at a time: the METIS ordering inside each copy of the library (this binary and
/// each FMU) draws from libc's process-wide `rand()`, so two copies ordering at the same
/// moment may get different orderings and answers that differ in the last bits (see
/// `models/src/solve/ordering.rs`).
static ONE_COPY_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

const SMALL: [(&str, f64); 3] = [("cells_x", 2.0), ("cells_y", 4.0), ("cells_z", 3.0)];
const STEPS: [(f64, f64); 3] = [(2.0, 0.0), (6.0, 50.0), (10.0, 100.0)];

/// Reaction forces of the in-process scene for the STEPS inputs.
fn in_process() -> Vec<f64> {
    let mut s = CutBlock::new();
    for (n, v) in SMALL {
        s.set(n, v).unwrap();
    }
    s.initialize(0.0).unwrap();
    STEPS
        .iter()
        .enumerate()
        .map(|(k, &(pull, x))| {
            s.set("pull", pull).unwrap();
            s.set("scalpel_x", x).unwrap();
            s.do_step(k as f64, 1.0).unwrap();
            s.get("reaction_force").unwrap()
        })
        .collect()
}

fn fmi2_vr(name: &str) -> u32 {
    fmu::instance::fmi2_scalars(CutBlock::new().variables())
        .iter()
        .position(|s| s.name == name)
        .unwrap() as u32
}

#[test]
fn fmi2_cutblock_through_the_fmi_crate_matches_in_process() {
    let _one = ONE_COPY_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let import: Fmi2Import = import::from_path(fmu("cutblock-fmi2.fmu")).unwrap();
    let mut cs = import.instantiate_cs("cutblock", false, false).unwrap();
    cs.setup_experiment(None, 0.0, None).unwrap();
    for (n, v) in SMALL {
        cs.set_real(&[fmi2_vr(n)], &[v]).unwrap();
    }
    cs.enter_initialization_mode().unwrap();
    cs.exit_initialization_mode().unwrap();
    let mut got = Vec::new();
    for (k, &(pull, x)) in STEPS.iter().enumerate() {
        cs.set_real(&[fmi2_vr("pull"), fmi2_vr("scalpel_x")], &[pull, x])
            .unwrap();
        cs.do_step(k as f64, 1.0, true).unwrap();
        let mut f = [0.0];
        cs.get_real(&[fmi2_vr("reaction_force")], &mut f).unwrap();
        got.push(f[0]);
    }
    assert_eq!(
        got.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        in_process().iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    assert!(
        cs.set_real(&[fmi2_vr("nu")], &[0.5]).is_err(),
        "ν = 0.5 is refused"
    );
}

#[test]
fn fmi3_cutblock_through_the_fmi_crate_matches_in_process() {
    let _one = ONE_COPY_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let import: Fmi3Import = import::from_path(fmu("cutblock-fmi3.fmu")).unwrap();
    let mut cs = import
        .instantiate_cs("cutblock", false, false, false, false, &[])
        .unwrap();
    let scene = CutBlock::new();
    let vr = |n: &str| scene.lookup(n).unwrap();
    for (n, v) in SMALL {
        cs.set_float64(&[vr(n)], &[v]).unwrap();
    }
    cs.enter_initialization_mode(None, 0.0, None).unwrap();
    cs.exit_initialization_mode().unwrap();
    let mut got = Vec::new();
    let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
    for (k, &(pull, x)) in STEPS.iter().enumerate() {
        cs.set_float64(&[vr("pull"), vr("scalpel_x")], &[pull, x])
            .unwrap();
        cs.do_step(
            k as f64,
            1.0,
            true,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        )
        .unwrap();
        let mut f = [0.0];
        cs.get_float64(&[vr("reaction_force")], &mut f).unwrap();
        got.push(f[0]);
    }
    assert_eq!(last, 3.0);
    assert_eq!(
        got.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        in_process().iter().map(|x| x.to_bits()).collect::<Vec<_>>()
    );
    // The profile is one array of 181 values.
    let mut profile = vec![0.0; models::scene::cutblock::PROFILE_STATIONS];
    cs.get_float64(&[vr("profile_x50")], &mut profile).unwrap();
    assert!(profile[0].is_finite());
}
