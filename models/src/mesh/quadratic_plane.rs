//! Quadratic triangles on a linear 2D mesh: the 6-node triangles of
//! [`crate::element::tri6`] (corners, then the mid-edge nodes of edges 0–1, 1–2, 2–0) with
//! the mid-edge nodes at the edge midpoints ([`super::mid_edges`]); the line elements become
//! 3-node lines (end, mid-edge node, end) sharing the triangles' mid-edge nodes; regions
//! carry over.

use super::mid_edges::MidEdges;
use super::Mesh2d;
use crate::element::tri6::EDGES;

/// A mesh of 6-node triangles derived from a [`Mesh2d`].
#[derive(Debug, Clone)]
pub struct QuadraticPlaneMesh {
    nodes: Vec<[f64; 2]>,
    triangles: Vec<[usize; 6]>,
    regions: Vec<u16>,
    lines: Vec<[usize; 3]>,
    line_regions: Vec<u16>,
    mid: MidEdges,
}

impl QuadraticPlaneMesh {
    /// Adds the mid-edge nodes of `mesh`.
    pub fn new(mesh: &Mesh2d) -> Self {
        let mut nodes = mesh.nodes().to_vec();
        let mut mid = MidEdges::with_capacity(3 * nodes.len());
        let triangles = mesh
            .triangles()
            .iter()
            .map(|t| {
                let mut q = [t[0], t[1], t[2], 0, 0, 0];
                for (k, [i, j]) in EDGES.iter().enumerate() {
                    q[3 + k] = mid.node(t[*i], t[*j], &mut nodes);
                }
                q
            })
            .collect();
        let lines = mesh
            .lines()
            .iter()
            .map(|&[a, b]| [a, mid.node(a, b, &mut nodes), b])
            .collect();
        Self {
            nodes,
            triangles,
            regions: mesh.triangle_regions().to_vec(),
            lines,
            line_regions: mesh.line_regions().to_vec(),
            mid,
        }
    }

    /// The 3-node lines (end, mid-edge node, end).
    pub fn lines(&self) -> &[[usize; 3]] {
        &self.lines
    }

    /// The region tag (tissue) of each line.
    pub fn line_regions(&self) -> &[u16] {
        &self.line_regions
    }

    /// Coordinates of the three nodes of line `i`.
    pub fn line(&self, i: usize) -> [[f64; 2]; 3] {
        self.lines[i].map(|n| self.nodes[n])
    }

    /// Node coordinates (mm): the linear mesh's nodes, then the mid-edge nodes.
    pub fn nodes(&self) -> &[[f64; 2]] {
        &self.nodes
    }

    /// The triangles' six nodes each: corners, then the mid-edge nodes of edges 0–1, 1–2,
    /// 2–0.
    pub fn triangles(&self) -> &[[usize; 6]] {
        &self.triangles
    }

    /// The region tag (tissue) of each triangle.
    pub fn triangle_regions(&self) -> &[u16] {
        &self.regions
    }

    /// Coordinates of the six nodes of triangle `i`.
    pub fn triangle(&self, i: usize) -> [[f64; 2]; 6] {
        self.triangles[i].map(|n| self.nodes[n])
    }

    /// Two displacement dofs per node.
    pub fn n_dofs(&self) -> usize {
        2 * self.nodes.len()
    }

    /// The mid-edge node between corners `a` and `b`, if they share an edge.
    pub fn mid(&self, a: usize, b: usize) -> Option<usize> {
        self.mid.get(a, b)
    }

    /// Moves the mid-edge node between corners `a` and `b` to `to` (a curved edge); false if
    /// they share no edge.
    pub fn move_mid(&mut self, a: usize, b: usize, to: [f64; 2]) -> bool {
        match self.mid.get(a, b) {
            Some(m) => {
                self.nodes[m] = to;
                true
            }
            None => false,
        }
    }

    /// Moves the mid-edge node of every edge between two nodes of `corners` to `onto(mid)`,
    /// e.g. onto the arc the corners lie on, so that the edge is the parabola through the
    /// three (isoparametric curved edges).
    pub fn curve(&mut self, corners: &[usize], onto: impl Fn([f64; 2]) -> [f64; 2]) {
        let n_corners = corners.len();
        for &m in &self.mid.extend(corners)[n_corners..] {
            self.nodes[m] = onto(self.nodes[m]);
        }
    }

    /// A set of corner nodes with the mid-edge nodes of the edges between them (a node set
    /// on a straight boundary stays the nodes on it).
    pub fn extend(&self, corners: &[usize]) -> Vec<usize> {
        self.mid.extend(corners)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::tri6;
    use crate::mesh::generate;

    #[test]
    fn mid_edge_nodes_sit_at_midpoints_shared_by_neighbours() {
        let m = generate::rectangle(3.0, 2.0, 3, 2).unwrap();
        let q = QuadraticPlaneMesh::new(&m);
        // Edges of a 3 × 2 grid of cells with one diagonal each: 3·3 + 4·2 + 6 = 23.
        assert_eq!(q.nodes().len(), m.nodes().len() + 23);
        let mut area = 0.0;
        for i in 0..q.triangles().len() {
            let p = q.triangle(i);
            let corners = [p[0], p[1], p[2]];
            assert_eq!(p, tri6::straight(&corners));
            area += tri6::area(&p);
        }
        assert!((area - 6.0).abs() < 1e-12);
        let left = m.node_sets().get("left").unwrap();
        let extended = q.extend(left);
        assert_eq!(extended.len(), 2 * left.len() - 1);
        assert!(extended.iter().all(|&n| q.nodes()[n][0] == 0.0));
    }
}
