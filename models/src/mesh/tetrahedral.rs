//! 3D mesh: nodes, 4-node tetrahedra, boundary faces (derived), named node sets.

use super::{check_all_used, check_connectivity, NodeSets, DEGENERATE_TOL};
use crate::element::tet4;
use crate::error::ModelError;

/// A triangle on the mesh boundary: its nodes ordered counter-clockwise seen from outside,
/// and the tetrahedron it belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BoundaryFace {
    /// Its nodes, counter-clockwise seen from outside.
    pub nodes: [usize; 3],
    /// The tetrahedron it belongs to.
    pub tet: usize,
}

/// A validated tetrahedral mesh (all tetrahedra with positive volume).
#[derive(Debug, Clone)]
pub struct Mesh3d {
    nodes: Vec<[f64; 3]>,
    tets: Vec<[usize; 4]>,
    boundary: Vec<BoundaryFace>,
    node_sets: NodeSets,
}

/// Faces of tetrahedron (0,1,2,3) with outward orientation for positive volume; face k is
/// opposite node k.
const TET_FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 3, 2], [0, 1, 3], [0, 2, 1]];

impl Mesh3d {
    /// Builds and validates a mesh: indices in range, every node used, no degenerate or
    /// inverted tetrahedron. Derives the boundary faces.
    pub fn new(nodes: Vec<[f64; 3]>, tets: Vec<[usize; 4]>) -> Result<Self, ModelError> {
        let mut used = vec![false; nodes.len()];
        check_connectivity("tetrahedron", &tets, &mut used)?;
        check_all_used(&used)?;
        let mut mesh = Self {
            nodes,
            tets,
            boundary: Vec::new(),
            node_sets: NodeSets::default(),
        };
        mesh.check_shapes()?;
        mesh.boundary = mesh.find_boundary();
        Ok(mesh)
    }

    /// The mesh with its nodes at `nodes` (one position per node): the tetrahedra, boundary
    /// faces and node sets kept, the shapes checked again (a boundary face keeps its
    /// outward orientation while no tetrahedron inverts).
    pub fn moved(&self, nodes: Vec<[f64; 3]>) -> Result<Self, ModelError> {
        if nodes.len() != self.nodes.len() {
            return Err(ModelError::SizeMismatch {
                name: "moved mesh nodes",
                expected: self.nodes.len(),
                got: nodes.len(),
            });
        }
        let mesh = Self {
            nodes,
            tets: self.tets.clone(),
            boundary: self.boundary.clone(),
            node_sets: self.node_sets.clone(),
        };
        mesh.check_shapes()?;
        Ok(mesh)
    }

    fn check_shapes(&self) -> Result<(), ModelError> {
        let tol = DEGENERATE_TOL * self.extent().powi(3);
        for index in 0..self.tets.len() {
            let vol = tet4::signed_volume(&self.tet(index));
            if vol.is_nan() || vol <= tol {
                return Err(ModelError::DegenerateElement {
                    kind: "tetrahedron",
                    index,
                    measure_name: "volume",
                    measure: vol,
                });
            }
        }
        Ok(())
    }

    /// Faces that belong to exactly one tetrahedron, in tetrahedron order: every face's
    /// sorted node triple and its index packed into one 128-bit key (32 bits each), the keys
    /// sorted, so that a face shared by two tetrahedra is a run of two (a sort of integers
    /// instead of a hash map: this runs at every blade advance).
    fn find_boundary(&self) -> Vec<BoundaryFace> {
        let faces: Vec<BoundaryFace> = self
            .tets
            .iter()
            .enumerate()
            .flat_map(|(tet, t)| {
                TET_FACES.map(|f| BoundaryFace {
                    nodes: f.map(|i| t[i]),
                    tet,
                })
            })
            .collect();
        let id = |n: usize| u32::try_from(n).expect("fewer than 2³² nodes and faces") as u128;
        let mut keys: Vec<u128> = faces
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let mut k = f.nodes;
                k.sort_unstable();
                id(k[0]) << 96 | id(k[1]) << 64 | id(k[2]) << 32 | id(i)
            })
            .collect();
        keys.sort_unstable();
        let mut single = vec![false; faces.len()];
        for run in keys.chunk_by(|a, b| a >> 32 == b >> 32) {
            if let [key] = run {
                single[(key & u128::from(u32::MAX)) as usize] = true;
            }
        }
        faces
            .into_iter()
            .zip(single)
            .filter_map(|(f, single)| single.then_some(f))
            .collect()
    }

    /// Largest bounding-box side length.
    pub fn extent(&self) -> f64 {
        (0..3)
            .map(|d| {
                let (lo, hi) = self.nodes.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                    (lo.min(p[d]), hi.max(p[d]))
                });
                hi - lo
            })
            .fold(0.0, f64::max)
    }

    /// Adds a named node set (validated).
    pub fn add_node_set(&mut self, name: &str, nodes: Vec<usize>) -> Result<(), ModelError> {
        self.node_sets.insert(name, nodes, self.nodes.len())
    }

    /// Node coordinates (mm).
    pub fn nodes(&self) -> &[[f64; 3]] {
        &self.nodes
    }
    /// The tetrahedra's four nodes each (positive volume).
    pub fn tets(&self) -> &[[usize; 4]] {
        &self.tets
    }
    /// The boundary faces (derived from the tetrahedra).
    pub fn boundary(&self) -> &[BoundaryFace] {
        &self.boundary
    }
    /// The named node sets.
    pub fn node_sets(&self) -> &NodeSets {
        &self.node_sets
    }

    /// Number of degrees of freedom (3 per node).
    pub fn n_dofs(&self) -> usize {
        3 * self.nodes.len()
    }

    /// Coordinates of tetrahedron `i`.
    pub fn tet(&self, i: usize) -> [[f64; 3]; 4] {
        self.tets[i].map(|n| self.nodes[n])
    }

    /// Global dofs of tetrahedron `i` in element order.
    pub fn tet_dofs(&self, i: usize) -> [usize; 12] {
        let t = self.tets[i];
        std::array::from_fn(|k| 3 * t[k / 3] + k % 3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unit_tet() -> Vec<[f64; 3]> {
        vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
        ]
    }

    #[test]
    fn single_tet_has_four_outward_faces() {
        let m = Mesh3d::new(unit_tet(), vec![[0, 1, 2, 3]]).unwrap();
        assert_eq!(m.boundary().len(), 4);
        let centroid = nalgebra::Vector3::new(0.25, 0.25, 0.25);
        for f in m.boundary() {
            let p = f.nodes.map(|n| m.nodes()[n]);
            let normal = tet4::face_area_normal(&p[0], &p[1], &p[2]);
            let to_face = nalgebra::Vector3::from(p[0]) - centroid;
            assert!(normal.dot(&to_face) > 0.0);
        }
    }

    #[test]
    fn inverted_tet_is_named_with_its_volume() {
        let err = Mesh3d::new(unit_tet(), vec![[0, 2, 1, 3]]).unwrap_err();
        assert_eq!(
            err,
            ModelError::DegenerateElement {
                kind: "tetrahedron",
                index: 0,
                measure_name: "volume",
                measure: -1.0 / 6.0
            }
        );
    }
}
