//! Self-contact search cost versus surface size on flat, curved and folded surfaces, against
//! a top-down median-split AABB tree and (at 1k facets) brute force. Counters are printed to
//! standard error once per case.
//!
//! Run: `cargo bench -p models --bench contact`.

use divan::Bencher;
use models::contact::search::median_split;
use models::contact::{brute_force, BvKind, Bvh, Search, Surface};

fn main() {
    divan::main();
}

const TOL: f64 = 0.3;
const SIZES: [usize; 3] = [1_000, 10_000, 100_000];
const SHAPES: [&str; 3] = ["flat", "curved", "folded"];

/// A sheet of about `facets` triangles: flat; a half cylinder; or a strip folded back on
/// itself with its legs 0.2 apart.
fn surface(shape: &str, facets: usize) -> (Surface, Vec<[f64; 3]>) {
    let nx = ((facets / 2) as f64).sqrt().round() as usize;
    let ny = nx;
    let point = |i: usize, j: usize| -> [f64; 3] {
        let (x, y) = (i as f64, j as f64);
        match shape {
            "flat" => [x, y, 0.0],
            "curved" => {
                let t = std::f64::consts::PI * x / nx as f64;
                let r = nx as f64 / std::f64::consts::PI;
                [r * t.cos(), r * t.sin(), y]
            }
            _ => {
                let half = nx as f64 / 2.0;
                if x <= half - 2.0 {
                    [half - 2.0 - x, y, 0.1]
                } else if x >= half + 2.0 {
                    [x - half - 2.0, y, -0.1]
                } else {
                    let t = std::f64::consts::PI * (x - half + 2.0) / 4.0;
                    [-0.1 * t.sin(), y, 0.1 * t.cos()]
                }
            }
        }
    };
    let id = |i: usize, j: usize| i + (nx + 1) * j;
    let mut f = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            f.extend([[a, b, c], [a, c, d]]);
        }
    }
    let points: Vec<[f64; 3]> = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| (i, j)))
        .map(|(i, j)| point(i, j))
        .collect();
    let s = Surface::new(3, &f);
    let p = s.positions(&points, None, 3);
    (s, p)
}

fn cases() -> Vec<(&'static str, usize)> {
    SHAPES
        .iter()
        .flat_map(|&s| SIZES.iter().map(move |&n| (s, n)))
        .collect()
}

fn label(case: &(&str, usize)) -> String {
    format!("{}-{}", case.0, case.1)
}

#[divan::bench(args = cases().iter().map(label).collect::<Vec<_>>(), sample_count = 10)]
fn clustered_build(bencher: Bencher, case: &str) {
    let (shape, n) = case
        .split_once('-')
        .map(|(s, n)| (s, n.parse().unwrap()))
        .unwrap();
    let (s, p) = surface(shape, n);
    bencher.bench(|| Bvh::build(&s, &p, BvKind::Aabb));
}

#[divan::bench(args = cases().iter().map(label).collect::<Vec<_>>())]
fn clustered_refit_and_search(bencher: Bencher, case: &str) {
    let (shape, n) = case
        .split_once('-')
        .map(|(s, n)| (s, n.parse().unwrap()))
        .unwrap();
    let (s, p) = surface(shape, n);
    let mut bvh = Bvh::build(&s, &p, BvKind::Aabb);
    bvh.refit(&s, &p, TOL);
    let (pairs, c) = Search::run(&s, &bvh, &p, TOL);
    eprintln!(
        "clustered {case}: {} facets, {} pairs, {c:?}",
        s.facets.len(),
        pairs.len()
    );
    bencher.bench_local(|| {
        bvh.refit(&s, &p, TOL);
        Search::run(&s, &bvh, &p, TOL)
    });
}

#[divan::bench(args = cases().iter().map(label).collect::<Vec<_>>())]
fn median_split_build_and_search(bencher: Bencher, case: &str) {
    let (shape, n) = case
        .split_once('-')
        .map(|(s, n)| (s, n.parse().unwrap()))
        .unwrap();
    let (s, p) = surface(shape, n);
    let (pairs, c) = median_split(&s, &p, TOL);
    eprintln!("median split {case}: {} pairs, {c:?}", pairs.len());
    bencher.bench(|| median_split(&s, &p, TOL));
}

#[divan::bench(args = ["flat-1000", "curved-1000", "folded-1000"], sample_count = 5)]
fn brute_force_search(bencher: Bencher, case: &str) {
    let (shape, n) = case
        .split_once('-')
        .map(|(s, n)| (s, n.parse().unwrap()))
        .unwrap();
    let (s, p) = surface(shape, n);
    bencher.bench(|| brute_force(&s, &p, TOL));
}

/// The default cut block's whole boundary surface (cut over the full width), deformed by a
/// 10 mm pull (flanks open) or a 3 mm compression without contact (flanks through each
/// other): refit + search.
#[divan::bench(args = [10.0, -3.0])]
fn cut_block_surface(bencher: Bencher, pull: f64) {
    use models::scene::cutblock::CutBlock;
    use models::scene::Scene;
    let mut block = CutBlock::new();
    let vr = block.lookup("contact").unwrap();
    block.set_string(vr, "none").unwrap();
    block.initialize(0.0).unwrap();
    block.set("scalpel_x", 100.0).unwrap();
    block.set("pull", pull).unwrap();
    block.do_step(0.0, 1.0).unwrap();
    let (solid, u) = block.field().unwrap();
    let mesh = solid.corner_mesh().unwrap();
    let s = Surface::of_mesh3d(&mesh);
    let p = s.positions(mesh.nodes(), Some(u), 3);
    let mut bvh = Bvh::build(&s, &p, BvKind::Aabb);
    bvh.refit(&s, &p, 0.05);
    let (pairs, c) = Search::run(&s, &bvh, &p, 0.05);
    eprintln!(
        "cut block pull {pull}: {} facets, {} pairs, {c:?}",
        s.facets.len(),
        pairs.len()
    );
    bencher.bench_local(|| {
        bvh.refit(&s, &p, 0.05);
        Search::run(&s, &bvh, &p, 0.05)
    });
}
