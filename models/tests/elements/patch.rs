//! Patch tests: a linear displacement field imposed on the boundary of an irregular mesh is
//! reproduced exactly inside; rigid-body motions produce no nodal forces. Also the truss
//! element against hand solutions of bar networks.

use models::assembly::plane::{self, Continuum, PlaneProperties, Truss};
use models::assembly::{tetrahedra, Assembler};
use models::element::Elastic;
use models::linalg::{Factorization, Ordering};
use models::mesh::{generate, Mesh2d};
use models::solve::{statics::reactions, Statics};
use models::stress;

use crate::common::{boundary_nodes, irregular_block, jittered};

/// A rectangle mesh with interior nodes moved by up to 30 % of the cell size.
fn irregular_plane() -> (Mesh2d, Vec<usize>) {
    let rect = generate::rectangle(4.0, 3.0, 8, 6).unwrap();
    let boundary = boundary_nodes(rect.node_sets(), &["left", "right", "top", "bottom"]);
    let nodes = jittered(rect.nodes(), &boundary, 0.15);
    let mesh = Mesh2d::new(
        nodes,
        rect.triangles().to_vec(),
        rect.triangle_regions().to_vec(),
        vec![],
        vec![],
    )
    .unwrap();
    (mesh, boundary)
}

fn plane_props(nu: f64) -> PlaneProperties {
    PlaneProperties {
        continua: vec![Continuum {
            elastic: Elastic::new("m", 2.5, nu).unwrap(),
            density: 1.0,
        }],
        trusses: vec![Truss::new("bar", 7.0, 0.5, 1.0).unwrap()],
    }
}

fn linear2(p: &[f64; 2]) -> [f64; 2] {
    [
        0.01 + 0.002 * p[0] - 0.003 * p[1],
        -0.02 + 0.004 * p[0] + 0.001 * p[1],
    ]
}

#[test]
fn tri3_patch_test_on_an_irregular_mesh() {
    let (mesh, boundary) = irregular_plane();
    let props = plane_props(0.3);
    let asm: Assembler = plane::assembler(&mesh);
    let mut k = asm.zeros();
    plane::stiffness(&mesh, &asm, &props, &mut k);
    let mut u = vec![0.0; mesh.n_dofs()];
    let fixed: Vec<usize> = boundary.iter().flat_map(|&n| [2 * n, 2 * n + 1]).collect();
    for &n in &boundary {
        let ue = linear2(&mesh.nodes()[n]);
        u[2 * n] = ue[0];
        u[2 * n + 1] = ue[1];
    }
    let mut statics = Statics::new(&asm, &fixed, Factorization::Simplicial).unwrap();
    statics.factorize(&k).unwrap();
    statics.solve(asm.matrix(&k), &vec![0.0; mesh.n_dofs()], &mut u);
    let worst = (0..mesh.nodes().len())
        .map(|n| {
            let ue = linear2(&mesh.nodes()[n]);
            (u[2 * n] - ue[0]).abs().max((u[2 * n + 1] - ue[1]).abs())
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-10, "max deviation {worst:e}");
    // The constant stress of the field in every element: ε = (0.002, 0.001, 0.001).
    let s = stress::triangle_stresses(&mesh, &props, &u);
    let expect = Elastic::new("m", 2.5, 0.3).unwrap().plane_strain()
        * nalgebra::Vector3::new(0.002, 0.001, 0.001);
    for e in s {
        assert!(
            (e.xx - expect[0]).abs() < 1e-10
                && (e.yy - expect[1]).abs() < 1e-10
                && (e.xy - expect[2]).abs() < 1e-10
        );
    }
}

#[test]
fn rigid_motions_give_zero_nodal_forces_2d_and_3d() {
    let (mesh, _) = irregular_plane();
    let asm = plane::assembler(&mesh);
    let mut k = asm.zeros();
    plane::stiffness(&mesh, &asm, &plane_props(0.3), &mut k);
    let u: Vec<f64> = (0..mesh.n_dofs())
        .map(|d| {
            let p = mesh.nodes()[d / 2];
            // translation (0.3, −0.2) + rotation 0.01 about the origin
            if d % 2 == 0 {
                0.3 - 0.01 * p[1]
            } else {
                -0.2 + 0.01 * p[0]
            }
        })
        .collect();
    let mut r = vec![0.0; u.len()];
    reactions(asm.matrix(&k), &u, &vec![0.0; u.len()], &mut r);
    let kmax = k.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    assert!(r.iter().all(|x| x.abs() < 1e-12 * kmax));

    let (mesh, _) = irregular_block();
    let asm = tetrahedra::assembler(&mesh);
    let mut k = asm.zeros();
    tetrahedra::stiffness(&mesh, &asm, &block_material(), &mut k);
    let w = nalgebra::Vector3::new(0.01, -0.02, 0.005);
    let u: Vec<f64> = (0..mesh.n_dofs())
        .map(|d| {
            let x = nalgebra::Vector3::from(mesh.nodes()[d / 3]);
            [0.1, 0.2, -0.3][d % 3] + w.cross(&x)[d % 3]
        })
        .collect();
    let mut r = vec![0.0; u.len()];
    reactions(asm.matrix(&k), &u, &vec![0.0; u.len()], &mut r);
    let kmax = k.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    assert!(r.iter().all(|x| x.abs() < 1e-12 * kmax));
}

fn block_material() -> Continuum {
    Continuum {
        elastic: Elastic::new("m", 1.3, 0.35).unwrap(),
        density: 1.0,
    }
}

#[test]
fn tet4_patch_test_on_an_irregular_mesh() {
    let (mesh, boundary) = irregular_block();
    let asm = tetrahedra::assembler(&mesh);
    let mut k = asm.zeros();
    tetrahedra::stiffness(&mesh, &asm, &block_material(), &mut k);
    let g = nalgebra::Matrix3::new(0.01, 0.002, -0.003, 0.004, -0.02, 0.001, 0.0, 0.003, 0.015);
    let field =
        |p: &[f64; 3]| g * nalgebra::Vector3::from(*p) + nalgebra::Vector3::new(0.1, 0.0, -0.05);
    let mut u = vec![0.0; mesh.n_dofs()];
    let mut fixed = Vec::new();
    for &n in &boundary {
        let ue = field(&mesh.nodes()[n]);
        for d in 0..3 {
            fixed.push(3 * n + d);
            u[3 * n + d] = ue[d];
        }
    }
    let mut statics = Statics::new(
        &asm,
        &fixed,
        Factorization::Supernodal(Ordering::NestedDissection),
    )
    .unwrap();
    statics.factorize(&k).unwrap();
    statics.solve(asm.matrix(&k), &vec![0.0; mesh.n_dofs()], &mut u);
    let worst = (0..mesh.nodes().len())
        .flat_map(|n| {
            let ue = field(&mesh.nodes()[n]);
            (0..3).map(move |d| (n, d, ue[d]))
        })
        .map(|(n, d, e)| (u[3 * n + d] - e).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-10, "max deviation {worst:e}");
}

/// A mesh of line elements only, with one truss property.
fn truss(nodes: Vec<[f64; 2]>, lines: Vec<[usize; 2]>, areas: &[f64]) -> (Mesh2d, PlaneProperties) {
    let regions = (0..lines.len() as u16).collect();
    let mesh = Mesh2d::new(nodes, vec![], vec![], lines, regions).unwrap();
    let trusses = areas
        .iter()
        .map(|&a| Truss::new("bar", 200.0, a, 1.0).unwrap())
        .collect();
    (
        mesh,
        PlaneProperties {
            continua: vec![],
            trusses,
        },
    )
}

fn solve_truss(
    mesh: &Mesh2d,
    props: &PlaneProperties,
    fixed_nodes: &[usize],
    f: &[f64],
) -> Vec<f64> {
    let asm = plane::assembler(mesh);
    let mut k = asm.zeros();
    plane::stiffness(mesh, &asm, props, &mut k);
    let fixed: Vec<usize> = fixed_nodes
        .iter()
        .flat_map(|n| [2 * n, 2 * n + 1])
        .collect();
    let mut statics = Statics::new(&asm, &fixed, Factorization::Simplicial).unwrap();
    statics.factorize(&k).unwrap();
    let mut u = vec![0.0; mesh.n_dofs()];
    statics.solve(asm.matrix(&k), f, &mut u);
    u
}

#[test]
fn two_bar_truss_matches_hand_solution() {
    // Supports at (∓3, 0), load P downward at (0, −4): L = 5, sin θ = 4/5.
    // N = P / (2 sin θ) (tension), δ = P L / (2 E A sin²θ).
    let (p, e, a) = (10.0, 200.0, 2.0);
    let (mesh, props) = truss(
        vec![[-3.0, 0.0], [3.0, 0.0], [0.0, -4.0]],
        vec![[0, 2], [1, 2]],
        &[a, a],
    );
    let mut f = vec![0.0; 6];
    f[5] = -p;
    let u = solve_truss(&mesh, &props, &[0, 1], &f);
    let delta = p * 5.0 / (2.0 * e * a * 0.64);
    assert!(
        (u[5] + delta).abs() < 1e-12 * delta,
        "{} vs {}",
        u[5],
        -delta
    );
    assert!(u[4].abs() < 1e-14);
    let s = stress::line_stresses(&mesh, &props, &u);
    let n = p / (2.0 * 0.8);
    for sigma in s {
        assert!((sigma * a - n).abs() < 1e-10 * n);
    }
}

#[test]
fn statically_indeterminate_three_bar_truss_matches_hand_solution() {
    // Middle bar vertical (length h = 4, area am), side bars to (∓3, 0) (L = 5, area as).
    // Compatibility: δ = P / (E am / h + 2 E as sin²θ / L).
    let (p, e, am, side) = (12.0, 200.0, 1.5, 0.7);
    let (mesh, props) = truss(
        vec![[-3.0, 0.0], [3.0, 0.0], [0.0, 0.0], [0.0, -4.0]],
        vec![[0, 3], [1, 3], [2, 3]],
        &[side, side, am],
    );
    let mut f = vec![0.0; 8];
    f[7] = -p;
    let u = solve_truss(&mesh, &props, &[0, 1, 2], &f);
    let delta = p / (e * am / 4.0 + 2.0 * e * side * 0.64 / 5.0);
    assert!((u[7] + delta).abs() < 1e-12 * delta);
    let s = stress::line_stresses(&mesh, &props, &u);
    assert!((s[2] - e * delta / 4.0).abs() < 1e-10);
    assert!((s[0] - e * delta * 0.8 / 5.0).abs() < 1e-10);
    // Equilibrium: the vertical bar forces carry P.
    let carried = s[2] * am + 2.0 * s[0] * side * 0.8;
    assert!((carried - p).abs() < 1e-10 * p);
}
