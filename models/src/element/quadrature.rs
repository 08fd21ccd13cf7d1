//! Quadrature rules on the tetrahedron, in barycentric coordinates (λ₀, λ₁, λ₂, λ₃) with
//! weights that sum to 1 (multiply by the volume).
//!
//! - [`TET_1`]: the centroid, exact for degree 1 (the linear tetrahedron's constant gradient);
//! - [`TET_4`]: four points (a, a, a, 1 − 3a) with a = (5 − √5)/20, exact for degree 2 (the
//!   quadratic tetrahedron's linear-elastic stiffness on straight edges);
//! - [`TET_14`]: the symmetric 14-point rule with positive weights, exact for degree 5
//!   (Walkington's rule; the parameters below were solved from the moment equations and are
//!   checked against every monomial up to degree 5 by the tests). The quadratic tetrahedron
//!   uses it for finite strain, where the integrand is not a polynomial: the shipped data
//!   sets were generated with a rule of order 4.

/// A quadrature point: barycentric coordinates and weight (fraction of the volume).
pub type Point = ([f64; 4], f64);

pub const TET_1: [Point; 1] = [([0.25; 4], 1.0)];

const A4: f64 = 0.138_196_601_125_010_5;
const B4: f64 = 1.0 - 3.0 * A4;
pub const TET_4: [Point; 4] = [
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
pub const TET_14: [Point; 14] = [
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

    fn check(rule: &[Point], degree: u32) {
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
