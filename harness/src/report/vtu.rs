//! Fields for ParaView: meshes with displacement and stress as VTK XML unstructured grids
//! (`.vtu`, written with vtkio, atomically).
//!
//! - abdomen: triangles (VTK_TRIANGLE) and the membrane line elements (VTK_LINE); point data
//!   `displacement` (mm, z = 0); cell data `stress` (MPa: von Mises for triangles, axial
//!   stress for lines) and `tissue` (0 cavity, 1 diaphragm, 2 abdominal wall, 3 pelvic floor).
//! - cut block: linear tetrahedra (VTK_TETRA) or quadratic ones (VTK_QUADRATIC_TETRA); point
//!   data `displacement` (mm); cell data `von_mises` (MPa, Cauchy stress at the centroid).

use std::path::Path;

use anyhow::{anyhow, Result};
use models::assembly::tetrahedra::{Elements, Solid};
use models::scene::abdomen::discretization::FieldView;
use models::stress;
use vtkio::model::{
    Attribute, Attributes, ByteOrder, CellType, Cells, DataSet, UnstructuredGridPiece, Version,
    VertexNumbers, Vtk,
};

use crate::atomic::temporary;

/// Cells given as vertex lists with their VTK type.
struct Grid {
    points: Vec<f64>,
    cells: Vec<(CellType, Vec<usize>)>,
    point_data: Vec<Attribute>,
    cell_data: Vec<Attribute>,
}

fn write(path: &Path, title: &str, g: Grid) -> Result<()> {
    let mut connectivity = Vec::new();
    let mut offsets = Vec::new();
    for (_, v) in &g.cells {
        connectivity.extend(v.iter().map(|&i| i as u64));
        offsets.push(connectivity.len() as u64);
    }
    let vtk = Vtk {
        version: Version::new(),
        title: title.into(),
        byte_order: ByteOrder::LittleEndian,
        file_path: None,
        data: DataSet::inline(UnstructuredGridPiece {
            points: g.points.into(),
            cells: Cells {
                cell_verts: VertexNumbers::XML {
                    connectivity,
                    offsets,
                },
                types: g.cells.iter().map(|c| c.0).collect(),
            },
            data: Attributes {
                point: g.point_data,
                cell: g.cell_data,
            },
        }),
    };
    let tmp = temporary(path);
    vtk.export(&tmp)
        .map_err(|e| anyhow!("writing {}: {e:?}", path.display()))?;
    std::fs::rename(&tmp, path)?;
    Ok(())
}

/// Writes the abdomen's mesh — 3-node triangles and 2-node lines, or 6-node triangles
/// (VTK_QUADRATIC_TRIANGLE, whose node order is ours) and 3-node lines (VTK_QUADRATIC_EDGE:
/// ends first, then the middle) — with the view's displacement and stresses.
pub fn abdomen(path: &Path, view: &FieldView<'_>) -> Result<()> {
    let (nodes, triangles, lines, triangle_type, line_type) = match view.quadratic {
        Some(q) => (
            q.nodes(),
            q.triangles().iter().map(|t| t.to_vec()).collect::<Vec<_>>(),
            q.lines()
                .iter()
                .map(|&[a, m, b]| vec![a, b, m])
                .collect::<Vec<_>>(),
            CellType::QuadraticTriangle,
            CellType::QuadraticEdge,
        ),
        None => (
            view.mesh.nodes(),
            view.mesh
                .triangles()
                .iter()
                .map(|t| t.to_vec())
                .collect::<Vec<_>>(),
            view.mesh
                .lines()
                .iter()
                .map(|l| l.to_vec())
                .collect::<Vec<_>>(),
            CellType::Triangle,
            CellType::Line,
        ),
    };
    let points = nodes.iter().flat_map(|p| [p[0], p[1], 0.0]).collect();
    let displacement = view
        .u
        .chunks(2)
        .flat_map(|d| [d[0], d[1], 0.0])
        .collect::<Vec<_>>();
    let mut cells = Vec::new();
    let mut stress = Vec::new();
    let mut tissue = Vec::new();
    for (t, s) in triangles.into_iter().zip(view.triangle_stresses()) {
        cells.push((triangle_type, t));
        stress.push(s.von_mises());
        tissue.push(0.0);
    }
    let regions = view.mesh.line_regions();
    for ((l, r), s) in lines.into_iter().zip(regions).zip(view.line_stresses()) {
        cells.push((line_type, l));
        stress.push(s);
        tissue.push(f64::from(*r) + 1.0);
    }
    write(
        path,
        "tissuefmu abdomen",
        Grid {
            points,
            cells,
            point_data: vec![Attribute::vectors("displacement").with_data(displacement)],
            cell_data: vec![
                Attribute::scalars("stress", 1).with_data(stress),
                Attribute::scalars("tissue", 1).with_data(tissue),
            ],
        },
    )
}

/// Writes the cut block's solid (linear tetrahedra as VTK_TETRA, quadratic ones as
/// VTK_QUADRATIC_TETRA, whose node order is the solid's) with displacement `u` (all dofs)
/// and the von Mises stress at each element's centroid.
pub fn cutblock(path: &Path, solid: &Solid, u: &[f64]) -> Result<()> {
    let points = solid.nodes().iter().flatten().copied().collect();
    let von_mises: Vec<f64> = stress::solid_centroids(solid, u)
        .map(|c| stress::mises(&c.stress))
        .collect();
    let cells = match &solid.elements() {
        Elements::Tet4(t) => t.iter().map(|e| (CellType::Tetra, e.to_vec())).collect(),
        Elements::Tet10(t) => t
            .iter()
            .map(|e| (CellType::QuadraticTetra, e.to_vec()))
            .collect(),
    };
    write(
        path,
        "tissuefmu cut block",
        Grid {
            points,
            cells,
            point_data: vec![Attribute::vectors("displacement").with_data(u.to_vec())],
            cell_data: vec![Attribute::scalars("von_mises", 1).with_data(von_mises)],
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use models::scene::abdomen::Abdomen;
    use models::scene::cutblock::CutBlock;
    use models::scene::Scene;
    use vtkio::model::IOBuffer;

    /// The file read back by vtkio's parser holds the scene's solid and displacement, for
    /// linear and quadratic tetrahedra.
    #[test]
    fn cut_block_round_trips_through_the_vtu_reader() {
        for (element, cell) in [
            ("tet4", CellType::Tetra),
            ("tet10", CellType::QuadraticTetra),
        ] {
            let mut s = CutBlock::new();
            for (n, v) in [("cells_x", 2.0), ("cells_y", 4.0), ("cells_z", 2.0)] {
                s.set(n, v).unwrap();
            }
            let vr = s.lookup("element").unwrap();
            s.set_string(vr, element).unwrap();
            s.initialize(0.0).unwrap();
            s.set("pull", 5.0).unwrap();
            s.do_step(0.0, 1.0).unwrap();
            let (solid, u) = s.field().unwrap();
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("block.vtu");
            cutblock(&path, solid, u).unwrap();
            let vtk = Vtk::import(&path).unwrap();
            let DataSet::UnstructuredGrid { pieces, .. } = vtk.data else {
                panic!("an unstructured grid")
            };
            let piece = pieces[0].load_piece_data(None).unwrap();
            assert_eq!(piece.num_points(), solid.nodes().len());
            assert_eq!(piece.cells.types.len(), solid.len());
            assert_eq!(piece.cells.types[0], cell);
            let Attribute::DataArray(d) = &piece.data.point[0] else {
                panic!("displacement is a data array")
            };
            let IOBuffer::F64(read) = &d.data else {
                panic!("f64 data")
            };
            assert_eq!(read, u);
            assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        }
    }

    /// Triangles and membrane lines both arrive, each with its stress and tissue, for
    /// either element: 6-node triangles with all their nodes and displacements.
    #[test]
    fn abdomen_writes_triangles_and_lines_with_their_tissue() {
        for (element, types) in [
            ("tri3", (CellType::Triangle, CellType::Line)),
            (
                "tri6",
                (CellType::QuadraticTriangle, CellType::QuadraticEdge),
            ),
        ] {
            let mut a = Abdomen::new();
            a.set("target_triangles", 300.0).unwrap();
            a.set_str("element", element).unwrap();
            a.set_str("kinematics", "linear").unwrap();
            a.initialize(0.0).unwrap();
            let u = a.static_displacement(0.5).unwrap();
            let view = a.view(&u).unwrap();
            let dir = tempfile::tempdir().unwrap();
            let path = dir.path().join("abdomen.vtu");
            abdomen(&path, &view).unwrap();
            let DataSet::UnstructuredGrid { pieces, .. } = Vtk::import(&path).unwrap().data else {
                panic!("an unstructured grid")
            };
            let piece = pieces[0].load_piece_data(None).unwrap();
            let (tris, lines) = (view.mesh.triangles().len(), view.mesh.lines().len());
            assert_eq!(piece.cells.types.len(), tris + lines);
            assert_eq!((piece.cells.types[0], piece.cells.types[tris]), types);
            assert_eq!(3 * piece.points.len() / 3, 3 * u.len() / 2, "{element}");
            let Attribute::DataArray(t) = &piece.data.cell[1] else {
                panic!("tissue is a data array")
            };
            let IOBuffer::F64(tissue) = &t.data else {
                panic!("f64 data")
            };
            assert!(tissue[..tris].iter().all(|&x| x == 0.0));
            for region in 1..=3 {
                let n = tissue[tris..]
                    .iter()
                    .filter(|&&x| x == f64::from(region))
                    .count();
                assert!(n > 0, "membrane {region} has lines");
            }
        }
    }
}
