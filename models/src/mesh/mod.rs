//! Meshes: a 2D mesh of 3-node triangles plus 2-node line elements sharing its nodes
//! ([`Mesh2d`]) and a 3D mesh of 4-node tetrahedra with its boundary faces ([`Mesh3d`]).
//! Both validate on construction; both carry named node sets (supports, loads, landmarks).
//! A [`QuadraticMesh`] adds mid-edge nodes to a 3D mesh for 10-node tetrahedra, a
//! [`QuadraticPlaneMesh`] to a 2D mesh for 6-node triangles.

pub mod cut;
pub mod generate;
pub(crate) mod mid_edges;
mod node_sets;
mod plane;
mod quadratic;
mod quadratic_plane;
mod tetrahedral;

pub use node_sets::NodeSets;
pub use plane::Mesh2d;
pub use quadratic::QuadraticMesh;
pub use quadratic_plane::QuadraticPlaneMesh;
pub use tetrahedral::{BoundaryFace, Mesh3d};

use crate::error::ModelError;

/// The dofs (x, y of each node) of a 2D element with nodes `nodes`: D = 2N.
pub fn plane_dofs<const N: usize, const D: usize>(nodes: &[usize; N]) -> [usize; D] {
    std::array::from_fn(|k| 2 * nodes[k / 2] + k % 2)
}

/// Checks that every element node index is in range and every node is used.
fn check_connectivity<const N: usize>(
    kind: &'static str,
    elements: &[[usize; N]],
    used: &mut [bool],
) -> Result<(), ModelError> {
    let n_nodes = used.len();
    for (index, element) in elements.iter().enumerate() {
        for &node in element {
            if node >= n_nodes {
                return Err(ModelError::NodeOutOfRange {
                    kind,
                    index,
                    node,
                    n_nodes,
                });
            }
            used[node] = true;
        }
    }
    Ok(())
}

fn check_all_used(used: &[bool]) -> Result<(), ModelError> {
    match used.iter().position(|u| !u) {
        Some(node) => Err(ModelError::UnusedNode { node }),
        None => Ok(()),
    }
}

/// Relative size below which an element's area/volume counts as degenerate (scaled by the
/// mesh's bounding-box extent to the element's dimension).
const DEGENERATE_TOL: f64 = 1e-12;
