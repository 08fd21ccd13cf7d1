//! Largest eigenvalue of the generalized problem K φ = ω² M_L φ with a lumped (diagonal)
//! mass, for the stability limits of the explicit schemes. Lanczos iteration with full
//! re-orthogonalization on the symmetric operator M_L^{−½} K M_L^{−½}; the largest Ritz value
//! of the tridiagonal matrix (nalgebra's symmetric eigensolver) converges from below.

use nalgebra::{DMatrix, SymmetricEigen};

use super::structure::Structure;
use crate::assembly::mul_add;
use crate::linalg::product::dot;

/// Lanczos steps (fewer if the Krylov space is exhausted first).
const STEPS: usize = 120;

/// ω²_max of K φ = ω² M_L φ on the structure's free dofs.
pub fn max_omega_squared(s: &Structure) -> f64 {
    let n = s.n();
    let scale: Vec<f64> = s.lumped_mass().iter().map(|m| 1.0 / m.sqrt()).collect();
    let apply = |x: &[f64], y: &mut [f64]| {
        let xs: Vec<f64> = x.iter().zip(&scale).map(|(a, b)| a * b).collect();
        y.fill(0.0);
        mul_add(s.stiffness(), &xs, 1.0, y);
        y.iter_mut().zip(&scale).for_each(|(a, b)| *a *= b);
    };
    let steps = STEPS.min(n);
    let mut basis: Vec<Vec<f64>> = Vec::with_capacity(steps);
    // Deterministic start vector with components in every direction.
    let mut q: Vec<f64> = (0..n)
        .map(|i| 1.0 + ((i * 7919) % 104_729) as f64 / 104_729.0)
        .collect();
    normalize(&mut q);
    let (mut alpha, mut beta) = (Vec::new(), Vec::new());
    let mut w = vec![0.0; n];
    for _ in 0..steps {
        apply(&q, &mut w);
        alpha.push(dot(&q, &w));
        basis.push(q.clone());
        for _ in 0..2 {
            for b in &basis {
                let c = dot(b, &w);
                w.iter_mut().zip(b).for_each(|(x, y)| *x -= c * y);
            }
        }
        let norm = dot(&w, &w).sqrt();
        if norm <= 1e-12 * alpha.last().unwrap().abs() || basis.len() == steps {
            break;
        }
        beta.push(norm);
        q.iter_mut().zip(&w).for_each(|(x, y)| *x = y / norm);
    }
    let k = alpha.len();
    let t = DMatrix::from_fn(k, k, |i, j| match i.abs_diff(j) {
        0 => alpha[i],
        1 => beta[i.min(j)],
        _ => 0.0,
    });
    SymmetricEigen::new(t).eigenvalues.max()
}

fn normalize(x: &mut [f64]) {
    let n = dot(x, x).sqrt();
    x.iter_mut().for_each(|v| *v /= n);
}
