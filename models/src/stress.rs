//! Stress recovery, computed only when asked for: constant element stresses of triangles
//! (plane strain) and tetrahedra, the Cauchy stress and strain at the centroids of a
//! [`Solid`] of any law, von Mises equivalent stress (seed 002 eq. 4.4), area- or
//! volume-weighted nodal averages, and axial stresses of line elements.

use nalgebra::{Matrix3, Vector6};

use crate::assembly::plane::PlaneProperties;
use crate::assembly::tetrahedra::Solid;
use crate::element::mixed::Formulation;
use crate::element::recovery;
use crate::element::{line2, line3, tet4, tri3, Elastic, Law};
use crate::mesh::{plane_dofs, Mesh2d, Mesh3d, QuadraticPlaneMesh};

/// The state at an element's centroid: Cauchy stress, strain and the element's volume.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Centroid {
    /// Cauchy stress σ (MPa).
    pub stress: Matrix3<f64>,
    /// Strain: Green–Lagrange at finite strain, sym(F − I) for the linear law.
    pub strain: Matrix3<f64>,
    /// The element's reference volume (mm³).
    pub volume: f64,
}

/// The Cauchy stress and the strain at each element's centroid for displacements `u`, in
/// element order: finite strain σ = J⁻¹ P Fᵀ and the Green–Lagrange strain ½(FᵀF − I); the
/// linear law σ = P (small strain) and ε = sym(F − I). Computed as iterated.
pub fn solid_centroids<'a>(solid: &'a Solid, u: &'a [f64]) -> impl Iterator<Item = Centroid> + 'a {
    let m = solid.material;
    solid.centroids(u).map(move |(f, volume)| {
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
}

/// von Mises stress of a symmetric 3 × 3 stress.
pub fn mises(s: &Matrix3<f64>) -> f64 {
    let dev = s - Matrix3::identity() * (s.trace() / 3.0);
    (1.5 * dev.norm_squared()).sqrt()
}

/// An upper bound of the largest eigenvalue of a symmetric 3 × 3 matrix: tr/3 + √(2/3) ‖dev‖
/// (a traceless symmetric matrix of Frobenius norm N has no eigenvalue above √(2/3) N,
/// reached when the other two are equal), raised by 1e-12 of its terms so that round-off
/// cannot put it below an eigenvalue that attains it.
pub fn largest_eigenvalue_bound(s: &Matrix3<f64>) -> f64 {
    let mean = s.trace() / 3.0;
    let dev = s - Matrix3::identity() * mean;
    let spread = (2.0 / 3.0 * dev.norm_squared()).sqrt();
    mean + spread + 1e-12 * (mean.abs() + spread)
}

/// The largest eigenvalue over symmetric 3 × 3 matrices (−∞ for none), decomposing only
/// those whose [`largest_eigenvalue_bound`] exceeds the largest found so far.
pub fn largest_eigenvalue(matrices: impl IntoIterator<Item = Matrix3<f64>>) -> f64 {
    matrices.into_iter().fold(f64::NEG_INFINITY, |largest, s| {
        if largest_eigenvalue_bound(&s) > largest {
            largest.max(s.symmetric_eigenvalues().max())
        } else {
            largest
        }
    })
}

/// Plane-strain stress of a triangle (MPa). σ_zz = λ(ε_xx + ε_yy) keeps ε_zz = 0.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PlaneStress {
    /// Normal stress σ_xx.
    pub xx: f64,
    /// Normal stress σ_yy.
    pub yy: f64,
    /// Shear stress τ_xy.
    pub xy: f64,
    /// Out-of-plane normal stress σ_zz.
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

/// Linear maps from each element's dofs to `R` values (stress components), stored flat:
/// the element's dofs, then its R × width operator row by row. Built once per mesh and
/// material, so that recovering a stress after a step is R · width multiply-adds.
#[derive(Debug, Clone)]
struct Operators<const R: usize> {
    width: usize,
    dofs: Vec<usize>,
    values: Vec<f64>,
}

impl<const R: usize> Operators<R> {
    fn new(width: usize, elements: usize) -> Self {
        Self {
            width,
            dofs: Vec::with_capacity(width * elements),
            values: Vec::with_capacity(R * width * elements),
        }
    }

    /// Appends an element with its dofs and operator entries `op(row, column)`.
    fn push(&mut self, dofs: &[usize], op: impl Fn(usize, usize) -> f64) {
        debug_assert_eq!(dofs.len(), self.width);
        self.dofs.extend_from_slice(dofs);
        for r in 0..R {
            self.values.extend((0..self.width).map(|c| op(r, c)));
        }
    }

    /// The values of element `i` for the displacement `u` (all dofs).
    fn apply(&self, i: usize, u: &[f64]) -> [f64; R] {
        let w = self.width;
        let dofs = &self.dofs[w * i..w * (i + 1)];
        let op = &self.values[R * w * i..R * w * (i + 1)];
        std::array::from_fn(|r| {
            op[r * w..(r + 1) * w]
                .iter()
                .zip(dofs)
                .map(|(a, &d)| a * u[d])
                .sum()
        })
    }

    fn len(&self) -> usize {
        self.dofs.len() / self.width
    }
}

/// Per-triangle stress operators S with (σxx, σyy, σxy, σzz) = S u_e: for 3-node triangles
/// the plane-strain D·B and λ times the first two rows of B for σzz = λ(ε_xx + ε_yy); for
/// 6-node triangles [`recovery::stress_operator`] at the centroid.
#[derive(Debug, Clone)]
pub struct TriangleStresses(Operators<4>);

impl TriangleStresses {
    /// Operators of the 3-node triangles of `mesh`.
    pub fn new(mesh: &Mesh2d, props: &PlaneProperties) -> Self {
        let d: Vec<_> = props
            .continua
            .iter()
            .map(|c| (c.elastic.plane_strain(), c.elastic.lambda()))
            .collect();
        let mut ops = Operators::new(6, mesh.triangles().len());
        for i in 0..mesh.triangles().len() {
            let (dm, lambda) = &d[usize::from(mesh.triangle_regions()[i])];
            let (b, _) = tri3::b_matrix(&mesh.triangle(i));
            let db = dm * b;
            ops.push(&mesh.triangle_dofs(i), |r, c| match r {
                3 => (b[(0, c)] + b[(1, c)]) * lambda,
                _ => db[(r, c)],
            });
        }
        Self(ops)
    }

    /// Operators of the 6-node triangles of `mesh` in `formulation`, at their centroids.
    pub fn quadratic(
        mesh: &QuadraticPlaneMesh,
        props: &PlaneProperties,
        formulation: Formulation,
    ) -> Self {
        let centroid = [1.0 / 3.0; 3];
        let mut ops = Operators::new(12, mesh.triangles().len());
        for (i, t) in mesh.triangles().iter().enumerate() {
            let elastic = &props.continua[usize::from(mesh.triangle_regions()[i])].elastic;
            let s = recovery::stress_operator(formulation, &mesh.triangle(i), centroid, elastic);
            ops.push(&plane_dofs::<6, 12>(t), |r, c| s[(r, c)]);
        }
        Self(ops)
    }

    /// Stress of triangle `i` for nodal displacements `u` (all dofs).
    pub fn stress(&self, i: usize, u: &[f64]) -> PlaneStress {
        let [xx, yy, xy, zz] = self.0.apply(i, u);
        PlaneStress { xx, yy, xy, zz }
    }

    /// Stresses of all triangles.
    pub fn all(&self, u: &[f64]) -> Vec<PlaneStress> {
        (0..self.0.len()).map(|i| self.stress(i, u)).collect()
    }
}

/// Stresses of all 3-node triangles (builds the operators; keep a [`TriangleStresses`] when
/// recovering repeatedly).
pub fn triangle_stresses(mesh: &Mesh2d, props: &PlaneProperties, u: &[f64]) -> Vec<PlaneStress> {
    TriangleStresses::new(mesh, props).all(u)
}

/// Per-line axial stress rows: σ = s · u_e (MPa, positive in tension), for 2-node lines
/// ([`line2::axial_stress`]) or 3-node lines ([`line3::axial_stress`]).
#[derive(Debug, Clone)]
pub struct LineStresses(Operators<1>);

impl LineStresses {
    /// Rows of the 2-node lines of `mesh`.
    pub fn new(mesh: &Mesh2d, props: &PlaneProperties) -> Self {
        let mut ops = Operators::new(4, mesh.lines().len());
        for (i, &r) in mesh.line_regions().iter().enumerate() {
            let (p, young) = (mesh.line(i), props.trusses[usize::from(r)].young);
            // The stress is linear in u_e: its row is its value on each unit vector.
            ops.push(&mesh.line_dofs(i), |_, c| {
                line2::axial_stress(&p, young, &line2::Dofs::from_fn(|k, _| unit(k, c)))
            });
        }
        Self(ops)
    }

    /// Rows of the 3-node lines of `mesh`.
    pub fn quadratic(mesh: &QuadraticPlaneMesh, props: &PlaneProperties) -> Self {
        let mut ops = Operators::new(6, mesh.lines().len());
        for (i, (l, &r)) in mesh.lines().iter().zip(mesh.line_regions()).enumerate() {
            let (p, young) = (mesh.line(i), props.trusses[usize::from(r)].young);
            ops.push(&plane_dofs::<3, 6>(l), |_, c| {
                line3::axial_stress(&p, young, &line3::Dofs::from_fn(|k, _| unit(k, c)))
            });
        }
        Self(ops)
    }

    /// Axial stress of line `i` for nodal displacements `u` (all dofs).
    pub fn stress(&self, i: usize, u: &[f64]) -> f64 {
        self.0.apply(i, u)[0]
    }

    /// Axial stresses of all lines.
    pub fn all(&self, u: &[f64]) -> Vec<f64> {
        (0..self.0.len()).map(|i| self.stress(i, u)).collect()
    }
}

/// Component k of the c-th unit vector.
fn unit(k: usize, c: usize) -> f64 {
    f64::from(u8::from(k == c))
}

/// Axial stresses of all 2-node line elements (MPa, positive in tension).
pub fn line_stresses(mesh: &Mesh2d, props: &PlaneProperties, u: &[f64]) -> Vec<f64> {
    LineStresses::new(mesh, props).all(u)
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
/// s_n = Σ_e w_e s_e / Σ_e w_e over the elements e that contain node n, for `elements` as
/// (nodes, w_e, s_e), into `average` (0 at a node of no element), with `weight` as scratch
/// (both of the node count). Allocates nothing.
pub fn nodal_average<const N: usize>(
    elements: impl IntoIterator<Item = ([usize; N], f64, f64)>,
    average: &mut [f64],
    weight: &mut [f64],
) {
    average.fill(0.0);
    weight.fill(0.0);
    for (nodes, w, v) in elements {
        for n in nodes {
            average[n] += w * v;
            weight[n] += w;
        }
    }
    for (s, &w) in average.iter_mut().zip(weight.iter()) {
        *s = if w > 0.0 { *s / w } else { 0.0 };
    }
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

    /// The bound is reached by diag(a, b, b) and holds for rotated matrices; the search
    /// finds the largest eigenvalue of a set, compressive ones included.
    #[test]
    fn the_largest_eigenvalue_is_bounded_and_found() {
        let d = Matrix3::from_diagonal(&nalgebra::Vector3::new(0.3, -0.1, -0.1));
        assert!((largest_eigenvalue_bound(&d) - 0.3).abs() < 1e-12);
        let r = nalgebra::Rotation3::from_euler_angles(0.3, -0.7, 1.1).into_inner();
        let set: Vec<Matrix3<f64>> = [[0.2, 0.05, -0.4], [-0.3, -0.2, -0.25], [0.1, 0.25, 0.0]]
            .iter()
            .map(|v| r * Matrix3::from_diagonal(&nalgebra::Vector3::from(*v)) * r.transpose())
            .collect();
        for (s, largest) in set.iter().zip([0.2, -0.2, 0.25]) {
            assert!(largest_eigenvalue_bound(s) >= largest - 1e-15);
        }
        assert!((largest_eigenvalue(set.clone()) - 0.25).abs() < 1e-14);
        assert!((largest_eigenvalue(set[1..2].to_vec()) + 0.2).abs() < 1e-14);
        assert_eq!(largest_eigenvalue([]), f64::NEG_INFINITY);
    }

    #[test]
    fn nodal_average_weights_by_measure() {
        let (mut avg, mut weight) = ([f64::NAN; 4], [f64::NAN; 4]);
        nodal_average(
            [([0, 1], 1.0, 10.0), ([1, 2], 3.0, 20.0)],
            &mut avg,
            &mut weight,
        );
        assert_eq!(avg, [10.0, 17.5, 20.0, 0.0]);
    }
}
