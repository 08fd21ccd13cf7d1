//! Finite-strain solids (total Lagrangian, neo-Hookean and St. Venant–Kirchhoff, linear and
//! quadratic tetrahedra) and the Newton solver, against closed-form homogeneous
//! deformations: uniaxial stretch with free lateral contraction, and a rigid rotation.

use models::assembly::tetrahedra::{Body, Solid, Tetrahedron};
use models::assembly::{Assembler, InternalForces};
use models::element::{Elastic, Law, Material};
use models::error::ModelError;
use models::linalg::{Factorization, Ordering};
use models::mesh::generate;
use models::solve::newton::{Newton, Report, Settings};
use std::sync::atomic::{AtomicU64, Ordering::Relaxed};

const SIZE: [f64; 3] = [2.0, 3.0, 1.5];
const E: f64 = 0.05;
const NU: f64 = 0.43;

/// A Newton solver on a supernodal factorization ordered by nested dissection.
fn supernodal_newton(asm: &Assembler, fixed: &[usize], settings: Settings) -> Newton {
    Newton::new(
        asm,
        fixed,
        Factorization::Supernodal(Ordering::NestedDissection),
        settings,
    )
    .unwrap()
}

fn material(law: Law) -> Material {
    Material::new(law, Elastic::new("m", E, NU).unwrap())
}

/// A block of 2 × 3 × 2 cubes with the given tetrahedra and law, and its assembler.
fn block(kind: Tetrahedron, law: Law) -> (Solid, Assembler) {
    let mesh = generate::block(SIZE, [2, 3, 2]).unwrap();
    let solid = Solid::new(&mesh, kind, material(law));
    let asm = Assembler::new(solid.nodes().len(), 3, &solid.connectivity());
    (solid, asm)
}

fn nodes_where(solid: &Solid, pred: impl Fn(&[f64; 3]) -> bool) -> Vec<usize> {
    (0..solid.nodes().len())
        .filter(|&n| pred(&solid.nodes()[n]))
        .collect()
}

/// Solves x = 0 by bisection on [lo, hi] (f changes sign there).
fn root(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if (f(mid) > 0.0) == (f(lo) > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// Uniaxial stretch λ along y with free lateral stretch a: the closed-form (a, P_yy).
fn uniaxial(law: Law, stretch: f64) -> (f64, f64) {
    let m = material(law);
    let el = m.elastic;
    let (l, mu) = (el.lambda(), el.shear());
    match law {
        Law::NeoHookean => {
            // P_xx = μ a + (λ ln J − μ)/a = 0 with J = a² λ.
            let a = root(|a| mu * a * a + l * (a * a * stretch).ln() - mu, 0.2, 1.5);
            let j = a * a * stretch;
            (a, mu * stretch + (l * j.ln() - mu) / stretch)
        }
        Law::StVenantKirchhoff => {
            // S_xx = λ tr E + 2μ E_xx = 0 with E = diag((a²−1)/2, (λ²−1)/2, (a²−1)/2).
            let e_yy = 0.5 * (stretch * stretch - 1.0);
            let e_xx = root(|e| l * (e_yy + 2.0 * e) + 2.0 * mu * e, -0.49, 0.5);
            let s_yy = l * (e_yy + 2.0 * e_xx) + 2.0 * mu * e_yy;
            ((1.0 + 2.0 * e_xx).sqrt(), stretch * s_yy)
        }
        Law::Linear => unreachable!("a finite-strain law"),
    }
}

/// Sliding supports: u_y = 0 on y = 0 and u_y = δ on y = L, u_x = u_z = 0 at the origin,
/// u_z = 0 at (L_x, 0, 0); everything else free. Returns (constrained dofs, prescribed
/// values, pulled nodes).
fn sliding(solid: &Solid, delta: f64) -> (Vec<usize>, Vec<f64>, Vec<usize>) {
    let near = |a: f64, b: f64| (a - b).abs() < 1e-12;
    let y0 = nodes_where(solid, |p| near(p[1], 0.0));
    let y1 = nodes_where(solid, |p| near(p[1], SIZE[1]));
    let origin = nodes_where(solid, |p| {
        near(p[0], 0.0) && near(p[1], 0.0) && near(p[2], 0.0)
    })[0];
    let corner = nodes_where(solid, |p| {
        near(p[0], SIZE[0]) && near(p[1], 0.0) && near(p[2], 0.0)
    })[0];
    let mut fixed: Vec<usize> = y0.iter().chain(&y1).map(|n| 3 * n + 1).collect();
    fixed.extend([3 * origin, 3 * origin + 2, 3 * corner + 2]);
    let mut prescribed = vec![0.0; solid.n_dofs()];
    for n in &y1 {
        prescribed[3 * n + 1] = delta;
    }
    (fixed, prescribed, y1)
}

/// Solves the solid from `u` to the prescribed values, with no external loads.
fn pull<'a>(
    newton: &'a mut Newton,
    solid: &Solid,
    asm: &Assembler,
    u: &mut [f64],
    prescribed: &[f64],
) -> Result<&'a Report, ModelError> {
    let zero = vec![0.0; solid.n_dofs()];
    newton.solve(&Body { solid, asm }, u, prescribed, &zero)
}

#[test]
fn uniaxial_stretch_matches_the_closed_form_for_both_tetrahedra_and_laws() {
    for kind in Tetrahedron::ALL {
        for law in [Law::NeoHookean, Law::StVenantKirchhoff] {
            for strain in [0.01, 0.2, 0.5] {
                let (solid, asm) = block(kind, law);
                let delta = strain * SIZE[1];
                let (fixed, prescribed, pulled) = sliding(&solid, delta);
                let settings = Settings {
                    max_increment: 0.2,
                    ..Settings::default()
                };
                let mut newton = supernodal_newton(&asm, &fixed, settings);
                let mut u = vec![0.0; solid.n_dofs()];
                pull(&mut newton, &solid, &asm, &mut u, &prescribed).unwrap();
                let force: f64 = pulled
                    .iter()
                    .map(|n| newton.internal_forces()[3 * n + 1])
                    .sum();
                let (a, p) = uniaxial(law, 1.0 + strain);
                let expected = p * SIZE[0] * SIZE[2];
                let far = nodes_where(&solid, |q| (q[0] - SIZE[0]).abs() < 1e-12);
                let lateral = 1.0 + u[3 * far[0]] / SIZE[0];
                println!("{kind:?} {law:?} {strain}: force {force:.10} vs {expected:.10}, lateral {lateral:.10} vs {a:.10}");
                assert!(
                    (force - expected).abs() <= 1e-8 * expected.abs(),
                    "{kind:?} {law:?} {strain}"
                );
                assert!((lateral - a).abs() <= 1e-8 * a, "{kind:?} {law:?} {strain}");
            }
        }
    }
}

/// Both end faces turned by 90° about the z axis, in ten solves of 9° (the prescribed
/// displacements move along chords in between, which compress the block slightly): the
/// finite-strain laws end stress-free (zero internal forces everywhere), the linear one
/// does not.
#[test]
fn a_rigid_rotation_is_stress_free_at_finite_strain_only() {
    for law in Law::ALL {
        let (solid, asm) = block(Tetrahedron::Tet4, law);
        let ends = nodes_where(&solid, |p| p[1] == 0.0 || p[1] == SIZE[1]);
        let fixed: Vec<usize> = ends
            .iter()
            .flat_map(|n| [3 * n, 3 * n + 1, 3 * n + 2])
            .collect();
        let mut newton = supernodal_newton(&asm, &fixed, Settings::default());
        let mut u = vec![0.0; solid.n_dofs()];
        let mut prescribed = vec![0.0; solid.n_dofs()];
        for step in 1..=10 {
            let angle = f64::from(step) * std::f64::consts::FRAC_PI_2 / 10.0;
            let (c, s) = (angle.cos(), angle.sin());
            for &n in &ends {
                let [x, y, _] = solid.nodes()[n];
                prescribed[3 * n] = c * x - s * y - x;
                prescribed[3 * n + 1] = s * x + c * y - y;
            }
            pull(&mut newton, &solid, &asm, &mut u, &prescribed).unwrap();
        }
        let largest = newton
            .internal_forces()
            .iter()
            .fold(0.0f64, |a, f| a.max(f.abs()));
        println!("{law:?}: largest internal force after a 90° rotation {largest:e} N");
        if law.finite() {
            assert!(
                largest < 1e-11 * E * SIZE[0] * SIZE[2],
                "{law:?}: {largest:e}"
            );
        } else {
            assert!(
                largest > 0.01 * E * SIZE[0] * SIZE[2],
                "{law:?}: {largest:e}"
            );
        }
    }
}

/// The residual history of the last increment falls quadratically: the convergence order
/// estimated from the last three residuals above round-off is near 2.
#[test]
fn newton_converges_quadratically() {
    let (solid, asm) = block(Tetrahedron::Tet10, Law::NeoHookean);
    let (fixed, prescribed, _) = sliding(&solid, 0.4 * SIZE[1]);
    let settings = Settings {
        max_increment: 1.2,
        residual_tolerance: 1e-12,
        reuse_contraction: 0.0,
        ..Settings::default()
    };
    let mut newton = supernodal_newton(&asm, &fixed, settings);
    let mut u = vec![0.0; solid.n_dofs()];
    let report = pull(&mut newton, &solid, &asm, &mut u, &prescribed)
        .unwrap()
        .clone();
    // The first three residuals of the increment, all above round-off (1e-15).
    let r = &report.residuals;
    println!("iterations {:?}, residuals {r:?}", report.iterations);
    assert!(r.len() >= 3 && r[2] > 1e-15, "{r:?}");
    let order = (r[2] / r[1]).ln() / (r[1] / r[0]).ln();
    assert!(order > 1.8, "order {order}: {r:?}");
}

/// A compression that inverts elements fails with a message naming the load reached, and
/// the displacement keeps the last equilibrium.
#[test]
fn a_failed_solve_names_the_load_reached_and_keeps_the_state() {
    let (solid, asm) = block(Tetrahedron::Tet4, Law::StVenantKirchhoff);
    let (fixed, mut prescribed, pulled) = sliding(&solid, 0.1 * SIZE[1]);
    let mut newton = supernodal_newton(&asm, &fixed, Settings::default());
    let mut u = vec![0.0; solid.n_dofs()];
    let zero = vec![0.0; solid.n_dofs()];
    let body = Body {
        solid: &solid,
        asm: &asm,
    };
    newton.solve(&body, &mut u, &prescribed, &zero).unwrap();
    let before = u.clone();
    for n in &pulled {
        prescribed[3 * n + 1] = -1.5 * SIZE[1]; // through the opposite face
    }
    let e = newton.solve(&body, &mut u, &prescribed, &zero).unwrap_err();
    assert!(matches!(e, ModelError::NotConverged { .. }), "{e}");
    assert!(e.to_string().contains("% of the load change"), "{e}");
    assert_eq!(u, before);
}

/// A start that does not converge at an unchanged load (the equilibrium of a 30 % stretch
/// with its lateral displacements 10 % off, given two iterations) is retried once, from a
/// fresh factorization since it started on the kept one, and not cut back further — its
/// halves would be the same problem; the solve then goes on from the last equilibrium,
/// converged there at once. The report counts the failed attempts' iterations: 2 × 2.
#[test]
fn a_start_that_fails_at_an_unchanged_load_is_retried_once_and_counted() {
    let (solid, asm) = block(Tetrahedron::Tet10, Law::NeoHookean);
    let (fixed, prescribed, _) = sliding(&solid, 0.3 * SIZE[1]);
    let mut newton = supernodal_newton(&asm, &fixed, Settings::default());
    let mut u = vec![0.0; solid.n_dofs()];
    pull(&mut newton, &solid, &asm, &mut u, &prescribed).unwrap();
    let equilibrium = u.clone();
    let start: Vec<f64> = u
        .iter()
        .enumerate()
        .map(|(d, v)| if d % 3 == 1 { *v } else { 1.1 * v })
        .collect();
    let max_iterations = 2;
    let settings = Settings {
        max_iterations,
        ..Settings::default()
    };
    newton.set_settings(settings).unwrap();
    let zero = vec![0.0; solid.n_dofs()];
    let body = Body {
        solid: &solid,
        asm: &asm,
    };
    let report = newton
        .solve_from(&body, &mut u, &start, &prescribed, &zero)
        .unwrap();
    assert_eq!(report.cutbacks, 1, "{report:?}");
    assert_eq!(report.failed_iterations, 2 * max_iterations, "{report:?}");
    assert_eq!(report.iterations, [0], "{report:?}");
    assert_eq!(u, equilibrium);
}

/// A body pulled by forces of its own that follow the load: `force` along y on each of the
/// `nodes`, times the load fraction s of the solve (as the abdomen's diaphragm tension
/// follows its activation), declared as following the load or not.
struct Following<'a> {
    body: Body<'a>,
    nodes: Vec<usize>,
    force: f64,
    s: AtomicU64,
    declared: bool,
}

impl InternalForces for Following<'_> {
    fn at_load_fraction(&self, s: f64) {
        self.s.store(s.to_bits(), Relaxed);
    }

    fn follow_the_load(&self) -> bool {
        self.declared
    }

    fn internal(&self, u: &[f64], f: &mut [f64], k: Option<&mut [f64]>) -> Result<(), ModelError> {
        self.body.internal(u, f, k)?;
        let s = f64::from_bits(self.s.load(Relaxed));
        for n in &self.nodes {
            f[3 * n + 1] -= s * self.force;
        }
        Ok(())
    }
}

/// A solve whose prescribed values and external forces stay put but whose own forces follow
/// the load (a stretch of about 40 % by forces that grow along the load fraction, five
/// iterations per increment) is still cut back, and converges; the same solve with the
/// forces not declared as following the load is taken in one increment, which fails, and
/// not cut back.
#[test]
fn forces_that_follow_the_load_are_cut_back_at_an_unchanged_load() {
    let (solid, asm) = block(Tetrahedron::Tet4, Law::NeoHookean);
    let (mut fixed, _, pulled) = sliding(&solid, 0.0);
    let pulled_y: Vec<usize> = pulled.iter().map(|n| 3 * n + 1).collect();
    fixed.retain(|d| !pulled_y.contains(d));
    let (_, stress) = uniaxial(Law::NeoHookean, 1.4);
    let force = stress * SIZE[0] * SIZE[2] / pulled.len() as f64;
    let settings = Settings {
        max_iterations: 5,
        ..Settings::default()
    };
    let zero = vec![0.0; solid.n_dofs()];
    let solve = |declared: bool| {
        let body = Following {
            body: Body {
                solid: &solid,
                asm: &asm,
            },
            nodes: pulled.clone(),
            force,
            s: AtomicU64::new(0),
            declared,
        };
        let mut newton = supernodal_newton(&asm, &fixed, settings);
        let mut u = vec![0.0; solid.n_dofs()];
        let solved = newton.solve(&body, &mut u, &zero, &zero).map(drop);
        (solved, newton.report().clone())
    };
    let (solved, report) = solve(true);
    solved.unwrap();
    assert!(report.cutbacks >= 1, "{report:?}");
    let (solved, report) = solve(false);
    let e = solved.unwrap_err();
    assert!(matches!(e, ModelError::NotConverged { .. }), "{e}");
    assert_eq!(report.cutbacks, 0, "{report:?}");
}

/// Modified Newton (the factorization kept while the residual falls by 10× per iteration)
/// reaches the equilibrium full Newton–Raphson reaches, with fewer factorizations, on a
/// clamped block pulled by 30 % (an inhomogeneous state).
#[test]
fn a_kept_factorization_reaches_the_same_equilibrium_with_fewer_factorizations() {
    let (solid, asm) = block(Tetrahedron::Tet10, Law::NeoHookean);
    let clamped = nodes_where(&solid, |p| p[1] == 0.0);
    let pulled = nodes_where(&solid, |p| p[1] == SIZE[1]);
    let mut fixed: Vec<usize> = clamped
        .iter()
        .flat_map(|n| [3 * n, 3 * n + 1, 3 * n + 2])
        .collect();
    fixed.extend(pulled.iter().map(|n| 3 * n + 1));
    let mut prescribed = vec![0.0; solid.n_dofs()];
    for n in &pulled {
        prescribed[3 * n + 1] = 0.3 * SIZE[1];
    }
    let zero = vec![0.0; solid.n_dofs()];
    let run = |reuse_contraction: f64| {
        let settings = Settings {
            max_increment: 0.1 * SIZE[1],
            reuse_contraction,
            ..Settings::default()
        };
        let mut newton = supernodal_newton(&asm, &fixed, settings);
        let mut u = vec![0.0; solid.n_dofs()];
        let body = Body {
            solid: &solid,
            asm: &asm,
        };
        let report = newton.solve(&body, &mut u, &prescribed, &zero).unwrap();
        (u, report.factorizations)
    };
    let (full, full_count) = run(0.0);
    let (kept, kept_count) = run(0.1);
    let size = full.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    let diff = full
        .iter()
        .zip(&kept)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
    println!("factorizations: full Newton {full_count}, kept {kept_count}; difference {diff:e}");
    assert!(diff < 1e-9 * size, "{diff:e}");
    assert!(kept_count < full_count, "{kept_count} vs {full_count}");
}

/// A solver done with (a pull and a press) and recycled ([`Newton::recycle`]: its storage
/// kept, its state reset) solves the next equations of its pattern exactly as a new one of
/// that pattern ([`Newton::same_pattern`]) does: the same iterations and factorizations, bit
/// for bit the same displacements and the same checkpoint (load, kept tangent's state).
/// The equations change as at a blade advance within a cell: the same connectivity with
/// the nodes moved (a taller block), and another ν.
#[test]
fn a_recycled_solver_solves_as_a_new_one_of_its_pattern() {
    for factorization in [
        Factorization::Supernodal(Ordering::NestedDissection),
        Factorization::SupernodalSingle(Ordering::MinimumDegree),
    ] {
        let (solid, asm) = block(Tetrahedron::Tet4, Law::NeoHookean);
        let (fixed, prescribed, _) = sliding(&solid, 0.3 * SIZE[1]);
        let settings = Settings {
            max_increment: 0.1 * SIZE[1],
            reuse_contraction: 0.25,
            ..Settings::default()
        };
        let mut used = Newton::new(&asm, &fixed, factorization, settings).unwrap();
        let (_, _, pulled) = sliding(&solid, 0.0);
        let mut pressed = vec![0.0; solid.n_dofs()];
        for n in pulled {
            pressed[3 * n + 2] = -1e-3;
        }
        let mut u = vec![0.0; solid.n_dofs()];
        let body = Body {
            solid: &solid,
            asm: &asm,
        };
        used.solve(&body, &mut u, &prescribed, &pressed).unwrap();

        let taller = generate::block([SIZE[0], SIZE[1], 1.2 * SIZE[2]], [2, 3, 2]).unwrap();
        let other = Material::new(Law::NeoHookean, Elastic::new("m", E, 0.3).unwrap());
        let moved = Solid::new(&taller, Tetrahedron::Tet4, other);
        let (_, target, _) = sliding(&moved, 0.2 * SIZE[1]);
        let next = Settings {
            max_increment: 0.05 * SIZE[1],
            ..settings
        };
        let mut new = used.same_pattern(next).unwrap();
        used.recycle(next).unwrap();
        let solve = |newton: &mut Newton| {
            let mut u = vec![0.0; moved.n_dofs()];
            let report = pull(newton, &moved, &asm, &mut u, &target).unwrap();
            (u, report.iterations.clone(), report.factorizations)
        };
        let (fresh, recycled) = (solve(&mut new), solve(&mut used));
        println!(
            "{factorization:?}: iterations {:?}, {} factorizations",
            fresh.1, fresh.2
        );
        assert_eq!(fresh.1, recycled.1, "iterations");
        assert_eq!(fresh.2, recycled.2, "factorizations");
        assert!(fresh.0 == recycled.0, "displacements differ");
        assert!(fresh.0.iter().any(|&x| x != 0.0));
        assert_eq!(new.checkpoint(), used.checkpoint());
    }
}
