//! Contact of the cut flanks (issue "self-contact"): when a press or a negative pull closes
//! the incision, the flank facets are searched for facing pairs (the seed-001 search in
//! `crate::contact`) and non-penetration is enforced node-to-facet by penalty springs, with an
//! active-set loop: solve, search, hold every flank node found behind a facing flank facet
//! of its twin's neighbourhood, release every held node whose spring would pull, re-solve,
//! until the set repeats. Quadratic flank faces take part as their four sub-triangles
//! (corners and mid-edge nodes), so mid-edge nodes are held too.
//!
//! The search tolerance is h, the y size of the cell in front of the cut: facing flank
//! facets closer than that are candidates, and the signed node-to-facet gap decides (flat
//! flanks that have slid through each other neither touch nor cross, so a proximity search
//! with a small tolerance would miss them).
//!
//! No adhesion: a spring pushes (g < 0 at equilibrium) or is released. A node joins the set
//! when it lies behind a facing flank facet (g < 0) and leaves it when the gap of its spring
//! at the new equilibrium is no longer negative, i.e. when the spring would pull the flanks
//! together. Once the set repeats, the springs are linearized again at the equilibrium,
//! each against its own facet, and the set settled again, until the linearization no longer
//! changes ([`FlankContact::linearized_alike`]): the springs are then linearized where they
//! hold, not where their nodes were caught, and the answer is the same whatever the loading
//! history (a block closed and then pulled open ends with no springs, as a block pulled open
//! at once; a cut pulled open and then closed ends as one closed at once, to 1e-9). Where
//! that does not settle in the step's bound of solves, or lets a node slide deeper than
//! the small-sliding limit below, the answer with the springs linearized where their nodes
//! were caught stays, and the scene warns once per run. Not so under a press on closed
//! flanks: one load step or two end at different equilibria there (docs/theory/cutblock.md),
//! and the scene warns once per run that the answer may depend on the loading history.
//!
//! Penalty stiffness k_p = 1000 · E · h (N/mm): a thousand times the axial stiffness of that
//! cell per unit face area, so the penetration under a contact force F is F / k_p. The gap of
//! node s against facet m (unit outward normal n, barycentric weights N_i of the projection
//! of s) is g = n · (x_s − Σ N_i x_i) on the deformed configuration; with n and N_i frozen
//! per search or re-linearization it is linear in u, g = g₀ + Bᵀu, giving the force
//! k_p g B and the stiffness k_p B Bᵀ (in the linear model the load −k_p g₀ B).
//!
//! The pattern includes, once per topology, a potential contact element between each flank
//! node and each facet of the opposite flank around its twin (small sliding), so activating
//! contacts refactorizes numerically on the existing symbolic analysis. Beyond that range
//! (a node behind a facet away from its twin, which no spring can hold, or springs whose
//! normals froze before a large rotation) the flanks end up passing through each other: a
//! penetration deeper than [`SLIDING_LIMIT`] · h is reported as a runtime error rather than
//! returned as an answer. Within range the penalty leaves F / k_p (0.2 µm at 3 mm closing).

use std::collections::HashMap;

use nalgebra::{SMatrix, SVector, Vector3};

use crate::assembly::Assembler;
use crate::contact::{sorting, BvKind, Bvh, Search, Surface};

/// Penalty stiffness per (E · h).
pub const PENALTY_FACTOR: f64 = 1000.0;

/// The deepest penetration the scene accepts, per h (5 µm on 5 mm cells: a quarter of the
/// scanner's noise).
pub const SLIDING_LIMIT: f64 = 1e-3;

/// Smallest barycentric coordinate of a node's projection that still lies on a facet.
const EDGE: f64 = -1e-6;

/// How close a spring's linearization must be to the one at the present state (B, and the
/// gap per h) for the springs to count as linearized where they are.
const RELINEARIZED: f64 = 1e-6;

/// Tree degradation (see `Bvh::degradation`) beyond which the flank tree is rebuilt.
pub const REBUILD_DEGRADATION: f64 = 1.5;

/// One active contact: element index in the assembler, the held node, B vector, g₀.
#[derive(Debug, Clone, PartialEq)]
pub struct Spring {
    pub element: usize,
    pub node: usize,
    pub b: SVector<f64, 12>,
    pub g0: f64,
}

/// What a solve changes in the contact: the springs and what the last detection found.
#[derive(Debug, Clone, PartialEq)]
pub struct Held {
    pub active: Vec<Spring>,
    pub penetration: f64,
    pub deepest: Option<usize>,
}

/// Flank contact of one cut topology.
#[derive(Debug)]
pub struct FlankContact {
    surface: Surface,
    bvh: Bvh,
    /// (mesh node, flank facet) → assembler element.
    candidates: HashMap<(usize, usize), usize>,
    /// Node lists of the candidate elements: [slave, master₀, master₁, master₂].
    pub elements: Vec<[usize; 4]>,
    tolerance: f64,
    first_element: usize,
    /// The springs of the current factorization.
    pub active: Vec<Spring>,
    /// Deepest penetration found by the last detection (mm, ≥ 0) and the node (held or
    /// not) that penetrates that deep.
    pub penetration: f64,
    pub deepest: Option<usize>,
}

/// The deepest penetration seen so far and its node.
#[derive(Default)]
struct Deepest {
    depth: f64,
    node: Option<usize>,
}

impl Deepest {
    fn record(&mut self, node: usize, depth: f64) {
        if depth > self.depth {
            (self.depth, self.node) = (depth, Some(node));
        }
    }
}

impl FlankContact {
    /// The springs and the last detection's result, to put back with [`Self::hold`].
    pub fn held(&self) -> Held {
        Held {
            active: self.active.clone(),
            penetration: self.penetration,
            deepest: self.deepest,
        }
    }

    pub fn hold(&mut self, held: &Held) {
        self.active.clone_from(&held.active);
        (self.penetration, self.deepest) = (held.penetration, held.deepest);
    }

    /// Contact of the flank `facets` (triangles of flank nodes, outward), for the facing
    /// node pairs `flank_pairs`; `first_element` is the assembler index of the first
    /// candidate element. `None` if there are no flank facets.
    pub fn new(
        nodes: &[[f64; 3]],
        facets: Vec<[usize; 3]>,
        flank_pairs: &[(usize, usize)],
        first_element: usize,
        h: f64,
    ) -> Option<Self> {
        if facets.is_empty() {
            return None;
        }
        let surface = Surface::new(3, &facets);
        let mut facets_at: HashMap<usize, Vec<usize>> = HashMap::new();
        for (i, f) in facets.iter().enumerate() {
            for &n in f {
                facets_at.entry(n).or_default().push(i);
            }
        }
        let mut candidates = HashMap::new();
        let mut elements = Vec::new();
        for &(front, back) in flank_pairs {
            for (slave, twin) in [(front, back), (back, front)] {
                for &facet in facets_at.get(&twin).into_iter().flatten() {
                    let f = facets[facet];
                    if f.contains(&slave) {
                        continue;
                    }
                    candidates.insert((slave, facet), first_element + elements.len());
                    elements.push([slave, f[0], f[1], f[2]]);
                }
            }
        }
        let positions = surface.positions(nodes, None, 3);
        let bvh = Bvh::build(&surface, &positions, BvKind::Aabb);
        Some(Self {
            surface,
            bvh,
            candidates,
            elements,
            tolerance: h,
            first_element,
            active: Vec::new(),
            penetration: 0.0,
            deepest: None,
        })
    }

    /// Searches the deformed flanks (displacements `u`) and returns the springs that should
    /// be active, sorted: every node behind a facing facet, and every held node whose spring
    /// still pushes; also updates `penetration`.
    pub fn detect(&mut self, nodes: &[[f64; 3]], u: &[f64]) -> Vec<Spring> {
        let positions = self.surface.positions(nodes, Some(u), 3);
        self.bvh.refit(&self.surface, &positions, self.tolerance);
        if self.bvh.degradation() > REBUILD_DEGRADATION {
            self.bvh = Bvh::build(&self.surface, &positions, BvKind::Aabb);
            self.bvh.refit(&self.surface, &positions, self.tolerance);
        }
        let (pairs, _) = Search::run(&self.surface, &self.bvh, &positions, self.tolerance);
        // One spring per penetrating node: against the facet it lies deepest behind.
        let mut best: HashMap<usize, (f64, Spring)> = HashMap::new();
        let mut deepest = Deepest::default();
        for o in sorting::sort(&self.surface, &pairs) {
            for (slave_facet, master) in [(o.slave, o.master), (o.master, o.slave)] {
                for &local in &self.surface.facets[slave_facet] {
                    let node = self.surface.nodes[local];
                    let Some((g, g0, b)) = gap(nodes, u, node, self.mesh_facet(master), EDGE)
                    else {
                        continue;
                    };
                    if g >= 0.0 {
                        continue;
                    }
                    deepest.record(node, -g);
                    let Some(&element) = self.candidates.get(&(node, master)) else {
                        continue;
                    };
                    let spring = Spring {
                        element,
                        node,
                        b,
                        g0,
                    };
                    match best.get(&node) {
                        Some((depth, _)) if *depth >= -g => {}
                        _ => {
                            best.insert(node, (-g, spring));
                        }
                    }
                }
            }
        }
        // A held node the search no longer sees (its projection slid off the facet's edge)
        // stays held while its spring still pushes (its own linearized gap is negative).
        for s in &self.active {
            if let std::collections::hash_map::Entry::Vacant(slot) = best.entry(s.node) {
                let g = self.gap_of(s, u);
                if g < 0.0 {
                    deepest.record(s.node, -g);
                    slot.insert((-g, s.clone()));
                }
            }
        }
        (self.penetration, self.deepest) = (deepest.depth, deepest.node);
        let mut springs: Vec<Spring> = best.into_values().map(|(_, s)| s).collect();
        springs.sort_by_key(|s| s.node);
        springs
    }

    fn mesh_facet(&self, facet: usize) -> [usize; 3] {
        self.surface.facets[facet].map(|v| self.surface.nodes[v])
    }

    /// Whether `springs` hold the same nodes as the current factorization's (a node that
    /// slid onto a neighbouring facet of the same flank does not restart the loop).
    pub fn same_as_active(&self, springs: &[Spring]) -> bool {
        springs.len() == self.active.len()
            && springs
                .iter()
                .zip(&self.active)
                .all(|(a, b)| a.node == b.node)
    }

    /// The active springs linearized at displacements `u`, each against the facet it was
    /// caught on (its projection clamped onto it, however far off); `None` if a facet has
    /// degenerated to zero area.
    pub fn relinearized(&self, nodes: &[[f64; 3]], u: &[f64]) -> Option<Vec<Spring>> {
        self.active
            .iter()
            .map(|s| {
                let [node, m @ ..] = self.elements[s.element - self.first_element];
                let (_, g0, b) = gap(nodes, u, node, m, f64::NEG_INFINITY)?;
                Some(Spring { g0, b, ..s.clone() })
            })
            .collect()
    }

    /// Whether `springs` (the active ones linearized again, [`Self::relinearized`]) are
    /// the active ones within [`RELINEARIZED`] in B and [`RELINEARIZED`] · h in the gaps
    /// g₀ + Bᵀu.
    pub fn linearized_alike(&self, springs: &[Spring], u: &[f64]) -> bool {
        springs.len() == self.active.len()
            && springs.iter().zip(&self.active).all(|(a, b)| {
                (a.b - b.b).amax() <= RELINEARIZED
                    && (self.gap_of(a, u) - self.gap_of(b, u)).abs()
                        <= RELINEARIZED * self.tolerance
            })
    }

    /// Adds k_p B Bᵀ of the active springs to `k`.
    pub fn add_stiffness(&self, asm: &Assembler, penalty: f64, k: &mut [f64]) {
        for s in &self.active {
            let ke: SMatrix<f64, 12, 12> = s.b * s.b.transpose() * penalty;
            asm.add(k, s.element, &ke);
        }
    }

    /// The linearized gap g₀ + Bᵀu of a spring.
    fn gap_of(&self, s: &Spring, u: &[f64]) -> f64 {
        let nodes = self.elements[s.element - self.first_element];
        s.g0 + (0..12)
            .map(|k| s.b[k] * u[3 * nodes[k / 3] + k % 3])
            .sum::<f64>()
    }

    /// Adds the spring forces k_p (g₀ + Bᵀu) B of the active springs to `f`.
    pub fn add_forces(&self, penalty: f64, u: &[f64], f: &mut [f64]) {
        for s in &self.active {
            let g = self.gap_of(s, u);
            let nodes = self.elements[s.element - self.first_element];
            for (i, &n) in nodes.iter().enumerate() {
                for d in 0..3 {
                    f[3 * n + d] += penalty * g * s.b[3 * i + d];
                }
            }
        }
    }

    /// Adds −k_p g₀ B of the active springs to `f`.
    pub fn add_loads(&self, penalty: f64, f: &mut [f64]) {
        for s in &self.active {
            let nodes = self.elements[s.element - self.first_element];
            for (i, &n) in nodes.iter().enumerate() {
                for d in 0..3 {
                    f[3 * n + d] -= penalty * s.g0 * s.b[3 * i + d];
                }
            }
        }
    }
}

/// Gap of node `node` against facet `m` (outward normal from the node order) at
/// displacements `u`: (g, g₀, B), or `None` if the projection misses the facet (a
/// barycentric coordinate below `edge`, or a facet of zero area); a projection off the
/// facet by less (any, for `edge` = −∞) is clamped onto it, its barycentric coordinates
/// cut at zero and scaled to sum to one.
fn gap(
    nodes: &[[f64; 3]],
    u: &[f64],
    node: usize,
    m: [usize; 3],
    edge: f64,
) -> Option<(f64, f64, SVector<f64, 12>)> {
    let x = |n: usize| Vector3::from(nodes[n]) + Vector3::new(u[3 * n], u[3 * n + 1], u[3 * n + 2]);
    let (a, b, c, s) = (x(m[0]), x(m[1]), x(m[2]), x(node));
    let normal = (b - a).cross(&(c - a));
    let area2 = normal.norm();
    if area2 == 0.0 {
        return None;
    }
    let n = normal / area2;
    let p = s - n * n.dot(&(s - a));
    let w = |q: Vector3<f64>, r: Vector3<f64>| (q - p).cross(&(r - p)).dot(&n) / area2;
    let mut weights = [w(b, c), w(c, a), w(a, b)];
    if weights.iter().any(|&l| l < 0.0) {
        if weights.iter().any(|&l| l < edge) {
            return None;
        }
        // Clamped onto the facet.
        weights = weights.map(|l| l.max(0.0));
        let sum: f64 = weights.iter().sum();
        weights = weights.map(|l| l / sum);
    }
    let mut bvec = SVector::<f64, 12>::zeros();
    for d in 0..3 {
        bvec[d] = n[d];
        for (i, &l) in weights.iter().enumerate() {
            bvec[3 * (i + 1) + d] = -l * n[d];
        }
    }
    let reference = |k: usize| Vector3::from(nodes[k]);
    let x0 = reference(node)
        - weights
            .iter()
            .zip(m)
            .map(|(&l, k)| reference(k) * l)
            .sum::<Vector3<f64>>();
    Some((n.dot(&(s - a)), n.dot(&x0), bvec))
}
