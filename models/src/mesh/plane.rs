//! 2D mesh: nodes, 3-node triangles and 2-node line elements on the same nodes, a region tag
//! per element (tissue), named node sets.

use super::{check_all_used, check_connectivity, NodeSets, DEGENERATE_TOL};
use crate::element::tri3;
use crate::error::ModelError;

/// A validated 2D mesh. Triangles are counter-clockwise (positive area).
#[derive(Debug, Clone)]
pub struct Mesh2d {
    nodes: Vec<[f64; 2]>,
    triangles: Vec<[usize; 3]>,
    triangle_regions: Vec<u16>,
    lines: Vec<[usize; 2]>,
    line_regions: Vec<u16>,
    node_sets: NodeSets,
}

impl Mesh2d {
    /// Builds and validates a mesh: indices in range, every node used, no degenerate or
    /// clockwise triangle, no zero-length line, one region tag per element.
    pub fn new(
        nodes: Vec<[f64; 2]>,
        triangles: Vec<[usize; 3]>,
        triangle_regions: Vec<u16>,
        lines: Vec<[usize; 2]>,
        line_regions: Vec<u16>,
    ) -> Result<Self, ModelError> {
        check_len("triangle_regions", triangles.len(), triangle_regions.len())?;
        check_len("line_regions", lines.len(), line_regions.len())?;
        let mut used = vec![false; nodes.len()];
        check_connectivity("triangle", &triangles, &mut used)?;
        check_connectivity("line", &lines, &mut used)?;
        check_all_used(&used)?;
        let mesh = Self {
            nodes,
            triangles,
            triangle_regions,
            lines,
            line_regions,
            node_sets: NodeSets::default(),
        };
        mesh.check_shapes()?;
        Ok(mesh)
    }

    fn check_shapes(&self) -> Result<(), ModelError> {
        let extent = self.extent();
        for index in 0..self.triangles.len() {
            let area = tri3::signed_area(&self.triangle(index));
            if area.is_nan() || area <= DEGENERATE_TOL * extent * extent {
                return Err(ModelError::DegenerateElement {
                    kind: "triangle",
                    index,
                    measure_name: "area",
                    measure: area,
                });
            }
        }
        for index in 0..self.lines.len() {
            let [a, b] = self.line(index);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            if len.is_nan() || len <= DEGENERATE_TOL * extent {
                return Err(ModelError::DegenerateElement {
                    kind: "line",
                    index,
                    measure_name: "length",
                    measure: len,
                });
            }
        }
        Ok(())
    }

    /// Largest bounding-box side length.
    pub fn extent(&self) -> f64 {
        (0..2)
            .map(|d| {
                let (lo, hi) = self.nodes.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                    (lo.min(p[d]), hi.max(p[d]))
                });
                hi - lo
            })
            .fold(0.0, f64::max)
    }

    /// The same mesh with line elements `lines` (region tags `line_regions`) added on its
    /// nodes; node sets are kept.
    pub fn with_lines(
        self,
        lines: Vec<[usize; 2]>,
        line_regions: Vec<u16>,
    ) -> Result<Self, ModelError> {
        let mut all_lines = self.lines;
        all_lines.extend(lines);
        let mut all_regions = self.line_regions;
        all_regions.extend(line_regions);
        let mut mesh = Self::new(
            self.nodes,
            self.triangles,
            self.triangle_regions,
            all_lines,
            all_regions,
        )?;
        mesh.node_sets = self.node_sets;
        Ok(mesh)
    }

    /// The same mesh with every node moved to `map(node)` (validated again: a map that
    /// folds or flattens a triangle is an error); elements, regions and node sets are kept.
    pub fn mapped(&self, map: impl Fn([f64; 2]) -> [f64; 2]) -> Result<Self, ModelError> {
        let mut mesh = Self::new(
            self.nodes.iter().map(|&p| map(p)).collect(),
            self.triangles.clone(),
            self.triangle_regions.clone(),
            self.lines.clone(),
            self.line_regions.clone(),
        )?;
        mesh.node_sets = self.node_sets.clone();
        Ok(mesh)
    }

    /// Adds a named node set (validated).
    pub fn add_node_set(&mut self, name: &str, nodes: Vec<usize>) -> Result<(), ModelError> {
        self.node_sets.insert(name, nodes, self.nodes.len())
    }

    /// Node coordinates (mm).
    pub fn nodes(&self) -> &[[f64; 2]] {
        &self.nodes
    }
    /// The triangles' nodes, counter-clockwise.
    pub fn triangles(&self) -> &[[usize; 3]] {
        &self.triangles
    }
    /// The region tag (tissue) of each triangle.
    pub fn triangle_regions(&self) -> &[u16] {
        &self.triangle_regions
    }
    /// The line elements' nodes.
    pub fn lines(&self) -> &[[usize; 2]] {
        &self.lines
    }
    /// The region tag (tissue) of each line element.
    pub fn line_regions(&self) -> &[u16] {
        &self.line_regions
    }
    /// The named node sets.
    pub fn node_sets(&self) -> &NodeSets {
        &self.node_sets
    }

    /// Number of degrees of freedom (2 per node).
    pub fn n_dofs(&self) -> usize {
        2 * self.nodes.len()
    }

    /// Coordinates of triangle `i`.
    pub fn triangle(&self, i: usize) -> [[f64; 2]; 3] {
        self.triangles[i].map(|n| self.nodes[n])
    }

    /// Coordinates of line element `i`.
    pub fn line(&self, i: usize) -> [[f64; 2]; 2] {
        self.lines[i].map(|n| self.nodes[n])
    }

    /// Global dofs of triangle `i` in element order.
    pub fn triangle_dofs(&self, i: usize) -> [usize; 6] {
        super::plane_dofs(&self.triangles[i])
    }

    /// Global dofs of line element `i` in element order.
    pub fn line_dofs(&self, i: usize) -> [usize; 4] {
        super::plane_dofs(&self.lines[i])
    }
}

pub(super) fn check_len(name: &'static str, expected: usize, got: usize) -> Result<(), ModelError> {
    if expected == got {
        Ok(())
    } else {
        Err(ModelError::SizeMismatch {
            name,
            expected,
            got,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
        (
            vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn valid_mesh_builds() {
        let (n, t) = square();
        let m = Mesh2d::new(n, t, vec![0, 0], vec![[0, 1]], vec![1]).unwrap();
        assert_eq!(m.n_dofs(), 8);
        assert_eq!(m.triangle_dofs(1), [0, 1, 4, 5, 6, 7]);
    }

    #[test]
    fn inverted_triangle_is_named_with_its_area() {
        let (n, _) = square();
        let err =
            Mesh2d::new(n, vec![[0, 1, 2], [0, 3, 2]], vec![0, 0], vec![], vec![]).unwrap_err();
        assert_eq!(
            err,
            ModelError::DegenerateElement {
                kind: "triangle",
                index: 1,
                measure_name: "area",
                measure: -0.5
            }
        );
    }

    #[test]
    fn out_of_range_and_unused_nodes_are_errors() {
        let (n, _) = square();
        let err = Mesh2d::new(n.clone(), vec![[0, 1, 7]], vec![0], vec![], vec![]).unwrap_err();
        assert!(matches!(err, ModelError::NodeOutOfRange { node: 7, .. }));
        let err = Mesh2d::new(n, vec![[0, 1, 2]], vec![0], vec![], vec![]).unwrap_err();
        assert_eq!(err, ModelError::UnusedNode { node: 3 });
    }

    #[test]
    fn collinear_triangle_is_degenerate() {
        let nodes = vec![[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]];
        let err = Mesh2d::new(nodes, vec![[0, 1, 2]], vec![0], vec![], vec![]).unwrap_err();
        assert!(err.to_string().contains("triangle element 0"), "{err}");
    }
}
