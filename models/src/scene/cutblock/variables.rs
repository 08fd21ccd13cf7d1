//! The cut block's variable table (value references, names, units, start values, ranges,
//! descriptions) — what `modelDescription.xml` is generated from.

use super::profiles::PROFILE_STATIONS;
use crate::scene::{memory_limit, Variability, Variable};

// Value references (indices into the table built by `table`).
pub const SIZE: [u32; 3] = [0, 1, 2];
pub const CELLS: [u32; 3] = [3, 4, 5];
pub const Y_CUT: u32 = 6;
pub const DEPTH: u32 = 7;
pub const PRESS_RADIUS: u32 = 8;
pub const STRATEGY: u32 = 9;
pub const SUPPORT: u32 = 10;
pub const YOUNG: u32 = 11;
pub const POISSON: u32 = 12;
pub const PULL: u32 = 13;
pub const PRESS: u32 = 14;
pub const SCALPEL: u32 = 15;
pub const CONTACT: u32 = 16;
pub const MEMORY_LIMIT: u32 = 17;
pub const MATERIAL: u32 = 18;
pub const ELEMENT: u32 = 19;
pub const MAX_INCREMENT: u32 = 20;
pub const MESH_GRADING: u32 = 21;
pub const FIRST_OUTPUT: u32 = 22;

/// The table, in value-reference order.
pub fn table() -> Vec<Variable> {
    use Variability::{Fixed, Tunable};
    let count = (1.0, 400.0);
    let length = (1e-3, 1e4);
    vec![
        Variable::parameter("size_x", Fixed, "mm", 100.0, length, "block length in x"),
        Variable::parameter("size_y", Fixed, "mm", 80.0, length, "block length in y (pull direction)"),
        Variable::parameter("size_z", Fixed, "mm", 17.0, length, "block height in z"),
        Variable::parameter("cells_x", Fixed, "1", 6.0, count, "cubes along x (whole number)"),
        Variable::parameter("cells_y", Fixed, "1", 16.0, count, "cubes along y (whole number)"),
        Variable::parameter("cells_z", Fixed, "1", 14.0, count, "cubes along z (whole number)"),
        Variable::parameter("y_cut", Fixed, "mm", 45.0, (0.0, 1e4), "plane of the incision; the y layers are graded so that it is a node plane"),
        Variable::parameter("cut_depth", Fixed, "mm", 8.5, (0.0, 1e4), "incision depth from the top (0: no cut); the z layers are graded so that the crack front is a node plane"),
        Variable::parameter("press_radius", Fixed, "mm", 5.0, (0.0, 1e4), "top faces whose centroid lies within this distance of the scalpel tip carry the press force (at least the nearest face)"),
        Variable::string("cut_strategy", "duplicate", "`duplicate` (split nodes on the cut faces) or `delete` (remove the element layer in front of the cut)"),
        Variable::string("support", "clamped", "`clamped` (face y = 0 fixed, face y = L: u_y prescribed, u_x, u_z free), `gripped` (face y = L also held in x and z) or `sliding` (only u_y on both faces, rigid modes removed)"),
        Variable::parameter("E", Tunable, "MPa", 0.0385, (1e-12, 1e9), "Young's modulus (seed 002 ch. 4: 0.0385 MPa)"),
        Variable::parameter("nu", Tunable, "1", 0.43, (-0.999, 0.499_999), "Poisson's ratio (seed 002 ch. 4: 0.43)"),
        Variable::input("pull", "mm", 0.0, (-1e3, 1e3), "prescribed u_y of the face y = L"),
        Variable::input("press_force", "N", 0.0, (0.0, 1e6), "downward force on the top surface at the scalpel tip"),
        Variable::input("scalpel_x", "mm", 0.0, (0.0, 1e4), "scalpel position; the incision covers x from 0 to the furthest position it has reached (a node plane lies at the blade)"),
        Variable::string("contact", "penalty", "`penalty` (closing cut flanks are kept apart, node-to-facet penalty) or `none` (flanks may pass through each other)"),
        memory_limit(),
        Variable::string("material", "neo-hookean", "`neo-hookean` (compressible, finite strain; the default: valid at the seed's 10 mm pull), `linear` (small strain, the fast path; warns beyond 5 % strain) or `stvk` (St. Venant-Kirchhoff, finite strain)"),
        Variable::string("element", "tet4", "`tet4` (linear tetrahedra) or `tet10` (quadratic tetrahedra: mid-edge nodes, 14-point quadrature)"),
        Variable::parameter("max_increment", Tunable, "mm", 5.0, (1e-6, 1e3), "finite strain: largest change of the pull per Newton load increment (an increment that fails is halved)"),
        Variable::parameter("mesh_grading", Fixed, "1", 1.0, (1.0, 4.0), "β of the grading towards the cut plane, the crack front, the faces and the tip: the y and z layers of each side (face to cut plane or cut bottom, n layers) at the fractions ξ^β / (ξ^β + (1 − ξ)^β), ξ = i/n, x planes at the front ± L (k/n)^β (1: uniform; 2: the optimal rate of linear elements at the crack front)"),
        Variable::output("reaction_force", "N", 1, "y-reaction force on the pulled face y = L (y-internal force summed over the face)"),
        Variable::output("cut_opening", "mm", 1, "largest gap between facing flank nodes on the top surface"),
        Variable::output("bottom_lift", "mm", 1, "largest upward displacement of the bottom surface under the cut plane"),
        Variable::output("x_contraction", "mm", 1, "largest inward x-displacement of the end faces x = 0 and x = size_x"),
        Variable::output("max_von_mises", "MPa", 1, "maximum of the volume-weighted nodal averages of element von Mises stress (seed 002 eq. 4.4)"),
        Variable::output("cut_length", "mm", 1, "incision length in x: the furthest the scalpel has been, clamped to the block (the cut never heals)"),
        Variable::output("contact_points", "1", 1, "number of flank nodes held by contact springs"),
        Variable::output("penetration", "mm", 1, "deepest penetration of a flank node into the opposite flank"),
        Variable::output("max_strain", "1", 1, "largest principal strain at the element centroids (small-strain for the linear law, Green-Lagrange for the finite-strain ones)"),
        Variable::output("profile_x25", "mm", PROFILE_STATIONS, "deformed top-surface height along x = 25 mm at y = 0, 0.5, …, 90 mm (NaN: no surface, e.g. in the open cut)"),
        Variable::output("profile_x50", "mm", PROFILE_STATIONS, "deformed top-surface height along x = 50 mm, stations as profile_x25"),
        Variable::output("profile_x75", "mm", PROFILE_STATIONS, "deformed top-surface height along x = 75 mm, stations as profile_x25"),
    ]
}
