//! The recursive self-contact pair search (seed 001 §3.5) with the cost counters of §3.7,
//! a brute-force reference and a top-down median-split BVH baseline.
//!
//! Search within a node: if its direction bits are non-empty (curvature criterion) nothing
//! inside can touch; else search both children and then the pair of children. Search
//! between two nodes: no bounding-volume overlap → nothing; if the two are adjacent (their
//! border nodes intersect) and share a direction bit, their union cannot fold onto itself →
//! nothing; two leaves → the exact facet test [`contact`]; else descend into the larger. Adjacency is only
//! re-evaluated while the pair is adjacent: once two clusters are found apart, none of their
//! descendants can share a node, so the flag is passed down instead of recomputed — the
//! repetition seed 001 points out at the end of §3.5.1.

use super::bvh::{facet_normal, Bvh};
use super::geometry::within;
use super::surface::Surface;

/// How often each test ran (seed 001 §3.7 cost model).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Counters {
    /// Bounding-volume overlap tests.
    pub bv_tests: u64,
    /// Curvature-criterion tests: of a node's direction bits, and of the bits two adjacent
    /// nodes share.
    pub curvature_tests: u64,
    /// Adjacency tests (intersections of two nodes' border lists).
    pub adjacency_tests: u64,
    /// Leaf pairs that reached the exact facet test (those sharing a node included).
    pub facet_tests: u64,
}

/// A search over one surface and hierarchy.
pub struct Search<'a> {
    surface: &'a Surface,
    bvh: &'a Bvh,
    positions: &'a [[f64; 3]],
    tolerance: f64,
    /// How often each test ran so far.
    pub counters: Counters,
    pairs: Vec<(usize, usize)>,
}

impl<'a> Search<'a> {
    /// Facet pairs satisfying [`contact`] (closer than `tolerance`, facing, not sharing a node),
    /// sorted. The hierarchy
    /// must have been refitted with the same positions and tolerance.
    pub fn run(
        surface: &'a Surface,
        bvh: &'a Bvh,
        positions: &'a [[f64; 3]],
        tolerance: f64,
    ) -> (Vec<(usize, usize)>, Counters) {
        let mut s = Self {
            surface,
            bvh,
            positions,
            tolerance,
            counters: Counters::default(),
            pairs: Vec::new(),
        };
        s.within_node(bvh.root());
        s.pairs.sort_unstable();
        s.pairs.dedup();
        (s.pairs, s.counters)
    }

    fn within_node(&mut self, node: usize) {
        self.counters.curvature_tests += 1;
        if self.bvh.dirs[node] != 0 || self.bvh.is_leaf(node) {
            return;
        }
        let [l, r] = self.bvh.children(node);
        self.within_node(l);
        self.within_node(r);
        self.between(l, r, true);
    }

    fn between(&mut self, a: usize, b: usize, maybe_adjacent: bool) {
        self.counters.bv_tests += 1;
        if !self.bvh.overlap(a, b) {
            return;
        }
        let mut adjacent = false;
        if maybe_adjacent {
            self.counters.adjacency_tests += 1;
            adjacent = sorted_intersect(self.bvh.border(a), self.bvh.border(b));
            if adjacent {
                self.counters.curvature_tests += 1;
                if self.bvh.dirs[a] & self.bvh.dirs[b] != 0 {
                    return;
                }
            }
        }
        match (self.bvh.is_leaf(a), self.bvh.is_leaf(b)) {
            (true, true) => self.facets(a, b),
            (false, true) => self.split(a, b, adjacent),
            (true, false) => self.split(b, a, adjacent),
            (false, false) => {
                if self.bvh.size[a] >= self.bvh.size[b] {
                    self.split(a, b, adjacent)
                } else {
                    self.split(b, a, adjacent)
                }
            }
        }
    }

    fn split(&mut self, big: usize, other: usize, adjacent: bool) {
        let [l, r] = self.bvh.children(big);
        self.between(l, other, adjacent);
        self.between(r, other, adjacent);
    }

    fn facets(&mut self, a: usize, b: usize) {
        self.counters.facet_tests += 1;
        if self.surface.adjacent(a, b) {
            return;
        }
        if contact(self.surface, self.positions, a, b, self.tolerance) {
            self.pairs.push((a.min(b), a.max(b)));
        }
    }
}

/// Whether two facets face each other: their normals point in opposite half-spaces
/// (n_a · n_b < 0), as the two sides of a closing fold, crushed wall or cut do. Neighbouring
/// facets of a smooth bend (normals less than 90° apart) are not contact, however close.
pub fn facing(surface: &Surface, positions: &[[f64; 3]], a: usize, b: usize) -> bool {
    let n = |f: usize| facet_normal(&surface.facets[f].map(|v| positions[v]), surface.arity);
    n(a).dot(&n(b)) < 0.0
}

/// The contact-pair predicate: not adjacent, facing, and within `tolerance`.
pub fn contact(
    surface: &Surface,
    positions: &[[f64; 3]],
    a: usize,
    b: usize,
    tolerance: f64,
) -> bool {
    let at = |f: usize| surface.facets[f].map(|v| positions[v]);
    !surface.adjacent(a, b)
        && facing(surface, positions, a, b)
        && within(&at(a), &at(b), surface.arity, tolerance)
}

fn sorted_intersect(a: &[usize], b: &[usize]) -> bool {
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => i += 1,
            std::cmp::Ordering::Greater => j += 1,
            std::cmp::Ordering::Equal => return true,
        }
    }
    false
}

/// Every pair satisfying [`contact`], by testing all pairs: the reference.
pub fn brute_force(
    surface: &Surface,
    positions: &[[f64; 3]],
    tolerance: f64,
) -> Vec<(usize, usize)> {
    let n = surface.facets.len();
    let mut pairs = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            if contact(surface, positions, i, j, tolerance) {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// Baseline: a top-down AABB tree split at the median centroid along the longest axis, no
/// curvature pruning; every overlapping leaf pair that is not adjacent gets the exact test.
pub fn median_split(
    surface: &Surface,
    positions: &[[f64; 3]],
    tolerance: f64,
) -> (Vec<(usize, usize)>, Counters) {
    struct Node {
        lo: [f64; 3],
        hi: [f64; 3],
        kids: Option<[usize; 2]>,
        facet: usize,
    }
    fn bounds(
        surface: &Surface,
        positions: &[[f64; 3]],
        facets: &[usize],
        tol: f64,
    ) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for &f in facets {
            for &v in &surface.facets[f][..surface.arity] {
                for d in 0..3 {
                    lo[d] = lo[d].min(positions[v][d] - 0.5 * tol);
                    hi[d] = hi[d].max(positions[v][d] + 0.5 * tol);
                }
            }
        }
        (lo, hi)
    }
    fn build(
        surface: &Surface,
        positions: &[[f64; 3]],
        facets: &mut [usize],
        tol: f64,
        nodes: &mut Vec<Node>,
    ) -> usize {
        let (lo, hi) = bounds(surface, positions, facets, tol);
        if facets.len() == 1 {
            nodes.push(Node {
                lo,
                hi,
                kids: None,
                facet: facets[0],
            });
            return nodes.len() - 1;
        }
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(0);
        let centroid = |f: usize| {
            surface.facets[f][..surface.arity]
                .iter()
                .map(|&v| positions[v][axis])
                .sum::<f64>()
        };
        let mid = facets.len() / 2;
        facets.select_nth_unstable_by(mid, |&a, &b| centroid(a).total_cmp(&centroid(b)));
        let (left, right) = facets.split_at_mut(mid);
        let l = build(surface, positions, left, tol, nodes);
        let r = build(surface, positions, right, tol, nodes);
        nodes.push(Node {
            lo,
            hi,
            kids: Some([l, r]),
            facet: usize::MAX,
        });
        nodes.len() - 1
    }
    let mut facets: Vec<usize> = (0..surface.facets.len()).collect();
    let mut nodes = Vec::new();
    let root = build(surface, positions, &mut facets, tolerance, &mut nodes);
    let mut counters = Counters::default();
    let mut pairs = Vec::new();
    let overlap = |a: &Node, b: &Node| (0..3).all(|d| a.lo[d] <= b.hi[d] && b.lo[d] <= a.hi[d]);
    let mut stack = Vec::new();
    // Self pairs of every internal node become pair searches between its children.
    let mut within_stack = vec![root];
    while let Some(n) = within_stack.pop() {
        if let Some([l, r]) = nodes[n].kids {
            within_stack.extend([l, r]);
            stack.push((l, r));
        }
    }
    while let Some((a, b)) = stack.pop() {
        counters.bv_tests += 1;
        if !overlap(&nodes[a], &nodes[b]) {
            continue;
        }
        match (nodes[a].kids, nodes[b].kids) {
            (None, None) => {
                counters.facet_tests += 1;
                let (fa, fb) = (nodes[a].facet, nodes[b].facet);
                if contact(surface, positions, fa, fb, tolerance) {
                    pairs.push((fa.min(fb), fa.max(fb)));
                }
            }
            (Some([l, r]), _) => stack.extend([(l, b), (r, b)]),
            (None, Some([l, r])) => stack.extend([(a, l), (a, r)]),
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    (pairs, counters)
}
