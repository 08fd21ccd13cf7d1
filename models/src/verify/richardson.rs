//! Richardson extrapolation of an output computed on three meshes refined by a constant
//! ratio r (Richardson 1911; Roache, J. Fluids Eng. 116 (1994) 405, the grid convergence
//! index): with f₁, f₂, f₃ from coarse to fine, the observed order is
//! p = ln((f₁ − f₂)/(f₂ − f₃)) / ln r, the extrapolated value f* = f₃ + (f₃ − f₂)/(rᵖ − 1),
//! and the estimated error of the finest value |f* − f₃|. It assumes the three are in the
//! asymptotic range (f_h = f* + C hᵖ): convergence that changes direction or whose changes
//! grow has no (positive) order and is refused.

use crate::error::ModelError;

/// The result of [`extrapolate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extrapolation {
    /// Observed order of convergence p.
    pub order: f64,
    /// Extrapolated value f*.
    pub value: f64,
    /// Estimated error of the finest value, |f* − f₃|.
    pub error: f64,
}

/// Extrapolates `values` (coarse, medium, fine) computed with mesh sizes in the ratio `ratio`
/// (> 1) between consecutive meshes.
pub fn extrapolate(values: [f64; 3], ratio: f64) -> Result<Extrapolation, ModelError> {
    if !(ratio > 1.0 && ratio.is_finite()) {
        return Err(ModelError::InvalidParameter {
            name: "refinement ratio".into(),
            value: ratio,
            reason: "Richardson extrapolation needs a ratio of mesh sizes above 1",
        });
    }
    let [f1, f2, f3] = values;
    let (d12, d23) = (f1 - f2, f2 - f3);
    let same_direction = d12 * d23;
    if same_direction.is_nan() || same_direction <= 0.0 {
        return Err(ModelError::InvalidParameter {
            name: "values on three meshes".into(),
            value: f3,
            reason: "the changes between meshes differ in sign or vanish: no order of \
                     convergence (not in the asymptotic range)",
        });
    }
    if d23.abs() >= d12.abs() {
        return Err(ModelError::InvalidParameter {
            name: "values on three meshes".into(),
            value: f3,
            reason: "the change between the finer meshes is not smaller than the one before: \
                     no positive order of convergence (not in the asymptotic range)",
        });
    }
    let order = (d12 / d23).ln() / ratio.ln();
    let correction = -d23 / (ratio.powf(order) - 1.0);
    Ok(Extrapolation {
        order,
        value: f3 + correction,
        error: correction.abs(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_power_law_sequence_gives_back_its_order_and_limit() {
        for (order, ratio) in [(2.0, 2.0), (3.0, 2.0), (1.3, 1.5)] {
            let f = |h: f64| 7.25 - 0.4 * h.powf(order);
            let hs = [1.0, 1.0 / ratio, 1.0 / (ratio * ratio)];
            let e = extrapolate(hs.map(f), ratio).unwrap();
            assert!((e.order - order).abs() < 1e-10, "{e:?}");
            assert!((e.value - 7.25).abs() < 1e-12, "{e:?}");
            assert!((e.error - (7.25 - f(hs[2])).abs()).abs() < 1e-12, "{e:?}");
        }
    }

    #[test]
    fn oscillating_stalled_or_growing_sequences_and_bad_ratios_are_refused() {
        for (values, ratio) in [
            ([1.0, 2.0, 1.5], 2.0),
            ([1.0, 1.0, 1.0], 2.0),
            ([1.0, 1.1, 1.3], 2.0),
            ([1.0, 2.0, 2.5], 1.0),
            ([1.0, 2.0, 2.5], f64::NAN),
        ] {
            assert!(extrapolate(values, ratio).is_err(), "{values:?} {ratio}");
        }
    }
}
