//! An error indicator for an approximate state of the full equation of motion — a reduced
//! model's state expanded, or a state Newton's method stopped short of (issue 29, item 2).
//!
//! The residual of the full equations at a state (u, u̇, ü) at time t,
//!
//! r = f(t) − M ü − C u̇ − f_int(u),
//!
//! is measured by the displacement a static correction with the stiffness at rest K₀ would
//! add, e = K₀⁻¹ r, relative to the displacement, both in the energy norm of K₀:
//!
//! η = ‖e‖_K₀ / ‖u‖_K₀ = √(rᵀ K₀⁻¹ r) / √(uᵀ K₀ u).
//!
//! For a linear static problem (K₀ u* = f, v = a = 0) e = u* − u is the error itself, so η
//! is the relative energy-norm error exactly; for dynamics and finite strain it is the
//! static, linearized measure of the same residual (the a-posteriori indicator of
//! reduced-order models: the residual of the full equations at the expanded state, as in
//! Farhat, Avery, Chapman & Cortial, IJNME 98 (2014) §6, made dimensionless by K₀).

use super::structure::Structure;
use crate::error::ModelError;
use crate::linalg::cholesky::Cholesky;
use crate::linalg::product::dot;

/// K₀ of a structure factorized, and the work vectors of [`Indicator::estimate`].
#[derive(Debug)]
pub struct Indicator {
    stiffness: Cholesky,
    residual: Vec<f64>,
    correction: Vec<f64>,
    work: [Vec<f64>; 2],
}

/// A state of the full structure on its free dofs: displacement, velocity, acceleration.
#[derive(Debug, Clone, Copy)]
pub struct Motion<'a> {
    /// Displacement (mm).
    pub u: &'a [f64],
    /// Velocity (mm/s).
    pub v: &'a [f64],
    /// Acceleration (mm/s²).
    pub a: &'a [f64],
}

impl Indicator {
    /// Factorizes the stiffness at rest of `s` (for a finite-strain structure its tangent
    /// at rest, which [`Structure::stiffness`] holds).
    pub fn new(s: &Structure) -> Result<Self, ModelError> {
        let mut stiffness = s.analyze()?;
        stiffness.factorize(s.stiffness())?;
        Ok(Self {
            stiffness,
            residual: vec![0.0; s.n()],
            correction: vec![0.0; s.n()],
            work: s.residual_work(),
        })
    }

    /// η of the state `x` of `s` under the load `f` (free dofs, at the state's time); 0 for
    /// the state at rest with no residual. Allocates nothing.
    pub fn estimate(&mut self, s: &Structure, f: &[f64], x: Motion<'_>) -> Result<f64, ModelError> {
        let n = s.n();
        let lengths = [
            ("f", f.len()),
            ("u", x.u.len()),
            ("v", x.v.len()),
            ("a", x.a.len()),
        ];
        for (name, len) in lengths {
            if len != n {
                return Err(ModelError::SizeMismatch {
                    name,
                    expected: n,
                    got: len,
                });
            }
        }
        s.equation_residual(f, [x.u, x.v, x.a], &mut self.residual, &mut self.work)?;
        self.correction.copy_from_slice(&self.residual);
        self.stiffness.solve_in_place(&mut self.correction);
        let error = dot(&self.residual, &self.correction).max(0.0);
        let size = s.stiffness_norm_squared(x.u, &mut self.residual);
        Ok(if error == 0.0 {
            0.0
        } else {
            (error / size).sqrt()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::Mat;

    /// A symmetric positive definite 5 × 5 stiffness, a mass and a damping matrix.
    fn matrices() -> [Mat<f64>; 3] {
        let k = Mat::from_fn(5, 5, |i, j| match i.abs_diff(j) {
            0 => 4.0 + i as f64,
            1 => -1.0,
            2 => 0.25,
            _ => 0.0,
        });
        let m = Mat::from_fn(5, 5, |i, j| if i == j { 2.0 } else { 0.1 });
        let c = Mat::from_fn(5, 5, |i, j| if i == j { 0.3 } else { 0.0 });
        [k, m, c]
    }

    fn structure() -> Structure {
        let [k, m, c] = matrices();
        Structure::dense(k.as_ref(), m.as_ref(), c.as_ref()).unwrap()
    }

    /// Σ A_i x_i with the dense matrices, independently of the structure's products.
    fn apply(terms: [(&Mat<f64>, &[f64]); 3]) -> Vec<f64> {
        (0..5)
            .map(|i| {
                terms
                    .iter()
                    .map(|(a, x)| (0..5).map(|j| a[(i, j)] * x[j]).sum::<f64>())
                    .sum()
            })
            .collect()
    }

    /// √(xᵀ K x) with the dense K.
    fn norm_k(k: &Mat<f64>, x: &[f64]) -> f64 {
        let zero = Mat::zeros(5, 5);
        let kx = apply([(k, x), (&zero, x), (&zero, x)]);
        kx.iter().zip(x).map(|(a, b)| a * b).sum::<f64>().sqrt()
    }

    #[test]
    fn a_linear_static_state_gets_its_relative_energy_error() {
        let s = structure();
        let [k, m, c] = matrices();
        let exact = [1.0, -2.0, 0.5, 3.0, -1.0];
        let zero = [0.0; 5];
        let f = apply([(&k, &exact), (&m, &zero), (&c, &zero)]); // f = K u*
        let error = [0.1, 0.0, -0.3, 0.05, 0.2];
        let u: Vec<f64> = exact.iter().zip(&error).map(|(x, e)| x + e).collect();
        let motion = Motion {
            u: &u,
            v: &zero,
            a: &zero,
        };
        let eta = Indicator::new(&s)
            .unwrap()
            .estimate(&s, &f, motion)
            .unwrap();
        let expected = norm_k(&k, &error) / norm_k(&k, &u);
        assert!(
            (eta - expected).abs() <= 1e-12 * expected,
            "{eta} vs {expected}"
        );
    }

    #[test]
    fn a_state_that_satisfies_the_equation_of_motion_gets_zero() {
        let s = structure();
        let (u, v, a) = (
            [0.3, 0.1, -0.2, 0.4, 0.0],
            [1.0, 2.0, 0.0, -1.0, 0.5],
            [3.0; 5],
        );
        let [k, m, c] = matrices();
        let f = apply([(&k, &u), (&m, &a), (&c, &v)]); // f = K u + M a + C v
        let motion = Motion {
            u: &u,
            v: &v,
            a: &a,
        };
        let mut indicator = Indicator::new(&s).unwrap();
        let eta = indicator.estimate(&s, &f, motion).unwrap();
        assert!(eta <= 1e-14, "{eta}");
        // Leaving out the inertia is an error the indicator sees.
        let still = Motion {
            a: &[0.0; 5],
            ..motion
        };
        assert!(indicator.estimate(&s, &f, still).unwrap() > 0.1);
    }

    #[test]
    fn vectors_of_the_wrong_length_are_refused_by_name() {
        let s = structure();
        let zero = [0.0; 5];
        let short = Motion {
            u: &zero,
            v: &zero[..4],
            a: &zero,
        };
        let err = Indicator::new(&s)
            .unwrap()
            .estimate(&s, &zero, short)
            .unwrap_err();
        assert_eq!(err.to_string(), "size mismatch for `v`: expected 5, got 4");
        let rest = Motion {
            u: &zero,
            v: &zero,
            a: &zero,
        };
        assert_eq!(
            Indicator::new(&s)
                .unwrap()
                .estimate(&s, &zero, rest)
                .unwrap(),
            0.0
        );
    }
}
