//! The abdomen's scalar outputs, computed together on the first request after a step.
//!
//! What does not change between steps — which line elements form the pelvic floor and their
//! lengths, triangle areas, which triangles lie along the floor, the dofs of the point
//! outputs — is gathered once per mesh in an [`OutputPlan`]. The outputs read the
//! displacement through a [`Source`]: the field of all dofs ([`Field`], full order), or the
//! modal coordinates through precomputed output rows ([`Rows`], reduced order: every floor
//! stress, triangle stress component and point displacement is linear in u, so all of them
//! are one small matrix–vector product). The cavity-wide von Mises statistics visit every
//! triangle of the field (a modal model expands it first) and are computed only when one of
//! them is read. No computation allocates.

use super::discretization::Recovery;
use crate::assembly::Dirichlet;
use crate::element::tri3;
use crate::mesh::Mesh2d;
use crate::scene::SceneError;
use crate::solve::ModalBasis;
use crate::stress::PlaneStress;
use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, MatMut, MatRef, Par};

/// Number of outputs: in table order from `floor_stress_mean`, the floor stress mean and max;
/// von Mises mean and max along the floor and over the cavity; x and y displacement of the
/// diaphragm apex, the floor midpoint and the wall midpoint; the pressing force — then the
/// contents' mean pressure ([`CAVITY_PRESSURE`], added after them to the table).
pub const COUNT: usize = 14;

/// The position of the contents' mean pressure among the outputs.
pub const CAVITY_PRESSURE: usize = 13;

/// The cavity-wide outputs (von Mises mean and max over all triangles, the contents' mean
/// pressure): they visit every triangle of the field.
pub const CAVITY: [usize; 3] = [4, 5, CAVITY_PRESSURE];

/// Line region of the pelvic floor (diaphragm 0, wall 1, floor 2).
const FLOOR: u16 = 2;

/// Where the outputs read the displacement.
pub trait Source {
    /// Axial stress of the k-th pelvic-floor line element (plan order).
    fn floor_stress(&self, k: usize) -> f64;
    /// Plane-strain stress of the k-th triangle along the floor (plan order).
    fn along_stress(&self, k: usize) -> PlaneStress;
    /// Component k of the point displacements (apex x, y; floor midpoint x, y; wall
    /// midpoint x, y).
    fn point(&self, k: usize) -> f64;
}

/// The per-mesh data the outputs need.
#[derive(Debug, Clone)]
pub struct OutputPlan {
    /// Pelvic-floor line elements and their lengths.
    floor_lines: Vec<(usize, f64)>,
    /// Area of every triangle.
    areas: Vec<f64>,
    /// The triangles with an edge on the pelvic floor.
    along: Vec<usize>,
    /// Dofs of the point outputs (x, y of the diaphragm apex, floor midpoint, wall midpoint).
    point_dofs: [usize; 6],
}

impl OutputPlan {
    /// The contents' mean pressure p̄ of `field` (MPa; see [`OutputPlan::compute`]).
    pub fn pressure(&self, field: &Field<'_>) -> f64 {
        self.cavity(field).1.mean()
    }

    /// The area-weighted statistics of the triangles' von Mises stress and of their mean
    /// pressure −tr σ/3, at their centroids.
    fn cavity(&self, field: &Field<'_>) -> (Stats, Stats) {
        let (mut all, mut pressure) = (Stats::default(), Stats::default());
        for (i, &area) in self.areas.iter().enumerate() {
            let s = field.recovery.triangle(i, field.u);
            all.add(s.von_mises(), area);
            pressure.add(-(s.xx + s.yy + s.zz) / 3.0, area);
        }
        (all, pressure)
    }

    /// The plan for the 3-node `mesh` (for `tri6`, its corners: the 6-node triangles and
    /// lines are numbered as theirs, and straight-sided).
    pub fn new(mesh: &Mesh2d) -> Result<Self, SceneError> {
        let floor_lines = (0..mesh.lines().len())
            .filter(|&i| mesh.line_regions()[i] == FLOOR)
            .map(|i| {
                let [a, b] = mesh.line(i);
                (i, (b[0] - a[0]).hypot(b[1] - a[1]))
            })
            .collect();
        let floor = mesh.node_sets().get("pelvic_floor")?;
        let along = (0..mesh.triangles().len())
            .filter(|&i| {
                let t = mesh.triangles()[i];
                t.iter().filter(|n| floor.binary_search(n).is_ok()).count() >= 2
            })
            .collect();
        let areas = (0..mesh.triangles().len())
            .map(|i| tri3::signed_area(&mesh.triangle(i)))
            .collect();
        let mut point_dofs = [0; 6];
        for (k, set) in ["diaphragm_apex", "floor_mid", "wall_mid"]
            .iter()
            .enumerate()
        {
            let node = mesh.node_sets().get(set)?[0];
            point_dofs[2 * k] = 2 * node;
            point_dofs[2 * k + 1] = 2 * node + 1;
        }
        Ok(Self {
            floor_lines,
            areas,
            along,
            point_dofs,
        })
    }

    /// The outputs read from `source` with pressing force `press`; the cavity-wide ones
    /// ([`CAVITY`]) from `cavity`, the displacement field, if given, else NaN: not computed.
    ///
    /// The contents' mean pressure is p̄ = −Σₑ Aₑ tr σₑ / 3 / Σₑ Aₑ over all triangles: σₑ the
    /// Cauchy stress at the centroid with its plane-strain σ_zz (the law's out-of-plane
    /// stress at ε_zz = 0, not zero), Aₑ the reference corner-triangle areas; positive in
    /// compression. The von Mises statistics use the same centroid stresses and weights.
    pub fn compute(
        &self,
        source: &impl Source,
        cavity: Option<&Field<'_>>,
        press: f64,
    ) -> [f64; COUNT] {
        let mut floor = Stats::default();
        for (k, &(_, length)) in self.floor_lines.iter().enumerate() {
            floor.add(source.floor_stress(k), length);
        }
        let mut along = Stats::default();
        for (k, &i) in self.along.iter().enumerate() {
            along.add(source.along_stress(k).von_mises(), self.areas[i]);
        }
        let (mean, max, pressure) = match cavity {
            Some(field) => {
                let (all, pressure) = self.cavity(field);
                (all.mean(), all.max, pressure.mean())
            }
            None => (f64::NAN, f64::NAN, f64::NAN),
        };
        let p = |k| source.point(k);
        [
            floor.mean(),
            floor.max,
            along.mean(),
            along.max,
            mean,
            max,
            p(0),
            p(1),
            p(2),
            p(3),
            p(4),
            p(5),
            press,
            pressure,
        ]
    }
}

/// A displacement field of all dofs as the outputs' source.
#[derive(Debug, Clone, Copy)]
pub struct Field<'a> {
    pub plan: &'a OutputPlan,
    pub recovery: &'a Recovery,
    pub u: &'a [f64],
}

impl Source for Field<'_> {
    fn floor_stress(&self, k: usize) -> f64 {
        self.recovery.line(self.plan.floor_lines[k].0, self.u)
    }

    fn along_stress(&self, k: usize) -> PlaneStress {
        self.recovery.triangle(self.plan.along[k], self.u)
    }

    fn point(&self, k: usize) -> f64 {
        self.u[self.plan.point_dofs[k]]
    }
}

/// The outputs near the floor as rows over a modal basis: the floor stresses, the stress
/// components (σxx, σyy, σxy, σzz) of the triangles along the floor and the point
/// displacements, each a linear function of the modal coordinates. One matrix–vector
/// product evaluates them all.
#[derive(Debug, Clone)]
pub struct Rows {
    /// Floor stresses, then 4 rows per triangle along the floor, then the 6 points.
    rows: Mat<f64>,
    /// The rows applied to the last coordinates.
    values: Vec<f64>,
    n_floor: usize,
}

impl Rows {
    /// Evaluates every row on each basis vector (expanded to all dofs by `bc`).
    pub fn new(field: Field<'_>, basis: &ModalBasis, bc: &Dirichlet) -> Self {
        let (n_floor, n_along) = (field.plan.floor_lines.len(), field.plan.along.len());
        let n_rows = n_floor + 4 * n_along + 6;
        let mut rows = Mat::zeros(n_rows, basis.dim());
        let mut u = vec![0.0; field.u.len()];
        for j in 0..basis.dim() {
            bc.expand(basis.column(j), &mut u);
            let f = Field { u: &u, ..field };
            let (floor, rest) = rows.col_as_slice_mut(j).split_at_mut(n_floor);
            let (along, points) = rest.split_at_mut(4 * n_along);
            floor
                .iter_mut()
                .enumerate()
                .for_each(|(k, x)| *x = f.floor_stress(k));
            for (k, x) in along.chunks_exact_mut(4).enumerate() {
                let s = f.along_stress(k);
                x.copy_from_slice(&[s.xx, s.yy, s.xy, s.zz]);
            }
            points
                .iter_mut()
                .enumerate()
                .for_each(|(k, x)| *x = f.point(k));
        }
        Self {
            rows,
            values: vec![0.0; n_rows],
            n_floor,
        }
    }

    /// Applies the rows to modal coordinates `q`; the rows then act as a source of those
    /// values. Allocates nothing.
    pub fn evaluate(&mut self, q: &[f64]) {
        let q = MatRef::from_column_major_slice(q, q.len(), 1);
        let y = MatMut::from_column_major_slice_mut(&mut self.values, self.rows.nrows(), 1);
        matmul(y, Accum::Replace, &self.rows, q, 1.0, Par::Seq);
    }
}

impl Source for Rows {
    fn floor_stress(&self, k: usize) -> f64 {
        self.values[k]
    }

    fn along_stress(&self, k: usize) -> PlaneStress {
        let s = &self.values[self.n_floor + 4 * k..self.n_floor + 4 * k + 4];
        PlaneStress {
            xx: s[0],
            yy: s[1],
            xy: s[2],
            zz: s[3],
        }
    }

    fn point(&self, k: usize) -> f64 {
        self.values[self.values.len() - 6 + k]
    }
}

/// Weighted mean and maximum.
#[derive(Debug)]
struct Stats {
    sum: f64,
    weight: f64,
    max: f64,
}

impl Default for Stats {
    fn default() -> Self {
        Self {
            sum: 0.0,
            weight: 0.0,
            max: f64::NEG_INFINITY,
        }
    }
}

impl Stats {
    fn add(&mut self, value: f64, weight: f64) {
        self.sum += value * weight;
        self.weight += weight;
        self.max = self.max.max(value);
    }

    fn mean(&self) -> f64 {
        self.sum / self.weight
    }
}
