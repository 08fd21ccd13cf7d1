//! Linear isotropic elasticity (seed 003 App. A.3, eq. C.15 and C.29).

use nalgebra::{Matrix3, Matrix6};

use crate::error::{positive, ModelError};

/// An isotropic linear-elastic material: Young's modulus `E` (MPa = N/mm²) and Poisson's
/// ratio `ν`. Construction validates `E > 0` and `−1 < ν < 0.5`, both finite.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    young: f64,
    poisson: f64,
}

impl Elastic {
    /// Validated constructor; `name` prefixes the variable names in the error message
    /// (e.g. `"cavity"` gives `cavity.E`).
    pub fn new(name: &str, young: f64, poisson: f64) -> Result<Self, ModelError> {
        positive(&format!("{name}.E"), young)?;
        if !(poisson.is_finite() && poisson > -1.0 && poisson < 0.5) {
            return Err(ModelError::InvalidParameter {
                name: format!("{name}.nu"),
                value: poisson,
                reason: "Poisson's ratio must be finite and in (-1, 0.5)",
            });
        }
        Ok(Self { young, poisson })
    }

    /// Young's modulus E in MPa.
    pub fn young(&self) -> f64 {
        self.young
    }

    /// Poisson's ratio ν.
    pub fn poisson(&self) -> f64 {
        self.poisson
    }

    /// Lamé's first parameter λ = Eν / ((1+ν)(1−2ν)).
    pub fn lambda(&self) -> f64 {
        let (e, nu) = (self.young, self.poisson);
        e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    }

    /// Shear modulus μ = E / (2(1+ν)).
    pub fn shear(&self) -> f64 {
        self.young / (2.0 * (1.0 + self.poisson))
    }

    /// Plane-strain constitutive matrix for (ε_xx, ε_yy, γ_xy) (seed 003 eq. C.15).
    pub fn plane_strain(&self) -> Matrix3<f64> {
        let (l, m) = (self.lambda(), self.shear());
        Matrix3::new(l + 2.0 * m, l, 0.0, l, l + 2.0 * m, 0.0, 0.0, 0.0, m)
    }

    /// 3D constitutive matrix for (ε_xx, ε_yy, ε_zz, γ_xy, γ_yz, γ_zx) (seed 003 eq. C.29).
    pub fn solid(&self) -> Matrix6<f64> {
        let (l, m) = (self.lambda(), self.shear());
        let mut d = Matrix6::zeros();
        for i in 0..3 {
            for j in 0..3 {
                d[(i, j)] = l;
            }
            d[(i, i)] = l + 2.0 * m;
            d[(i + 3, i + 3)] = m;
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_values_and_names_them() {
        for (e, nu, var) in [
            (0.0, 0.3, "wall.E"),
            (-1.0, 0.3, "wall.E"),
            (f64::NAN, 0.3, "wall.E"),
            (1.0, 0.5, "wall.nu"),
            (1.0, -1.0, "wall.nu"),
            (1.0, f64::INFINITY, "wall.nu"),
        ] {
            let err = Elastic::new("wall", e, nu).unwrap_err().to_string();
            assert!(err.contains(var), "{err}");
        }
        assert!(Elastic::new("wall", 1.0, 0.499).is_ok());
    }

    #[test]
    fn plane_strain_matches_textbook_form() {
        // D = E/((1+ν)(1−2ν)) [[1−ν, ν, 0], [ν, 1−ν, 0], [0, 0, (1−2ν)/2]]
        let m = Elastic::new("m", 210.0, 0.3).unwrap();
        let f = 210.0 / (1.3 * 0.4);
        let d = m.plane_strain();
        assert!((d[(0, 0)] - f * 0.7).abs() < 1e-12);
        assert!((d[(0, 1)] - f * 0.3).abs() < 1e-12);
        assert!((d[(2, 2)] - f * 0.2).abs() < 1e-12);
    }
}
