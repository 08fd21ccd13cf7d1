//! Convergence against analytical solutions: the L2 displacement error of linear elements
//! must fall as h² under uniform refinement (plane strain: Lamé cylinder; 3D: a manufactured
//! quadratic displacement field with its constant body force).

use models::assembly::{tetrahedra, Assembler};
use models::element::mixed::Formulation;
use models::element::{tet4, Elastic};
use models::linalg::{Factorization, Ordering};
use models::mesh::generate;
use models::solve::Statics;
use models::verify::lame::Lame;
use models::verify::richardson;
use nalgebra::{Matrix3, Vector3};

fn rates(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

#[test]
fn lame_cylinder_l2_error_converges_at_rate_two() {
    let lame = Lame {
        a: 10.0,
        b: 20.0,
        p: 0.1,
        material: Elastic::new("m", 1.0, 0.3).unwrap(),
    };
    let mut errors = Vec::new();
    for n in [4, 8, 16, 32] {
        let s = lame.solve(n, 2 * n).unwrap();
        println!(
            "lame nr={n:3} triangles={:6} L2 rel error={:.4e} u_r(a): fe={:.6} exact={:.6}",
            s.triangles, s.l2_error, s.inner_fe, s.inner_exact
        );
        errors.push(s.l2_error);
    }
    let r = rates(&errors);
    println!("lame rates {r:.3?}");
    for rate in &r[1..] {
        assert!((rate - 2.0).abs() < 0.15, "rates {r:?}");
    }
}

/// Quadratic triangles with curved (isoparametric) arcs: the L2 displacement error falls as
/// h³ and the L2 stress error as h². The mixed P2/P0 element does the same (the Lamé
/// solution's volume strain is constant, which its element pressure represents exactly), also
/// at ν = 0.4999, where the displacement element's displacements still converge at h³ but its
/// stresses carry the pressure's oscillations: 20 % error at 16 × 32 cells.
#[test]
fn lame_cylinder_with_quadratic_triangles_converges_at_rate_three() {
    println!("Lamé, tri6: relative L2 errors of u and σ at nr = 2, 4, 8, 16 (nt = 2 nr)");
    let sci = |v: &[f64]| {
        v.iter()
            .map(|x| format!("{x:.2e}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for (nu, formulation) in [
        (0.3, Formulation::Displacement),
        (0.3, Formulation::Mixed),
        (0.4999, Formulation::Displacement),
        (0.4999, Formulation::Mixed),
    ] {
        let lame = Lame {
            a: 10.0,
            b: 20.0,
            p: 0.1,
            material: Elastic::new("m", 1.0, nu).unwrap(),
        };
        let (mut u, mut sigma) = (Vec::new(), Vec::new());
        for n in [2, 4, 8, 16] {
            let s = lame.solve_quadratic(n, 2 * n, formulation).unwrap();
            u.push(s.l2_error);
            sigma.push(s.stress_error);
        }
        let (ru, rs) = (rates(&u), rates(&sigma));
        println!(
            "ν = {nu} {formulation:?}: u [{}] rates {ru:.2?}; σ [{}] rates {rs:.2?}",
            sci(&u),
            sci(&sigma)
        );
        let last = |r: &[f64]| r[r.len() - 1];
        assert!(last(&ru) >= 2.8, "{formulation:?} ν = {nu}: u rates {ru:?}");
        let oscillating = nu > 0.49 && formulation == Formulation::Displacement;
        if oscillating {
            assert!(sigma[3] > 0.1, "σ {sigma:?}");
        } else {
            assert!(last(&rs) >= 1.8, "{formulation:?} ν = {nu}: σ rates {rs:?}");
            assert!(sigma[3] < 2e-3, "{formulation:?} ν = {nu}: σ {sigma:?}");
        }
    }
}

/// Richardson extrapolation where the answer is known: the inner radial displacement of the
/// Lamé cylinder on three tri6 meshes (nr = 8, 16, 32). Displacement formulation: the
/// extrapolated value is 20× closer to the exact one than the finest mesh and the estimated
/// error of the finest is its actual error to 10 %. Mixed: its point value converges less
/// regularly; the estimate is conservative (twice the actual error). On nr = 4, 8, 16 the
/// mixed element overshoots and comes back (not yet asymptotic): the extrapolation refuses it.
#[test]
fn richardson_extrapolation_recovers_the_lame_displacement() {
    let lame = Lame {
        a: 10.0,
        b: 20.0,
        p: 0.1,
        material: Elastic::new("m", 1.0, 0.3).unwrap(),
    };
    let exact = lame.radial(lame.a);
    let inner = |formulation, meshes: [usize; 3]| {
        meshes.map(|n| {
            lame.solve_quadratic(n, 2 * n, formulation)
                .unwrap()
                .inner_fe
        })
    };
    for formulation in [Formulation::Displacement, Formulation::Mixed] {
        let values = inner(formulation, [8, 16, 32]);
        let e = richardson::extrapolate(values, 2.0).unwrap();
        let finest = (values[2] - exact).abs();
        println!(
            "{formulation:?}: u_r(a) {values:.10?}, order {:.2}, extrapolated {:.10} ± {:.1e}, exact {exact:.10}, finest error {finest:.1e}",
            e.order, e.value, e.error
        );
        if formulation == Formulation::Displacement {
            assert!((e.value - exact).abs() < finest / 10.0, "{e:?}");
            assert!((e.error / finest - 1.0).abs() < 0.1, "{e:?} {finest:e}");
        } else {
            assert!(
                e.error > finest && e.error < 3.0 * finest,
                "{e:?} {finest:e}"
            );
        }
    }
    assert!(richardson::extrapolate(inner(Formulation::Mixed, [4, 8, 16]), 2.0).is_err());
}

/// u_i = ½ H_ijk x_j x_k; then σ is linear and −div σ = b is constant:
/// b_i = −(μ Σ_j H_ijj + (λ + μ) Σ_j H_jji).
struct Manufactured {
    h: [Matrix3<f64>; 3],
    material: Elastic,
}

impl Manufactured {
    fn u(&self, x: &[f64; 3]) -> Vector3<f64> {
        let x = Vector3::from(*x);
        Vector3::from_fn(|i, _| 0.5 * (x.transpose() * self.h[i] * x)[0])
    }
    fn body_force(&self) -> Vector3<f64> {
        let (l, m) = (self.material.lambda(), self.material.shear());
        Vector3::from_fn(|i, _| {
            -(m * self.h[i].trace() + (l + m) * (0..3).map(|j| self.h[j][(j, i)]).sum::<f64>())
        })
    }
}

#[test]
fn tet4_manufactured_solution_converges_at_rate_two() {
    let sym = |m: Matrix3<f64>| (m + m.transpose()) * 0.5;
    let field = Manufactured {
        h: [
            sym(Matrix3::new(0.2, 0.0, 0.0, 0.0, 0.0, 0.05, 0.0, 0.05, -0.1)),
            sym(Matrix3::new(
                0.0, 0.0, -0.03, 0.0, 0.16, 0.0, -0.03, 0.0, 0.04,
            )),
            sym(Matrix3::new(
                0.0, 0.03, 0.06, 0.03, 0.0, 0.0, 0.06, 0.0, 0.08,
            )),
        ],
        material: Elastic::new("m", 1.0, 0.3).unwrap(),
    };
    let b = field.body_force();
    let mut errors = Vec::new();
    for n in [2, 4, 8, 16] {
        let mesh = generate::block([1.0, 1.0, 1.0], [n, n, n]).unwrap();
        let asm: Assembler = tetrahedra::assembler(&mesh);
        let mut k = asm.zeros();
        let material = models::assembly::plane::Continuum {
            elastic: field.material,
            density: 1.0,
        };
        tetrahedra::stiffness(&mesh, &asm, &material, &mut k);
        let mut f = vec![0.0; mesh.n_dofs()];
        for (i, tet) in mesh.tets().iter().enumerate() {
            let v = tet4::signed_volume(&mesh.tet(i));
            for &node in tet {
                for d in 0..3 {
                    f[3 * node + d] += b[d] * v / 4.0;
                }
            }
        }
        let mut u = vec![0.0; mesh.n_dofs()];
        let mut fixed = Vec::new();
        for face in ["x0", "x1", "y0", "y1", "z0", "z1"] {
            for &node in mesh.node_sets().get(face).unwrap() {
                let ue = field.u(&mesh.nodes()[node]);
                for d in 0..3 {
                    fixed.push(3 * node + d);
                    u[3 * node + d] = ue[d];
                }
            }
        }
        let mut statics = Statics::new(
            &asm,
            &fixed,
            Factorization::Supernodal(Ordering::NestedDissection),
        )
        .unwrap();
        statics.factorize(&k).unwrap();
        statics.solve(asm.matrix(&k), &f, &mut u);
        // Degree-2 rule for tetrahedra: 4 points, weight V/4.
        let (qa, qb) = (0.585_410_196_624_968_5, 0.138_196_601_125_010_5);
        let (mut err, mut norm) = (0.0, 0.0);
        for (i, tet) in mesh.tets().iter().enumerate() {
            let p = mesh.tet(i);
            let w = tet4::signed_volume(&p) / 4.0;
            for q in 0..4 {
                let l: [f64; 4] = std::array::from_fn(|k| if k == q { qa } else { qb });
                let x: [f64; 3] = std::array::from_fn(|d| (0..4).map(|k| l[k] * p[k][d]).sum());
                let uh = Vector3::from_fn(|d, _| (0..4).map(|k| l[k] * u[3 * tet[k] + d]).sum());
                let ue = field.u(&x);
                err += w * (uh - ue).norm_squared();
                norm += w * ue.norm_squared();
            }
        }
        let e = (err / norm).sqrt();
        println!(
            "tet4 n={n:2} tets={:6} L2 rel error={e:.4e}",
            mesh.tets().len()
        );
        errors.push(e);
    }
    let r = rates(&errors);
    println!("tet4 rates {r:.3?}");
    for rate in &r[1..] {
        assert!((rate - 2.0).abs() < 0.15, "rates {r:?}");
    }
}
