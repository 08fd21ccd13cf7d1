//! The mid-edge nodes of a quadratic mesh derived from a linear one (tri6 from tri3, tet10
//! from tet4): the corners keep their numbers, every edge gets one node at its midpoint,
//! numbered after the corners in order of first appearance.

use std::collections::{HashMap, HashSet};

/// Corner pair (smaller index first) → mid-edge node.
#[derive(Debug, Clone, Default)]
pub struct MidEdges(HashMap<(usize, usize), usize>);

/// The midpoint of `p` and `r`.
fn midpoint<const D: usize>(p: [f64; D], r: [f64; D]) -> [f64; D] {
    std::array::from_fn(|d| 0.5 * (p[d] + r[d]))
}

/// The corner pair of an edge, smaller index first.
pub fn key(a: usize, b: usize) -> (usize, usize) {
    (a.min(b), a.max(b))
}

impl MidEdges {
    pub fn with_capacity(edges: usize) -> Self {
        Self(HashMap::with_capacity(edges))
    }

    /// The mid-edge node of the edge `a`–`b`, appended to `nodes` at the midpoint when the
    /// edge is new.
    pub fn node<const D: usize>(&mut self, a: usize, b: usize, nodes: &mut Vec<[f64; D]>) -> usize {
        *self.0.entry(key(a, b)).or_insert_with(|| {
            nodes.push(midpoint(nodes[a], nodes[b]));
            nodes.len() - 1
        })
    }

    /// Puts every mid-edge node of `nodes` at the midpoint of its edge's corners there.
    pub fn place<const D: usize>(&self, nodes: &mut [[f64; D]]) {
        for (&(a, b), &m) in &self.0 {
            nodes[m] = midpoint(nodes[a], nodes[b]);
        }
    }

    /// The mid-edge node between corners `a` and `b`, if they share an edge.
    pub fn get(&self, a: usize, b: usize) -> Option<usize> {
        self.0.get(&key(a, b)).copied()
    }

    /// Every edge (corner pair, smaller first) with its mid-edge node, in no particular order.
    pub fn iter(&self) -> impl Iterator<Item = ((usize, usize), usize)> + '_ {
        self.0.iter().map(|(&k, &m)| (k, m))
    }

    /// A set of corner nodes with the mid-edge nodes of the edges between them, sorted after
    /// the corners (a node set on a straight edge or a planar face stays the nodes on it).
    pub fn extend(&self, corners: &[usize]) -> Vec<usize> {
        let inside: HashSet<usize> = corners.iter().copied().collect();
        let mut mids: Vec<usize> = self
            .iter()
            .filter(|((a, b), _)| inside.contains(a) && inside.contains(b))
            .map(|(_, m)| m)
            .collect();
        mids.sort_unstable();
        let mut out = corners.to_vec();
        out.extend(mids);
        out
    }
}
