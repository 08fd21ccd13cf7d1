//! A step of every integrator (linear, and Houbolt / Newmark at finite strain), a static
//! re-solve, Newton iterations at finite strain, an abdomen scene's step with all its
//! outputs read, and reading the cut block's outputs allocate nothing. Verified with a
//! counting global allocator (per thread, so parallel tests do not interfere).

use std::alloc::{GlobalAlloc, Layout as AllocLayout, System};
use std::cell::Cell;

use models::assembly::Dirichlet;
use models::linalg::{Factorization, Ordering};
use models::scene::abdomen::Abdomen;
use models::scene::{outputs, Scene};
use models::solve::{Damping, IntegratorKind, Statics, Structure};
use models::verify::problems;

struct Counting;

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

// Unsafe code: a global allocator is an unsafe trait; this one forwards to the system's.
#[allow(unsafe_code)]
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: AllocLayout) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: AllocLayout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: AllocLayout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.with(|c| c.set(c.get() + 1));
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations_during(f: impl FnOnce()) -> usize {
    let before = ALLOCATIONS.with(Cell::get);
    f();
    ALLOCATIONS.with(Cell::get) - before
}

fn structure() -> Structure {
    let p = problems::plane(12, 10).unwrap();
    let a = p.assemble();
    let bc = Dirichlet::new(&a.asm, &p.fixed).unwrap();
    let damping = Damping {
        alpha: 0.5,
        beta: 1e-4,
    };
    Structure::new(
        bc,
        &a.k,
        &a.m,
        &a.lumped,
        damping,
        Factorization::Simplicial,
    )
    .unwrap()
}

#[test]
fn integrator_steps_allocate_nothing() {
    let s = structure();
    for kind in IntegratorKind::ALL {
        let mut integ = kind.create();
        integ.prepare(&s, 1e-5).unwrap();
        let mut load =
            |t: f64, f: &mut [f64]| f.iter_mut().for_each(|x| *x = 1e-4 * (50.0 * t).sin());
        integ
            .start(&s, 0.0, &vec![0.0; s.n()], &vec![0.0; s.n()], &mut load)
            .unwrap();
        let n = allocations_during(|| {
            for _ in 0..50 {
                integ.step(&s, &mut load).unwrap();
            }
        });
        assert_eq!(n, 0, "{kind:?} allocated {n} times in 50 steps");
        // A new step size re-prepares (that may allocate), then steps are again free.
        integ.prepare(&s, 2e-5).unwrap();
        let n = allocations_during(|| {
            for _ in 0..50 {
                integ.step(&s, &mut load).unwrap();
            }
        });
        assert_eq!(n, 0, "{kind:?} allocated {n} times after a change of dt");
        if integ.critical_time_step().is_none() {
            // Implicit: re-preparing for new matrices is a numeric refactorization on the
            // existing symbolic analysis, which allocates nothing either.
            let n = allocations_during(|| integ.prepare(&s, 2e-5).unwrap());
            assert_eq!(n, 0, "{kind:?} re-prepare allocated {n} times");
        }
    }
}

#[test]
fn static_resolve_allocates_nothing() {
    let p = problems::block([3, 4, 3], 1.0).unwrap();
    let models::verify::problems::Assembled { asm, k, .. } = p.assemble();
    let mut statics = Statics::new(
        &asm,
        &p.fixed,
        Factorization::Supernodal(Ordering::NestedDissection),
    )
    .unwrap();
    statics.factorize(&k).unwrap();
    let f = vec![0.0; p.mesh.n_dofs()];
    let mut u = p.prescribed.clone();
    statics.solve(asm.matrix(&k), &f, &mut u);
    let n = allocations_during(|| {
        for _ in 0..20 {
            statics.solve(asm.matrix(&k), &f, &mut u);
        }
    });
    assert_eq!(n, 0);
    // A numeric refactorization reuses the symbolic analysis and its workspace too.
    let n = allocations_during(|| statics.factorize(&k).unwrap());
    assert_eq!(n, 0, "refactorization allocated {n} times");
}

#[test]
fn abdomen_step_and_outputs_allocate_nothing() {
    for (kinematics, order) in [
        ("finite", "full"),
        ("finite", "reduced"),
        ("linear", "full"),
        ("linear", "modal"),
    ] {
        let mut s = Abdomen::new();
        s.set("target_triangles", 500.0).unwrap();
        s.set_str("kinematics", kinematics).unwrap();
        s.set_str("model_order", order).unwrap();
        s.set("modes", 20.0).unwrap();
        s.initialize(0.0).unwrap();
        let outs: Vec<u32> = outputs(s.variables()).map(|v| v.vr).collect();
        let mut x = [0.0];
        s.do_step(0.0, 1e-3).unwrap();
        // The first read of the error indicator factorizes its stiffness: once.
        for &vr in &outs {
            s.get_real(vr, &mut x).unwrap();
        }
        let steps = allocations_during(|| {
            for k in 1..20 {
                s.do_step(f64::from(k) * 1e-3, 1e-3).unwrap();
            }
        });
        let reads = allocations_during(|| {
            for k in 20..40 {
                s.do_step(f64::from(k) * 1e-3, 1e-3).unwrap();
                for &vr in &outs {
                    s.get_real(vr, &mut x).unwrap();
                }
            }
        });
        assert_eq!(
            (steps, reads),
            (0, 0),
            "{kinematics} {order}: allocations in 19 steps, in 20 steps with outputs"
        );
    }
}

/// Newton at finite strain (neo-Hookean tet10 block, 20 % stretch in 4 increments), full
/// Newton (every iteration reassembles and refactorizes) and modified Newton (a kept
/// factorization, Anderson-accelerated iterations on it): after a first solve has sized the
/// report, a solve of the same length allocates nothing.
#[test]
fn newton_iterations_allocate_nothing() {
    use models::assembly::tetrahedra::{Body, Solid, Tetrahedron};
    use models::assembly::Assembler;
    use models::element::{Elastic, Law, Material};
    use models::solve::newton::{Newton, Settings};

    let mesh = models::mesh::generate::block([2.0, 3.0, 1.5], [2, 3, 2]).unwrap();
    let material = Material::new(Law::NeoHookean, Elastic::new("m", 0.05, 0.43).unwrap());
    let solid = Solid::new(&mesh, Tetrahedron::Tet10, material);
    let asm = Assembler::new(solid.nodes().len(), 3, &solid.connectivity());
    let ends: Vec<usize> = (0..solid.nodes().len())
        .filter(|&n| solid.nodes()[n][1] == 0.0 || solid.nodes()[n][1] == 3.0)
        .collect();
    let fixed: Vec<usize> = ends
        .iter()
        .flat_map(|n| [3 * n, 3 * n + 1, 3 * n + 2])
        .collect();
    let zero = vec![0.0; solid.n_dofs()];
    let mut prescribed = vec![0.0; solid.n_dofs()];
    let body = Body {
        solid: &solid,
        asm: &asm,
    };
    let mut pull_to = |newton: &mut Newton, u: &mut Vec<f64>, stretch: f64| {
        for &n in &ends {
            prescribed[3 * n + 1] = if solid.nodes()[n][1] == 0.0 {
                0.0
            } else {
                stretch
            };
        }
        newton
            .solve(&body, u, &prescribed, &zero)
            .unwrap()
            .iterations
            .iter()
            .sum::<usize>()
    };
    for reuse_contraction in [0.0, 0.25] {
        let settings = Settings {
            max_increment: 0.15,
            reuse_contraction,
            ..Settings::default()
        };
        let mut newton = Newton::new(
            &asm,
            &fixed,
            Factorization::Supernodal(Ordering::NestedDissection),
            settings,
        )
        .unwrap();
        let mut u = vec![0.0; solid.n_dofs()];
        let first = pull_to(&mut newton, &mut u, 0.6);
        let mut iterations = 0;
        let n = allocations_during(|| iterations = pull_to(&mut newton, &mut u, 1.2));
        println!("{reuse_contraction}: {first} then {iterations} iterations; {n} allocations");
        assert!(iterations >= 8, "{iterations}");
        assert_eq!(n, 0, "{n} allocations in {iterations} iterations");
    }
}

#[test]
fn finite_strain_steps_allocate_nothing() {
    use models::assembly::plane::{Continuum, PlaneProperties};
    use models::assembly::quadratic_plane::{self, Formulation, PlaneBody};
    use models::element::{Elastic, Law, Material};
    use models::mesh::{generate, QuadraticPlaneMesh};
    use std::sync::Arc;

    let linear = generate::rectangle(4.0, 1.0, 8, 2).unwrap();
    let mesh = Arc::new(QuadraticPlaneMesh::new(&linear));
    let asm = Arc::new(quadratic_plane::assembler(&mesh));
    let elastic = Elastic::new("m", 1.0, 0.45).unwrap();
    let props = PlaneProperties {
        continua: vec![Continuum {
            elastic,
            density: 1e-9,
        }],
        trusses: vec![],
    };
    let (mut k, mut m) = (asm.zeros(), asm.zeros());
    quadratic_plane::stiffness(&mesh, &asm, &props, Formulation::Displacement, &mut k);
    quadratic_plane::mass(&mesh, &asm, &props, &mut m);
    let lumped = quadratic_plane::lumped_mass(&mesh, &props);
    let clamped: Vec<usize> = (0..mesh.nodes().len())
        .filter(|&n| mesh.nodes()[n][0] == 0.0)
        .flat_map(|n| [2 * n, 2 * n + 1])
        .collect();
    let bc = Dirichlet::new(&asm, &clamped).unwrap();
    let materials = Arc::from([Material::new(Law::NeoHookean, elastic)]);
    let s = Structure::new(
        bc,
        &k,
        &m,
        &lumped,
        Damping::NONE,
        Factorization::Simplicial,
    )
    .unwrap()
    .with_internal_forces(Arc::new(PlaneBody::triangles(
        mesh,
        asm,
        materials,
        Formulation::Displacement,
    )));
    for kind in [IntegratorKind::Houbolt, IntegratorKind::Newmark] {
        let mut integ = kind.create();
        integ.prepare(&s, 1e-4).unwrap();
        let mut load =
            |t: f64, f: &mut [f64]| f.iter_mut().for_each(|x| *x = -2e-4 * (300.0 * t).sin());
        integ
            .start(&s, 0.0, &vec![0.0; s.n()], &vec![0.0; s.n()], &mut load)
            .unwrap();
        for _ in 0..3 {
            integ.step(&s, &mut load).unwrap();
        }
        let mut iterations = 0;
        let n = allocations_during(|| {
            for _ in 0..30 {
                integ.step(&s, &mut load).unwrap();
                iterations = iterations.max(integ.newton_iterations());
            }
        });
        assert!(
            iterations >= 2,
            "{kind:?}: the load should need Newton iterations"
        );
        assert_eq!(
            n, 0,
            "{kind:?} allocated {n} times in 30 finite-strain steps"
        );
    }
}

/// Reading every output of the cut block allocates nothing once the output buffers have
/// grown to the mesh (the first read after the blade moved): after steps of the pull with
/// the flanks open and closed (contact held); linear tet4, neo-Hookean tet4 and tet10.
#[test]
fn cutblock_output_reads_allocate_nothing() {
    use models::scene::cutblock::CutBlock;
    for (material, element) in [
        ("linear", "tet4"),
        ("neo-hookean", "tet4"),
        ("neo-hookean", "tet10"),
    ] {
        let mut s = CutBlock::new();
        for (name, value) in [("material", material), ("element", element)] {
            let vr = s.lookup(name).unwrap();
            s.set_string(vr, value).unwrap();
        }
        s.set("cells_x", 6.0).unwrap();
        s.set("cells_y", 8.0).unwrap();
        s.set("cells_z", 6.0).unwrap();
        s.initialize(0.0).unwrap();
        let outs: Vec<(u32, usize)> = outputs(s.variables()).map(|v| (v.vr, v.len)).collect();
        let mut x = vec![0.0; outs.iter().map(|o| o.1).max().unwrap()];
        let mut read_all = |s: &mut CutBlock| {
            for &(vr, n) in &outs {
                s.get_real(vr, &mut x[..n]).unwrap();
            }
        };
        s.set("scalpel_x", 60.0).unwrap();
        s.do_step(0.0, 1.0).unwrap();
        read_all(&mut s);
        for pull in [2.0, 3.0, -2.0, -2.5] {
            s.set("pull", pull).unwrap();
            s.do_step(0.0, 1.0).unwrap();
            let n = allocations_during(|| read_all(&mut s));
            assert_eq!(n, 0, "{material} {element} at pull {pull}: {n} allocations");
            let held = s.get("contact_points").unwrap();
            assert_eq!(held > 0.0, pull < 0.0, "{material} {element}: {held} held");
        }
    }
}
