//! The FMU backend (feature `fmu`): the same sweep run through the packaged FMI 2 FMUs
//! (loaded by the `fmi` crate) and in process gives the same numbers bit for bit, and a case
//! the FMU refuses is recorded with the FMU's own message. Needs the bundled FMUs
//! (`bash fmu/bundle.sh`, or `cargo build --release -p fmu && target/release/bundle`; tests/run.sh
//! bundles its own build).
#![cfg(feature = "fmu")]

use std::path::{Path, PathBuf};

use harness::sweep::Experiment;
use harness::sweep::{self, Outcome};

fn fmu(name: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../target/fmu")
        .join(name);
    assert!(
        p.is_file(),
        "{} missing: bundle the FMUs first",
        p.display()
    );
    p
}

const CUTBLOCK: &str = r#"
name = "cut"
scene = "cutblock"
stop_time = 4.0
step = 1.0
record = ["reaction_force", "cut_opening", "bottom_lift"]
[parameters]
cells_x = 2
cells_y = 4
cells_z = 3
[inputs.pull]
time = [0.0, 4.0]
value = [0.0, 8.0]
[inputs.scalpel_x]
time = [0.0, 4.0]
value = [0.0, 100.0]
[[sweep]]
design = "grid"
values = { cut_strategy = ["duplicate", "delete"] }
ranges = { nu = { min = 0.3, max = 0.45, levels = 2 } }
"#;

const ABDOMEN: &str = r#"
name = "abd"
scene = "abdomen"
stop_time = 0.1
step = 0.01
record = ["floor_stress_max", "apex_uy"]
[parameters]
target_triangles = 300
[inputs.press_force]
time = [0.0, 0.1]
value = [0.0, 0.3]
[[sweep]]
design = "list"
values = { configuration = ["wide", "normal"], memory_limit = [8000.0, 1.0] }
[[sweep]]
design = "list"
values = { "anatomy.outlet" = [105.0] }
"#;

/// Outcomes in process and through the FMU, and the folder holding both sweeps.
fn run_both(text: &str, fmu_file: &str) -> (Vec<Outcome>, Vec<Outcome>, tempfile::TempDir) {
    let tmp = tempfile::tempdir().unwrap();
    let here = Experiment::parse(text, tmp.path()).unwrap();
    let with_fmu = text.replacen(
        "\nrecord",
        &format!("\nbackend = \"fmu\"\nfmu = {:?}\nrecord", fmu(fmu_file)),
        1,
    );
    let there = Experiment::parse(&with_fmu, tmp.path()).unwrap();
    let (a, b) = (tmp.path().join("in_process"), tmp.path().join("fmu"));
    let outcomes = |s: sweep::Sweep| s.results.into_iter().map(|r| r.outcome).collect();
    (
        outcomes(sweep::run(&here, &a).unwrap()),
        outcomes(sweep::run(&there, &b).unwrap()),
        tmp,
    )
}

fn same_case_files(tmp: &tempfile::TempDir, n: usize) {
    let (a, b) = (tmp.path().join("in_process"), tmp.path().join("fmu"));
    for i in 0..n {
        let f = format!("cases/case_{i:04}.csv");
        if a.join(&f).is_file() {
            assert_eq!(
                std::fs::read(a.join(&f)).unwrap(),
                std::fs::read(b.join(&f)).unwrap(),
                "{f}"
            );
        }
    }
}

#[test]
fn cut_block_through_both_fmus_equals_in_process_bit_for_bit() {
    for file in ["cutblock-fmi2.fmu", "cutblock-fmi3.fmu"] {
        let (here, there, tmp) = run_both(CUTBLOCK, file);
        assert_eq!(here.len(), 4);
        assert!(here.iter().all(|o| matches!(o, Outcome::Finished { .. })));
        assert_eq!(here, there, "{file}");
        same_case_files(&tmp, 4);
    }
}

#[test]
fn abdomen_through_both_fmus_equals_in_process_and_reports_the_fmu_error() {
    for file in ["abdomen-fmi2.fmu", "abdomen-fmi3.fmu"] {
        let (here, there, tmp) = run_both(ABDOMEN, file);
        assert!(matches!(here[0], Outcome::Finished { .. }));
        assert!(matches!(here[2], Outcome::Finished { .. }), "{:?}", here[2]);
        assert_eq!(here[0], there[0], "{file}");
        assert_eq!(
            here[2], there[2],
            "{file}: generated configuration files reach the FMU"
        );
        same_case_files(&tmp, 3);
        // A model larger than the case's memory_limit: known only once it is meshed.
        let Outcome::Failed(message) = &there[1] else {
            panic!("a case over its memory_limit fails")
        };
        assert!(message.contains("above memory_limit = 1 MB"), "{message}");
    }
}

/// The default press of 0.3 N/mm at 0.5 Hz from t = 5 s.
const STARTED_LATE: &str = r#"
name = "late"
scene = "abdomen"
start_time = 5.0
stop_time = 5.1
step = 0.01
record = ["press_total", "apex_uy"]
[parameters]
target_triangles = 300
press_amplitude = 0.3
"#;

/// Started at 5 s, the FMUs and the in-process scene see the same absolute times: the
/// recorded press is the applied one, 0.3 (1 − cos(2π · 0.5 Hz · t))/2 N/mm, at every point.
#[test]
fn a_start_time_reaches_the_fmus_as_the_fmi_time() {
    for file in ["abdomen-fmi2.fmu", "abdomen-fmi3.fmu"] {
        let (here, there, tmp) = run_both(STARTED_LATE, file);
        assert_eq!(here, there, "{file}");
        same_case_files(&tmp, 1);
        let path = tmp.path().join("fmu/cases/case_0000.csv");
        let series = harness::sweep::Series::read_csv(&path).unwrap();
        assert_eq!(series.rows[0][0], 5.0);
        for row in &series.rows {
            let applied = 0.15 * (1.0 - (std::f64::consts::PI * row[0]).cos());
            assert!((row[1] - applied).abs() < 1e-12, "{row:?}");
        }
    }
}
