//! Hard cases: near-incompressibility on the Lamé cylinder (the locking cantilever is in
//! `locking.rs`), a stiffness contrast of 1e6 between line elements and triangles, strongly
//! graded meshes, and singular systems that must be reported, never solved into garbage.

use models::assembly::plane::{self, Continuum, PlaneProperties, Truss};
use models::assembly::quadratic_plane::{self, Formulation};
use models::element::Elastic;
use models::linalg::Factorization;
use models::mesh::generate;
use models::mesh::Mesh2d;
use models::mesh::QuadraticPlaneMesh;
use models::solve::{statics::reactions, Damping, IntegratorKind, Statics};
use models::verify::{lame::Lame, problems};
use models::ModelError;

fn lame(nu: f64) -> Lame {
    Lame {
        a: 10.0,
        b: 20.0,
        p: 0.1,
        material: Elastic::new("m", 1.0, nu).unwrap(),
    }
}

#[test]
fn near_incompressible_lame_cylinder_stays_accurate_on_alternating_meshes() {
    // The Lamé solution as ν → 0.5 is nearly divergence-free (u_r ∝ b²/r); on the
    // alternating-diagonal mesh the linear triangles still converge at rate 2, with an error
    // constant ~1.7× that of ν = 0.3 that saturates as ν → 0.5 (no locking, no NaN).
    for n in [4, 8, 16, 32] {
        let (a, b) = (
            lame(0.3).solve(n, 2 * n).unwrap(),
            lame(0.499).solve(n, 2 * n).unwrap(),
        );
        println!(
            "nr={n:2}: L2 error nu=0.3 {:.3e}, nu=0.499 {:.3e}; stress error nu=0.3 {:.3e}, nu=0.499 {:.3e}; u_r(a)/exact nu=0.499: {:.4}",
            a.l2_error,
            b.l2_error,
            a.stress_error,
            b.stress_error,
            b.inner_fe / b.inner_exact
        );
        assert!(b.l2_error.is_finite() && b.inner_fe.is_finite());
        assert!(b.l2_error < 2.0 * a.l2_error);
    }
}

/// Uniaxial tension of a plane-strain rectangle with line elements along the top and bottom
/// edges that are `ratio` times stiffer than the continuum. Sliding supports (u_x = 0 on the
/// left edge, u_y = 0 at one node), u_x = δ prescribed on the right edge: the strain field
/// ε_xx = δ/L, σ_yy = 0 is exact for linear elements, so the reaction force must be
/// (E/(1−ν²) H + 2 E_bar A_bar) δ/L to round-off, whatever the contrast.
#[test]
fn stiffness_contrast_of_a_million_is_solved_to_round_off() {
    let (l, h, delta) = (30.0, 10.0, 0.3);
    let rect = generate::rectangle(l, h, 30, 10).unwrap();
    let sets = rect.node_sets();
    let mut lines = Vec::new();
    for set in ["top", "bottom"] {
        lines.extend(sets.get(set).unwrap().windows(2).map(|w| [w[0], w[1]]));
    }
    let n_lines = lines.len();
    let mesh = rect.clone().with_lines(lines, vec![0; n_lines]).unwrap();
    let (e, nu, area) = (0.01, 0.45, 2.0);
    for ratio in [1.0, 1e3, 1e6] {
        let props = PlaneProperties {
            continua: vec![Continuum {
                elastic: Elastic::new("cavity", e, nu).unwrap(),
                density: 1e-9,
            }],
            trusses: vec![Truss::new("wall", ratio * e, area, 1e-9).unwrap()],
        };
        // Linear triangles and lines (None), then 6-node triangles and 3-node lines in both
        // formulations: the exact field is linear, so all reproduce it.
        let quadratic = QuadraticPlaneMesh::new(&mesh);
        for kind in [
            None,
            Some(Formulation::Displacement),
            Some(Formulation::Mixed),
        ] {
            let asm = match kind {
                None => plane::assembler(&mesh),
                Some(_) => quadratic_plane::assembler(&quadratic),
            };
            let nodes = |set: &[usize]| match kind {
                None => set.to_vec(),
                Some(_) => quadratic.extend(set),
            };
            let mut k = asm.zeros();
            match kind {
                None => plane::stiffness(&mesh, &asm, &props, &mut k),
                Some(f) => quadratic_plane::stiffness(&quadratic, &asm, &props, f, &mut k),
            }
            let (left, right) = (
                nodes(sets.get("left").unwrap()),
                nodes(sets.get("right").unwrap()),
            );
            let mut fixed: Vec<usize> = left.iter().map(|n| 2 * n).collect();
            fixed.push(1);
            let mut u = vec![0.0; asm.n_dofs()];
            for &n in &right {
                fixed.push(2 * n);
                u[2 * n] = delta;
            }
            let mut statics = Statics::new(&asm, &fixed, Factorization::Simplicial).unwrap();
            statics.factorize(&k).unwrap();
            let f = vec![0.0; u.len()];
            statics.solve(asm.matrix(&k), &f, &mut u);
            let mut r = vec![0.0; u.len()];
            reactions(asm.matrix(&k), &u, &f, &mut r);
            let force: f64 = right.iter().map(|n| r[2 * n]).sum();
            let expect = (e / (1.0 - nu * nu) * h + 2.0 * ratio * e * area) * delta / l;
            println!("{kind:?}, ratio {ratio:.0e}: reaction {force:.10e}, exact {expect:.10e}");
            assert!(((force - expect) / expect).abs() < 1e-9, "{kind:?}");
        }
    }
}

#[test]
fn houbolt_stays_bounded_with_a_million_fold_stiffness_contrast() {
    let mut p = problems::plane(30, 25).unwrap();
    p.props.trusses[0] =
        Truss::new("wall", 1e6 * p.props.continua[0].elastic.young(), 1.0, 1e-9).unwrap();
    let assembled = p.assemble();
    let (asm, k) = (&assembled.asm, &assembled.k);
    let s = assembled
        .structure(&p.fixed, Damping::NONE, Factorization::Simplicial)
        .unwrap();
    let mut h = IntegratorKind::Houbolt.create();
    h.prepare(&s, 1e-3).unwrap();
    // Step load on the top edge.
    let top: Vec<usize> = p
        .mesh
        .node_sets()
        .get("top")
        .unwrap()
        .iter()
        .filter_map(|n| s.dirichlet().equation(2 * n + 1))
        .collect();
    let mut load = |_: f64, f: &mut [f64]| {
        f.fill(0.0);
        top.iter().for_each(|&e| f[e] = -0.01);
    };
    h.start(&s, 0.0, &vec![0.0; s.n()], &vec![0.0; s.n()], &mut load)
        .unwrap();
    let mut peak: f64 = 0.0;
    for _ in 0..2000 {
        h.step(&s, &mut load).unwrap();
        peak = peak.max(h.state().u.iter().fold(0.0f64, |a, b| a.max(b.abs())));
    }
    // A suddenly applied load overshoots the static deflection at most twice.
    let mut statics = Statics::new(asm, &p.fixed, Factorization::Simplicial).unwrap();
    statics.factorize(k).unwrap();
    let mut f = vec![0.0; p.mesh.n_dofs()];
    for n in p.mesh.node_sets().get("top").unwrap() {
        if s.dirichlet().equation(2 * n + 1).is_some() {
            f[2 * n + 1] = -0.01;
        }
    }
    let mut u = vec![0.0; p.mesh.n_dofs()];
    statics.solve(asm.matrix(k), &f, &mut u);
    let stat = u.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    println!("peak dynamic {peak:.4e}, static {stat:.4e}");
    assert!(peak.is_finite() && peak <= 2.0 * stat * (1.0 + 1e-6));
}

/// A strongly graded mesh (cell sizes in a geometric progression over three decades) still
/// passes the patch test.
#[test]
fn strongly_graded_mesh_passes_the_patch_test() {
    let n = 20;
    let grade = |s: f64| (1000f64.powf(s) - 1.0) / 999.0;
    let mesh = generate::rectangle(1.0, 1.0, n, n)
        .unwrap()
        .mapped(|[x, y]| [grade(x) * 50.0, grade(y) * 20.0])
        .unwrap();
    let props = PlaneProperties {
        continua: vec![Continuum {
            elastic: Elastic::new("m", 3.0, 0.4).unwrap(),
            density: 1.0,
        }],
        trusses: vec![],
    };
    let asm = plane::assembler(&mesh);
    let mut k = asm.zeros();
    plane::stiffness(&mesh, &asm, &props, &mut k);
    let field = |p: [f64; 2]| [1e-3 * p[0] - 2e-3 * p[1], 3e-3 * p[0] + 5e-4 * p[1]];
    let mut u = vec![0.0; mesh.n_dofs()];
    let mut fixed = Vec::new();
    for set in ["left", "right", "top", "bottom"] {
        for &node in mesh.node_sets().get(set).unwrap() {
            let ue = field(mesh.nodes()[node]);
            fixed.extend([2 * node, 2 * node + 1]);
            u[2 * node] = ue[0];
            u[2 * node + 1] = ue[1];
        }
    }
    let mut statics = Statics::new(&asm, &fixed, Factorization::Simplicial).unwrap();
    statics.factorize(&k).unwrap();
    statics.solve(asm.matrix(&k), &vec![0.0; mesh.n_dofs()], &mut u);
    let worst = (0..mesh.nodes().len())
        .map(|i| {
            let ue = field(mesh.nodes()[i]);
            (u[2 * i] - ue[0]).abs().max((u[2 * i + 1] - ue[1]).abs())
        })
        .fold(0.0, f64::max);
    assert!(worst < 1e-10, "{worst:e}");
}

fn factorize_with(
    mesh: &Mesh2d,
    props: &PlaneProperties,
    fixed: &[usize],
) -> Result<(), ModelError> {
    let asm = plane::assembler(mesh);
    let mut k = asm.zeros();
    plane::stiffness(mesh, &asm, props, &mut k);
    let mut statics = Statics::new(&asm, fixed, Factorization::Simplicial)?;
    statics.factorize(&k)
}

#[test]
fn floating_bodies_and_mechanisms_are_reported_as_singular() {
    let mesh = generate::rectangle(2.0, 1.0, 4, 2).unwrap();
    let props = PlaneProperties {
        continua: vec![Continuum {
            elastic: Elastic::new("m", 1.0, 0.3).unwrap(),
            density: 1.0,
        }],
        trusses: vec![],
    };
    // No support at all.
    let err = factorize_with(&mesh, &props, &[]).unwrap_err();
    assert!(matches!(err, ModelError::Singular { .. }), "{err}");
    assert!(err.to_string().contains("singular or indefinite system"));
    // One pinned node: the body can still rotate about it.
    let err = factorize_with(&mesh, &props, &[0, 1]).unwrap_err();
    assert!(matches!(err, ModelError::Singular { .. }), "{err}");
    // Two pinned nodes: fine.
    let right = mesh.node_sets().get("right").unwrap()[0];
    factorize_with(&mesh, &props, &[0, 1, 2 * right + 1]).unwrap();
    // A square truss without diagonal is a mechanism.
    let nodes = vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let truss = Mesh2d::new(
        nodes,
        vec![],
        vec![],
        vec![[0, 1], [1, 2], [2, 3], [3, 0]],
        vec![0; 4],
    )
    .unwrap();
    let tprops = PlaneProperties {
        continua: vec![],
        trusses: vec![Truss::new("bar", 1.0, 1.0, 1.0).unwrap()],
    };
    let err = factorize_with(&truss, &tprops, &[0, 1, 3]).unwrap_err();
    assert!(matches!(err, ModelError::Singular { .. }), "{err}");
}
