//! Shift-invert Lanczos and the modal reduction on a small plane-strain cantilever (96 free
//! dofs) against a dense generalized eigen-decomposition (nalgebra) and against the full
//! system's own runs.

use crate::dense;
use models::assembly::plane::{self, Continuum, PlaneProperties};
use models::assembly::Dirichlet;
use models::element::Elastic;
use models::linalg::Factorization;
use models::mesh::generate;
use models::solve::{lanczos, Carried, Damping, IntegratorKind, ModalBasis, Reduction, Structure};
use models::ModelError;
use nalgebra::{DMatrix, SymmetricEigen};

/// Cantilever 6 × 1 mm, 12 × 3 cells, left edge clamped, Rayleigh damping (so that the
/// reduced damping matrix is not a multiple of the reduced mass); and its tip load pattern.
fn cantilever() -> (Structure, Vec<f64>) {
    let mesh = generate::rectangle(6.0, 1.0, 12, 3).unwrap();
    let props = PlaneProperties {
        continua: vec![Continuum {
            elastic: Elastic::new("m", 1.0, 0.3).unwrap(),
            density: 1e-3,
        }],
        trusses: vec![],
    };
    let asm = plane::assembler(&mesh);
    let (mut k, mut m) = (asm.zeros(), asm.zeros());
    plane::stiffness(&mesh, &asm, &props, &mut k);
    plane::mass(&mesh, &asm, &props, &mut m);
    let sets = mesh.node_sets();
    let fixed: Vec<usize> = sets
        .get("left")
        .unwrap()
        .iter()
        .flat_map(|n| [2 * n, 2 * n + 1])
        .collect();
    let bc = Dirichlet::new(&asm, &fixed).unwrap();
    let mut f_full = vec![0.0; mesh.n_dofs()];
    for &n in sets.get("right").unwrap() {
        f_full[2 * n + 1] = -0.01;
    }
    let mut f = vec![0.0; bc.n_free()];
    bc.reduce(&f_full, &mut f);
    let lumped = plane::lumped_mass(&mesh, &props);
    let damping = Damping {
        alpha: 0.5,
        beta: 2e-3,
    };
    let s = Structure::new(bc, &k, &m, &lumped, damping, Factorization::Simplicial).unwrap();
    (s, f)
}

/// All eigenvalues of K φ = λ M φ, ascending, from a dense solve.
fn dense_eigenvalues(s: &Structure) -> Vec<f64> {
    let l = dense(s.mass()).cholesky().unwrap().l();
    let linv = l.try_inverse().unwrap();
    let eig = SymmetricEigen::new(&linv * dense(s.stiffness()) * linv.transpose());
    let mut values: Vec<f64> = eig.eigenvalues.iter().copied().collect();
    values.sort_by(f64::total_cmp);
    values
}

fn lanczos_modes(s: &Structure, count: usize) -> Result<lanczos::Modes, ModelError> {
    let mut chol = s.analyze()?;
    chol.factorize(s.stiffness())?;
    lanczos::lowest(s.stiffness(), s.mass(), &mut chol, count)
}

#[test]
fn lanczos_modes_match_a_dense_generalized_eigen_solve() {
    let (s, _) = cantilever();
    let reference = dense_eigenvalues(&s);
    let modes = lanczos_modes(&s, 12).unwrap();
    println!("{} Lanczos steps for 12 of {} modes", modes.steps, s.n());
    for (i, (got, want)) in modes.values.iter().zip(&reference).enumerate() {
        assert!(
            ((got - want) / want).abs() < 1e-10,
            "mode {i}: {got} against {want}"
        );
    }
    let phi = DMatrix::from_fn(s.n(), 12, |i, j| modes.vectors[(i, j)]);
    let gram = phi.transpose() * dense(s.mass()) * &phi;
    let off = (gram - DMatrix::identity(12, 12)).amax();
    assert!(off < 1e-12, "M-orthonormality off by {off:e}");
    // Each pair satisfies K φ = λ M φ.
    let (k, m) = (dense(s.stiffness()), dense(s.mass()));
    for j in 0..12 {
        let col = phi.column(j);
        let r = (&k * col - &m * col * modes.values[j]).amax() / (&k * col).amax();
        assert!(r < 1e-8, "mode {j}: relative residual {r:e}");
    }
}

#[test]
fn lanczos_finds_every_mode_of_the_full_space() {
    let (s, _) = cantilever();
    let reference = dense_eigenvalues(&s);
    let modes = lanczos_modes(&s, s.n()).unwrap();
    // The high end of the spectrum is resolved relative to the largest eigenvalue of the
    // inverted operator (1/λ_min), i.e. less sharply than the low end.
    for (i, (got, want)) in modes.values.iter().zip(&reference).enumerate() {
        let tol = 1e-10 * (want / reference[0]).max(1.0);
        assert!(
            ((got - want) / want).abs() < tol,
            "mode {i}: {got} against {want}"
        );
    }
}

#[test]
fn a_bad_mode_count_is_refused_by_name() {
    let (s, _) = cantilever();
    for count in [0, s.n() + 1] {
        let err = lanczos_modes(&s, count).unwrap_err();
        assert!(err.to_string().contains("modes"), "{err}");
    }
}

/// Runs `kind` on `s` for `steps` steps of `dt` from rest under f(t) = sin(2π·3t)·pattern;
/// returns the displacement history (free dofs of `s`).
fn history(
    s: &Structure,
    pattern: &[f64],
    kind: IntegratorKind,
    dt: f64,
    steps: usize,
) -> Vec<Vec<f64>> {
    let mut integ = kind.create();
    integ.prepare(s, dt).unwrap();
    let mut load = |t: f64, f: &mut [f64]| {
        let a = (2.0 * std::f64::consts::PI * 3.0 * t).sin();
        f.iter_mut().zip(pattern).for_each(|(f, p)| *f = a * p);
    };
    let zero = vec![0.0; s.n()];
    integ.start(s, 0.0, &zero, &zero, &mut load).unwrap();
    (0..steps)
        .map(|_| {
            integ.step(s, &mut load).unwrap();
            integ.state().u.clone()
        })
        .collect()
}

#[test]
fn the_reduced_run_with_all_modes_is_the_full_run() {
    let (s, f) = cantilever();
    let basis = ModalBasis::new(&s, Reduction::Eigenmodes, s.n(), &f, None).unwrap();
    // The static response lies in the span of all modes: no correction vector is added.
    assert_eq!(basis.dim(), s.n());
    let reduced = basis.reduce(&s).unwrap();
    let mut fr = vec![0.0; basis.dim()];
    basis.project(&f, &mut fr);
    for kind in [IntegratorKind::Houbolt, IntegratorKind::Newmark] {
        let full = history(&s, &f, kind, 2e-3, 300);
        let modal = history(&reduced, &fr, kind, 2e-3, 300);
        let peak = full.iter().flatten().fold(0.0f64, |a, x| a.max(x.abs()));
        let mut u = vec![0.0; s.n()];
        let mut worst = 0.0f64;
        for (uf, q) in full.iter().zip(&modal) {
            basis.expand(q, &mut u);
            worst = uf
                .iter()
                .zip(&u)
                .fold(worst, |a, (x, y)| a.max((x - y).abs()));
        }
        println!(
            "{kind:?}: largest difference {:.2e} of the peak",
            worst / peak
        );
        assert!(
            worst < 1e-9 * peak,
            "{kind:?}: {worst:e} against peak {peak:e}"
        );
    }
}

/// Largest relative error of the reduced static response Φ K_r⁻¹ Φᵀ f against K⁻¹ f.
fn static_error(s: &Structure, basis: &ModalBasis, f: &[f64]) -> f64 {
    let mut exact = f.to_vec();
    let mut chol = s.analyze().unwrap();
    chol.factorize(s.stiffness()).unwrap();
    chol.solve_in_place(&mut exact);
    let reduced = basis.reduce(s).unwrap();
    let mut q = vec![0.0; basis.dim()];
    basis.project(f, &mut q);
    let mut chol_r = reduced.analyze().unwrap();
    chol_r.factorize(reduced.stiffness()).unwrap();
    chol_r.solve_in_place(&mut q);
    let mut u = vec![0.0; s.n()];
    basis.expand(&q, &mut u);
    let peak = exact.iter().fold(0.0f64, |a, x| a.max(x.abs()));
    exact
        .iter()
        .zip(&u)
        .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()))
        / peak
}

#[test]
fn the_static_correction_makes_the_static_response_exact() {
    let (s, f) = cantilever();
    let corrected = ModalBasis::new(&s, Reduction::Eigenmodes, 4, &f, None).unwrap();
    assert_eq!(corrected.dim(), 5);
    let plain = ModalBasis::new(&s, Reduction::Truncated, 4, &f, None).unwrap();
    let ritz = ModalBasis::new(&s, Reduction::Ritz, 5, &f, None).unwrap();
    let (with, without) = (
        static_error(&s, &corrected, &f),
        static_error(&s, &plain, &f),
    );
    let krylov = static_error(&s, &ritz, &f);
    println!(
        "4 modes: static error {without:.2e} without, {with:.2e} with the correction; \
         5 load-dependent Ritz vectors {krylov:.2e}"
    );
    assert!(with < 1e-10 && krylov < 1e-10, "{with:e} {krylov:e}");
    // Four bending modes alone miss the tip load's local (high-mode) response.
    assert!(without > 1e-3, "{without:e}");
}

/// A state carried onto a basis (a reduced model's when its matrices change) comes back
/// through it to round-off, where the basis for the load alone misses it; its displacement
/// adds a Krylov sequence, a zero velocity nothing; the basis stays M-orthonormal.
#[test]
fn a_basis_carries_the_state_it_is_given() {
    let (s, f) = cantilever();
    let n = s.n();
    let state: Vec<f64> = (0..n).map(|i| ((i * 7 % 11) as f64 - 5.0) / 5.0).collect();
    let still = vec![0.0; n];
    let carried = Carried {
        vibrating: [&state, &still],
        others: vec![&f],
    };
    let plain = ModalBasis::new(&s, Reduction::Ritz, 4, &f, None).unwrap();
    let basis = ModalBasis::new(&s, Reduction::Ritz, 4, &f, Some(&carried)).unwrap();
    // The state, its sequence of 4 and the load's pattern (the Krylov basis starts from
    // K⁻¹f, not f): at most 9 more columns.
    assert!((5..=13).contains(&basis.dim()), "{}", basis.dim());
    // A zero vector and its (empty) sequence add nothing: carrying only zeros gives the
    // load's basis.
    let zeros = Carried {
        vibrating: [&still, &still],
        others: vec![],
    };
    let nothing = ModalBasis::new(&s, Reduction::Ritz, 4, &f, Some(&zeros)).unwrap();
    assert_eq!(nothing.dim(), plain.dim());
    let back = |b: &ModalBasis| {
        let mut q = vec![0.0; b.dim()];
        b.coordinates(s.mass(), &state, &mut q);
        let mut u = vec![0.0; n];
        b.expand(&q, &mut u);
        let peak = state.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        state
            .iter()
            .zip(&u)
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()))
            / peak
    };
    let (with, without) = (back(&basis), back(&plain));
    println!(
        "the state through the basis: {with:.1e} carried ({} vectors), {without:.1e} not",
        basis.dim()
    );
    assert!(with < 1e-10 && without > 1e-2, "{with:e} {without:e}");
    let r = basis.dim();
    let phi = DMatrix::from_fn(n, r, |i, j| basis.column(j)[i]);
    let m = phi.transpose() * dense(s.mass()) * &phi;
    assert!((m - DMatrix::identity(r, r)).amax() < 1e-12);
}

#[test]
fn every_basis_is_m_orthonormal_and_diagonalizes_k() {
    let (s, f) = cantilever();
    for reduction in [Reduction::Ritz, Reduction::Eigenmodes, Reduction::Truncated] {
        let basis = ModalBasis::new(&s, reduction, 10, &f, None).unwrap();
        let r = basis.dim();
        let phi = DMatrix::from_fn(s.n(), r, |i, j| basis.column(j)[i]);
        let m = phi.transpose() * dense(s.mass()) * &phi;
        let k = phi.transpose() * dense(s.stiffness()) * &phi;
        let m_off = (m - DMatrix::identity(r, r)).amax();
        let k_off = (k - DMatrix::from_diagonal(&basis.values.clone().into())).amax();
        let scale = basis.values[r - 1];
        println!(
            "{reduction:?}: |ΦᵀMΦ − I| {m_off:.1e}, |ΦᵀKΦ − Λ| {:.1e} of λ_max",
            k_off / scale
        );
        assert!(m_off < 1e-12 && k_off < 1e-12 * scale, "{reduction:?}");
        assert!(basis.values.windows(2).all(|w| w[0] <= w[1]));
    }
}
