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

/// Corner offsets (as in [`EVEN_CUBE`]) of the six tetrahedra of a cube split for
/// [`Split::ExtrudedX`], unmirrored (corner c ↦ c XOR 1 mirrors it in x): its (y, z)
/// square cut along the diagonal from corner 0 (even `parity`) or from corner 2 (odd), each
/// triangle p < q < r (corners of the x = 0 face, ordered by their (y, z) grid index, which
/// neighbouring cubes share) extruded to the x = 1 face (corner + 1) and split into
/// [p q r r'], [p q q' r'], [p p' q' r']. Each
/// rectangle between two prisms is then cut along the diagonal from the lower-indexed
/// corner's x = 0 end to the other's x = 1 end in both prisms, so the mesh is conforming.
fn extruded_cube(parity: usize) -> [[usize; 4]; 6] {
    // The x = 0 corners in (y, z) grid order: 0 (y0 z0) < 2 (y1 z0) < 4 (y0 z1) < 6 (y1 z1).
    let triangles = if parity == 0 {
        [[0, 2, 6], [0, 4, 6]]
    } else {
        [[0, 2, 4], [2, 4, 6]]
    };
    let prism = |[p, q, r]: [usize; 3]| {
        [
            [p, q, r, r + 1],
            [p, q, q + 1, r + 1],
            [p, p + 1, q + 1, r + 1],
        ]
    };
    let [a, b] = triangles.map(prism);
    [a[0], a[1], a[2], b[0], b[1], b[2]]
}

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
    block_on_planes(&planes, Split::Alternating { mirrored: false })
}

/// Memory of a block mesh with `n` node planes per axis and of its assembled system,
/// estimated before anything is allocated: per node its coordinates and about 120 stored
/// entries of the 3-dof stiffness pattern (counted: BENCHMARKS.md, "Memory estimates"), each
/// an index and three value copies (element sum, with contact, reduced); per cube five
/// tetrahedra with 32 bytes and a 12 × 12 scatter map of 8-byte indices each (the
/// assembler's map is smaller, 16 node pairs of 16 bytes, so that even the six tetrahedra of
/// [`Split::ExtrudedX`] take about 4 kB less per cube than estimated: the estimate errs
/// towards refusing, and is kept so that the refusals of the FMUs' tested ranges stay where
/// they were).
fn block_bytes(n: [usize; 3]) -> usize {
    let nodes = n[0].saturating_mul(n[1]).saturating_mul(n[2]);
    let cells = (n[0] - 1).saturating_mul(n[1] - 1).saturating_mul(n[2] - 1);
    let per_node = 24 + 120 * (8 + 3 * 8);
    let per_cell = 5 * (32 + 144 * 8);
    nodes
        .saturating_mul(per_node)
        .saturating_add(cells.saturating_mul(per_cell))
}

/// How the cubes of a block are split into tetrahedra.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Split {
    /// Five per cube, the split mirrored in every other cube (seed 002 §3.1); cube
    /// (i, j, k) is mirrored when i + j + k + `mirrored` is odd, so that a caller that adds
    /// a plane can keep the split of the cubes beyond it.
    Alternating {
        /// Whether the alternation is shifted by one: the cubes with i + j + k even are
        /// mirrored instead of those with i + j + k odd.
        mirrored: bool,
    },
    /// Six per cube: each (y, z) square split into two triangles along alternating
    /// diagonals, each triangle extruded along x into a prism of three tetrahedra, the
    /// prisms of every other x layer mirrored in x (layer i mirrored when i + `mirrored` is
    /// odd, so that a caller can keep a layer's split as the planes move, and a block with
    /// an even number of layers is mirror-symmetric). Every tetrahedron has an edge along
    /// x, so a layer thin in x does not lock: as its width δ → 0 its energy bounds only
    /// the differences across it, which ties its two planes node to node — the mesh
    /// without it. (The five-tetrahedra split's central tetrahedron joins four corners with
    /// four different (y, z) positions: flattened, it also forces every square of the
    /// layer to stay planar, a stiffening that stays as δ → 0.)
    ExtrudedX {
        /// Whether the alternation is shifted by one: the layers with i even are mirrored
        /// instead of those with i odd.
        mirrored: bool,
    },
}

/// Like [`block`], but on arbitrary (strictly increasing) node planes per axis, so that a
/// caller can place a node plane exactly where it needs one (a cut plane, a cut depth), and
/// with the cubes split by `split`.
pub fn block_on_planes(planes: &[Vec<f64>; 3], split: Split) -> Result<Mesh3d, ModelError> {
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
    let mut tets = Vec::with_capacity(6 * (n[0] - 1) * (n[1] - 1) * (n[2] - 1));
    for k in 0..n[2] - 1 {
        for j in 0..n[1] - 1 {
            for i in 0..n[0] - 1 {
                let corner = |c: usize| id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
                match split {
                    Split::Alternating { mirrored } => {
                        let flip = (i + j + k + usize::from(mirrored)) % 2;
                        tets.extend(EVEN_CUBE.map(|t| t.map(|c| corner(c ^ flip))));
                    }
                    Split::ExtrudedX { mirrored } => {
                        let flip = (i + usize::from(mirrored)) % 2;
                        let cube = extruded_cube((j + k) % 2);
                        tets.extend(cube.map(|t| t.map(|c| corner(c ^ flip))));
                    }
                }
            }
        }
    }
    for tet in &mut tets {
        if tet4::signed_volume(&tet.map(|v| nodes[v])) < 0.0 {
            tet.swap(2, 3);
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

    /// The split along x: conforming (the boundary is the box surface, 2 triangles per
    /// cube face), filling the box, every tetrahedron with an edge along x (so a layer thin
    /// in x does not lock), and with an even number of layers mirror-symmetric in x: the
    /// mesh reflected at x = 2 is the same set of tetrahedra.
    #[test]
    fn split_along_x_is_conforming_with_an_x_edge_in_every_tet_and_mirror_symmetric() {
        let planes = [
            vec![0.0, 0.5, 1.5, 2.0],
            vec![0.0, 1.0, 2.0, 3.0],
            vec![0.0, 0.4, 1.0],
        ];
        for mirrored in [false, true] {
            let m = block_on_planes(&planes, Split::ExtrudedX { mirrored }).unwrap();
            assert_eq!(m.tets().len(), 6 * 18);
            let vol: f64 = (0..m.tets().len())
                .map(|i| tet4::signed_volume(&m.tet(i)))
                .sum();
            assert!((vol - 6.0).abs() < 1e-12, "{vol}");
            assert_eq!(m.boundary().len(), 2 * (2 * (3 * 2 + 3 * 2 + 3 * 3)));
            for t in 0..m.tets().len() {
                let p = m.tet(t);
                let x_edge = (0..4).any(|a| {
                    (a + 1..4)
                        .any(|b| p[a][0] != p[b][0] && p[a][1] == p[b][1] && p[a][2] == p[b][2])
                });
                assert!(x_edge, "tet {t}: {p:?}");
            }
        }
        let key = |p: [f64; 3]| p.map(|c| (c * 1e9).round() as i64);
        let tets = |m: &Mesh3d, reflect: bool| {
            let mut all: Vec<[[i64; 3]; 4]> = (0..m.tets().len())
                .map(|t| {
                    let mut c = m
                        .tet(t)
                        .map(|p| key([if reflect { 2.0 - p[0] } else { p[0] }, p[1], p[2]]));
                    c.sort();
                    c
                })
                .collect();
            all.sort();
            all
        };
        // Three layers (odd) are not symmetric; four, with planes symmetric about x = 1, are.
        let even = [
            vec![0.0, 0.5, 1.0, 1.5, 2.0],
            planes[1].clone(),
            planes[2].clone(),
        ];
        let m = block_on_planes(&even, Split::ExtrudedX { mirrored: false }).unwrap();
        assert_eq!(tets(&m, true), tets(&m, false));
        let m = block_on_planes(&planes, Split::ExtrudedX { mirrored: false }).unwrap();
        assert_ne!(tets(&m, true), tets(&m, false));
    }
}
