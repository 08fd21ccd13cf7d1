//! The stresses of the 6-node plane-strain triangle at a point: the small-strain stress
//! operator of either formulation (σ = S u, σ_zz included) and the finite-strain Cauchy
//! stress, for the outputs and the fields the scenes recover.

use nalgebra::{Matrix3, SMatrix, Vector3};

use super::mixed::{dilatation, mean_volume_ratio, mixed_points, split, Formulation};
use super::total_lagrangian::{deformation_at, Inverted};
use super::tri6::{b_matrix, Dofs, Tri6};
use super::{Elastic, Material};

/// The Cauchy stress σ = J⁻¹ P Fᵀ at area coordinates `l` for a finite-strain `material` in
/// `formulation` (for the linear law σ = P, the small-strain stress): the mixed formulation
/// takes F̄ = (θ̄/J)^{1/3} F with the element's mean volume ratio θ̄ ([`internal_mixed`]),
/// so σ = P(F̄) F̄ᵀ / θ̄. An inverted point is an error.
pub fn cauchy(
    formulation: Formulation,
    p: &[[f64; 2]; 6],
    l: [f64; 3],
    u: &Dofs,
    material: &Material,
) -> Result<Matrix3<f64>, Inverted> {
    let mut f = deformation_at::<Tri6, 6, 2, 12>(p, u, &l);
    if formulation == Formulation::Mixed {
        let theta = mean_volume_ratio(&mixed_points(p, u)?).1;
        f *= (theta / f.determinant()).cbrt();
    }
    let stress = material.stress(&f);
    if !material.law.finite() {
        return Ok(stress);
    }
    let j = Inverted::check(f.determinant())?;
    Ok(stress * f.transpose() / j)
}

/// The stress operator S at area coordinates `l`: (σ_xx, σ_yy, σ_xy, σ_zz) = S u for the
/// element displacements u. Displacement formulation: D B, and σ_zz = λ (ε_xx + ε_yy) for
/// ε_zz = 0. Mixed: D_dev B plus the element's pressure p = κ θ̄ = κ g·u / A on the normal
/// stresses, and σ_zz = −(2μ/3)(ε_xx + ε_yy) + p (the deviatoric part of the 3D law at
/// ε_zz = 0, plus p).
pub fn stress_operator(
    formulation: Formulation,
    p: &[[f64; 2]; 6],
    l: [f64; 3],
    elastic: &Elastic,
) -> SMatrix<f64, 4, 12> {
    let b = b_matrix(p, l).0;
    let volumetric = b.row(0) + b.row(1);
    let mut s = SMatrix::<f64, 4, 12>::zeros();
    match formulation {
        Formulation::Displacement => {
            s.fixed_rows_mut::<3>(0)
                .copy_from(&(elastic.plane_strain() * b));
            s.set_row(3, &(volumetric * elastic.lambda()));
        }
        Formulation::Mixed => {
            let (dev, kappa) = split(elastic);
            let (g, a) = dilatation(p);
            let pressure = g.transpose() * (kappa / a);
            s.fixed_rows_mut::<3>(0).copy_from(&(dev * b));
            for r in 0..2 {
                let row = s.row(r) + pressure;
                s.set_row(r, &row);
            }
            s.set_row(3, &(volumetric * (-2.0 * elastic.shear() / 3.0) + pressure));
        }
    }
    s
}

/// Stress (σ_xx, σ_yy, σ_xy) at area coordinates `l` for the element displacements `u`
/// (the first rows of [`stress_operator`]).
pub fn stress(
    formulation: Formulation,
    p: &[[f64; 2]; 6],
    l: [f64; 3],
    u: &Dofs,
    elastic: &Elastic,
) -> Vector3<f64> {
    (stress_operator(formulation, p, l, elastic) * u)
        .fixed_rows::<3>(0)
        .into()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::tri6::straight;

    fn element() -> [[f64; 2]; 6] {
        straight(&[[0.3, 0.1], [2.1, 0.4], [0.9, 1.7]])
    }

    /// On a constant strain both formulations give Hooke's 3D law at ε_zz = 0, σ_zz included
    /// (σ_zz = ν (σ_xx + σ_yy)); the neo-Hookean Cauchy stress approaches it as the strain
    /// shrinks (the difference is second order).
    #[test]
    fn stress_operators_give_the_plane_strain_law_on_a_constant_strain() {
        use crate::element::material::Law;
        let p = element();
        let elastic = Elastic::new("m", 7.0, 0.45).unwrap();
        let (exx, eyy, gxy) = (0.01, -0.004, 0.006);
        let motion = |scale: f64| {
            Dofs::from_fn(|k, _| {
                let [x, y] = p[k / 2];
                scale
                    * if k.is_multiple_of(2) {
                        exx * x + gxy * y
                    } else {
                        eyy * y
                    }
            })
        };
        let (l, m) = (elastic.lambda(), elastic.shear());
        let hooke = [
            l * (exx + eyy) + 2.0 * m * exx,
            l * (exx + eyy) + 2.0 * m * eyy,
            m * gxy,
            l * (exx + eyy),
        ];
        let u = motion(1.0);
        for formulation in [Formulation::Displacement, Formulation::Mixed] {
            let s = stress_operator(formulation, &p, [0.2, 0.3, 0.5], &elastic) * u;
            for (a, b) in s.iter().zip(hooke) {
                assert!((a - b).abs() < 1e-12, "{formulation:?}: {a} vs {b}");
            }
            assert!((s[3] - 0.45 * (s[0] + s[1])).abs() < 1e-12);
        }
        let neo = Material::new(Law::NeoHookean, elastic);
        let gap = |scale: f64| {
            let c = cauchy(
                Formulation::Displacement,
                &p,
                [0.2, 0.3, 0.5],
                &motion(scale),
                &neo,
            )
            .unwrap();
            let linear = [hooke[0], hooke[1], hooke[2], hooke[3]].map(|x| x * scale);
            let got = [c[(0, 0)], c[(1, 1)], c[(0, 1)], c[(2, 2)]];
            got.iter()
                .zip(linear)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max)
                / scale
        };
        let (coarse, fine) = (gap(1e-2), gap(1e-3));
        assert!(
            coarse < 2e-3 && (fine / coarse - 0.1).abs() < 0.02,
            "{coarse} {fine}"
        );
    }
}
