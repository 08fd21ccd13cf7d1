//! Cut-block scene benchmarks on the default block (6 × 16 × 14 cubes × 6 tetrahedra, split
//! along x as the scene splits them) and, where named, on the accurate setting.
//!
//! Run: `cargo bench -p models --bench cutblock`.

use divan::Bencher;
use models::scene::cutblock::{CutBlock, Setting, PROFILE_STATIONS};
use models::scene::Scene;

fn main() {
    divan::main();
}

/// The default block uncut, split as the scene splits it.
fn default_block() -> models::mesh::Mesh3d {
    use models::mesh::generate::{block_on_planes, Split};
    let planes = [(100.0, 6), (80.0, 16), (17.0, 14)]
        .map(|(l, n)| (0..=n).map(|i| l * f64::from(i) / f64::from(n)).collect());
    block_on_planes(&planes, Split::ExtrudedX { mirrored: false }).unwrap()
}

fn initialized() -> CutBlock {
    let mut s = CutBlock::new();
    s.initialize(0.0).unwrap();
    s.set("scalpel_x", 50.0).unwrap();
    s.do_step(0.0, 1.0).unwrap();
    s
}

/// The block of `setting`, initialized: "MATERIAL ELEMENT" on the default cells, or
/// "accurate" ([`models::scene::cutblock::ACCURATE`]: neo-Hookean tet10 on 7 × 18 × 10 cubes graded with β = 2.25).
fn initialized_as(setting: &str) -> CutBlock {
    let mut s = CutBlock::new();
    let (material, element) = setting.split_once(' ').unwrap_or((setting, ""));
    Setting::named(material, element)
        .unwrap()
        .apply(&mut s)
        .unwrap();
    s.initialize(0.0).unwrap();
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

/// The blade advanced by 1 mm at a 10 mm pull, as in continuous cutting (the set-up, outside
/// the timing, pulls with the blade at FROM − 3 mm and advances it by 1 mm three times): a
/// new mesh, assembly, factorization and solve; the finite-strain laws start Newton from
/// the last equilibria extrapolated along the blade's path (carried onto the new mesh where
/// it changes). From 55 to 56 mm the mesh keeps its connectivity (the front moves within a
/// cell): the pattern and symbolic analysis are reused, and the storage of the solver the
/// set-up's last advance replaced; from 50 to 51 mm a cell appears at x = 0 and all are
/// made anew. The accurate setting's x planes lie at the front ± 100 (k/7)^2.25 mm, so that
/// its mesh changes where one of them crosses an end face (at 1.3, 6.0, 14.9, 28.4, 29.3,
/// 46.9, 53.1, 70.7, 71.6, 85.1, 94.0 and 98.8 mm): for it 55 → 56 and 50 → 51 mm keep the
/// mesh and 53 → 54 mm (a cell vanishes at x = 100) changes it; for the others 53 → 54 mm
/// keeps it.
#[divan::bench(
    args = ["linear tet4", "neo-hookean tet4", "neo-hookean tet10", "accurate"],
    consts = [55, 50, 53],
    sample_count = 5,
    sample_size = 1
)]
fn blade_advance_1mm<const FROM: usize>(bencher: Bencher, setting: &str) {
    let from = FROM as f64;
    bencher
        .with_inputs(|| {
            let mut s = initialized_as(setting);
            s.set("scalpel_x", from - 3.0).unwrap();
            s.set("pull", 10.0).unwrap();
            for x in [from - 3.0, from - 2.0, from - 1.0, from] {
                s.set("scalpel_x", x).unwrap();
                s.do_step(0.0, 1.0).unwrap();
            }
            s.set("scalpel_x", from + 1.0).unwrap();
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

    fn base() -> models::mesh::Mesh3d {
        default_block()
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
        bencher.bench_local(|| models::assembly::tetrahedra::assembler(&b));
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

/// The block of each setting with the full cut, pulled 0 → 10 mm in one step in the default load
/// increments (`max_increment` = 5 mm): the finite-strain Newton solve (the set-up and the
/// cut are outside the timing). Iterations and the assembly / factorization / solve split:
/// `cargo run --release -p models --example cutblock_pull -- MATERIAL ELEMENT` (or
/// `-- accurate`).
#[divan::bench(args = ["linear tet4", "neo-hookean tet4", "neo-hookean tet10", "accurate"], sample_count = 5, sample_size = 1)]
fn pull_to_10mm(bencher: Bencher, setting: &str) {
    bencher
        .with_inputs(|| {
            let mut s = initialized_as(setting);
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

/// The neo-Hookean internal forces (`false`) and with them the tangent (`true`) of the
/// default block (uncut, 1 mm stretch in y) on rayon pools of 1 and 2 threads: the parallel
/// element assembly.
mod tangent {
    use super::*;
    use models::assembly::tetrahedra::Solid;
    use models::element::{Elastic, Law, Material};
    use models::mesh::QuadraticMesh;

    #[divan::bench(
        args = [("tet4", 1), ("tet4", 2), ("tet10", 1), ("tet10", 2)],
        consts = [false, true]
    )]
    fn neo_hookean<const TANGENT: bool>(bencher: Bencher, (element, threads): (&str, usize)) {
        let mesh = default_block();
        let material = Material::new(Law::NeoHookean, Elastic::new("m", 0.0385, 0.43).unwrap());
        let solid = match element {
            "tet4" => Solid::linear(&mesh, material),
            _ => Solid::quadratic(&QuadraticMesh::new(&mesh), material),
        };
        let asm = models::assembly::Assembler::new(solid.nodes().len(), 3, &solid.connectivity());
        let u: Vec<f64> = solid
            .nodes()
            .iter()
            .flat_map(|p| [0.0, p[1] / 80.0, 0.0])
            .collect();
        let (mut f, mut k) = (vec![0.0; u.len()], asm.zeros());
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        bencher.bench_local(|| {
            let k = TANGENT.then_some(k.as_mut_slice());
            pool.install(|| solid.add_internal(&asm, &u, &mut f, k).unwrap());
        });
    }
}
