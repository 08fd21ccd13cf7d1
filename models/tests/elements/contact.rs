//! The self-contact search against brute force on flat, curved, folded (2D and 3D), crushed
//! and cut-block surfaces; pruning counters; determinism; master/slave sorting.

use models::contact::search::median_split;
use models::contact::{brute_force, sorting, BvKind, Bvh, Search, Surface};
use models::scene::cutblock::CutBlock;
use models::scene::Scene;

/// A triangulated sheet: `point(i, j)` on an (nx+1) × (ny+1) grid.
fn sheet(
    nx: usize,
    ny: usize,
    point: impl Fn(usize, usize) -> [f64; 3],
) -> (Surface, Vec<[f64; 3]>) {
    let id = |i: usize, j: usize| i + (nx + 1) * j;
    let mut facets = Vec::new();
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            facets.extend([[a, b, c], [a, c, d]]);
        }
    }
    let points: Vec<[f64; 3]> = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| (i, j)))
        .map(|(i, j)| point(i, j))
        .collect();
    let surface = Surface::new(3, &facets);
    let positions = surface.positions(&points, None, 3);
    (surface, positions)
}

/// Runs the search (all BV kinds) and both references; returns the pairs.
fn check(surface: &Surface, positions: &[[f64; 3]], tol: f64, label: &str) -> Vec<(usize, usize)> {
    let reference = brute_force(surface, positions, tol);
    for kind in [BvKind::Aabb, BvKind::Dop14, BvKind::Dop18, BvKind::Dop26] {
        let mut bvh = Bvh::build(surface, positions, kind);
        bvh.refit(surface, positions, tol);
        let (pairs, counters) = Search::run(surface, &bvh, positions, tol);
        assert_eq!(
            pairs, reference,
            "{label} {kind:?}: search differs from brute force"
        );
        println!(
            "{label} {kind:?}: {} facets, {} pairs, {counters:?}",
            surface.facets.len(),
            pairs.len()
        );
    }
    let (baseline, counters) = median_split(surface, positions, tol);
    assert_eq!(baseline, reference, "{label}: median split differs");
    println!("{label} median split: {counters:?}");
    assert!(reference.iter().all(|&(a, b)| !surface.adjacent(a, b)));
    reference
}

#[test]
fn flat_sheet_has_no_pairs_and_costs_one_test() {
    let (s, p) = sheet(30, 30, |i, j| [i as f64, j as f64, 0.0]);
    assert!(check(&s, &p, 0.5, "flat").is_empty());
    let mut bvh = Bvh::build(&s, &p, BvKind::Aabb);
    bvh.refit(&s, &p, 0.5);
    assert_eq!(bvh.n_nodes(), 2 * s.facets.len() - 1);
    let (_, c) = Search::run(&s, &bvh, &p, 0.5);
    assert_eq!((c.curvature_tests, c.bv_tests, c.facet_tests), (1, 0, 0));
}

#[test]
fn curved_half_cylinder_has_no_pairs() {
    let (s, p) = sheet(24, 10, |i, j| {
        let t = std::f64::consts::PI * i as f64 / 24.0;
        [10.0 * t.cos(), 10.0 * t.sin(), 2.0 * j as f64]
    });
    assert!(check(&s, &p, 0.3, "half cylinder").is_empty());
}

#[test]
fn strip_folded_back_on_itself_in_3d() {
    // Legs at z = ±0.2 joined by a half circle; tolerance 0.6 > gap 0.4.
    let (nl, nb, nw) = (20, 8, 4);
    let (s, p) = sheet(2 * nl + nb, nw, |i, j| {
        let y = j as f64;
        if i <= nl {
            [(nl - i) as f64, y, 0.2]
        } else if i < nl + nb {
            let t = std::f64::consts::PI * (i - nl) as f64 / nb as f64;
            [-0.2 * t.sin(), y, 0.2 * t.cos()]
        } else {
            [(i - nl - nb) as f64, y, -0.2]
        }
    });
    let pairs = check(&s, &p, 0.6, "folded strip");
    assert!(pairs.len() > 100);
}

#[test]
fn hairpin_in_2d() {
    // A polyline out along y = 0.1, around, and back along y = −0.1, as segments.
    let n = 40;
    let mut points = Vec::new();
    for i in 0..=n {
        points.push([(n - i) as f64, 0.1, 0.0]);
    }
    for i in 1..=n {
        points.push([i as f64, -0.1, 0.0]);
    }
    let segments: Vec<[usize; 3]> = (0..points.len() - 1).map(|i| [i, i + 1, i + 1]).collect();
    let s = Surface::new(2, &segments);
    let p = s.positions(&points, None, 3);
    let pairs = check(&s, &p, 0.3, "hairpin 2D");
    assert!(pairs.len() >= n as usize - 2);
}

#[test]
fn crushed_can() {
    // A closed tube of radius 5, squashed in x to 3 % so that its walls come within 0.4.
    let (s, p) = sheet(32, 12, |i, j| {
        let t = 2.0 * std::f64::consts::PI * i as f64 / 32.0;
        [0.03 * 5.0 * t.cos(), 5.0 * t.sin(), 1.5 * j as f64]
    });
    // Close the seam: node (32, j) coincides with (0, j); join them.
    let nx = 32;
    let id = |i: usize, j: usize| i + (nx + 1) * j;
    let facets: Vec<[usize; 3]> = s
        .facets
        .iter()
        .map(|f| {
            f.map(|v| s.nodes[v]).map(|n| {
                if n % (nx + 1) == nx {
                    id(0, n / (nx + 1))
                } else {
                    n
                }
            })
        })
        .collect();
    let points: Vec<[f64; 3]> = (0..s.nodes.len()).map(|k| p[k]).collect();
    let can = Surface::new(3, &facets);
    let positions = can.positions(&points, None, 3);
    let pairs = check(&can, &positions, 0.4, "crushed can");
    assert!(!pairs.is_empty());
}

#[test]
fn cut_block_with_closed_flanks() {
    let mut block = CutBlock::new();
    for (k, v) in [("cells_x", 3.0), ("cells_y", 8.0), ("cells_z", 7.0)] {
        block.set(k, v).unwrap();
    }
    block.initialize(0.0).unwrap();
    block.set("scalpel_x", 100.0).unwrap();
    block.set("pull", -0.5).unwrap();
    block.do_step(0.0, 1.0).unwrap();
    let (solid, u) = block.field().unwrap();
    let mesh = solid.corner_mesh().unwrap();
    let s = Surface::of_mesh3d(&mesh);
    let p = s.positions(mesh.nodes(), Some(u), 3);
    let pairs = check(&s, &p, 0.05, "cut block, flanks pressed together");
    assert!(!pairs.is_empty());
}

#[test]
fn output_is_deterministic_and_sorting_is_stable() {
    let (s, p) = sheet(40, 3, |i, j| {
        let t = std::f64::consts::PI * i as f64 / 20.0;
        [
            3.0 * t.cos(),
            3.0 * t.sin(),
            0.05 * i as f64 + j as f64 * 0.0 + 0.9 * (j as f64),
        ]
    });
    let run = || {
        let mut bvh = Bvh::build(&s, &p, BvKind::Dop18);
        bvh.refit(&s, &p, 0.6);
        Search::run(&s, &bvh, &p, 0.6).0
    };
    let (a, b) = (run(), run());
    assert_eq!(a, b);
    let oriented = sorting::sort(&s, &a);
    assert_eq!(
        oriented,
        sorting::sort(&s, &a.iter().rev().copied().collect::<Vec<_>>())
    );
    for o in &oriented {
        assert!(o.master_patch <= o.slave_patch);
    }
}

#[test]
fn refit_follows_deformation_and_reports_degradation() {
    let (s, p) = sheet(20, 20, |i, j| [i as f64, j as f64, 0.0]);
    let mut bvh = Bvh::build(&s, &p, BvKind::Aabb);
    bvh.refit(&s, &p, 0.1);
    assert!((bvh.degradation() - 1.0).abs() < 0.05);
    // Fold the sheet over at x = 10: the refitted tree must find the new contacts.
    let folded: Vec<[f64; 3]> = p
        .iter()
        .map(|q| {
            if q[0] > 10.0 {
                [20.0 - q[0], q[1], 0.05]
            } else {
                *q
            }
        })
        .collect();
    bvh.refit(&s, &folded, 0.1);
    let (pairs, _) = Search::run(&s, &bvh, &folded, 0.1);
    assert_eq!(pairs, brute_force(&s, &folded, 0.1));
    assert!(!pairs.is_empty());
    // Scrambling the nodes pulls every cluster apart: the tree says it should be rebuilt.
    let scrambled: Vec<[f64; 3]> = (0..p.len()).map(|k| p[(k * 97) % p.len()]).collect();
    bvh.refit(&s, &scrambled, 0.1);
    assert!(bvh.degradation() > 1.5, "{}", bvh.degradation());
}

#[test]
fn boundary_segments_of_a_2d_mesh_run_counter_clockwise() {
    let mesh = models::mesh::generate::rectangle(4.0, 2.0, 8, 4).unwrap();
    let s = Surface::of_mesh2d(&mesh);
    assert_eq!(s.arity, 2);
    assert_eq!(s.facets.len(), 2 * (8 + 4));
    let points: Vec<[f64; 3]> = mesh.nodes().iter().map(|p| [p[0], p[1], 0.0]).collect();
    let p = s.positions(&points, None, 2);
    // Outward normals: (Δy, −Δx) points away from the centre (2, 1).
    for f in &s.facets {
        let (a, b) = (p[f[0]], p[f[1]]);
        let n = [b[1] - a[1], -(b[0] - a[0])];
        let mid = [(a[0] + b[0]) / 2.0 - 2.0, (a[1] + b[1]) / 2.0 - 1.0];
        assert!(n[0] * mid[0] + n[1] * mid[1] > 0.0);
    }
    // Each segment has exactly two neighbours on a closed loop.
    assert!(s.neighbours.iter().all(|nb| nb.len() == 2));
    assert!(check(&s, &p, 0.1, "rectangle boundary").is_empty());
}

#[test]
fn master_slave_assignment_is_stable_under_small_motion() {
    let fold = |z: f64| {
        sheet(40, 4, move |i, j| {
            let y = j as f64;
            if i <= 18 {
                [(18 - i) as f64, y, z]
            } else if i < 22 {
                let t = std::f64::consts::PI * (i - 18) as f64 / 4.0;
                [-z * t.sin(), y, z * t.cos()]
            } else {
                [(i - 22) as f64, y, -z]
            }
        })
    };
    let orient = |z: f64| {
        let (s, p) = fold(z);
        let mut bvh = Bvh::build(&s, &p, BvKind::Aabb);
        bvh.refit(&s, &p, 0.6);
        let (pairs, _) = Search::run(&s, &bvh, &p, 0.6);
        sorting::sort(&s, &pairs)
    };
    let (a, b) = (orient(0.2), orient(0.21));
    let common: Vec<_> = a
        .iter()
        .filter(|o| {
            b.iter().any(|q| {
                (q.master, q.slave) == (o.master, o.slave)
                    || (q.slave, q.master) == (o.master, o.slave)
            })
        })
        .collect();
    assert!(!common.is_empty());
    for o in common {
        assert!(
            b.iter().any(|q| (q.master, q.slave) == (o.master, o.slave)),
            "pair {o:?} flipped"
        );
    }
}
