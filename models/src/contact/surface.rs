//! A contact surface: facets (triangles in 3D, segments in 2D) over node indices, node
//! positions (3D; 2D points have z = 0), and facet adjacency through shared nodes.

use crate::mesh::{Mesh2d, Mesh3d};

/// Facets over nodes. For segments the third entry repeats the second.
#[derive(Debug, Clone)]
pub struct Surface {
    /// 3 for triangles, 2 for segments.
    pub arity: usize,
    /// Each facet's surface nodes (numbered compactly); a segment repeats its second node.
    pub facets: Vec<[usize; 3]>,
    /// For each facet, the facets sharing at least one node with it (sorted).
    pub neighbours: Vec<Vec<usize>>,
    /// The mesh node of each surface node and the number of surface nodes.
    pub nodes: Vec<usize>,
}

impl Surface {
    /// Surface of facets given over mesh node numbers; renumbers the nodes compactly.
    pub fn new(arity: usize, mesh_facets: &[[usize; 3]]) -> Self {
        let mut nodes: Vec<usize> = mesh_facets
            .iter()
            .flat_map(|f| f[..arity].to_vec())
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        let local = |n: usize| nodes.binary_search(&n).expect("collected above");
        let facets: Vec<[usize; 3]> = mesh_facets
            .iter()
            .map(|f| {
                let l = f.map(local);
                if arity == 2 {
                    [l[0], l[1], l[1]]
                } else {
                    l
                }
            })
            .collect();
        let mut by_node: Vec<Vec<usize>> = vec![Vec::new(); nodes.len()];
        for (i, f) in facets.iter().enumerate() {
            for &n in &f[..arity] {
                by_node[n].push(i);
            }
        }
        let neighbours = facets
            .iter()
            .enumerate()
            .map(|(i, f)| {
                let mut nb: Vec<usize> = f[..arity]
                    .iter()
                    .flat_map(|&n| by_node[n].iter().copied())
                    .filter(|&j| j != i)
                    .collect();
                nb.sort_unstable();
                nb.dedup();
                nb
            })
            .collect();
        Self {
            arity,
            facets,
            neighbours,
            nodes,
        }
    }

    /// The boundary triangles of a tetrahedral mesh (cut flanks are boundary faces too).
    pub fn of_mesh3d(mesh: &Mesh3d) -> Self {
        let faces: Vec<[usize; 3]> = mesh.boundary().iter().map(|f| f.nodes).collect();
        Self::new(3, &faces)
    }

    /// The boundary segments of a triangle mesh (edges belonging to one triangle), oriented
    /// counter-clockwise around the body.
    pub fn of_mesh2d(mesh: &Mesh2d) -> Self {
        let mut count = std::collections::HashMap::new();
        for t in mesh.triangles() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                *count.entry((a.min(b), a.max(b))).or_insert(0) += 1;
            }
        }
        let mut segments = Vec::new();
        for t in mesh.triangles() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                if count[&(a.min(b), a.max(b))] == 1 {
                    segments.push([a, b, b]);
                }
            }
        }
        Self::new(2, &segments)
    }

    /// Surface-node positions gathered from mesh positions plus displacements (`dim` = 2 or
    /// 3 dofs per node).
    pub fn positions(
        &self,
        mesh_points: &[[f64; 3]],
        u: Option<&[f64]>,
        dim: usize,
    ) -> Vec<[f64; 3]> {
        self.nodes
            .iter()
            .map(|&n| {
                let mut p = mesh_points[n];
                if let Some(u) = u {
                    for d in 0..dim {
                        p[d] += u[dim * n + d];
                    }
                }
                p
            })
            .collect()
    }

    /// Whether facets `a` and `b` share a node.
    pub fn adjacent(&self, a: usize, b: usize) -> bool {
        self.neighbours[a].binary_search(&b).is_ok()
    }
}
