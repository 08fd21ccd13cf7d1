//! FE-core benchmarks on the two sizes: a 2D mesh of 6,000 triangles + 170 line
//! elements, and the cut block of 6 × 16 × 14 cubes × 5 tetrahedra.
//!
//! Run: `cargo bench -p models --bench core` (divan prints median and spread per case).

use std::sync::LazyLock;

use divan::Bencher;
use models::assembly::{plane, tetrahedra, Dirichlet};
use models::linalg::{Cholesky, Factorization, Ordering};
use models::solve::{Damping, IntegratorKind, Statics, Structure};
use models::verify::problems::{self, Assembled, BlockProblem, PlaneProblem};

fn main() {
    divan::main();
}

static PLANE: LazyLock<(PlaneProblem, Assembled)> = LazyLock::new(|| {
    let p = problems::plane(60, 50).unwrap();
    let a = p.assemble();
    (p, a)
});

static BLOCK: LazyLock<(BlockProblem, Assembled)> = LazyLock::new(|| {
    let p = problems::block([6, 16, 14], 10.0).unwrap();
    let a = p.assemble();
    (p, a)
});

fn plane_structure(factorization: Factorization) -> Structure {
    let (p, a) = &*PLANE;
    a.structure(
        &p.fixed,
        Damping {
            alpha: 1.0,
            beta: 1e-4,
        },
        factorization,
    )
    .unwrap()
}

mod plane2d {
    use super::*;

    #[divan::bench]
    fn pattern(bencher: Bencher) {
        let p = &PLANE.0;
        bencher.bench(|| plane::assembler(&p.mesh));
    }

    #[divan::bench]
    fn assemble_stiffness(bencher: Bencher) {
        let (p, a) = &*PLANE;
        let mut k = a.asm.zeros();
        bencher.bench_local(|| plane::stiffness(&p.mesh, &a.asm, &p.props, &mut k));
    }

    #[divan::bench]
    fn assemble_mass(bencher: Bencher) {
        let (p, a) = &*PLANE;
        let mut m = a.asm.zeros();
        bencher.bench_local(|| plane::mass(&p.mesh, &a.asm, &p.props, &mut m));
    }

    #[divan::bench(args = [Factorization::Simplicial, Factorization::Supernodal(Ordering::NestedDissection)])]
    fn symbolic_factorization(bencher: Bencher, factorization: Factorization) {
        let s = plane_structure(factorization);
        bencher.bench(|| s.analyze().unwrap());
    }

    #[divan::bench(args = [Factorization::Simplicial, Factorization::Supernodal(Ordering::NestedDissection)])]
    fn houbolt_prepare(bencher: Bencher, factorization: Factorization) {
        let s = plane_structure(factorization);
        let mut h = IntegratorKind::Houbolt.create();
        h.prepare(&s, 1e-3).unwrap();
        // Same dt: one numeric refactorization of the effective matrix (as after a
        // stiffness change).
        bencher.bench_local(|| h.prepare(&s, 1e-3).unwrap());
    }

    #[divan::bench(args = [Factorization::Simplicial, Factorization::Supernodal(Ordering::NestedDissection)])]
    fn houbolt_step(bencher: Bencher, factorization: Factorization) {
        let s = plane_structure(factorization);
        let mut h = IntegratorKind::Houbolt.create();
        h.prepare(&s, 1e-3).unwrap();
        let mut load = |t: f64, f: &mut [f64]| f.fill(1e-3 * (10.0 * t).sin());
        h.start(&s, 0.0, &vec![0.0; s.n()], &vec![0.0; s.n()], &mut load)
            .unwrap();
        for _ in 0..3 {
            h.step(&s, &mut load).unwrap();
        }
        bencher.bench_local(|| h.step(&s, &mut load).unwrap());
    }

    #[divan::bench]
    fn static_solve(bencher: Bencher) {
        let (p, a) = &*PLANE;
        let mut statics = Statics::new(&a.asm, &p.fixed, Factorization::Simplicial).unwrap();
        statics.factorize(&a.k).unwrap();
        let f = vec![1e-3; p.mesh.n_dofs()];
        let mut u = vec![0.0; p.mesh.n_dofs()];
        bencher.bench_local(|| statics.solve(a.asm.matrix(&a.k), &f, &mut u));
    }
}

mod block3d {
    use super::*;

    #[divan::bench]
    fn assemble_stiffness(bencher: Bencher) {
        let (p, a) = &*BLOCK;
        let mut k = a.asm.zeros();
        bencher.bench_local(|| tetrahedra::stiffness(&p.mesh, &a.asm, &p.material, &mut k));
    }

    #[divan::bench(args = [Factorization::Simplicial, Factorization::Supernodal(Ordering::NestedDissection)])]
    fn symbolic_factorization(bencher: Bencher, factorization: Factorization) {
        let (p, a) = &*BLOCK;
        let bc = Dirichlet::new(&a.asm, &p.fixed).unwrap();
        bencher.bench(|| Cholesky::analyze(bc.symbolic().as_ref(), factorization).unwrap());
    }

    #[divan::bench(args = [Factorization::Simplicial, Factorization::Supernodal(Ordering::NestedDissection)])]
    fn numeric_factorization(bencher: Bencher, factorization: Factorization) {
        let (p, a) = &*BLOCK;
        let mut statics = Statics::new(&a.asm, &p.fixed, factorization).unwrap();
        bencher.bench_local(|| statics.factorize(&a.k).unwrap());
    }

    #[divan::bench]
    fn solve(bencher: Bencher) {
        let (p, a) = &*BLOCK;
        let mut statics = Statics::new(
            &a.asm,
            &p.fixed,
            Factorization::Supernodal(Ordering::NestedDissection),
        )
        .unwrap();
        statics.factorize(&a.k).unwrap();
        let f = vec![0.0; p.mesh.n_dofs()];
        let mut u = p.prescribed.clone();
        bencher.bench_local(|| statics.solve(a.asm.matrix(&a.k), &f, &mut u));
    }

    /// Everything a static solve needs from scratch: stiffness assembly on the existing
    /// pattern, numeric factorization, solve.
    #[divan::bench]
    fn static_total(bencher: Bencher) {
        let (p, a) = &*BLOCK;
        let mut statics = Statics::new(
            &a.asm,
            &p.fixed,
            Factorization::Supernodal(Ordering::NestedDissection),
        )
        .unwrap();
        let mut k = a.asm.zeros();
        let f = vec![0.0; p.mesh.n_dofs()];
        let mut u = p.prescribed.clone();
        bencher.bench_local(|| {
            tetrahedra::stiffness(&p.mesh, &a.asm, &p.material, &mut k);
            statics.factorize(&k).unwrap();
            statics.solve(a.asm.matrix(&k), &f, &mut u);
        });
    }
}

mod parts {
    use super::*;

    #[divan::bench]
    fn plane_matvec(bencher: Bencher) {
        let s = plane_structure(Factorization::Simplicial);
        let x = vec![1.0; s.n()];
        let mut y = vec![0.0; s.n()];
        bencher.bench_local(|| models::assembly::mul_add(s.mass(), &x, 1.0, &mut y));
    }

    #[divan::bench]
    fn plane_triangular_solve(bencher: Bencher) {
        let s = plane_structure(Factorization::Simplicial);
        let mut chol = s.analyze().unwrap();
        let mut a = vec![0.0; s.dirichlet().nnz()];
        s.effective(2e6, 0.0, &mut a);
        chol.factorize(s.dirichlet().matrix(&a)).unwrap();
        eprintln!(
            "n = {}, nnz(A) = {}, nnz(L) = {}",
            s.n(),
            a.len(),
            chol.factor_nnz()
        );
        let mut x = vec![1.0; s.n()];
        bencher.bench_local(|| chol.solve_in_place(&mut x));
    }
}

/// 6-node triangles on the same 300 × 250 mm plate with 30 × 25 cells (1,500 triangles,
/// about as many dofs as the 6,000 linear triangles above; no line elements), left edge
/// fixed: a linear Houbolt step, and a finite-strain one (neo-Hookean, Newton within the
/// step) under a sinusoidal body load.
mod plane2d_quadratic {
    use super::*;
    use models::assembly::quadratic_plane::{self, Formulation};
    use models::assembly::Assembler;
    use models::element::{Law, Material};
    use models::mesh::{generate, QuadraticPlaneMesh};
    use std::sync::Arc;

    fn structure(finite: bool) -> Structure {
        let (p, _) = &*PLANE;
        let linear = generate::rectangle(300.0, 250.0, 30, 25).unwrap();
        let mesh = Arc::new(QuadraticPlaneMesh::new(&linear));
        let asm: Arc<Assembler> = Arc::new(quadratic_plane::assembler(&mesh));
        let props = p.props.clone();
        let (mut k, mut m) = (asm.zeros(), asm.zeros());
        quadratic_plane::stiffness(&mesh, &asm, &props, Formulation::Displacement, &mut k);
        quadratic_plane::mass(&mesh, &asm, &props, &mut m);
        let lumped = quadratic_plane::lumped_mass(&mesh, &props);
        let fixed: Vec<usize> = (0..mesh.nodes().len())
            .filter(|&n| mesh.nodes()[n][0] == 0.0)
            .flat_map(|n| [2 * n, 2 * n + 1])
            .collect();
        let bc = Dirichlet::new(&asm, &fixed).unwrap();
        let damping = Damping {
            alpha: 1.0,
            beta: 1e-4,
        };
        let s = Structure::new(bc, &k, &m, &lumped, damping, Factorization::Simplicial).unwrap();
        if !finite {
            return s;
        }
        let materials = Arc::from([Material::new(Law::NeoHookean, props.continua[0].elastic)]);
        s.with_internal_forces(Arc::new(quadratic_plane::PlaneBody::triangles(
            mesh,
            asm,
            materials,
            Formulation::Displacement,
        )))
    }

    #[divan::bench(args = [false, true])]
    fn houbolt_step(bencher: Bencher, finite: bool) {
        let s = structure(finite);
        let mut h = IntegratorKind::Houbolt.create();
        h.prepare(&s, 1e-3).unwrap();
        // A body load of up to 2e-4 N/mm per dof: the soft (5 kPa) plate deflects by about a
        // tenth of its size (printed); loads 50 times larger invert elements.
        let mut load = |t: f64, f: &mut [f64]| f.fill(2e-4 * (10.0 * t).sin());
        h.start(&s, 0.0, &vec![0.0; s.n()], &vec![0.0; s.n()], &mut load)
            .unwrap();
        for _ in 0..20 {
            h.step(&s, &mut load).unwrap();
        }
        let (mut steps, mut iterations) = (0, 0);
        bencher.bench_local(|| {
            h.step(&s, &mut load).unwrap();
            steps += 1;
            iterations += h.newton_iterations();
        });
        eprintln!(
            "tri6, {} equations, finite = {finite}: {:.2} Newton iterations per step over {steps} steps, peak |u| {:.3} mm",
            s.n(),
            iterations as f64 / steps.max(1) as f64,
            h.state().u.iter().fold(0.0f64, |m, x| m.max(x.abs()))
        );
    }
}
