//! Cut-block scene benchmarks on the default block (6 × 16 × 14 cubes × 5 tetrahedra).
//!
//! Run: `cargo bench -p models --bench cutblock`.

use divan::Bencher;
use models::scene::cutblock::{CutBlock, PROFILE_STATIONS};
use models::scene::Scene;

fn main() {
    divan::main();
}

fn initialized() -> CutBlock {
    let mut s = CutBlock::new();
    s.initialize(0.0).unwrap();
    s.set("scalpel_x", 50.0).unwrap();
    s.do_step(0.0, 1.0).unwrap();
    s
}

/// A step that only changes the pull: one solve with the existing factorization.
#[divan::bench]
fn load_only_step(bencher: Bencher) {
    let mut s = initialized();
    let mut pull = 0.0;
    bencher.bench_local(|| {
        pull = if pull == 10.0 { 5.0 } else { 10.0 };
        s.set("pull", pull).unwrap();
        s.do_step(0.0, 1.0).unwrap();
    });
}

/// All outputs after a step (reaction, flank and surface measures, von Mises, profiles).
#[divan::bench]
fn all_outputs(bencher: Bencher) {
    let mut s = initialized();
    s.set("pull", 10.0).unwrap();
    let names = [
        "reaction_force",
        "cut_opening",
        "bottom_lift",
        "x_contraction",
        "max_von_mises",
    ];
    let vrs: Vec<u32> = names.iter().map(|n| s.lookup(n).unwrap()).collect();
    let profile = s.lookup("profile_x50").unwrap();
    let mut p = vec![0.0; PROFILE_STATIONS];
    bencher.bench_local(|| {
        s.do_step(0.0, 1.0).unwrap();
        let mut x = [0.0];
        for &vr in &vrs {
            s.get_real(vr, &mut x).unwrap();
        }
        s.get_real(profile, &mut p).unwrap();
    });
}

/// The blade advanced by 1 mm at a 10 mm pull, from 50 to 51 mm (the set-up outside the
/// timing): new mesh, pattern, symbolic analysis, assembly, factorization, and the solve
/// from the unloaded state (Newton in 1 mm load increments for the finite-strain laws).
#[divan::bench(args = [("linear", "tet4"), ("neo-hookean", "tet4"), ("neo-hookean", "tet10")], sample_count = 5, sample_size = 1)]
fn blade_advance_1mm(bencher: Bencher, (material, element): (&str, &str)) {
    bencher
        .with_inputs(|| {
            let mut s = CutBlock::new();
            for (name, value) in [("material", material), ("element", element)] {
                let vr = s.lookup(name).unwrap();
                s.set_string(vr, value).unwrap();
            }
            s.initialize(0.0).unwrap();
            s.set("scalpel_x", 50.0).unwrap();
            s.set("pull", 10.0).unwrap();
            s.do_step(0.0, 1.0).unwrap();
            s.set("scalpel_x", 51.0).unwrap();
            s
        })
        .bench_local_values(|mut s| {
            s.do_step(1.0, 1.0).unwrap();
            s
        });
}

/// A change of E: reassembly and numeric refactorization.
#[divan::bench]
fn material_change_step(bencher: Bencher) {
    let mut s = initialized();
    let mut e = 0.0385;
    bencher.bench_local(|| {
        e = if e == 0.0385 { 0.04 } else { 0.0385 };
        s.set("E", e).unwrap();
        s.do_step(0.0, 1.0).unwrap();
    });
}

mod parts {
    use super::*;
    use models::mesh::cut::{split, Incision};
    use models::mesh::generate;

    fn base() -> models::mesh::Mesh3d {
        generate::block([100.0, 80.0, 17.0], [6, 16, 14]).unwrap()
    }

    #[divan::bench]
    fn split_nodes(bencher: Bencher) {
        let b = base();
        let inc = Incision {
            y: 45.0,
            x: (0.0, 50.0),
            z: (8.5, 17.0),
        };
        bencher.bench_local(|| split(&b, &inc).unwrap());
    }

    #[divan::bench]
    fn mesh_new(bencher: Bencher) {
        let b = base();
        bencher.bench_local(|| {
            models::mesh::Mesh3d::new(b.nodes().to_vec(), b.tets().to_vec()).unwrap()
        });
    }

    #[divan::bench]
    fn pattern(bencher: Bencher) {
        let b = base();
        bencher.bench_local(|| models::assembly::solid::assembler(&b));
    }
}

/// A load step with the flanks pressed together (3 mm compression, full-width cut): solve,
/// flank search, active-set iterations with refactorization.
#[divan::bench(sample_count = 20)]
fn contact_step(bencher: Bencher) {
    let mut s = CutBlock::new();
    s.initialize(0.0).unwrap();
    s.set("scalpel_x", 100.0).unwrap();
    let mut pull = -3.0;
    bencher.bench_local(|| {
        pull = if pull == -3.0 { -2.5 } else { -3.0 };
        s.set("pull", pull).unwrap();
        s.do_step(0.0, 1.0).unwrap();
    });
}

/// The default block with the full cut, pulled 0 → 10 mm in one step with 1 mm load
/// increments (`max_increment` = 1): the finite-strain Newton solve (the set-up and the
/// cut are outside the timing). Iterations and the assembly / factorization / solve split:
/// `cargo run --release -p models --example cutblock_pull -- MATERIAL ELEMENT`.
#[divan::bench(args = [("linear", "tet4"), ("neo-hookean", "tet4"), ("neo-hookean", "tet10")], sample_count = 5, sample_size = 1)]
fn pull_to_10mm(bencher: Bencher, (material, element): (&str, &str)) {
    bencher
        .with_inputs(|| {
            let mut s = CutBlock::new();
            for (name, value) in [("material", material), ("element", element)] {
                let vr = s.lookup(name).unwrap();
                s.set_string(vr, value).unwrap();
            }
            s.initialize(0.0).unwrap();
            s.set("scalpel_x", 100.0).unwrap();
            s.do_step(0.0, 1.0).unwrap();
            s.set("pull", 10.0).unwrap();
            s
        })
        .bench_local_values(|mut s| {
            s.do_step(1.0, 1.0).unwrap();
            s
        });
}
