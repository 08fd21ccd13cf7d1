//! Integrators on a small plane-strain FE model (a cantilever, 48 free dofs) against the
//! modal reference solution from a dense generalized eigen-decomposition (nalgebra), and
//! their stability limits.

use crate::dense;
use models::assembly::plane::{self, Continuum, PlaneProperties};
use models::assembly::Dirichlet;
use models::element::Elastic;
use models::linalg::Factorization;
use models::mesh::generate;
use models::solve::{Damping, IntegratorKind, Statics, Structure};
use models::ModelError;
use nalgebra::{DMatrix, DVector, SymmetricEigen};

struct Model {
    s: Structure,
    u0: Vec<f64>,
    /// M-orthonormal mode shapes (columns) and circular frequencies.
    phi: DMatrix<f64>,
    omega: DVector<f64>,
    m: DMatrix<f64>,
}

/// Cantilever 4 × 1 mm, 8 × 2 cells, left edge clamped; initial state: the static deflection
/// under a tip load, at rest.
fn model() -> Model {
    let mesh = generate::rectangle(4.0, 1.0, 8, 2).unwrap();
    let props = PlaneProperties {
        continua: vec![Continuum {
            elastic: Elastic::new("m", 1.0, 0.3).unwrap(),
            density: 1.0,
        }],
        trusses: vec![],
    };
    let asm = plane::assembler(&mesh);
    let (mut k, mut m) = (asm.zeros(), asm.zeros());
    plane::stiffness(&mesh, &asm, &props, &mut k);
    plane::mass(&mesh, &asm, &props, &mut m);
    let fixed: Vec<usize> = mesh
        .node_sets()
        .get("left")
        .unwrap()
        .iter()
        .flat_map(|n| [2 * n, 2 * n + 1])
        .collect();
    let mut statics = Statics::new(&asm, &fixed, Factorization::Simplicial).unwrap();
    statics.factorize(&k).unwrap();
    let mut f = vec![0.0; mesh.n_dofs()];
    for &n in mesh.node_sets().get("right").unwrap() {
        f[2 * n + 1] = -0.01;
    }
    let mut u_full = vec![0.0; mesh.n_dofs()];
    statics.solve(asm.matrix(&k), &f, &mut u_full);
    let bc = Dirichlet::new(&asm, &fixed).unwrap();
    let mut u0 = vec![0.0; bc.n_free()];
    bc.reduce(&u_full, &mut u0);
    let lumped = plane::lumped_mass(&mesh, &props);
    let s = Structure::new(
        bc,
        &k,
        &m,
        &lumped,
        Damping::NONE,
        Factorization::Simplicial,
    )
    .unwrap();
    let (kd, md) = (dense(s.stiffness()), dense(s.mass()));
    let l = md.clone().cholesky().unwrap().l();
    let linv = l.clone().try_inverse().unwrap();
    let eig = SymmetricEigen::new(&linv * kd * linv.transpose());
    let phi = linv.transpose() * eig.eigenvectors;
    let omega = eig.eigenvalues.map(f64::sqrt);
    Model {
        s,
        u0,
        phi,
        omega,
        m: md,
    }
}

impl Model {
    /// The same model started from the sum of its first two mode shapes, so that only
    /// modes that the step sizes below resolve are excited.
    fn with_low_modes(mut self) -> Self {
        // nalgebra does not sort eigenvalues.
        let mut order: Vec<usize> = (0..self.omega.len()).collect();
        order.sort_by(|&a, &b| self.omega[a].total_cmp(&self.omega[b]));
        let low = self.phi.column(order[0]) + self.phi.column(order[1]);
        let u =
            low * (DVector::from_column_slice(&self.u0).amax() / self.phi.column(order[0]).amax());
        self.u0 = u.as_slice().to_vec();
        self
    }

    fn reference(&self, t: f64) -> DVector<f64> {
        let q0 = self.phi.transpose() * &self.m * DVector::from_column_slice(&self.u0);
        let q = DVector::from_fn(q0.len(), |i, _| q0[i] * (self.omega[i] * t).cos());
        &self.phi * q
    }

    fn fundamental_period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.omega.min()
    }

    /// Runs `kind` with step `dt` for `steps` steps; returns the final displacement and the
    /// largest energy seen relative to the initial one.
    fn run(
        &self,
        kind: IntegratorKind,
        dt: f64,
        steps: usize,
    ) -> Result<(DVector<f64>, f64), ModelError> {
        let mut integ = kind.create();
        integ.prepare(&self.s, dt)?;
        let mut zero = |_: f64, f: &mut [f64]| f.fill(0.0);
        let v0 = vec![0.0; self.u0.len()];
        integ.start(&self.s, 0.0, &self.u0, &v0, &mut zero)?;
        let mut work = vec![0.0; self.u0.len()];
        let e0 = self.s.energy(&self.u0, &v0, &mut work);
        let mut worst: f64 = 1.0;
        for _ in 0..steps {
            integ.step(&self.s, &mut zero)?;
            let st = integ.state();
            worst = worst.max(self.s.energy(&st.u, &st.v, &mut work) / e0);
        }
        Ok((DVector::from_column_slice(&integ.state().u), worst))
    }
}

#[test]
fn implicit_schemes_converge_to_the_modal_solution_at_order_two_and_agree() {
    let model = model().with_low_modes();
    let t_end = 1.3 * model.fundamental_period();
    let reference = model.reference(t_end);
    let mut finals = Vec::new();
    for kind in [IntegratorKind::Houbolt, IntegratorKind::Newmark] {
        let mut errors = Vec::new();
        let mut runs = Vec::new();
        for n in [320, 640, 1280, 2560] {
            let (u, _) = model.run(kind, t_end / n as f64, n).unwrap();
            errors.push((&u - &reference).norm() / reference.norm());
            runs.push(u);
        }
        let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
        println!("{kind:?}: rel errors {errors:.3?} orders {orders:.3?}");
        assert!(
            orders.iter().skip(1).all(|p| (p - 2.0).abs() < 0.15),
            "{kind:?} {orders:?}"
        );
        finals.push(runs);
    }
    let gaps: Vec<f64> = (0..4)
        .map(|i| (&finals[0][i] - &finals[1][i]).norm() / reference.norm())
        .collect();
    println!("|houbolt - newmark| / |u|: {gaps:.3?}");
    assert!(gaps.windows(2).all(|w| w[1] < w[0] / 3.5), "{gaps:?}");
    assert!(gaps[3] < 5e-3);
}

fn lumped_omega_max(model: &Model) -> f64 {
    let k = dense(model.s.stiffness());
    let scale = DVector::from_iterator(
        model.u0.len(),
        model.s.lumped_mass().iter().map(|m| 1.0 / m.sqrt()),
    );
    let a = DMatrix::from_fn(k.nrows(), k.ncols(), |i, j| k[(i, j)] * scale[i] * scale[j]);
    SymmetricEigen::new(a).eigenvalues.max().sqrt()
}

#[test]
fn explicit_critical_steps_match_the_dense_spectrum() {
    let model = model();
    let omega_max = lumped_omega_max(&model);
    for (kind, factor) in [
        (IntegratorKind::CentralDifference, 2.0),
        (IntegratorKind::Rk4, 2.0 * 2f64.sqrt()),
    ] {
        let mut integ = kind.create();
        integ.prepare(&model.s, 1e-3).unwrap();
        let crit = integ.critical_time_step().unwrap();
        println!(
            "{kind:?}: critical dt {crit:.6e}, dense {:.6e}",
            factor / omega_max
        );
        assert!((crit * omega_max / factor - 1.0).abs() < 1e-8);
    }
}

#[test]
fn central_difference_is_stable_just_below_its_limit_and_unbounded_just_above() {
    let model = model();
    let crit = 2.0 / lumped_omega_max(&model);
    let (_, worst) = model
        .run(IntegratorKind::CentralDifference, 0.99 * crit, 5000)
        .unwrap();
    println!("0.99 dt_crit: max energy ratio {worst:.3}");
    assert!(worst < 2.0);
    match model.run(IntegratorKind::CentralDifference, 1.01 * crit, 5000) {
        Err(ModelError::Diverged { integrator, .. }) => {
            assert_eq!(integrator, "central_difference")
        }
        Ok((_, worst)) => assert!(worst > 1e6, "energy ratio only {worst}"),
        Err(e) => panic!("{e}"),
    }
}

#[test]
fn rk4_is_stable_just_below_its_limit() {
    let model = model();
    let crit = 2.0 * 2f64.sqrt() / lumped_omega_max(&model);
    let (_, worst) = model.run(IntegratorKind::Rk4, 0.99 * crit, 3000).unwrap();
    assert!(worst <= 1.0 + 1e-9, "{worst}");
    assert!(model.run(IntegratorKind::Rk4, 1.05 * crit, 3000).is_err());
}

#[test]
fn houbolt_is_bounded_and_dissipative_far_above_the_explicit_limit() {
    let model = model();
    let crit = 2.0 / lumped_omega_max(&model);
    let dt = 1000.0 * crit;
    let steps = 200;
    let (u, worst) = model.run(IntegratorKind::Houbolt, dt, steps).unwrap();
    let mut work = vec![0.0; model.u0.len()];
    let e0 = model
        .s
        .energy(&model.u0, &vec![0.0; model.u0.len()], &mut work);
    let e_end = model
        .s
        .energy(u.as_slice(), &vec![0.0; model.u0.len()], &mut work);
    println!("dt = {:.0} x explicit limit ({:.3} T1): max energy ratio {worst:.4}, final strain energy ratio {:.3e}",
        1000.0, dt / model.fundamental_period(), e_end / e0);
    assert!(worst <= 1.0 + 1e-9 && e_end < 1e-3 * e0);
}
