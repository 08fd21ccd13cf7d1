//! A displacement field carried from one cut mesh to another, where a blade advance that
//! changes the mesh starts Newton's method (issue 27: it re-solves from the previous
//! equilibrium, not from the unloaded block): the path of equilibria extrapolated to the
//! new front on the old mesh slid there ([`super::path`]), or the last equilibrium; and
//! the last equilibrium onto the new mesh slid back, the new pattern's path.
//!
//! Each node of the new mesh takes the old displacement field at its reference position
//! (clamped to the old mesh's extent in x):
//! the old element that contains the point is found through a grid of the old mesh's node
//! planes, and the field is evaluated with that element's shape functions (linear or
//! quadratic). A node on the cut plane that belongs to one flank reads the field from the
//! elements on its side of the plane, so the two flanks of a cut keep their opening; the
//! rest of the cut plane is continuous and reads either side. The result is a starting
//! point for Newton's method, not an equilibrium: nothing depends on it but the iterations.

use nalgebra::{Matrix3, Vector3};

use crate::assembly::tetrahedra::{Elements, Solid};
use crate::element::tet10;

/// Which side of the cut plane y = y_cut a node or element lies on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Side {
    Front,
    Back,
    /// A node whose elements lie on both sides (off the cut plane, or on its uncut part).
    Either,
}

/// A point location in the old mesh: its elements bucketed by the cell of the node-plane
/// grid that holds their centroid.
struct Grid {
    planes: [Vec<f64>; 3],
    cells: Vec<Vec<usize>>,
}

impl Grid {
    fn new(solid: &Solid) -> Self {
        let nodes = solid.nodes();
        let planes: [Vec<f64>; 3] = std::array::from_fn(|d| {
            let mut v: Vec<f64> = (0..solid.len())
                .flat_map(|e| solid.corners(e))
                .map(|n| nodes[n][d])
                .collect();
            v.sort_by(f64::total_cmp);
            v.dedup();
            v
        });
        let mut grid = Self {
            cells: vec![Vec::new(); planes.iter().map(|p| p.len() - 1).product()],
            planes,
        };
        for e in 0..solid.len() {
            let c = centroid(nodes, solid.corners(e));
            let i = grid.index(std::array::from_fn(|d| grid.cell(d, c[d])));
            grid.cells[i].push(e);
        }
        grid
    }

    /// The cell along axis `d` whose interior or lower face holds `x` (clamped).
    fn cell(&self, d: usize, x: f64) -> usize {
        let p = &self.planes[d];
        p.partition_point(|&q| q <= x).clamp(1, p.len() - 1) - 1
    }

    fn index(&self, c: [usize; 3]) -> usize {
        let n = self.planes.each_ref().map(|p| p.len() - 1);
        c[0] + n[0] * (c[1] + n[1] * c[2])
    }

    /// The elements of the cells that touch `p` (one cell, or up to eight on planes).
    fn near(&self, p: [f64; 3]) -> impl Iterator<Item = usize> + '_ {
        let range = |d: usize| {
            let c = self.cell(d, p[d]);
            let on_lower = c > 0 && (p[d] - self.planes[d][c]).abs() <= 1e-9;
            (if on_lower { c - 1 } else { c })..=c
        };
        let (rx, ry, rz) = (range(0), range(1), range(2));
        rz.flat_map(move |k| {
            let rx = rx.clone();
            ry.clone()
                .flat_map(move |j| rx.clone().map(move |i| [i, j, k]))
        })
        .flat_map(|c| self.cells[self.index(c)].iter().copied())
    }
}

fn centroid(nodes: &[[f64; 3]], corners: [usize; 4]) -> [f64; 3] {
    std::array::from_fn(|d| corners.iter().map(|&n| nodes[n][d]).sum::<f64>() / 4.0)
}

fn element_side(nodes: &[[f64; 3]], corners: [usize; 4], y_cut: f64) -> Side {
    if centroid(nodes, corners)[1] < y_cut {
        Side::Front
    } else {
        Side::Back
    }
}

/// Each node's side: that of its elements if they all lie on one side of the cut plane and
/// the node is on it, else `Either`.
fn node_sides(solid: &Solid, y_cut: f64) -> Vec<Side> {
    let nodes = solid.nodes();
    let mut seen = vec![(false, false); nodes.len()];
    for (e, element) in solid.connectivity().iter().enumerate() {
        let side = element_side(nodes, solid.corners(e), y_cut);
        for &n in element.iter() {
            match side {
                Side::Front => seen[n].0 = true,
                _ => seen[n].1 = true,
            }
        }
    }
    seen.iter()
        .zip(nodes)
        .map(|(&s, p)| match s {
            (true, false) if p[1] == y_cut => Side::Front,
            (false, true) if p[1] == y_cut => Side::Back,
            _ => Side::Either,
        })
        .collect()
}

/// Barycentric coordinates of `p` in the tetrahedron with corners `c`.
fn barycentric(c: [[f64; 3]; 4], p: [f64; 3]) -> Option<[f64; 4]> {
    let v = |a: [f64; 3]| Vector3::new(a[0] - c[0][0], a[1] - c[0][1], a[2] - c[0][2]);
    let m = Matrix3::from_columns(&[v(c[1]), v(c[2]), v(c[3])]);
    let l = m.try_inverse()? * v(p);
    Some([1.0 - l.sum(), l[0], l[1], l[2]])
}

/// The displacements (all dofs) of `to`'s nodes read from the field `u` on `from`, with
/// the cut plane at `y_cut`; a node beyond `from`'s ends in x reads the field on the end
/// face it lies beyond (meshes slid along x reach past each other's ends); `None` if a
/// node lies in no element of `from` otherwise (the meshes do not cover the same block).
pub fn transfer(from: &Solid, u: &[f64], to: &Solid, y_cut: f64) -> Option<Vec<f64>> {
    let grid = Grid::new(from);
    let (old, sides) = (from.nodes(), node_sides(to, y_cut));
    let connectivity = from.connectivity();
    let xs = &grid.planes[0];
    let (first, last) = (xs[0], xs[xs.len() - 1]);
    let mut out = vec![0.0; to.n_dofs()];
    for (n, &[x, y, z]) in to.nodes().iter().enumerate() {
        let p = [x.clamp(first, last), y, z];
        let (e, l) = grid.near(p).find_map(|e| {
            let corners = from.corners(e);
            let side = element_side(old, corners, y_cut);
            if sides[n] != Side::Either && side != sides[n] {
                return None;
            }
            let l = barycentric(corners.map(|c| old[c]), p)?;
            l.iter().all(|&x| x >= -1e-9).then_some((e, l))
        })?;
        let weights: Vec<f64> = match from.elements() {
            Elements::Tet4(_) => l.to_vec(),
            Elements::Tet10(_) => tet10::values(&l).iter().copied().collect(),
        };
        for (&node, w) in connectivity[e].iter().zip(weights) {
            for d in 0..3 {
                out[3 * n + d] += w * u[3 * node + d];
            }
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assembly::tetrahedra::Tetrahedron;
    use crate::element::{Elastic, Law, Material};
    use crate::mesh::generate::{block_on_planes, Split};

    fn solid(x: Vec<f64>, split: Split, kind: Tetrahedron) -> Solid {
        let planes = [x, vec![0.0, 1.0, 2.5, 4.0], vec![0.0, 1.5, 3.0]];
        let mesh = block_on_planes(&planes, split).unwrap();
        let material = Material::new(Law::NeoHookean, Elastic::new("m", 1.0, 0.3).unwrap());
        Solid::new(&mesh, kind, material)
    }

    /// The shape functions interpolate their own polynomials exactly: a linear field
    /// carried from one tet4 mesh to another with other x planes and the other split, and a
    /// quadratic field between tet10 meshes, arrive unchanged at every new node.
    #[test]
    fn fields_the_elements_represent_arrive_exactly() {
        let linear = |p: &[f64; 3]| [0.3 * p[0] - p[1] + 2.0, p[2] - 0.1 * p[0], 0.5 * p[1]];
        let quadratic = |p: &[f64; 3]| {
            let [a, b, c] = linear(p);
            [a + p[0] * p[1], b - p[2] * p[2], c + 0.2 * p[0] * p[0]]
        };
        type Field<'a> = &'a dyn Fn(&[f64; 3]) -> [f64; 3];
        let field: [(Tetrahedron, Field); 2] = [
            (Tetrahedron::Tet4, &linear),
            (Tetrahedron::Tet10, &quadratic),
        ];
        for (kind, f) in field {
            let from = solid(
                vec![0.0, 2.0, 4.0, 6.0],
                Split::Alternating { mirrored: false },
                kind,
            );
            let to = solid(
                vec![0.0, 0.7, 2.7, 4.7, 6.0],
                Split::ExtrudedX { mirrored: true },
                kind,
            );
            let u: Vec<f64> = from.nodes().iter().flat_map(f).collect();
            let carried = transfer(&from, &u, &to, 2.5).unwrap();
            for (n, p) in to.nodes().iter().enumerate() {
                let exact = f(p);
                for d in 0..3 {
                    let got = carried[3 * n + d];
                    assert!(
                        (got - exact[d]).abs() < 1e-12,
                        "{kind:?} node {n} {p:?}: {got}"
                    );
                }
            }
        }
    }

    /// A node beyond the old mesh's ends in x reads the field on the end face it lies
    /// beyond (at its own y and z); the nodes within read it exactly.
    #[test]
    fn nodes_beyond_the_ends_read_the_end_faces() {
        let f = |p: &[f64; 3]| [0.3 * p[0] - p[1] + 2.0, p[2] - 0.1 * p[0], 0.5 * p[1]];
        let split = Split::ExtrudedX { mirrored: false };
        let from = solid(vec![0.0, 2.0, 4.0, 6.0], split, Tetrahedron::Tet4);
        let to = solid(vec![-1.0, 0.7, 2.7, 4.7, 7.0], split, Tetrahedron::Tet4);
        let u: Vec<f64> = from.nodes().iter().flat_map(f).collect();
        let carried = transfer(&from, &u, &to, 2.5).unwrap();
        for (n, &[x, y, z]) in to.nodes().iter().enumerate() {
            let exact = f(&[x.clamp(0.0, 6.0), y, z]);
            for d in 0..3 {
                let got = carried[3 * n + d];
                assert!((got - exact[d]).abs() < 1e-12, "node {n} at x = {x}: {got}");
            }
        }
    }
}
