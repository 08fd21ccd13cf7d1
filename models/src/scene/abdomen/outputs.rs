//! The abdomen's scalar outputs, computed together on the first request after a step.

use crate::assembly::plane::PlaneProperties;
use crate::element::tri3;
use crate::mesh::Mesh2d;
use crate::stress::{self, TriangleStresses};

/// Output values in table order.
#[derive(Debug, Clone)]
pub struct Outputs(Vec<f64>);

impl Outputs {
    pub fn compute(
        mesh: &Mesh2d,
        props: &PlaneProperties,
        stresses: &TriangleStresses,
        u: &[f64],
        press: f64,
    ) -> Self {
        let mut out = Vec::with_capacity(13);
        // Pelvic-floor line elements (region 2).
        let axial = stress::line_stresses(mesh, props, u);
        let (mut sum, mut length, mut max) = (0.0, 0.0, f64::NEG_INFINITY);
        for (i, &r) in mesh.line_regions().iter().enumerate() {
            if r == 2 {
                let [a, b] = mesh.line(i);
                let l = (b[0] - a[0]).hypot(b[1] - a[1]);
                sum += axial[i] * l;
                length += l;
                max = max.max(axial[i]);
            }
        }
        out.extend([sum / length, max]);
        // Triangles: all, and those with an edge on the pelvic floor.
        let floor = mesh
            .node_sets()
            .get("pelvic_floor")
            .expect("mesher adds it");
        let on_floor = |n: &usize| floor.binary_search(n).is_ok();
        let vm: Vec<f64> = stresses
            .all(mesh, u)
            .iter()
            .map(|s| s.von_mises())
            .collect();
        let (mut all, mut along) = (Stats::default(), Stats::default());
        for (i, t) in mesh.triangles().iter().enumerate() {
            let area = tri3::signed_area(&mesh.triangle(i));
            all.add(vm[i], area);
            if t.iter().filter(|n| on_floor(n)).count() >= 2 {
                along.add(vm[i], area);
            }
        }
        out.extend([along.mean(), along.max, all.mean(), all.max]);
        for set in ["diaphragm_apex", "floor_mid", "wall_mid"] {
            let n = mesh.node_sets().get(set).expect("mesher adds it")[0];
            out.extend([u[2 * n], u[2 * n + 1]]);
        }
        out.push(press);
        Self(out)
    }

    /// Output number `i` in table order.
    pub fn get(&self, i: usize) -> f64 {
        self.0[i]
    }
}

/// Area-weighted mean and maximum.
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
