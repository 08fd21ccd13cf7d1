//! Quadratic tetrahedra on a linear mesh: the corner nodes keep their numbers, and every edge
//! gets one mid-edge node at its midpoint, numbered after the corners in order of first
//! appearance. Derived after a cut, the mesh duplicates mid-edge nodes consistently with the
//! corners: an edge between two duplicated corners exists once on each flank (its ends are
//! different nodes there), so it gets a mid-edge node per flank; an edge between two shared
//! crack-front corners is one edge with one shared mid-edge node.

use std::collections::HashMap;

use super::mid_edges::MidEdges;
use super::Mesh3d;
use crate::element::tet10::EDGES;

/// A mesh of 10-node tetrahedra (node order as [`crate::element::tet10`]).
#[derive(Debug, Clone)]
pub struct QuadraticMesh {
    nodes: Vec<[f64; 3]>,
    tets: Vec<[usize; 10]>,
    mid: MidEdges,
}

impl QuadraticMesh {
    /// Adds the mid-edge nodes of `mesh`.
    pub fn new(mesh: &Mesh3d) -> Self {
        let mut nodes = mesh.nodes().to_vec();
        let mut mid = MidEdges::with_capacity(7 * nodes.len());
        let tets = mesh
            .tets()
            .iter()
            .map(|t| {
                let mut q = [0; 10];
                q[..4].copy_from_slice(t);
                for (k, [i, j]) in EDGES.iter().enumerate() {
                    q[4 + k] = mid.node(t[*i], t[*j], &mut nodes);
                }
                q
            })
            .collect();
        Self { nodes, tets, mid }
    }

    /// The mesh on `corners`, the linear mesh it was derived from with its nodes moved: the
    /// corners at their new positions, every mid-edge node at its edge's new midpoint (the
    /// same nodes, to the bit, as [`Self::new`] of `corners` makes).
    pub fn moved(&self, corners: &Mesh3d) -> Self {
        let mut nodes = self.nodes.clone();
        nodes[..corners.nodes().len()].copy_from_slice(corners.nodes());
        self.mid.place(&mut nodes);
        Self {
            nodes,
            tets: self.tets.clone(),
            mid: self.mid.clone(),
        }
    }

    /// Node coordinates (mm): the corners, then the mid-edge nodes.
    pub fn nodes(&self) -> &[[f64; 3]] {
        &self.nodes
    }

    /// The tetrahedra's ten nodes each (node order as [`crate::element::tet10`]).
    pub fn tets(&self) -> &[[usize; 10]] {
        &self.tets
    }

    /// The mid-edge node between corners `a` and `b`, if they share an edge.
    pub fn mid(&self, a: usize, b: usize) -> Option<usize> {
        self.mid.get(a, b)
    }

    /// A set of corner nodes with the mid-edge nodes of the edges between them (a node set of
    /// a planar face stays the nodes on that face).
    pub fn extend(&self, corners: &[usize]) -> Vec<usize> {
        self.mid.extend(corners)
    }

    /// Pairs of nodes facing each other across a cut, from the corner pairs: the corner
    /// pairs themselves and the mid-edge nodes of facing flank edges. Crack-front corners
    /// (shared) count as facing themselves, so an edge from a front corner to a flank corner
    /// pairs with its twin on the other flank.
    pub fn facing_pairs(
        &self,
        corner_pairs: &[(usize, usize)],
        front: &[usize],
    ) -> Vec<(usize, usize)> {
        let mut twin: HashMap<usize, usize> = corner_pairs.iter().copied().collect();
        twin.extend(front.iter().map(|&n| (n, n)));
        let front_flank: std::collections::HashSet<usize> =
            corner_pairs.iter().map(|&(f, _)| f).collect();
        let mut pairs = corner_pairs.to_vec();
        // Edges with a corner on the front flank and both corners on the cut; their twins
        // join the twin corners.
        let mut mids: Vec<(usize, usize)> = self
            .mid
            .iter()
            .filter(|((a, b), _)| front_flank.contains(a) || front_flank.contains(b))
            .filter_map(|((a, b), m)| {
                let other = self.mid(*twin.get(&a)?, *twin.get(&b)?)?;
                (other != m).then_some((m, other))
            })
            .collect();
        mids.sort_unstable();
        pairs.extend(mids);
        pairs
    }

    /// The six nodes of the boundary face with these corners (in the order given), ordered
    /// as [`crate::element::tet10::FACES`] orders a face: corners, then the mid-edge nodes
    /// of the edges first–second, second–third, third–first.
    pub fn face(&self, corners: [usize; 3]) -> [usize; 6] {
        let m = |a: usize, b: usize| self.mid(a, b).expect("face edges are mesh edges");
        let [a, b, c] = corners;
        [a, b, c, m(a, b), m(b, c), m(c, a)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::cut::{split, Incision};
    use crate::mesh::generate;
    use crate::mesh::mid_edges::key;

    #[test]
    fn mid_edge_nodes_sit_at_midpoints_and_are_shared_by_neighbours() {
        let m = generate::block([2.0, 3.0, 1.0], [2, 3, 1]).unwrap();
        let q = QuadraticMesh::new(&m);
        // One mid-edge node per distinct edge of the linear mesh.
        let mut edges: Vec<(usize, usize)> = m
            .tets()
            .iter()
            .flat_map(|t| EDGES.map(|[i, j]| key(t[i], t[j])))
            .collect();
        edges.sort_unstable();
        edges.dedup();
        assert_eq!(q.nodes().len(), m.nodes().len() + edges.len());
        for t in q.tets() {
            for (k, [i, j]) in EDGES.iter().enumerate() {
                let (a, b, c) = (q.nodes()[t[*i]], q.nodes()[t[*j]], q.nodes()[t[4 + k]]);
                for d in 0..3 {
                    assert!((c[d] - 0.5 * (a[d] + b[d])).abs() < 1e-15);
                }
            }
        }
    }

    #[test]
    fn a_cut_duplicates_flank_mid_nodes_and_shares_front_ones() {
        let m = generate::block([2.0, 2.0, 2.0], [2, 2, 2]).unwrap();
        let cut = split(
            &m,
            &Incision {
                y: 1.0,
                x: (0.0, 2.0),
                z: (1.0, 2.0),
            },
        )
        .unwrap();
        let q = QuadraticMesh::new(&cut.mesh);
        let front: Vec<usize> = (0..cut.mesh.nodes().len())
            .filter(|&n| {
                let p = cut.mesh.nodes()[n];
                p[1] == 1.0 && p[2] == 1.0
            })
            .collect();
        let pairs = q.facing_pairs(&cut.flank_pairs, &front);
        assert!(pairs.len() > cut.flank_pairs.len());
        for &(a, b) in &pairs {
            assert_ne!(a, b);
            let (p, r) = (q.nodes()[a], q.nodes()[b]);
            assert!(
                p == r,
                "facing nodes share their reference position: {p:?} {r:?}"
            );
            assert!(p[1] == 1.0 && p[2] >= 1.0, "{p:?} lies on the cut");
        }
        // Every node at a reference position on the open cut above the front has a twin.
        let on_cut: Vec<usize> = (0..q.nodes().len())
            .filter(|&n| {
                let p = q.nodes()[n];
                p[1] == 1.0 && p[2] > 1.0
            })
            .collect();
        for n in on_cut {
            assert!(
                pairs.iter().any(|&(a, b)| a == n || b == n),
                "node {n} has no twin"
            );
        }
    }
}
