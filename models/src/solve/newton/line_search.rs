//! The line search of Newton's method: along the correction d from x, the step x − α d is
//! the minimizer of the system's energy along the line when its slope there vanishes,
//! η(α) = d·r(x − α d) / d·r(x) = 0 (η(0) = 1 for any positive definite matrix d came
//! from). Every system the crate solves is the gradient of an energy (hyperelastic elements,
//! membranes with their active tension, penalty springs, an implicit step's inertia), so the
//! slope is the energy's derivative along the line (Crisfield, Non-linear Finite Element
//! Analysis of Solids and Structures, vol. 1, §9.3).

use super::System;
use crate::error::ModelError;

/// Times a step is shortened (by the secant, or halved where an element inverts).
const BACKTRACKS: usize = 10;

/// A step is taken when |η| ≤ this: the energy's slope has fallen to a fifth.
const SLOPE: f64 = 0.8;

/// An overshoot is never shortened by more than this factor at once.
const SHORTEST: f64 = 0.1;

/// Steps from `x` along the correction `d` (whose residual r(x) is in `r`; `fresh`: d comes
/// from a factorization made at x). α = 1 is taken when |η| ≤ 0.8, or when the energy still
/// falls there after a fresh factorization; an overshoot (η < −0.8) shortens the step by the
/// secant α / (1 − η), an inverted element halves it, up to [`BACKTRACKS`] times. The trial
/// (in `trial`, its residual in `r`) is returned as (α, ‖r‖, scale); None — with `r` the
/// residual at x again — when d is no descent direction, when a kept factorization's full
/// step is too short (η > 0.8: refactorize), or when no step was found.
pub fn line_search<S: System>(
    system: &mut S,
    x: &[f64],
    d: &[f64],
    r: &mut [f64],
    trial: &mut [f64],
    fresh: bool,
) -> Result<Option<(f64, f64, f64)>, ModelError> {
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
    let slope = dot(d, r);
    // A direction along which the energy does not fall (or a NaN slope): no step.
    if slope.is_nan() || slope <= 0.0 {
        return Ok(None);
    }
    let mut alpha = 1.0;
    for _ in 0..=BACKTRACKS {
        for ((t, u), d) in trial.iter_mut().zip(x).zip(d) {
            *t = u - alpha * d;
        }
        let (norm, scale) = match system.residual(trial, r) {
            Ok(found) => found,
            Err(ModelError::Inverted { .. }) => {
                alpha *= 0.5;
                continue;
            }
            Err(e) => return Err(e),
        };
        let eta = dot(d, r) / slope;
        if eta.abs() <= SLOPE || (eta > 0.0 && (fresh || alpha < 1.0)) {
            return Ok(Some((alpha, norm, scale)));
        }
        if eta > 0.0 {
            break;
        }
        alpha *= (1.0 / (1.0 - eta)).max(SHORTEST);
    }
    system.residual(x, r)?;
    Ok(None)
}
