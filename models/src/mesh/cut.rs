//! Cuts in a tetrahedral mesh (seed 002 §1.4, §3.4): a planar incision y = y₀ over a
//! rectangle x ∈ [x₀, x₁], z ∈ [z₀, z₁], made between elements, either by duplicating the
//! nodes on the cut faces ([`split`]) or by deleting the layer of elements in front of the
//! cut ([`delete`]). Both return the new mesh and the pairs of flank nodes facing each other.

use std::collections::HashMap;

use super::{Mesh3d, NodeSets};
use crate::error::ModelError;

/// A planar incision in the plane y = `y` over `x` × `z` (mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Incision {
    /// The y coordinate y₀ of the cut plane (mm).
    pub y: f64,
    /// The incision's extent in x, (x₀, x₁) (mm).
    pub x: (f64, f64),
    /// The incision's extent in z, (z₀, z₁) (mm).
    pub z: (f64, f64),
}

/// A cut mesh and the node pairs (front flank, back flank) that faced each other across the
/// cut before it opened (front: y < y₀ side).
#[derive(Debug, Clone)]
pub struct CutMesh {
    /// The mesh after the cut.
    pub mesh: Mesh3d,
    /// The node pairs (front flank, back flank) facing each other across the cut.
    pub flank_pairs: Vec<(usize, usize)>,
}

/// Geometric tolerance relative to the mesh extent.
const TOL: f64 = 1e-9;

fn sorted(mut f: [usize; 3]) -> [usize; 3] {
    f.sort_unstable();
    f
}

/// Interior faces (shared by two tetrahedra) that lie in the incision: all three nodes on
/// the plane, centroid inside the rectangle.
pub fn cut_faces(mesh: &Mesh3d, cut: &Incision) -> Vec<[usize; 3]> {
    let tol = TOL * mesh.extent();
    let p = mesh.nodes();
    let mut count: HashMap<[usize; 3], u8> = HashMap::new();
    for t in mesh.tets() {
        for skip in 0..4 {
            let f = sorted(std::array::from_fn(|k| t[if k < skip { k } else { k + 1 }]));
            if f.iter().all(|&n| (p[n][1] - cut.y).abs() <= tol) {
                *count.entry(f).or_default() += 1;
            }
        }
    }
    let inside = |f: &[usize; 3]| {
        let c = |d: usize| f.iter().map(|&n| p[n][d]).sum::<f64>() / 3.0;
        let (cx, cz) = (c(0), c(2));
        cx >= cut.x.0 - tol && cx <= cut.x.1 + tol && cz >= cut.z.0 - tol && cz <= cut.z.1 + tol
    };
    let mut faces: Vec<_> = count
        .into_iter()
        .filter(|(f, c)| *c == 2 && inside(f))
        .map(|(f, _)| f)
        .collect();
    faces.sort_unstable();
    faces
}

/// Minimal union–find over `n` items.
struct Components(Vec<usize>);

impl Components {
    fn new(n: usize) -> Self {
        Self((0..n).collect())
    }
    fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }
    fn union(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.find(a), self.find(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

/// Cuts by node duplication (seed 002 §3.4): around each node of a cut face, the incident
/// tetrahedra are grouped into those still connected through uncut faces containing the
/// node; every group beyond the first gets its own copy of the node. Nodes on the crack front
/// stay shared (their tetrahedra remain connected around the front), so the cut ends there.
pub fn split(mesh: &Mesh3d, cut: &Incision) -> Result<CutMesh, ModelError> {
    let faces = cut_faces(mesh, cut);
    let is_cut: std::collections::HashSet<[usize; 3]> = faces.iter().copied().collect();
    let mut cut_nodes: Vec<usize> = faces.iter().flatten().copied().collect();
    cut_nodes.sort_unstable();
    cut_nodes.dedup();
    let mut incident: HashMap<usize, Vec<usize>> =
        cut_nodes.iter().map(|&n| (n, Vec::new())).collect();
    for (t, tet) in mesh.tets().iter().enumerate() {
        for n in tet {
            if let Some(list) = incident.get_mut(n) {
                list.push(t);
            }
        }
    }
    let mut nodes = mesh.nodes().to_vec();
    let mut tets = mesh.tets().to_vec();
    let mut copies: Vec<(usize, usize)> = Vec::new();
    for &n in &cut_nodes {
        let around = &incident[&n];
        let mut comp = Components::new(around.len());
        let mut by_face: HashMap<[usize; 3], usize> = HashMap::new();
        for (i, &t) in around.iter().enumerate() {
            let tet = mesh.tets()[t];
            for skip in 0..4 {
                let f = sorted(std::array::from_fn(|k| {
                    tet[if k < skip { k } else { k + 1 }]
                }));
                if !f.contains(&n) || is_cut.contains(&f) {
                    continue;
                }
                if let Some(&j) = by_face.get(&f) {
                    comp.union(i, j);
                } else {
                    by_face.insert(f, i);
                }
            }
        }
        // The group on the y > y₀ side (back flank) gets the new node.
        let roots: Vec<usize> = (0..around.len()).map(|i| comp.find(i)).collect();
        let mut distinct = roots.clone();
        distinct.sort_unstable();
        distinct.dedup();
        if distinct.len() < 2 {
            continue;
        }
        let centroid_y = |t: usize| {
            mesh.tets()[t]
                .iter()
                .map(|&v| mesh.nodes()[v][1])
                .sum::<f64>()
                / 4.0
        };
        for &root in &distinct {
            let members: Vec<usize> = (0..around.len())
                .filter(|&i| roots[i] == root)
                .map(|i| around[i])
                .collect();
            if centroid_y(members[0]) < cut.y {
                continue;
            }
            let copy = nodes.len();
            nodes.push(nodes[n]);
            copies.push((n, copy));
            for t in members {
                for v in tets[t].iter_mut().filter(|v| **v == n) {
                    *v = copy;
                }
            }
        }
    }
    let mut cut_mesh = Mesh3d::new(nodes, tets)?;
    copy_sets(mesh.node_sets(), &mut cut_mesh, |n| {
        std::iter::once(n)
            .chain(copies.iter().filter(move |c| c.0 == n).map(|c| c.1))
            .collect()
    })?;
    Ok(CutMesh {
        mesh: cut_mesh,
        flank_pairs: copies,
    })
}

/// Cuts by element deletion (seed 002 §1.4): removes the tetrahedra whose centroid lies in
/// the slab y₀ − `thickness` < y < y₀ over the incision rectangle, then drops nodes no
/// element uses. The flank pairs join nodes at the same (x, z) on both sides of the gap.
pub fn delete(mesh: &Mesh3d, cut: &Incision, thickness: f64) -> Result<CutMesh, ModelError> {
    let p = mesh.nodes();
    let tol = TOL * mesh.extent();
    let in_slab = |tet: &[usize; 4]| {
        let c = |d: usize| tet.iter().map(|&n| p[n][d]).sum::<f64>() / 4.0;
        let (x, y, z) = (c(0), c(1), c(2));
        y > cut.y - thickness
            && y < cut.y
            && x > cut.x.0
            && x < cut.x.1
            && z > cut.z.0
            && z < cut.z.1
    };
    let kept: Vec<[usize; 4]> = mesh
        .tets()
        .iter()
        .filter(|t| !in_slab(t))
        .copied()
        .collect();
    let mut new_index = vec![usize::MAX; p.len()];
    let mut nodes = Vec::new();
    for t in &kept {
        for &n in t {
            if new_index[n] == usize::MAX {
                new_index[n] = nodes.len();
                nodes.push(p[n]);
            }
        }
    }
    let tets = kept.iter().map(|t| t.map(|n| new_index[n])).collect();
    let mut cut_mesh = Mesh3d::new(nodes, tets)?;
    copy_sets(mesh.node_sets(), &mut cut_mesh, |n| {
        if new_index[n] == usize::MAX {
            vec![]
        } else {
            vec![new_index[n]]
        }
    })?;
    // Pair the nodes across the gap: front at y₀ − thickness, back at y₀, same (x, z).
    let np = cut_mesh.nodes();
    let key = |q: &[f64; 3]| ((q[0] / tol).round() as i64, (q[2] / tol).round() as i64);
    let face_nodes = |y: f64| {
        (0..np.len()).filter(move |&n| {
            let q = np[n];
            (q[1] - y).abs() <= tol
                && q[0] >= cut.x.0 - tol
                && q[0] <= cut.x.1 + tol
                && q[2] >= cut.z.0 - tol
        })
    };
    let back: HashMap<(i64, i64), usize> = face_nodes(cut.y).map(|n| (key(&np[n]), n)).collect();
    let flank_pairs = face_nodes(cut.y - thickness)
        .filter_map(|f| back.get(&key(&np[f])).map(|&b| (f, b)))
        .collect();
    Ok(CutMesh {
        mesh: cut_mesh,
        flank_pairs,
    })
}

/// Rebuilds every node set of `from` in `to`, mapping each old node to the new nodes that
/// stand for it; sets that lose all nodes are dropped.
fn copy_sets(
    from: &NodeSets,
    to: &mut Mesh3d,
    map: impl Fn(usize) -> Vec<usize>,
) -> Result<(), ModelError> {
    for (name, nodes) in from.iter() {
        let mapped: Vec<usize> = nodes.iter().flat_map(|&n| map(n)).collect();
        if !mapped.is_empty() {
            to.add_node_set(name, mapped)?;
        }
    }
    Ok(())
}

/// Connected components of the mesh (tetrahedra joined through shared nodes): the
/// component index of every node.
pub fn node_components(mesh: &Mesh3d) -> Vec<usize> {
    let mut comp = Components::new(mesh.nodes().len());
    for t in mesh.tets() {
        for k in 1..4 {
            comp.union(t[0], t[k]);
        }
    }
    (0..mesh.nodes().len()).map(|n| comp.find(n)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::generate;

    fn block() -> Mesh3d {
        generate::block([4.0, 4.0, 2.0], [2, 4, 2]).unwrap()
    }

    #[test]
    fn through_cut_splits_the_block_in_two() {
        let m = block();
        let cut = Incision {
            y: 2.0,
            x: (0.0, 4.0),
            z: (0.0, 2.0),
        };
        assert_eq!(cut_faces(&m, &cut).len(), 2 * 2 * 2);
        let c = split(&m, &cut).unwrap();
        // The whole 3 × 3 node plane at y = 2 is duplicated.
        assert_eq!(c.flank_pairs.len(), 9);
        assert_eq!(c.mesh.nodes().len(), m.nodes().len() + 9);
        let comps = node_components(&c.mesh);
        let mut distinct = comps.clone();
        distinct.sort_unstable();
        distinct.dedup();
        assert_eq!(distinct.len(), 2);
        // The boundary gains both flanks: 2 × 8 more triangles.
        assert_eq!(c.mesh.boundary().len(), m.boundary().len() + 16);
    }

    #[test]
    fn partial_cut_keeps_the_crack_front_shared() {
        let m = block();
        // Top half, first x cell: cut faces 1 cell × 1 cell = 2 triangles.
        let cut = Incision {
            y: 2.0,
            x: (0.0, 2.0),
            z: (1.0, 2.0),
        };
        let c = split(&m, &cut).unwrap();
        // The cut rectangle has nodes (x, z) ∈ {0, 2} × {1, 2}. Those on the crack front
        // (z = 1 or x = 2) stay shared because material below or beside the cut joins their
        // two sides; only the corner (0, 2), on the block's outer edge, is duplicated.
        assert_eq!(c.flank_pairs.len(), 1);
        assert_eq!(
            node_components(&c.mesh)
                .iter()
                .collect::<std::collections::HashSet<_>>()
                .len(),
            1
        );
    }

    #[test]
    fn deletion_removes_one_layer_and_pairs_the_gap() {
        let m = block();
        let cut = Incision {
            y: 2.0,
            x: (0.0, 4.0),
            z: (1.0, 2.0),
        };
        let c = delete(&m, &cut, 1.0).unwrap();
        assert_eq!(c.mesh.tets().len(), m.tets().len() - 2 * 5);
        // Gap faces: x ∈ {0, 2, 4}, z ∈ {1, 2} → 6 pairs.
        assert_eq!(c.flank_pairs.len(), 6);
        for (f, b) in c.flank_pairs {
            let (pf, pb) = (c.mesh.nodes()[f], c.mesh.nodes()[b]);
            assert_eq!((pf[0], pf[2]), (pb[0], pb[2]));
            assert_eq!(pb[1] - pf[1], 1.0);
        }
    }
}
