//! Meshing of the cavity: a constrained Delaunay triangulation of the sampled boundary with
//! Ruppert/Chew quality refinement (the `spade` crate), boundary edges kept as given so that
//! the line elements of diaphragm, abdominal wall and pelvic floor share their nodes.

use spade::{
    AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation,
};

use super::geometry::{Boundary, ControlPoints, Spacing, LANDMARKS, PARTS};
use crate::budget;
use crate::element::tri3;
use crate::mesh::mid_edges::MidEdges;
use crate::mesh::Mesh2d;
use crate::scene::SceneError;

/// Line-element regions (tissues) by boundary part; parts without line elements are `None`.
pub const LINE_REGION: [Option<u16>; 5] = [None, Some(2), None, Some(1), Some(0)];
/// Names of the line-element regions 0, 1, 2.
pub const LINE_TISSUES: [&str; 3] = ["diaphragm", "abdominal_wall", "pelvic_floor"];
/// The diaphragm's line-element region.
pub const DIAPHRAGM_REGION: u16 = 0;

/// Minimum angle the refinement asks for (degrees).
pub const ANGLE_LIMIT_DEG: f64 = 25.0;
/// Boundary spacing relative to the interior edge length.
const BOUNDARY_SPACING: f64 = 0.65;
/// Triangle-area bound relative to the target mean area.
const AREA_BOUND: f64 = 1.6;

/// A meshed cavity with its quality figures.
#[derive(Debug, Clone)]
pub struct Meshed {
    /// The mesh (mm): linear triangles of region 0, line elements on the diaphragm,
    /// abdominal wall and pelvic floor ([`LINE_REGION`]), node sets of the boundary parts
    /// and the landmarks.
    pub mesh: Mesh2d,
    /// Smallest interior angle of any triangle (degrees).
    pub min_angle: f64,
    /// Count of triangles by their smallest angle in 5° bins: [0, 5), [5, 10), …, [55, 60].
    pub angle_histogram: [usize; 12],
    /// The point of the boundary curve halfway along each boundary segment in the sampling's
    /// spacing count (the arc-length midpoint where the spacing is uniform; within the
    /// graded zone nearer the finer end), with the segment's end nodes: where a quadratic
    /// mesh puts its boundary mid-edge nodes, so that its boundary edges lie on the curve.
    pub boundary_mids: Vec<([usize; 2], [f64; 2])>,
}

/// Meshes the outline with about `target_triangles` triangles (more with `grading` > 0: the
/// boundary is sampled finer towards the ends of its parts, [`Spacing`], and the quality
/// refinement grades the interior from there; where a graded part meets a sharp corner a
/// few triangles may stay below [`ANGLE_LIMIT_DEG`], measured: 15.0° at the smallest, under
/// 0.5 % below 25°), then splits every triangle
/// into four `subdivisions` times (nested meshes, the new boundary nodes moved onto the
/// curve), claiming `bytes_per_triangle` for each triangle first (the caller's estimate of
/// the mesh and the system it will build). Node sets:
/// one per boundary part (with both end nodes) and the landmarks
/// ([`LANDMARKS`]: the same material points on every mesh).
pub fn mesh(
    points: &ControlPoints,
    target_triangles: usize,
    bytes_per_triangle: usize,
    subdivisions: u32,
    grading: f64,
) -> Result<Meshed, SceneError> {
    if target_triangles < 50 {
        return Err(SceneError::Config(format!(
            "target_triangles = {target_triangles} must be at least 50"
        )));
    }
    budget::claim(
        "the abdomen mesh and its sparse system",
        target_triangles
            .saturating_mul(bytes_per_triangle)
            .saturating_mul(1 << (2 * subdivisions.min(16))),
    )?;
    let coarse = Boundary::new(points, Spacing::uniform(1.0))?;
    let area = coarse.signed_area();
    // Equilateral triangles of the target mean area have side h. The boundary is sampled
    // finer (BOUNDARY_SPACING · h) so that the line elements resolve the membranes (about 200
    // of them at the default 6,000 triangles, as in seed 003); the area bound is
    // AREA_BOUND · mean, calibrated so that the count lands near the target.
    let mean = area / target_triangles as f64;
    let h = (4.0 * mean / 3f64.sqrt()).sqrt();
    let spacing = Spacing {
        h: BOUNDARY_SPACING * h,
        grading,
    };
    let boundary = Boundary::new(points, spacing)?;
    let (mut nodes, mut triangles, mut ring) = triangulate(&boundary, target_triangles, mean)?;
    for _ in 0..subdivisions {
        split(&mut nodes, &mut triangles, &mut ring);
    }
    let fine = match subdivisions {
        0 => boundary,
        _ => Boundary::subdivided(points, spacing, subdivisions)?,
    };
    debug_assert_eq!(fine.vertices.len(), ring.len());
    let halves = Boundary::subdivided(points, spacing, subdivisions + 1)?;
    let boundary_mids = (0..ring.len())
        .map(|i| {
            debug_assert_eq!(halves.vertices[2 * i], fine.vertices[i]);
            (
                [ring[i], ring[(i + 1) % ring.len()]],
                halves.vertices[2 * i + 1],
            )
        })
        .collect();
    for (&n, &p) in ring.iter().zip(&fine.vertices) {
        nodes[n] = p;
    }
    let mut lines = Vec::new();
    let mut line_regions = Vec::new();
    for (i, &part) in fine.segment_part.iter().enumerate() {
        if let Some(region) = LINE_REGION[part] {
            lines.push([ring[i], ring[(i + 1) % ring.len()]]);
            line_regions.push(region);
        }
    }
    let n_tri = triangles.len();
    let mut mesh = Mesh2d::new(nodes, triangles, vec![0; n_tri], lines, line_regions)?;
    add_node_sets(&mut mesh, &fine, &ring)?;
    let (min_angle, angle_histogram) = quality(&mesh);
    Ok(Meshed {
        mesh,
        min_angle,
        angle_histogram,
        boundary_mids,
    })
}

/// The refined constrained Delaunay triangulation of the sampled boundary: nodes,
/// counter-clockwise triangles and the boundary vertices' node numbers in boundary order.
type Triangulated = (Vec<[f64; 2]>, Vec<[usize; 3]>, Vec<usize>);

fn triangulate(
    boundary: &Boundary,
    target_triangles: usize,
    mean: f64,
) -> Result<Triangulated, SceneError> {
    let mut cdt = ConstrainedDelaunayTriangulation::<Point2<f64>>::new();
    let mut handles = Vec::with_capacity(boundary.vertices.len());
    for v in &boundary.vertices {
        let handle = cdt
            .insert(Point2::new(v[0], v[1]))
            .map_err(|e| SceneError::Config(format!("meshing: boundary vertex {v:?}: {e:?}")))?;
        handles.push(handle);
    }
    let n = handles.len();
    for i in 0..n {
        cdt.add_constraint(handles[i], handles[(i + 1) % n]);
    }
    let params = RefinementParameters::<f64>::new()
        .exclude_outer_faces(true)
        .keep_constraint_edges()
        .with_angle_limit(AngleLimit::from_deg(ANGLE_LIMIT_DEG))
        .with_max_allowed_area(AREA_BOUND * mean)
        .with_max_additional_vertices(20 * target_triangles);
    let result = cdt.refine(params);
    if !result.refinement_complete {
        return Err(SceneError::Config(
            "meshing: refinement did not complete (vertex budget exhausted)".into(),
        ));
    }
    let nodes: Vec<[f64; 2]> = cdt
        .vertices()
        .map(|v| [v.position().x, v.position().y])
        .collect();
    let mut triangles = Vec::new();
    for face in cdt.inner_faces() {
        if result.excluded_faces.contains(&face.fix()) {
            continue;
        }
        let mut t = face.vertices().map(|v| v.fix().index());
        if tri3::signed_area(&t.map(|i| nodes[i])) < 0.0 {
            t.swap(1, 2);
        }
        triangles.push(t);
    }
    let ring = handles.iter().map(|h| h.index()).collect();
    Ok((nodes, triangles, ring))
}

/// Splits every triangle into four at its edge midpoints (the children keep the parent's
/// orientation and angles), and each boundary segment of `ring` into two.
fn split(nodes: &mut Vec<[f64; 2]>, triangles: &mut Vec<[usize; 3]>, ring: &mut Vec<usize>) {
    let mut mid = MidEdges::with_capacity(3 * triangles.len() / 2 + ring.len());
    *triangles = triangles
        .iter()
        .flat_map(|&[a, b, c]| {
            let ab = mid.node(a, b, nodes);
            let bc = mid.node(b, c, nodes);
            let ca = mid.node(c, a, nodes);
            [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
        })
        .collect();
    let n = ring.len();
    *ring = (0..n)
        .flat_map(|i| [ring[i], mid.node(ring[i], ring[(i + 1) % n], nodes)])
        .collect();
}

/// The node sets of the boundary parts and the landmarks; `ring` holds the node of each
/// boundary vertex.
fn add_node_sets(mesh: &mut Mesh2d, boundary: &Boundary, ring: &[usize]) -> Result<(), SceneError> {
    let index = |i: usize| ring[i % ring.len()];
    for (p, name) in PARTS.iter().enumerate() {
        let nodes: Vec<usize> = (0..boundary.segment_part.len())
            .filter(|&i| boundary.segment_part[i] == p)
            .flat_map(|i| [index(i), index(i + 1)])
            .collect();
        mesh.add_node_set(name, nodes)?;
    }
    for ((name, _), &vertex) in LANDMARKS.iter().zip(&boundary.landmarks) {
        mesh.add_node_set(name, vec![index(vertex)])?;
    }
    Ok(())
}

/// Smallest angle of every triangle: the minimum and a 5° histogram.
fn quality(mesh: &Mesh2d) -> (f64, [usize; 12]) {
    let mut hist = [0; 12];
    let mut min = f64::INFINITY;
    for i in 0..mesh.triangles().len() {
        let p = mesh.triangle(i);
        let angle = (0..3)
            .map(|k| {
                let (a, b, c) = (p[k], p[(k + 1) % 3], p[(k + 2) % 3]);
                let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
                let cos = (u[0] * v[0] + u[1] * v[1]) / (u[0].hypot(u[1]) * v[0].hypot(v[1]));
                cos.clamp(-1.0, 1.0).acos().to_degrees()
            })
            .fold(f64::INFINITY, f64::min);
        min = min.min(angle);
        hist[((angle / 5.0) as usize).min(11)] += 1;
    }
    (min, hist)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::abdomen::anatomy::Anatomy;

    /// A claim per triangle for the tests' meshes.
    const TEST_BYTES: usize = 1_000;

    #[test]
    fn default_outline_meshes_near_target_with_quality() {
        let points = Anatomy::default().control_points().unwrap();
        let m = mesh(&points, 6000, TEST_BYTES, 0, 0.0).unwrap();
        let n = m.mesh.triangles().len();
        println!(
            "triangles {n}, lines {}, nodes {}, min angle {:.2}°, histogram {:?}",
            m.mesh.lines().len(),
            m.mesh.nodes().len(),
            m.min_angle,
            m.angle_histogram
        );
        assert!((4500..7500).contains(&n), "{n}");
        // The refinement's angle limit is 25°; the verification section prints the measured one.
        assert!(m.min_angle >= ANGLE_LIMIT_DEG, "{}", m.min_angle);
        assert!((120..260).contains(&m.mesh.lines().len()));
        for set in [
            "spine",
            "pelvic_floor",
            "pelvic_bone",
            "abdominal_wall",
            "diaphragm",
            "diaphragm_apex",
            "floor_mid",
            "wall_mid",
        ] {
            m.mesh.node_sets().get(set).unwrap();
        }
    }

    #[test]
    fn landmarks_are_the_same_points_on_every_mesh() {
        let points = Anatomy::default().control_points().unwrap();
        let at = |target, subdivisions, grading| {
            let m = mesh(&points, target, TEST_BYTES, subdivisions, grading).unwrap();
            ["diaphragm_apex", "floor_mid", "wall_mid"]
                .map(|set| m.mesh.nodes()[m.mesh.node_sets().get(set).unwrap()[0]])
        };
        let reference = at(750, 0, 0.0);
        for other in [at(3000, 0, 0.0), at(750, 1, 0.0), at(1200, 0, 0.5)] {
            for (p, q) in reference.iter().zip(&other) {
                assert!(
                    (p[0] - q[0]).abs() < 1e-9 && (p[1] - q[1]).abs() < 1e-9,
                    "{p:?} {q:?}"
                );
            }
        }
        // The apex is the highest point of the diaphragm's sampled curve.
        let m = mesh(&points, 1200, TEST_BYTES, 0, 0.5).unwrap();
        let top = m
            .mesh
            .node_sets()
            .get("diaphragm")
            .unwrap()
            .iter()
            .map(|&n| m.mesh.nodes()[n][1])
            .fold(f64::NEG_INFINITY, f64::max);
        assert!((reference[0][1] - top).abs() < 1e-9, "{top}");
    }

    #[test]
    fn grading_refines_towards_the_part_ends() {
        // The smallest boundary segment shrinks from about the uniform spacing to a small
        // fraction of it, for a modest increase of the triangle count.
        let points = Anatomy::default().control_points().unwrap();
        let shortest = |m: &Meshed| {
            m.mesh
                .lines()
                .iter()
                .map(|&[a, b]| {
                    let (p, q) = (m.mesh.nodes()[a], m.mesh.nodes()[b]);
                    (p[0] - q[0]).hypot(p[1] - q[1])
                })
                .fold(f64::INFINITY, f64::min)
        };
        let uniform = mesh(&points, 1500, TEST_BYTES, 0, 0.0).unwrap();
        let graded = mesh(&points, 1500, TEST_BYTES, 0, 0.5).unwrap();
        let (u, g) = (shortest(&uniform), shortest(&graded));
        let (nu, ng) = (
            uniform.mesh.triangles().len(),
            graded.mesh.triangles().len(),
        );
        println!("shortest line {u:.3} → {g:.4} mm, triangles {nu} → {ng}");
        assert!(g < 0.05 * u, "{u} {g}");
        assert!(ng < 2 * nu, "{nu} {ng}");
        // The refinement keeps the boundary segments, so next to the shortest of them a few
        // triangles stay below the angle limit (one of 15.0° on this mesh); none is
        // anywhere near degenerate.
        let below: usize = graded.angle_histogram[..5].iter().sum();
        assert!(graded.min_angle > 10.0, "{}", graded.min_angle);
        assert!(below * 200 < ng, "{below} of {ng} below 25°");
    }
}
