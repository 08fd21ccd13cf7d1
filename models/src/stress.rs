//! Stress recovery, computed only when asked for: constant element stresses of triangles
//! (plane strain) and tetrahedra, the Cauchy stress and strain at the centroids of a
//! [`Solid`] of any law, von Mises equivalent stress (seed 002 eq. 4.4), area- or
//! volume-weighted nodal averages, and axial stresses of line elements.

use nalgebra::{Matrix3, SMatrix, Vector6};

use crate::assembly::plane::PlaneProperties;
use crate::assembly::solid::Solid;
use crate::element::{line2, tet4, tri3, Elastic, Law};
use crate::mesh::{Mesh2d, Mesh3d};

/// The state at an element's centroid: Cauchy stress, strain and the element's volume.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Centroid {
    pub stress: Matrix3<f64>,
    pub strain: Matrix3<f64>,
    pub volume: f64,
}

/// The Cauchy stress and the strain at each element's centroid for displacements `u`:
/// finite strain σ = J⁻¹ P Fᵀ and the Green–Lagrange strain ½(FᵀF − I); the linear law
/// σ = P (small strain) and ε = sym(F − I).
pub fn solid_centroids(solid: &Solid, u: &[f64]) -> Vec<Centroid> {
    let m = solid.material;
    solid
        .centroids(u)
        .into_iter()
        .map(|(f, volume)| {
            let p = m.stress(&f);
            let (stress, strain) = match m.law {
                Law::Linear => (p, 0.5 * (f + f.transpose()) - Matrix3::identity()),
                _ => (
                    p * f.transpose() / f.determinant(),
                    0.5 * (f.transpose() * f - Matrix3::identity()),
                ),
            };
            Centroid {
                stress,
                strain,
                volume,
            }
        })
        .collect()
}

/// von Mises stress of a symmetric 3 × 3 stress.
pub fn mises(s: &Matrix3<f64>) -> f64 {
    let dev = s - Matrix3::identity() * (s.trace() / 3.0);
    (1.5 * dev.norm_squared()).sqrt()
}

/// Plane-strain stress of a triangle (MPa). σ_zz = λ(ε_xx + ε_yy) keeps ε_zz = 0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlaneStress {
    pub xx: f64,
    pub yy: f64,
    pub xy: f64,
    pub zz: f64,
}

impl PlaneStress {
    /// von Mises equivalent stress √(½[(σx−σy)² + (σy−σz)² + (σz−σx)²] + 3τ²).
    pub fn von_mises(&self) -> f64 {
        von_mises(&Vector6::new(self.xx, self.yy, self.zz, self.xy, 0.0, 0.0))
    }
}

/// von Mises stress of a 3D stress vector (σxx, σyy, σzz, τxy, τyz, τzx) (seed 002 eq. 4.4).
pub fn von_mises(s: &Vector6<f64>) -> f64 {
    let normal = (s[0] - s[1]).powi(2) + (s[1] - s[2]).powi(2) + (s[2] - s[0]).powi(2);
    let shear = s[3] * s[3] + s[4] * s[4] + s[5] * s[5];
    (0.5 * normal + 3.0 * shear).sqrt()
}

/// Per-triangle stress operators S (4 × 6) with (σxx, σyy, σxy, σzz) = S u_e: the
/// plane-strain D·B, and λ times the first two rows of B for σzz = λ(ε_xx + ε_yy). Built once
/// per mesh and material, so that recovering every stress after a step is 24 multiply-adds a
/// triangle.
#[derive(Debug, Clone)]
pub struct TriangleStresses {
    operators: Vec<SMatrix<f64, 4, 6>>,
}

impl TriangleStresses {
    pub fn new(mesh: &Mesh2d, props: &PlaneProperties) -> Self {
        let d: Vec<_> = props
            .continua
            .iter()
            .map(|c| (c.elastic.plane_strain(), c.elastic.lambda()))
            .collect();
        let operators = (0..mesh.triangles().len())
            .map(|i| {
                let (dm, lambda) = &d[usize::from(mesh.triangle_regions()[i])];
                let (b, _) = tri3::b_matrix(&mesh.triangle(i));
                let db = dm * b;
                let mut s = SMatrix::<f64, 4, 6>::zeros();
                s.fixed_rows_mut::<3>(0).copy_from(&db);
                s.set_row(3, &((b.row(0) + b.row(1)) * *lambda));
                s
            })
            .collect();
        Self { operators }
    }

    /// Stress of triangle `i` for nodal displacements `u` (all dofs).
    pub fn stress(&self, mesh: &Mesh2d, i: usize, u: &[f64]) -> PlaneStress {
        let ue = tri3::Dofs::from_fn(|k, _| u[mesh.triangle_dofs(i)[k]]);
        let s = self.operators[i] * ue;
        PlaneStress {
            xx: s[0],
            yy: s[1],
            xy: s[2],
            zz: s[3],
        }
    }

    /// Stresses of all triangles.
    pub fn all(&self, mesh: &Mesh2d, u: &[f64]) -> Vec<PlaneStress> {
        (0..self.operators.len())
            .map(|i| self.stress(mesh, i, u))
            .collect()
    }
}

/// Stresses of all triangles (builds the operators; keep a [`TriangleStresses`] when
/// recovering repeatedly).
pub fn triangle_stresses(mesh: &Mesh2d, props: &PlaneProperties, u: &[f64]) -> Vec<PlaneStress> {
    TriangleStresses::new(mesh, props).all(mesh, u)
}

/// Axial stresses of all line elements (MPa, positive in tension).
pub fn line_stresses(mesh: &Mesh2d, props: &PlaneProperties, u: &[f64]) -> Vec<f64> {
    (0..mesh.lines().len())
        .map(|i| {
            let young = props.trusses[usize::from(mesh.line_regions()[i])].young;
            let ue = line2::Dofs::from_fn(|k, _| u[mesh.line_dofs(i)[k]]);
            line2::axial_stress(&mesh.line(i), young, &ue)
        })
        .collect()
}

/// Stress (σxx, σyy, σzz, τxy, τyz, τzx) of every tetrahedron.
pub fn tet_stresses(mesh: &Mesh3d, material: &Elastic, u: &[f64]) -> Vec<Vector6<f64>> {
    let d = material.solid();
    (0..mesh.tets().len())
        .map(|i| {
            let ue = tet4::Dofs::from_fn(|k, _| u[mesh.tet_dofs(i)[k]]);
            d * tet4::strain(&mesh.tet(i), &ue)
        })
        .collect()
}

/// Nodal averages of element values weighted by element measure (area or volume):
/// s_n = Σ_e w_e s_e / Σ_e w_e over the elements e that contain node n.
pub fn nodal_average<const N: usize>(
    n_nodes: usize,
    elements: &[[usize; N]],
    weights: &[f64],
    values: &[f64],
) -> Vec<f64> {
    let mut sum = vec![0.0; n_nodes];
    let mut weight = vec![0.0; n_nodes];
    for ((e, &w), &v) in elements.iter().zip(weights).zip(values) {
        for &n in e {
            sum[n] += w * v;
            weight[n] += w;
        }
    }
    sum.iter()
        .zip(&weight)
        .map(|(s, w)| if *w > 0.0 { s / w } else { 0.0 })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn von_mises_of_uniaxial_and_pure_shear() {
        assert!((von_mises(&Vector6::new(3.0, 0.0, 0.0, 0.0, 0.0, 0.0)) - 3.0).abs() < 1e-14);
        let tau = 2.0;
        let vm = von_mises(&Vector6::new(0.0, 0.0, 0.0, tau, 0.0, 0.0));
        assert!((vm - 3f64.sqrt() * tau).abs() < 1e-14);
        // Hydrostatic stress has no von Mises part.
        assert!(von_mises(&Vector6::new(5.0, 5.0, 5.0, 0.0, 0.0, 0.0)).abs() < 1e-14);
    }

    #[test]
    fn nodal_average_weights_by_measure() {
        let avg = nodal_average(3, &[[0, 1], [1, 2]], &[1.0, 3.0], &[10.0, 20.0]);
        assert_eq!(avg, vec![10.0, 17.5, 20.0]);
    }
}
