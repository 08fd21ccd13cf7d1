//! The quadrature rules of the elements, in one place: on the tetrahedron in barycentric
//! coordinates (λ₀, λ₁, λ₂, λ₃) with weights that sum to 1 (multiply by the volume), on the
//! triangle in area coordinates (L₀, L₁, L₂) with weights that sum to 1 (multiply by the
//! area), and Gauss's on the line ξ ∈ [−1, 1] with weights that sum to 2.
//!
//! - [`TET_1`]: the centroid, exact for degree 1 (the linear tetrahedron's constant gradient);
//! - [`TET_4`]: four points (a, a, a, 1 − 3a) with a = (5 − √5)/20, exact for degree 2 (the
//!   quadratic tetrahedron's linear-elastic stiffness on straight edges);
//! - [`TET_14`]: the symmetric 14-point rule with positive weights, exact for degree 5
//!   (Walkington's rule; the parameters below were solved from the moment equations and are
//!   checked against every monomial up to degree 5 by the tests). The quadratic tetrahedron
//!   uses it for finite strain, where the integrand is not a polynomial: the shipped data
//!   sets were generated with a rule of order 4;
//! - [`TRI_3`], [`TRI_6`]: three and six points on the triangle, exact for degrees 2 and 4;
//! - [`GAUSS_1`], [`GAUSS_3`]: one and three Gauss points on the line, exact for degrees 1
//!   and 5.

/// A point of a rule on the tetrahedron: barycentric coordinates and weight (fraction of
/// the volume).
pub type TetPoint = ([f64; 4], f64);

/// The one-point rule at the centroid, exact for degree 1.
pub const TET_1: [TetPoint; 1] = [([0.25; 4], 1.0)];

const A4: f64 = 0.138_196_601_125_010_5;
const B4: f64 = 1.0 - 3.0 * A4;
/// The four-point rule (a, a, a, 1 − 3a), a = (5 − √5)/20, exact for degree 2.
pub const TET_4: [TetPoint; 4] = [
    ([B4, A4, A4, A4], 0.25),
    ([A4, B4, A4, A4], 0.25),
    ([A4, A4, B4, A4], 0.25),
    ([A4, A4, A4, B4], 0.25),
];

const A: f64 = 0.310_885_919_263_300_6;
const B: f64 = 1.0 - 3.0 * A;
const WA: f64 = 0.112_687_925_718_015_3;
const C: f64 = 0.092_735_250_310_891_0;
const D: f64 = 1.0 - 3.0 * C;
const WC: f64 = 0.073_493_043_116_361_6;
const E: f64 = 0.045_503_704_125_649_7;
const F: f64 = 0.5 - E;
const WE: f64 = 0.042_546_020_777_081_8;
/// Walkington's symmetric 14-point rule with positive weights, exact for degree 5.
pub const TET_14: [TetPoint; 14] = [
    ([B, A, A, A], WA),
    ([A, B, A, A], WA),
    ([A, A, B, A], WA),
    ([A, A, A, B], WA),
    ([D, C, C, C], WC),
    ([C, D, C, C], WC),
    ([C, C, D, C], WC),
    ([C, C, C, D], WC),
    ([E, E, F, F], WE),
    ([E, F, E, F], WE),
    ([E, F, F, E], WE),
    ([F, E, E, F], WE),
    ([F, E, F, E], WE),
    ([F, F, E, E], WE),
];

/// A quadrature point: area coordinates and a weight (the weights sum to 1; multiply by the
/// area).
pub type TriPoint = ([f64; 3], f64);

/// The 3-point rule at the edge midpoints' interior images (Strang & Fix), exact for degree 2.
pub const TRI_3: [TriPoint; 3] = [
    ([2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0], 1.0 / 3.0),
    ([1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0], 1.0 / 3.0),
    ([1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0], 1.0 / 3.0),
];

/// The 6-point rule of Dunavant (1985), exact for degree 4 (the consistent mass NᵀN).
pub const TRI_6: [TriPoint; 6] = {
    const A: f64 = 0.445_948_490_915_965;
    const WA: f64 = 0.223_381_589_678_011;
    const B: f64 = 0.091_576_213_509_771;
    const WB: f64 = 0.109_951_743_655_322;
    [
        ([1.0 - 2.0 * A, A, A], WA),
        ([A, 1.0 - 2.0 * A, A], WA),
        ([A, A, 1.0 - 2.0 * A], WA),
        ([1.0 - 2.0 * B, B, B], WB),
        ([B, 1.0 - 2.0 * B, B], WB),
        ([B, B, 1.0 - 2.0 * B], WB),
    ]
};

/// A quadrature rule on ξ ∈ [−1, 1]: points and weights (summing to 2).
pub type Rule<const Q: usize> = [(f64, f64); Q];

/// The one-point Gauss rule (exact for the 2-node line, whose stretch is constant).
pub const GAUSS_1: Rule<1> = [(0.0, 2.0)];

/// The three-point Gauss rule, exact for degree 5 (the 3-node line's small-strain
/// stiffness has degree 2; at finite strain the integrand is not a polynomial).
pub const GAUSS_3: Rule<3> = {
    const X: f64 = 0.774_596_669_241_483_4; // √(3/5)
    [(-X, 5.0 / 9.0), (0.0, 8.0 / 9.0), (X, 5.0 / 9.0)]
};

#[cfg(test)]
mod tests {
    use super::*;

    fn factorial(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    /// ∫ λ^α over the tetrahedron / volume = 3! Π αᵢ! / (|α| + 3)!.
    fn exact(alpha: [u32; 4]) -> f64 {
        let n: u32 = alpha.iter().sum();
        6.0 * alpha.iter().map(|&a| factorial(a)).product::<f64>() / factorial(n + 3)
    }

    fn check(rule: &[TetPoint], degree: u32) {
        let mut worst: f64 = 0.0;
        for a in 0..=degree {
            for b in 0..=degree - a {
                for c in 0..=degree - a - b {
                    for d in 0..=degree - a - b - c {
                        let alpha = [a, b, c, d];
                        let q: f64 = rule
                            .iter()
                            .map(|(l, w)| {
                                w * l
                                    .iter()
                                    .zip(alpha)
                                    .map(|(x, k)| x.powi(k as i32))
                                    .product::<f64>()
                            })
                            .sum();
                        worst = worst.max((q - exact(alpha)).abs() / exact(alpha));
                    }
                }
            }
        }
        assert!(worst < 1e-14, "degree {degree}: relative error {worst:e}");
    }

    #[test]
    fn rules_integrate_every_monomial_of_their_degree_exactly() {
        check(&TET_1, 1);
        check(&TET_4, 2);
        check(&TET_14, 5);
        for rule in [&TET_1[..], &TET_4[..], &TET_14[..]] {
            for (l, w) in rule {
                assert!(*w > 0.0 && (l.iter().sum::<f64>() - 1.0).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn the_fourteen_point_rule_is_not_exact_for_degree_six() {
        // A check that can fail: degree 6 is beyond the rule.
        let q: f64 = TET_14.iter().map(|(l, w)| w * l[0].powi(6)).sum();
        assert!((q - exact([6, 0, 0, 0])).abs() > 1e-6 * exact([6, 0, 0, 0]));
    }
}
