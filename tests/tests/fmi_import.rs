//! The packaged FMUs (`target/fmu/*.fmu`, written by the bundler) loaded through the `fmi`
//! crate — the importer the harness uses — give the in-process scene's numbers bit for bit,
//! alone or with every other copy of the library stepping at the same time in other threads.

use std::path::PathBuf;

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation as _, Common as _};
use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::{CoSimulation as _, Common as _, Fmi3Model as _, GetSet as _};
use fmi::import;
use models::scene::{self, Scene};

fn fmu(name: &str) -> PathBuf {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../target/fmu")
        .join(name);
    assert!(
        p.is_file(),
        "{} missing: build and bundle first (bash fmu/bundle.sh)",
        p.display()
    );
    p
}

/// A run: parameters before initialization, inputs before each step, outputs after it.
struct Scenario {
    scene: &'static str,
    parameters: &'static [(&'static str, f64)],
    inputs: fn(usize) -> Vec<(&'static str, f64)>,
    outputs: &'static [&'static str],
    steps: usize,
    h: f64,
}

/// The cut block with the scalpel crossing a small block cell by cell (a new topology, and
/// with it a new ordering, at every cell) while the pull grows. Its tet4 is ordered by AMD;
/// METIS orders the abdomen's finite-strain factor below.
const CUTBLOCK: Scenario = Scenario {
    scene: "cutblock",
    parameters: &[("cells_x", 6.0), ("cells_y", 4.0), ("cells_z", 3.0)],
    inputs: |k| {
        vec![
            ("pull", 0.8 * k as f64),
            ("scalpel_x", 100.0 * k as f64 / 6.0),
        ]
    },
    outputs: &["reaction_force", "cut_opening"],
    steps: 7,
    h: 1.0,
};

/// The abdomen's default press on a coarse mesh.
const ABDOMEN: Scenario = Scenario {
    scene: "abdomen",
    parameters: &[("target_triangles", 300.0)],
    inputs: |_| Vec::new(),
    outputs: &["floor_stress_mean", "apex_uy"],
    steps: 20,
    h: 0.01,
};

/// The outputs of every step as bits.
type Bits = Vec<u64>;

fn bits(x: &[f64]) -> Bits {
    x.iter().map(|v| v.to_bits()).collect()
}

fn in_process(s: &Scenario) -> Bits {
    let mut scene = scene::create(s.scene).unwrap();
    let vr = |scene: &dyn Scene, n: &str| scene.lookup(n).unwrap();
    for &(n, v) in s.parameters {
        scene.set_real(vr(scene.as_ref(), n), &[v]).unwrap();
    }
    scene.initialize(0.0).unwrap();
    let mut out = Vec::new();
    for k in 0..s.steps {
        for (n, v) in (s.inputs)(k) {
            scene.set_real(vr(scene.as_ref(), n), &[v]).unwrap();
        }
        scene.do_step(k as f64 * s.h, s.h).unwrap();
        for n in s.outputs {
            let mut x = [0.0];
            scene.get_real(vr(scene.as_ref(), n), &mut x).unwrap();
            out.push(x[0]);
        }
    }
    bits(&out)
}

/// The FMI 2 value reference of a scalar by name.
fn fmi2_vr(s: &Scenario, name: &str) -> u32 {
    fmu::addressing::fmi2_scalars(scene::create(s.scene).unwrap().variables())
        .iter()
        .position(|v| v.name == name)
        .unwrap() as u32
}

/// The run through the FMI 2 FMU, loaded (and so a copy of the library) of its own.
fn fmi2(s: &Scenario) -> Bits {
    let import: Fmi2Import = import::from_path(fmu(&format!("{}-fmi2.fmu", s.scene))).unwrap();
    let mut cs = import.instantiate_cs(s.scene, false, false).unwrap();
    cs.setup_experiment(None, 0.0, None).unwrap();
    for &(n, v) in s.parameters {
        cs.set_real(&[fmi2_vr(s, n)], &[v]).unwrap();
    }
    cs.enter_initialization_mode().unwrap();
    cs.exit_initialization_mode().unwrap();
    let mut out = Vec::new();
    for k in 0..s.steps {
        for (n, v) in (s.inputs)(k) {
            cs.set_real(&[fmi2_vr(s, n)], &[v]).unwrap();
        }
        cs.do_step(k as f64 * s.h, s.h, true).unwrap();
        for n in s.outputs {
            let mut x = [0.0];
            cs.get_real(&[fmi2_vr(s, n)], &mut x).unwrap();
            out.push(x[0]);
        }
    }
    bits(&out)
}

/// The run through the FMI 3 FMU, loaded of its own.
fn fmi3(s: &Scenario) -> Bits {
    let import: Fmi3Import = import::from_path(fmu(&format!("{}-fmi3.fmu", s.scene))).unwrap();
    let mut cs = import
        .instantiate_cs(s.scene, false, false, false, false, &[])
        .unwrap();
    let table = scene::create(s.scene).unwrap();
    let vr = |n: &str| table.lookup(n).unwrap();
    for &(n, v) in s.parameters {
        cs.set_float64(&[vr(n)], &[v]).unwrap();
    }
    cs.enter_initialization_mode(None, 0.0, None).unwrap();
    cs.exit_initialization_mode().unwrap();
    let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
    let mut out = Vec::new();
    for k in 0..s.steps {
        for (n, v) in (s.inputs)(k) {
            cs.set_float64(&[vr(n)], &[v]).unwrap();
        }
        cs.do_step(
            k as f64 * s.h,
            s.h,
            true,
            &mut event,
            &mut terminate,
            &mut early,
            &mut last,
        )
        .unwrap();
        for n in s.outputs {
            let mut x = [0.0];
            cs.get_float64(&[vr(n)], &mut x).unwrap();
            out.push(x[0]);
        }
    }
    assert_eq!(last, s.steps as f64 * s.h, "fmi3 lands on the last step");
    bits(&out)
}

#[test]
fn fmi2_and_fmi3_through_the_fmi_crate_match_in_process() {
    for s in [&CUTBLOCK, &ABDOMEN] {
        let expected = in_process(s);
        assert_eq!(fmi2(s), expected, "{} FMI 2", s.scene);
        assert_eq!(fmi3(s), expected, "{} FMI 3", s.scene);
    }
}

/// Both scenes, each through its FMI 2 and FMI 3 FMU (every run a copy of the library of
/// its own) and in process, all six at once in parallel threads, 20 times: every run equals
/// the serial in-process run to the last bit. METIS orders with a generator of each copy's
/// own, serialized within the copy (`models/src/linalg/ordering.rs`).
#[test]
fn every_copy_in_parallel_threads_gives_the_serial_results() {
    type Run = fn(&Scenario) -> Bits;
    let expected = [in_process(&CUTBLOCK), in_process(&ABDOMEN)];
    let runs: [(&Scenario, Run, &str); 6] = [
        (&CUTBLOCK, fmi2, "cutblock FMI 2"),
        (&CUTBLOCK, fmi3, "cutblock FMI 3"),
        (&CUTBLOCK, in_process, "cutblock in process"),
        (&ABDOMEN, fmi2, "abdomen FMI 2"),
        (&ABDOMEN, fmi3, "abdomen FMI 3"),
        (&ABDOMEN, in_process, "abdomen in process"),
    ];
    for repetition in 0..20 {
        std::thread::scope(|scope| {
            let handles: Vec<_> = runs
                .iter()
                .map(|&(s, run, name)| (name, s, scope.spawn(move || run(s))))
                .collect();
            for (name, s, handle) in handles {
                let got = handle.join().unwrap();
                let want = if s.scene == "cutblock" {
                    &expected[0]
                } else {
                    &expected[1]
                };
                assert_eq!(&got, want, "{name}, repetition {repetition}");
            }
        });
    }
}

#[test]
fn a_bad_value_is_refused_through_the_fmi_crate() {
    let import: Fmi2Import = import::from_path(fmu("cutblock-fmi2.fmu")).unwrap();
    let mut cs = import.instantiate_cs("cutblock", false, false).unwrap();
    cs.setup_experiment(None, 0.0, None).unwrap();
    assert!(
        cs.set_real(&[fmi2_vr(&CUTBLOCK, "nu")], &[0.5]).is_err(),
        "ν = 0.5 is refused"
    );
    let import: Fmi3Import = import::from_path(fmu("cutblock-fmi3.fmu")).unwrap();
    let mut cs = import
        .instantiate_cs("cutblock", false, false, false, false, &[])
        .unwrap();
    let table = scene::create("cutblock").unwrap();
    cs.enter_initialization_mode(None, 0.0, None).unwrap();
    cs.exit_initialization_mode().unwrap();
    // The profile is one array of 181 values.
    let mut profile = vec![0.0; models::scene::cutblock::PROFILE_STATIONS];
    cs.get_float64(&[table.lookup("profile_x50").unwrap()], &mut profile)
        .unwrap();
    assert!(profile[0].is_finite());
}
