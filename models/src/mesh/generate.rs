//! Structured mesh generators for verification problems and for the cut block.

use super::{Mesh2d, Mesh3d};
use crate::budget;
use crate::element::tet4;
use crate::error::{positive, ModelError};

fn divisions(name: &str, n: usize) -> Result<usize, ModelError> {
    if n == 0 {
        return Err(ModelError::InvalidParameter {
            name: name.to_string(),
            value: 0.0,
            reason: "needs at least one division",
        });
    }
    Ok(n)
}

/// How the cells of a structured triangle mesh are split.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Diagonals {
    /// Diagonal direction alternates from cell to cell (no preferred direction; linear
    /// triangles on this pattern do not lock as ν → 0.5 in the tests we ran).
    Alternating,
    /// Every cell split along the same diagonal (locks badly as ν → 0.5).
    Uniform,
}

/// Maps a structured (nx+1)×(ny+1) grid `point(i, j)` to a triangle mesh (two triangles per
/// cell). Node sets: `i0`, `i1` (first/last column), `j0`, `j1` (first/last row).
fn grid_triangles(
    nx: usize,
    ny: usize,
    diagonals: Diagonals,
    point: impl Fn(usize, usize) -> [f64; 2],
) -> Result<Mesh2d, ModelError> {
    let id = |i: usize, j: usize| i + (nx + 1) * j;
    let nodes: Vec<_> = (0..=ny)
        .flat_map(|j| (0..=nx).map(move |i| (i, j)))
        .map(|(i, j)| point(i, j))
        .collect();
    let mut tris = Vec::with_capacity(2 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if diagonals == Diagonals::Uniform || (i + j) % 2 == 0 {
                tris.extend([[a, b, c], [a, c, d]]);
            } else {
                tris.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    let n = tris.len();
    let mut mesh = Mesh2d::new(nodes, tris, vec![0; n], vec![], vec![])?;
    mesh.add_node_set("i0", (0..=ny).map(|j| id(0, j)).collect())?;
    mesh.add_node_set("i1", (0..=ny).map(|j| id(nx, j)).collect())?;
    mesh.add_node_set("j0", (0..=nx).map(|i| id(i, 0)).collect())?;
    mesh.add_node_set("j1", (0..=nx).map(|i| id(i, ny)).collect())?;
    Ok(mesh)
}

/// Rectangle [0, lx] × [0, ly] with nx × ny cells of two triangles each, alternating
/// diagonals. Node sets `left` (x = 0), `right` (x = lx), `bottom` (y = 0), `top` (y = ly).
pub fn rectangle(lx: f64, ly: f64, nx: usize, ny: usize) -> Result<Mesh2d, ModelError> {
    rectangle_with(lx, ly, nx, ny, Diagonals::Alternating)
}

/// [`rectangle`] with a choice of diagonal pattern.
pub fn rectangle_with(
    lx: f64,
    ly: f64,
    nx: usize,
    ny: usize,
    diagonals: Diagonals,
) -> Result<Mesh2d, ModelError> {
    let (lx, ly) = (positive("lx", lx)?, positive("ly", ly)?);
    let (nx, ny) = (divisions("nx", nx)?, divisions("ny", ny)?);
    let mut mesh = grid_triangles(nx, ny, diagonals, |i, j| {
        [lx * i as f64 / nx as f64, ly * j as f64 / ny as f64]
    })?;
    rename(
        &mut mesh,
        [
            ("i0", "left"),
            ("i1", "right"),
            ("j0", "bottom"),
            ("j1", "top"),
        ],
    )?;
    Ok(mesh)
}

/// Quarter annulus a ≤ r ≤ b, 0 ≤ θ ≤ π/2 with nr radial × nt circumferential cells. Node sets
/// `inner` (r = a), `outer` (r = b), `x_axis` (θ = 0), `y_axis` (θ = π/2).
pub fn quarter_annulus(a: f64, b: f64, nr: usize, nt: usize) -> Result<Mesh2d, ModelError> {
    let (a, b) = (positive("a", a)?, positive("b", b)?);
    if b <= a {
        return Err(ModelError::InvalidParameter {
            name: "b".into(),
            value: b,
            reason: "outer radius must exceed the inner radius",
        });
    }
    let (nr, nt) = (divisions("nr", nr)?, divisions("nt", nt)?);
    let mut mesh = grid_triangles(nr, nt, Diagonals::Alternating, |i, j| {
        let r = a + (b - a) * i as f64 / nr as f64;
        let t = std::f64::consts::FRAC_PI_2 * j as f64 / nt as f64;
        [r * t.cos(), r * t.sin()]
    })?;
    rename(
        &mut mesh,
        [
            ("i0", "inner"),
            ("i1", "outer"),
            ("j0", "x_axis"),
            ("j1", "y_axis"),
        ],
    )?;
    Ok(mesh)
}

fn rename(mesh: &mut Mesh2d, names: [(&str, &str); 4]) -> Result<(), ModelError> {
    for (from, to) in names {
        let nodes = mesh.node_sets().get(from)?.to_vec();
        mesh.add_node_set(to, nodes)?;
    }
    Ok(())
}

/// Corner offsets (bit 0 = x, bit 1 = y, bit 2 = z) of the five tetrahedra of a cube whose
/// corner 0 is "even". The central tetrahedron joins the four corners with an odd number of
/// set bits; each of the other four cuts off one even corner. Every cube face is split along
/// the diagonal between its two odd corners.
const EVEN_CUBE: [[usize; 4]; 5] = [
    [1, 2, 4, 7],
    [0, 1, 2, 4],
    [3, 1, 2, 7],
    [5, 1, 4, 7],
    [6, 2, 4, 7],
];

/// Box [0, lx] × [0, ly] × [0, lz] of nx × ny × nz cubes, 5 tetrahedra per cube, with the
/// split mirrored in every other cube (seed 002 §3.1): a cube (i, j, k) with i + j + k odd
/// uses the mirror image (corner c ↦ c XOR 1), so that the face diagonals of neighbouring
/// cubes coincide and the mesh is conforming. Node sets `x0`, `x1`, `y0`, `y1`, `z0`, `z1`
/// for the six faces.
pub fn block(size: [f64; 3], cells: [usize; 3]) -> Result<Mesh3d, ModelError> {
    let axes = ["x", "y", "z"];
    for d in 0..3 {
        positive(&format!("l{}", axes[d]), size[d])?;
        divisions(&format!("n{}", axes[d]), cells[d])?;
    }
    let planes: [Vec<f64>; 3] = std::array::from_fn(|d| {
        (0..=cells[d])
            .map(|i| size[d] * i as f64 / cells[d] as f64)
            .collect()
    });
    block_on_planes(&planes, false)
}

/// Memory of a block mesh with `n` node planes per axis and of its assembled system,
/// estimated before anything is allocated: per node its coordinates and about 120 stored
/// entries of the 3-dof stiffness pattern (measured: 103–112 on the default mesh and two
/// refinements), each an index and three value copies (element sum, with contact, reduced);
/// per cube five tetrahedra with 32 bytes and a 12 × 12 scatter map of 8-byte indices each
/// (the assembler's map is smaller since 2026-11-27, 16 node pairs of 16 bytes: the
/// estimate errs towards refusing by about 4 kB per cube, and is kept so that the refusals
/// of the FMUs' tested ranges stay where they were).
fn block_bytes(n: [usize; 3]) -> usize {
    let nodes = n[0].saturating_mul(n[1]).saturating_mul(n[2]);
    let cells = (n[0] - 1).saturating_mul(n[1] - 1).saturating_mul(n[2] - 1);
    let per_node = 24 + 120 * (8 + 3 * 8);
    let per_cell = 5 * (32 + 144 * 8);
    nodes
        .saturating_mul(per_node)
        .saturating_add(cells.saturating_mul(per_cell))
}

/// Like [`block`], but on arbitrary (strictly increasing) node planes per axis, so that a
/// caller can place a node plane exactly where it needs one (a cut plane, a cut depth), and
/// with every cube's split mirrored if `mirrored` (cube (i, j, k) mirrored when
/// i + j + k + `mirrored` is odd), so that a caller that adds a plane can keep the split of
/// the cubes beyond it.
pub fn block_on_planes(planes: &[Vec<f64>; 3], mirrored: bool) -> Result<Mesh3d, ModelError> {
    for (d, p) in planes.iter().enumerate() {
        if p.len() < 2 || !p.windows(2).all(|w| w[1] > w[0]) {
            return Err(ModelError::InvalidParameter {
                name: format!("planes[{d}]"),
                value: p.len() as f64,
                reason: "needs at least two strictly increasing coordinates",
            });
        }
    }
    let n = [planes[0].len(), planes[1].len(), planes[2].len()];
    budget::claim("the block mesh and its sparse system", block_bytes(n))?;
    let id = |i: usize, j: usize, k: usize| i + n[0] * (j + n[1] * k);
    let mut nodes = Vec::with_capacity(n[0] * n[1] * n[2]);
    for k in 0..n[2] {
        for j in 0..n[1] {
            for i in 0..n[0] {
                nodes.push([planes[0][i], planes[1][j], planes[2][k]]);
            }
        }
    }
    let mut tets = Vec::with_capacity(5 * (n[0] - 1) * (n[1] - 1) * (n[2] - 1));
    for k in 0..n[2] - 1 {
        for j in 0..n[1] - 1 {
            for i in 0..n[0] - 1 {
                let flip = (i + j + k + usize::from(mirrored)) % 2;
                let corner = |c: usize| {
                    let c = c ^ flip;
                    id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1))
                };
                for t in EVEN_CUBE {
                    let mut tet = t.map(corner);
                    if tet4::signed_volume(&tet.map(|v| nodes[v])) < 0.0 {
                        tet.swap(2, 3);
                    }
                    tets.push(tet);
                }
            }
        }
    }
    let mut mesh = Mesh3d::new(nodes, tets)?;
    for (d, axis) in ["x", "y", "z"].iter().enumerate() {
        for (end, label) in [(0, "0"), (n[d] - 1, "1")] {
            let set = (0..mesh.nodes().len())
                .filter(|&v| {
                    let ijk = [v % n[0], (v / n[0]) % n[1], v / (n[0] * n[1])];
                    ijk[d] == end
                })
                .collect();
            mesh.add_node_set(&format!("{axis}{label}"), set)?;
        }
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rectangle_area_and_sets() {
        let m = rectangle(3.0, 2.0, 6, 4).unwrap();
        let area: f64 = (0..m.triangles().len())
            .map(|i| crate::element::tri3::signed_area(&m.triangle(i)))
            .sum();
        assert!((area - 6.0).abs() < 1e-12);
        assert_eq!(m.node_sets().get("left").unwrap().len(), 5);
    }

    #[test]
    fn block_is_conforming_with_five_tets_per_cube() {
        let m = block([2.0, 3.0, 1.0], [2, 3, 2]).unwrap();
        assert_eq!(m.tets().len(), 5 * 12);
        let vol: f64 = (0..m.tets().len())
            .map(|i| tet4::signed_volume(&m.tet(i)))
            .sum();
        assert!((vol - 6.0).abs() < 1e-12);
        // Conforming: the boundary is exactly the box surface, 2 triangles per cube face.
        let faces = 2 * (2 * (2 * 3 + 3 * 2 + 2 * 2));
        assert_eq!(m.boundary().len(), faces);
        let area: f64 = m
            .boundary()
            .iter()
            .map(|f| {
                let p = f.nodes.map(|n| m.nodes()[n]);
                tet4::face_area_normal(&p[0], &p[1], &p[2]).norm()
            })
            .sum();
        assert!((area - 2.0 * (6.0 + 3.0 + 2.0)).abs() < 1e-12);
    }
}
