//! Richardson extrapolation of an output computed on three meshes (Richardson 1911; Roache,
//! J. Fluids Eng. 116 (1994) 405, the grid convergence index). With f₁, f₂, f₃ from coarse
//! to fine on meshes of sizes h₁ > h₂ > h₃, the observed order p is the one at which
//! f_h = f* + C hᵖ passes through the three: (h₁ᵖ − h₂ᵖ)/(h₂ᵖ − h₃ᵖ) = (f₁ − f₂)/(f₂ − f₃),
//! for a constant ratio r of the sizes p = ln((f₁ − f₂)/(f₂ − f₃)) / ln r
//! ([`extrapolate`]), for unequal ratios found by bisection ([`observed_order`]). The
//! extrapolated value is f* = f₃ + (f₃ − f₂) h₃ᵖ/(h₂ᵖ − h₃ᵖ) ([`limit`]), for a constant
//! ratio f₃ + (f₃ − f₂)/(rᵖ − 1), and the estimated error of the finest value |f* − f₃|.
//! It assumes the three are in the asymptotic range: convergence that changes direction or
//! whose changes grow has no (positive) order and is refused.

use crate::error::ModelError;

/// The result of [`extrapolate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RichardsonEstimate {
    /// Observed order of convergence p.
    pub order: f64,
    /// Extrapolated value f*.
    pub value: f64,
    /// Estimated error of the finest value, |f* − f₃|.
    pub error: f64,
}

/// Extrapolates `values` (coarse, medium, fine) computed with mesh sizes in the ratio `ratio`
/// (> 1) between consecutive meshes.
pub fn extrapolate(values: [f64; 3], ratio: f64) -> Result<RichardsonEstimate, ModelError> {
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
    Ok(RichardsonEstimate {
        order,
        value: f3 + correction,
        error: correction.abs(),
    })
}

/// The orders [`observed_order`] searches.
const ORDERS: (f64, f64) = (0.05, 12.0);

/// The observed order p of f(h) = f* + C hᵖ on meshes of sizes `h` (coarse to fine) whose
/// successive differences of the output are `d12` and `d23` (of one sign; or norms of the
/// differences of a field), found by bisection in [0.05, 12]: an error where the differences
/// do not shrink at an order in that range.
pub fn observed_order(h: [f64; 3], d12: f64, d23: f64) -> Result<f64, ModelError> {
    let ratio = d12 / d23;
    let model = |p: f64| (h[0].powf(p) - h[1].powf(p)) / (h[1].powf(p) - h[2].powf(p));
    let (mut lo, mut hi) = ORDERS;
    if !(ratio > model(lo) && ratio < model(hi)) {
        return Err(ModelError::InvalidParameter {
            name: "ratio of the successive differences on three meshes".into(),
            value: ratio,
            reason: "they do not converge monotonically at an order in [0.05, 12]",
        });
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if model(mid) < ratio {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Ok(0.5 * (lo + hi))
}

/// f* of f(h) = f* + C hᵖ through the two finest of the values `f` on meshes of sizes `h`
/// (coarse to fine), at the order `order`.
pub fn limit(h: [f64; 3], f: [f64; 3], order: f64) -> f64 {
    f[2] - (f[1] - f[2]) * h[2].powf(order) / (h[1].powf(order) - h[2].powf(order))
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

    /// At unequal ratios of the sizes the bisection finds the order of a power law and the
    /// limit through the finest two is its limit; a sequence that does not shrink is
    /// refused.
    #[test]
    fn unequal_ratios_give_back_the_order_and_limit_of_a_power_law() {
        let h = [1.0, 0.6, 0.45];
        for order in [1.0, 2.16, 3.5] {
            let f = h.map(|h: f64| 6.4375 + 0.3 * h.powf(order));
            let p = observed_order(h, f[0] - f[1], f[1] - f[2]).unwrap();
            assert!((p - order).abs() < 1e-9, "{p} {order}");
            assert!((limit(h, f, p) - 6.4375).abs() < 1e-9);
        }
        assert!(observed_order(h, 1.0, 1.0).is_err());
        assert!(observed_order(h, 1.0, -0.5).is_err());
    }
}
