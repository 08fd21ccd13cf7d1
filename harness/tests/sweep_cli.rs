//! The `harness sweep` command end to end: a case that cannot run is recorded and does not
//! stop the others; an interrupted sweep resumes without re-running finished cases and ends
//! with the same results as an uninterrupted one; a different plan in the same folder and an
//! invalid experiment file are refused before any work, naming the problem.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::Duration;

const EXPERIMENT: &str = r#"
name = "small"
scene = "abdomen"
stop_time = 0.2
step = 0.02
jobs = 2
record = ["floor_stress_max", "apex_uy"]
[parameters]
target_triangles = 400
[inputs.press_force]
time = [0.0, 0.2]
value = [0.0, 0.5]
[[sweep]]
design = "list"
values = { configuration = ["normal", "wide", "wide"], memory_limit = [8000, 1, 8000] }
[[sweep]]
design = "grid"
ranges = { floor_E = { min = 0.02, max = 0.2, log = true, levels = 3 } }
"#;

fn harness(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .output()
        .expect("the harness binary runs")
}

fn write_experiment(dir: &Path, text: &str) -> PathBuf {
    let p = dir.join("small.toml");
    std::fs::write(&p, text).unwrap();
    p
}

fn summary(dir: &Path) -> String {
    std::fs::read_to_string(dir.join("summary.csv")).unwrap()
}

fn sweep(exp: &Path, out: &Path) -> Output {
    harness(&[
        "sweep",
        exp.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ])
}

#[test]
fn failures_are_recorded_and_resuming_reruns_only_missing_cases() {
    let tmp = tempfile::tempdir().unwrap();
    let exp = write_experiment(tmp.path(), EXPERIMENT);
    let out = tmp.path().join("out");
    let o = sweep(&exp, &out);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = summary(&out);
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 7, "{text}");
    assert!(
        lines[2].contains("failed") && lines[2].contains("above memory_limit = 1 MB"),
        "{text}"
    );
    assert_eq!(text.matches(",finished,").count(), 5, "{text}");
    // The grid over the floor's modulus (×10 over three cases) acts: under the same press
    // (a load, not a displacement) the stiffer floor stretches less, so its stress grows,
    // but by less than the modulus; the apex descends less.
    let column = |name: &str| {
        let k = lines[0].split(',').position(|c| c == name).unwrap();
        lines[4..7]
            .iter()
            .map(|l| l.split(',').nth(k).unwrap().parse::<f64>().unwrap())
            .collect::<Vec<_>>()
    };
    let stress = column("floor_stress_max_peak");
    assert!(stress[0] < stress[1] && stress[1] < stress[2], "{stress:?}");
    assert!(stress[2] / stress[0] < 10.0, "{stress:?}");
    let apex = column("apex_uy_final");
    assert!(
        apex[0] < apex[1] && apex[1] < apex[2] && apex[2] < 0.0,
        "{apex:?}"
    );
    for f in [
        "report.md",
        "metric_vs_floor_E.png",
        "metric_vs_floor_E.svg",
        "histories.png",
        "plan.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }

    // Lose two finished cases, as if the run had been interrupted before them.
    let case = |i: usize| out.join(format!("cases/case_{i:04}.csv"));
    let kept = std::fs::metadata(case(0)).unwrap().modified().unwrap();
    let before = std::fs::read(case(3)).unwrap();
    std::fs::remove_file(case(3)).unwrap();
    std::fs::remove_file(case(5)).unwrap();
    let o = sweep(&exp, &out);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success());
    // The failed case is retried, the two lost ones rerun: three cases run now.
    assert!(
        stdout.contains("6 cases (3 run now, 3 finished earlier)"),
        "{stdout}"
    );
    assert_eq!(
        std::fs::metadata(case(0)).unwrap().modified().unwrap(),
        kept
    );
    assert_eq!(
        std::fs::read(case(3)).unwrap(),
        before,
        "reruns are deterministic"
    );
    assert_eq!(summary(&out), text);
    let leftovers: Vec<_> = std::fs::read_dir(out.join("cases"))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");

    // Another plan in the same folder is refused: other cases, or the same cases run longer.
    for change in [
        ("levels = 3", "levels = 4"),
        ("stop_time = 0.2", "stop_time = 0.4"),
    ] {
        let other = write_experiment(tmp.path(), &EXPERIMENT.replace(change.0, change.1));
        let o = sweep(&other, &out);
        assert!(!o.status.success(), "{change:?}");
        assert!(String::from_utf8_lossy(&o.stderr).contains("different plan"));
    }
    assert_eq!(summary(&out), text, "the refused runs changed nothing");
}

/// The finished case files of a sweep folder, each with its inode and modification time
/// (a rewritten file gets a new inode: files are written through a rename).
fn finished(dir: &Path) -> std::collections::BTreeMap<String, (u64, std::time::SystemTime)> {
    use std::os::unix::fs::MetadataExt;
    let Ok(entries) = std::fs::read_dir(dir.join("cases")) else {
        return Default::default();
    };
    entries
        .map(|e| e.unwrap())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".csv"))
        .map(|e| {
            let m = e.metadata().unwrap();
            (
                e.file_name().to_string_lossy().into_owned(),
                (m.ino(), m.modified().unwrap()),
            )
        })
        .collect()
}

/// Killed after its first case and run again, a sweep keeps the finished case files as they
/// are (same inode and time: not recomputed), computes the others, and ends with the results
/// of an uninterrupted run.
#[test]
fn a_killed_sweep_resumes_to_the_same_results() {
    let tmp = tempfile::tempdir().unwrap();
    let exp = write_experiment(
        tmp.path(),
        &EXPERIMENT
            .replace("jobs = 2", "jobs = 1")
            .replace("target_triangles = 400", "target_triangles = 1000"),
    );
    let clean = tmp.path().join("clean");
    assert!(sweep(&exp, &clean).status.success());

    let out = tmp.path().join("killed");
    let mut child = Command::new(env!("CARGO_BIN_EXE_harness"))
        .args([
            "sweep",
            exp.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Until the first case is written (or the sweep has ended on its own, which the
    // assertions below then report).
    while !out.join("cases/case_0000.csv").is_file() && child.try_wait().unwrap().is_none() {
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    let before = finished(&out);
    let all = finished(&clean);
    assert!(
        before.contains_key("case_0000.csv"),
        "the first case should have finished before the kill"
    );
    assert!(
        before.len() < all.len() && !out.join("summary.csv").is_file(),
        "the sweep should have been killed before its end ({} of {} cases)",
        before.len(),
        all.len()
    );
    let o = sweep(&exp, &out);
    assert!(o.status.success());
    let after = finished(&out);
    for (name, stamp) in &before {
        assert_eq!(after.get(name), Some(stamp), "{name} was recomputed");
    }
    assert_eq!(
        after.keys().collect::<Vec<_>>(),
        all.keys().collect::<Vec<_>>(),
        "the unfinished cases were computed"
    );
    assert_eq!(summary(&out), summary(&clean));
}

#[test]
fn invalid_experiments_fail_before_any_work_naming_the_key() {
    let tmp = tempfile::tempdir().unwrap();
    for (text, needle) in [
        (
            EXPERIMENT.replace("jobs = 2", "jobs = 2\nthreads = 4"),
            "threads",
        ),
        (
            EXPERIMENT.replace("max = 0.2, log", "max = -0.2, log"),
            "sweep[1].ranges.floor_E",
        ),
        // Each case's values on the scene before the first case runs: an unknown choice, a
        // configuration that does not resolve, values that do not go together.
        (
            EXPERIMENT.replace("memory_limit =", "kinematics = [\"finite\", \"finit\", \"linear\"], memory_limit ="),
            "`sweep` case 1 (configuration = wide, kinematics = finit, memory_limit = 1): `kinematics` = finit: unknown kinematics `finit`",
        ),
        (
            EXPERIMENT.replace("\"wide\", \"wide\"]", "\"wide\", \"no_such_pelvis\"]"),
            "`sweep` case 2 (configuration = no_such_pelvis, memory_limit = 8000): invalid configuration: configuration `no_such_pelvis` is no shipped configuration",
        ),
        (
            EXPERIMENT.replace("target_triangles = 400", "target_triangles = 400\nmodel_order = \"modal\""),
            "model_order = \"modal\" reduces the linear model: use kinematics = \"linear\"",
        ),
        (
            EXPERIMENT.replace("value = [0.0, 0.5]", "value = [0.0, 5000.0]"),
            "inputs.press_force",
        ),
    ] {
        let exp = write_experiment(tmp.path(), &text);
        let out = tmp.path().join("never");
        let o = sweep(&exp, &out);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success());
        assert!(err.contains(needle), "`{err}` should name `{needle}`");
        assert!(!out.exists(), "nothing is written for an invalid file");
    }
}

/// How close the modal sweep's peaks are to full order (relative): about three times the
/// largest difference measured on 2026-11-25, 4.7e-4.
const MODAL_PEAKS: f64 = 1.5e-3;

/// `model_order` in an experiment file: the same small sweep in modal order gives the
/// full-order peaks within a few times the difference measured on 2026-11-25.
#[test]
fn a_modal_sweep_gives_the_full_order_peaks() {
    use harness::sweep::experiment::Experiment;
    use harness::sweep::runner::{self, Outcome};

    let tmp = tempfile::tempdir().unwrap();
    let peaks = |order: &str| {
        let text = format!(
            "name = \"orders\"\nscene = \"abdomen\"\nstop_time = 1.0\nstep = 0.01\njobs = 2\n\
             record = [\"floor_stress_max\", \"apex_uy\"]\n\
             [parameters]\ntarget_triangles = 800\nkinematics = \"linear\"\n\
             model_order = \"{order}\"\n\
             [[sweep]]\ndesign = \"list\"\nvalues = {{ configuration = [\"narrow\", \"wide\"] }}\n"
        );
        let e = Experiment::parse(&text, tmp.path()).unwrap();
        let s = runner::run(&e, &tmp.path().join(order)).unwrap();
        s.results
            .iter()
            .flat_map(|r| match &r.outcome {
                Outcome::Finished { peak, .. } => peak.clone(),
                Outcome::Failed(e) => panic!("{order}: {e}"),
            })
            .collect::<Vec<f64>>()
    };
    let (full, modal) = (peaks("full"), peaks("modal"));
    assert_eq!(full.len(), 4);
    let worst = full
        .iter()
        .zip(&modal)
        .map(|(f, m)| (f - m).abs() / f.abs())
        .fold(0.0, f64::max);
    println!("modal against full order, largest relative difference of a peak: {worst:.2e}");
    assert!(worst <= MODAL_PEAKS, "full {full:?} modal {modal:?}");
}
