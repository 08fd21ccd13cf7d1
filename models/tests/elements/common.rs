//! Helpers shared by the integration tests: deterministic jitter and irregular meshes.

use models::mesh::{generate, Mesh3d, NodeSets};

/// Deterministic pseudo-random numbers in [−1, 1] (a hash of the index).
pub fn jitter(i: usize, salt: u64) -> f64 {
    let mut x = (i as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15) ^ salt;
    x ^= x >> 31;
    x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x ^= x >> 29;
    (x % 2_000_001) as f64 / 1_000_000.0 - 1.0
}

pub fn boundary_nodes(sets: &NodeSets, names: &[&str]) -> Vec<usize> {
    let mut b: Vec<usize> = names
        .iter()
        .flat_map(|n| sets.get(n).unwrap().to_vec())
        .collect();
    b.sort_unstable();
    b.dedup();
    b
}

/// A 3 × 3 × 3-cube block with interior nodes moved by up to 15 % of the cell size.
pub fn irregular_block() -> (Mesh3d, Vec<usize>) {
    let b = generate::block([3.0, 3.0, 3.0], [3, 3, 3]).unwrap();
    let boundary = boundary_nodes(b.node_sets(), &["x0", "x1", "y0", "y1", "z0", "z1"]);
    let nodes = jittered(b.nodes(), &boundary, 0.15);
    (Mesh3d::new(nodes, b.tets().to_vec()).unwrap(), boundary)
}

/// `nodes` with every node not in `boundary` (sorted) moved by up to `amplitude` along each
/// axis, deterministically.
pub fn jittered<const D: usize>(
    nodes: &[[f64; D]],
    boundary: &[usize],
    amplitude: f64,
) -> Vec<[f64; D]> {
    nodes
        .iter()
        .enumerate()
        .map(|(i, p)| {
            if boundary.binary_search(&i).is_ok() {
                *p
            } else {
                std::array::from_fn(|d| p[d] + amplitude * jitter(i, d as u64 + 1))
            }
        })
        .collect()
}
