//! Bottom-up bounding-volume hierarchy by face clustering (seed 001 §3.3): every facet is a
//! dual node; the dual edge of least cost
//!
//! E = (E_fit + k · N_E) · perim² / projArea          (seed 001 eq. 3.7, k = 1e-4)
//!
//! is contracted until one cluster remains, each contraction creating one tree node (2n − 1
//! nodes for n facets). E_fit is the mean squared distance of the cluster's vertices to their
//! least-squares plane, the smallest eigenvalue of the PCA covariance Z = A − b bᵀ/c built
//! from the cluster quadric (A, b, c) = Σ (v vᵀ, v, 1) (eq. 3.14–3.16), divided by c; for 2D
//! segment surfaces the fit is to a line. perim is the cluster's boundary length (2D: its
//! curve length), projArea the length of the area-weighted normal sum. Dual edges join facets
//! that share a node.
//!
//! Bounding volumes are k-DOPs over a selectable axis set (AABB = 3 axes), refitted bottom-up
//! in O(n) after deformation (§3.2.3). Each node also carries the 26-direction bit set of the
//! curvature criterion (§3.4.2): bit d is set if every unit facet normal in the node lies
//! within 45° of direction d (n̂·d ≥ cos 45°). Seed 001 asks only for n̂·d > 0, which rules out
//! interpenetration; the 45° cone also rules out proximity: any two normals of such a node are
//! at most 90° apart, so no two of its facets face each other (see `search::facing`), and the
//! node can be pruned without missing a pair. The border
//! nodes of each cluster (its nodes that also belong to facets outside it) make the adjacency
//! test of §3.4.3 a merge of two short sorted lists.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, HashMap};

use nalgebra::{Matrix2, Matrix3, SymmetricEigen, Vector3};

use super::surface::Surface;

/// cos 45°: the half-angle of the direction cones of the curvature criterion.
pub const CONE_COS: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The cost constant k of seed 001 eq. 3.7 (after Willmott 2000).
pub const K_COUNT: f64 = 1e-4;

/// Bounding-volume type (seed 001 §3.1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BvKind {
    /// Axis-aligned box: 3 axes.
    Aabb,
    /// 14-DOP: the 3 coordinate axes and the 4 cube diagonals.
    Dop14,
    /// 18-DOP: the 3 coordinate axes and the 6 face diagonals.
    Dop18,
    /// 26-DOP: all 13 axes.
    Dop26,
}

const COORD: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
const CORNER: [[f64; 3]; 4] = [
    [1.0, 1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, -1.0],
    [1.0, -1.0, -1.0],
];
const EDGE: [[f64; 3]; 6] = [
    [1.0, 1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 0.0, 1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, 1.0],
    [0.0, 1.0, -1.0],
];

impl BvKind {
    fn axes(self) -> Vec<Vector3<f64>> {
        let list: Vec<[f64; 3]> = match self {
            BvKind::Aabb => COORD.to_vec(),
            BvKind::Dop14 => COORD.iter().chain(&CORNER).copied().collect(),
            BvKind::Dop18 => COORD.iter().chain(&EDGE).copied().collect(),
            BvKind::Dop26 => COORD.iter().chain(&CORNER).chain(&EDGE).copied().collect(),
        };
        list.into_iter()
            .map(|a| Vector3::from(a).normalize())
            .collect()
    }
}

/// The 26 directions of the curvature criterion's direction box (cube corners, edge midpoints
/// and face centres, seed 001 Fig. 3.23).
fn directions() -> Vec<Vector3<f64>> {
    let mut d = Vec::with_capacity(26);
    for i in -1..=1 {
        for j in -1..=1 {
            for k in -1..=1 {
                if (i, j, k) != (0, 0, 0) {
                    d.push(Vector3::new(f64::from(i), f64::from(j), f64::from(k)).normalize());
                }
            }
        }
    }
    d
}

/// Area-weighted normal of a facet (outward for counter-clockwise triangles; for 2D segments
/// a → b of a counter-clockwise boundary, (Δy, −Δx)).
pub fn facet_normal(p: &[[f64; 3]; 3], arity: usize) -> Vector3<f64> {
    let (a, b, c) = (
        Vector3::from(p[0]),
        Vector3::from(p[1]),
        Vector3::from(p[2]),
    );
    if arity == 2 {
        let t = b - a;
        Vector3::new(t.y, -t.x, 0.0)
    } else {
        0.5 * (b - a).cross(&(c - a))
    }
}

/// Statistics of a cluster during construction.
#[derive(Debug, Clone)]
struct Cluster {
    a: Matrix3<f64>,
    b: Vector3<f64>,
    c: f64,
    normal: Vector3<f64>,
    count: usize,
    /// 3D: boundary edges (sorted node pairs) of the cluster; 2D: unused.
    edges: HashMap<(usize, usize), f64>,
    /// Boundary length (3D) or curve length (2D).
    perim: f64,
    neighbours: Vec<usize>,
    node: usize,
    version: u32,
}

impl Cluster {
    fn fit_error(a: &Matrix3<f64>, b: &Vector3<f64>, c: f64, arity: usize) -> f64 {
        let z = a - b * b.transpose() / c;
        let smallest = if arity == 2 {
            SymmetricEigen::new(Matrix2::new(z[(0, 0)], z[(0, 1)], z[(1, 0)], z[(1, 1)]))
                .eigenvalues
                .min()
        } else {
            SymmetricEigen::new(z).eigenvalues.min()
        };
        smallest.max(0.0) / c
    }

    /// Perimeter of the union of `self` and `other` (3D: boundary edges not shared).
    fn merged_perimeter(&self, other: &Cluster, arity: usize) -> f64 {
        if arity == 2 {
            return self.perim + other.perim;
        }
        let (small, large) = if self.edges.len() < other.edges.len() {
            (self, other)
        } else {
            (other, self)
        };
        let shared: f64 = small
            .edges
            .iter()
            .filter(|(e, _)| large.edges.contains_key(e))
            .map(|(_, l)| l)
            .sum();
        self.perim + other.perim - 2.0 * shared
    }

    fn cost(&self, other: &Cluster, arity: usize) -> f64 {
        let (a, b, c) = (self.a + other.a, self.b + other.b, self.c + other.c);
        let fit = Self::fit_error(&a, &b, c, arity);
        let perim = self.merged_perimeter(other, arity);
        let proj = (self.normal + other.normal).norm().max(1e-300);
        (fit + K_COUNT * (self.count + other.count) as f64) * perim * perim / proj
    }
}

/// The hierarchy: nodes `0..n` are the facets (leaves), `n..2n−1` the clusters in creation
/// order (children before parents), the last one the root.
#[derive(Debug, Clone)]
pub struct Bvh {
    kind: BvKind,
    axes: Vec<Vector3<f64>>,
    n_leaves: usize,
    children: Vec<[usize; 2]>,
    /// Facets below each node.
    pub size: Vec<usize>,
    lo: Vec<f64>,
    hi: Vec<f64>,
    /// Curvature-criterion direction bits per node (26 bits).
    pub dirs: Vec<u32>,
    /// Border nodes of each cluster (sorted).
    border: Vec<Vec<usize>>,
    /// Σ of internal-node extents relative to the root extent, at the last build.
    built_spread: f64,
    /// Inflation of the last refit.
    tolerance: f64,
}

impl Bvh {
    /// Builds the hierarchy for the surface at `positions` (surface-node numbering).
    pub fn build(surface: &Surface, positions: &[[f64; 3]], kind: BvKind) -> Self {
        let n = surface.facets.len();
        assert!(n > 0, "a contact surface needs at least one facet");
        let arity = surface.arity;
        let mut clusters: Vec<Cluster> = (0..n)
            .map(|i| leaf_cluster(surface, positions, i))
            .collect();
        let mut children = Vec::with_capacity(n.saturating_sub(1));
        let mut size: Vec<usize> = vec![1; n];
        let mut heap = BinaryHeap::new();
        let push = |heap: &mut BinaryHeap<_>, clusters: &[Cluster], u: usize, v: usize| {
            let cost = clusters[u].cost(&clusters[v], arity);
            heap.push(Reverse((
                Ordered(cost),
                u,
                v,
                clusters[u].version,
                clusters[v].version,
            )));
        };
        for u in 0..n {
            for &v in &clusters[u].neighbours.clone() {
                if u < v {
                    push(&mut heap, &clusters, u, v);
                }
            }
        }
        let mut alive: Vec<bool> = vec![true; n];
        while let Some(Reverse((_, u, v, vu, vv))) = heap.pop() {
            if !(alive[u] && alive[v] && clusters[u].version == vu && clusters[v].version == vv) {
                continue;
            }
            let (nu, nv) = (clusters[u].node, clusters[v].node);
            let w = merge(&mut clusters, &mut alive, u, v, arity, n + children.len());
            children.push([nu, nv]);
            size.push(size[nu] + size[nv]);
            for x in clusters[w].neighbours.clone() {
                push(&mut heap, &clusters, w, x);
            }
        }
        // Disconnected surfaces: join the remaining roots in index order.
        let mut roots: Vec<usize> = (0..clusters.len()).filter(|&i| alive[i]).collect();
        while roots.len() > 1 {
            let (u, v) = (roots[0], roots[1]);
            let (nu, nv) = (clusters[u].node, clusters[v].node);
            merge(&mut clusters, &mut alive, u, v, arity, n + children.len());
            children.push([nu, nv]);
            size.push(size[nu] + size[nv]);
            roots.remove(1);
        }
        let axes = kind.axes();
        let n_nodes = 2 * n - 1;
        let mut bvh = Self {
            kind,
            n_leaves: n,
            children,
            size,
            lo: vec![0.0; n_nodes * axes.len()],
            hi: vec![0.0; n_nodes * axes.len()],
            axes,
            dirs: vec![0; n_nodes],
            border: Vec::new(),
            built_spread: 0.0,
            tolerance: 0.0,
        };
        bvh.border = bvh.borders(surface);
        bvh.refit(surface, positions, 0.0);
        bvh.built_spread = bvh.spread();
        bvh
    }

    /// The bounding-volume type.
    pub fn kind(&self) -> BvKind {
        self.kind
    }

    /// Number of tree nodes: 2n − 1 for n facets.
    pub fn n_nodes(&self) -> usize {
        2 * self.n_leaves - 1
    }

    /// The root node (the last one).
    pub fn root(&self) -> usize {
        self.n_nodes() - 1
    }

    /// Whether `node` is a leaf (a facet: `node` < n).
    pub fn is_leaf(&self, node: usize) -> bool {
        node < self.n_leaves
    }

    /// The two children of the cluster `node`, which must not be a leaf.
    pub fn children(&self, node: usize) -> [usize; 2] {
        self.children[node - self.n_leaves]
    }

    /// The border nodes of `node` (sorted): its surface nodes that also belong to facets
    /// outside it.
    pub fn border(&self, node: usize) -> &[usize] {
        &self.border[node]
    }

    /// Border nodes per tree node: nodes of the cluster with facets outside it.
    fn borders(&self, surface: &Surface) -> Vec<Vec<usize>> {
        let mut incident = vec![0usize; surface.nodes.len()];
        for f in &surface.facets {
            for &v in &f[..surface.arity] {
                incident[v] += 1;
            }
        }
        // (node, facets of the cluster at that node), sorted by node.
        let mut counts: Vec<Vec<(usize, usize)>> = Vec::with_capacity(self.n_nodes());
        for f in &surface.facets {
            let mut c: Vec<(usize, usize)> = f[..surface.arity].iter().map(|&v| (v, 1)).collect();
            c.sort_unstable();
            c.dedup();
            counts.push(c);
        }
        for &[l, r] in &self.children {
            let (a, b) = (&counts[l], &counts[r]);
            let mut merged = Vec::with_capacity(a.len() + b.len());
            let (mut i, mut j) = (0, 0);
            while i < a.len() || j < b.len() {
                let next = match (a.get(i), b.get(j)) {
                    (Some(x), Some(y)) if x.0 == y.0 => {
                        i += 1;
                        j += 1;
                        (x.0, x.1 + y.1)
                    }
                    (Some(x), Some(y)) if x.0 < y.0 => {
                        i += 1;
                        *x
                    }
                    (Some(x), None) => {
                        i += 1;
                        *x
                    }
                    (_, Some(y)) => {
                        j += 1;
                        *y
                    }
                    (None, None) => unreachable!(),
                };
                if next.1 < incident[next.0] {
                    merged.push(next);
                }
            }
            counts.push(merged);
        }
        counts
            .into_iter()
            .map(|c| c.into_iter().map(|(v, _)| v).collect())
            .collect()
    }

    /// Recomputes bounding volumes (inflated by `tolerance / 2` on every side) and
    /// direction bits bottom-up for new positions: O(n).
    pub fn refit(&mut self, surface: &Surface, positions: &[[f64; 3]], tolerance: f64) {
        let k = self.axes.len();
        self.tolerance = tolerance;
        let dirs = directions();
        for (i, f) in surface.facets.iter().enumerate() {
            let p = f.map(|v| positions[v]);
            for (a, axis) in self.axes.iter().enumerate() {
                let proj = p[..surface.arity]
                    .iter()
                    .map(|q| axis.dot(&Vector3::from(*q)));
                let (lo, hi) = proj.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                });
                self.lo[i * k + a] = lo - 0.5 * tolerance;
                self.hi[i * k + a] = hi + 0.5 * tolerance;
            }
            let normal = facet_normal(&p, surface.arity).normalize();
            self.dirs[i] = dirs.iter().enumerate().fold(0, |bits, (d, dir)| {
                if normal.dot(dir) >= CONE_COS {
                    bits | (1 << d)
                } else {
                    bits
                }
            });
        }
        for (j, &[l, r]) in self.children.iter().enumerate() {
            let node = self.n_leaves + j;
            for a in 0..k {
                self.lo[node * k + a] = self.lo[l * k + a].min(self.lo[r * k + a]);
                self.hi[node * k + a] = self.hi[l * k + a].max(self.hi[r * k + a]);
            }
            self.dirs[node] = self.dirs[l] & self.dirs[r];
        }
    }

    /// Whether the bounding volumes of two nodes overlap.
    pub fn overlap(&self, a: usize, b: usize) -> bool {
        let k = self.axes.len();
        (0..k).all(|i| {
            self.lo[a * k + i] <= self.hi[b * k + i] && self.lo[b * k + i] <= self.hi[a * k + i]
        })
    }

    fn spread(&self) -> f64 {
        let k = self.axes.len();
        let extent = |n: usize| {
            (0..k)
                .map(|i| self.hi[n * k + i] - self.lo[n * k + i] - self.tolerance)
                .sum::<f64>()
        };
        let root = extent(self.root()).max(1e-300);
        (self.n_leaves..self.n_nodes()).map(extent).sum::<f64>() / root
    }

    /// Tree quality relative to the last build: the summed extents of the internal nodes
    /// (relative to the root's) now, divided by the same at build time. Clusters that were
    /// compact but have been pulled apart by the deformation raise it; rebuild when it
    /// exceeds about 1.5.
    pub fn degradation(&self) -> f64 {
        self.spread() / self.built_spread.max(1e-300)
    }
}

/// Total order on costs for the heap (NaN last).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Ordered(f64);
impl Eq for Ordered {}
impl PartialOrd for Ordered {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Ordered {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.0.total_cmp(&other.0)
    }
}

fn leaf_cluster(surface: &Surface, positions: &[[f64; 3]], i: usize) -> Cluster {
    let f = surface.facets[i];
    let arity = surface.arity;
    let p = f.map(|v| positions[v]);
    let mut a = Matrix3::zeros();
    let mut b = Vector3::zeros();
    for q in &p[..arity] {
        let v = Vector3::from(*q);
        a += v * v.transpose();
        b += v;
    }
    let mut edges = HashMap::new();
    let mut perim = 0.0;
    for k in 0..arity {
        let (u, w) = (f[k], f[(k + 1) % arity]);
        let len = (Vector3::from(positions[u]) - Vector3::from(positions[w])).norm();
        if arity == 3 {
            edges.insert((u.min(w), u.max(w)), len);
            perim += len;
        } else if k == 0 {
            perim = len;
        }
    }
    Cluster {
        a,
        b,
        c: arity as f64,
        normal: facet_normal(&p, arity),
        count: 1,
        edges,
        perim,
        neighbours: surface.neighbours[i].clone(),
        node: i,
        version: 0,
    }
}

/// Merges cluster v into u (the larger edge map survives); returns u, now standing for the
/// new tree node `node`.
fn merge(
    clusters: &mut [Cluster],
    alive: &mut [bool],
    u: usize,
    v: usize,
    arity: usize,
    node: usize,
) -> usize {
    let perim = clusters[u].merged_perimeter(&clusters[v], arity);
    let v_node = clusters[v].node;
    let other = std::mem::replace(
        &mut clusters[v],
        Cluster {
            a: Matrix3::zeros(),
            b: Vector3::zeros(),
            c: 0.0,
            normal: Vector3::zeros(),
            count: 0,
            edges: HashMap::new(),
            perim: 0.0,
            neighbours: Vec::new(),
            node: v_node,
            version: 0,
        },
    );
    alive[v] = false;
    let w = &mut clusters[u];
    let (mut small, mut large) = (other.edges, std::mem::take(&mut w.edges));
    if small.len() > large.len() {
        std::mem::swap(&mut small, &mut large);
    }
    for (e, l) in small {
        if large.remove(&e).is_none() {
            large.insert(e, l);
        }
    }
    w.edges = large;
    w.a += other.a;
    w.b += other.b;
    w.c += other.c;
    w.normal += other.normal;
    w.count += other.count;
    w.perim = perim;
    let mut nb: Vec<usize> = w
        .neighbours
        .iter()
        .chain(&other.neighbours)
        .copied()
        .filter(|&x| x != u && x != v)
        .collect();
    nb.sort_unstable();
    nb.dedup();
    w.neighbours = nb.clone();
    w.node = node;
    w.version += 1;
    for x in nb {
        let list = &mut clusters[x].neighbours;
        list.retain(|&y| y != v);
        if !list.contains(&u) {
            list.push(u);
        }
    }
    u
}
