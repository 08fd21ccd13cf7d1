//! The report commands end to end: each writes its folder with the files its report links,
//! and the shipped experiment files load.

use std::path::Path;
use std::process::Command;

use harness::sweep::Experiment;
use models::scene::Scene;

fn harness(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_harness"))
        .args(args)
        .output()
        .expect("the harness binary runs")
}

fn assert_files(dir: &Path, files: &[&str]) {
    let report = std::fs::read_to_string(dir.join("report.md")).unwrap();
    for f in files {
        assert!(dir.join(f).is_file(), "{f} missing");
        assert!(report.contains(f), "report.md does not link {f}");
    }
}

#[test]
fn fields_writes_the_stress_map_and_both_vtu_files() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("fields");
    let o = harness(&["fields", "--out", out.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("report.md"));
    assert_files(
        &out,
        &[
            "abdomen_stress.png",
            "abdomen_stress.svg",
            "abdomen.vtu",
            "cutblock.vtu",
        ],
    );
}

/// A small specimen (2 × 4 × 2 cells) for the `identify` command test.
const SPECIMEN: &str = r#"
size = [100.0, 80.0, 17.0]
cells = [2, 4, 2]
y_cut = 45.0
cut_depth = 8.5
cut_x = 100.0
support = "clamped"
[noise]
force = 0.01
profile = 0.02
"#;

#[test]
fn identify_fits_a_set_without_profiles_at_a_given_nu_and_refuses_a_bad_one() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::write(tmp.path().join("specimen_T.toml"), SPECIMEN).unwrap();
    // Forces proportional to the pull: the linear model's force is E · g · d, with g the
    // reaction of this specimen, fully cut, at E = 1 MPa, ν = 0.45 and 1 mm pull, so the
    // fit must give E = 0.8 / g.
    let mut block = models::scene::cutblock::CutBlock::new();
    for (name, value) in [
        ("cells_x", 2.0),
        ("cells_y", 4.0),
        ("cells_z", 2.0),
        ("E", 1.0),
        ("nu", 0.45),
    ] {
        block.set(name, value).unwrap();
    }
    block.initialize(0.0).unwrap();
    block.set("scalpel_x", 100.0).unwrap();
    block.set("pull", 1.0).unwrap();
    block.do_step(0.0, 1.0).unwrap();
    let expected = 0.8 / block.get("reaction_force").unwrap();
    let forces = tmp.path().join("force_displacement_T.csv");
    let mut text = String::from("displacement_mm,force_N\n");
    for d in 0..=5 {
        text += &format!("{d},{}\n", 0.8 * f64::from(d));
    }
    std::fs::write(&forces, text).unwrap();
    let out = tmp.path().join("id");
    let args = [
        "identify",
        "--data",
        tmp.path().to_str().unwrap(),
        "--set",
        "T",
        "--material",
        "linear",
        "--element",
        "tet4",
        "--nu",
        "0.45",
        "--out",
        out.to_str().unwrap(),
    ];
    let o = harness(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report = std::fs::read_to_string(out.join("report.md")).unwrap();
    let fitted = report
        .rsplit("| E (MPa) | ")
        .next()
        .and_then(|rest| rest.split_whitespace().next())
        .and_then(|e| e.parse::<f64>().ok())
        .unwrap_or_else(|| panic!("no E in {report}"));
    assert!((fitted - expected).abs() < 1e-5, "E {fitted} vs {expected}");
    assert_files(
        &out,
        &[
            "identify_T_linear_tet4_forces.png",
            "identify_T_linear_tet4_forces.svg",
        ],
    );

    let o = harness(&[&args[..3], &["--set", "T", "--out", out.to_str().unwrap()]].concat());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("--nu"),
        "a set without profiles needs ν: {err}"
    );

    std::fs::write(&forces, "displacement_mm,force_N\n1,abc\n").unwrap();
    let o = harness(&args);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("force_displacement_T.csv") && err.contains("row 1"),
        "{err}"
    );
}

#[test]
fn simulate_prints_the_series_and_names_bad_settings() {
    let tmp = tempfile::tempdir().unwrap();
    let inputs = tmp.path().join("in.csv");
    std::fs::write(&inputs, "time,pull\n0,0\n2,4\n").unwrap();
    let base = [
        "simulate",
        "cutblock",
        "--stop-time",
        "2",
        "--step",
        "1",
        "--set",
        "cells_x=2",
        "--set",
        "cells_y=4",
        "--set",
        "cut_strategy=delete",
        "--record",
        "pull,reaction_force",
    ];
    let o = harness(&[&base[..], &["--inputs", inputs.to_str().unwrap()]].concat());
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    let rows: Vec<Vec<&str>> = out.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows[0], ["time", "pull", "reaction_force"]);
    // The pull is sampled at each step's start and held: 0 then 2 (its value at t = 1 s).
    let pulls: Vec<&str> = rows[1..].iter().map(|r| r[1]).collect();
    assert_eq!(pulls, ["0.0", "0.0", "2.0"]);
    let force: f64 = rows[3][2].parse().unwrap();
    assert!(force > 0.0, "{out}");

    for (bad, needle) in [
        ("nu=abc", "abc"),
        ("poisson=0.3", "poisson"),
        ("nu", "name=value"),
    ] {
        let o = harness(&[&base[..], &["--set", bad]].concat());
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(needle), "{bad}: {err}");
    }
}

#[test]
fn shipped_experiments_load() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../experiments");
    let e = Experiment::load(&dir.join("pelvis_sweep.toml")).unwrap();
    assert_eq!(e.cases.len(), 5 + 32 + 5 * 5);
    assert_eq!(e.metric, "floor_stress_mean");
    let e = Experiment::load(&dir.join("cutblock_sweep.toml")).unwrap();
    assert_eq!(e.cases.len(), 15);
}
