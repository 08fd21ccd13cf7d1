//! The abdomen's scalar outputs, computed together on the first request after a step.
//!
//! What does not change between steps — which line elements form the pelvic floor and their
//! lengths, triangle areas, which triangles lie along the floor, the nodes of the point
//! outputs — is gathered once per mesh in an [`OutputPlan`]; a computation is then one pass
//! over the triangles and the floor lines, without allocation.

use crate::assembly::plane::PlaneProperties;
use crate::element::{line2, tri3};
use crate::mesh::Mesh2d;
use crate::scene::SceneError;
use crate::stress::TriangleStresses;

/// Number of outputs, in table order: floor stress mean and max; von Mises mean and max
/// along the floor and over the cavity; x and y displacement of the diaphragm apex, the floor
/// midpoint and the wall midpoint; the pressing force.
pub const COUNT: usize = 13;

/// Line region of the pelvic floor (diaphragm 0, wall 1, floor 2).
const FLOOR: u16 = 2;

/// The per-mesh data the outputs need.
#[derive(Debug, Clone)]
pub struct OutputPlan {
    /// Pelvic-floor line elements and their lengths.
    floor_lines: Vec<(usize, f64)>,
    /// Area of every triangle, and whether it has an edge on the pelvic floor.
    triangles: Vec<(f64, bool)>,
    /// Nodes of the point outputs: diaphragm apex, floor midpoint, wall midpoint.
    points: [usize; 3],
}

impl OutputPlan {
    pub fn new(mesh: &Mesh2d) -> Result<Self, SceneError> {
        let floor_lines = (0..mesh.lines().len())
            .filter(|&i| mesh.line_regions()[i] == FLOOR)
            .map(|i| {
                let [a, b] = mesh.line(i);
                (i, (b[0] - a[0]).hypot(b[1] - a[1]))
            })
            .collect();
        let floor = mesh.node_sets().get("pelvic_floor")?;
        let triangles = mesh
            .triangles()
            .iter()
            .enumerate()
            .map(|(i, t)| {
                let on_floor = t.iter().filter(|n| floor.binary_search(n).is_ok()).count();
                (tri3::signed_area(&mesh.triangle(i)), on_floor >= 2)
            })
            .collect();
        let mut points = [0; 3];
        for (p, set) in points
            .iter_mut()
            .zip(["diaphragm_apex", "floor_mid", "wall_mid"])
        {
            *p = mesh.node_sets().get(set)?[0];
        }
        Ok(Self {
            floor_lines,
            triangles,
            points,
        })
    }

    /// The outputs for nodal displacements `u` (all dofs) and pressing force `press`.
    pub fn compute(
        &self,
        mesh: &Mesh2d,
        props: &PlaneProperties,
        stresses: &TriangleStresses,
        u: &[f64],
        press: f64,
    ) -> [f64; COUNT] {
        let young = props.trusses[usize::from(FLOOR)].young;
        let mut floor = Stats::default();
        for &(i, length) in &self.floor_lines {
            let ue = line2::Dofs::from_fn(|k, _| u[mesh.line_dofs(i)[k]]);
            floor.add(line2::axial_stress(&mesh.line(i), young, &ue), length);
        }
        let (mut all, mut along) = (Stats::default(), Stats::default());
        for (i, &(area, on_floor)) in self.triangles.iter().enumerate() {
            let vm = stresses.stress(mesh, i, u).von_mises();
            all.add(vm, area);
            if on_floor {
                along.add(vm, area);
            }
        }
        let [a, f, w] = self.points;
        [
            floor.mean(),
            floor.max,
            along.mean(),
            along.max,
            all.mean(),
            all.max,
            u[2 * a],
            u[2 * a + 1],
            u[2 * f],
            u[2 * f + 1],
            u[2 * w],
            u[2 * w + 1],
            press,
        ]
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
