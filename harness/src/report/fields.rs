use anyhow::{Context, Result};

use super::plot::{self, MeshMap};
use super::{vtu, Depth, Report};
use crate::studies::fields::{abdomen_pressed, cutblock_pulled};

/// Adds the section to `report` (the same at every depth).
pub fn section(report: &mut Report, _: Depth) -> Result<()> {
    report.heading("Fields");
    abdomen(report)?;
    cutblock(report)
}

/// The abdomen under the default static press: stress map with arrows, and its VTU file.
fn abdomen(report: &mut Report) -> Result<()> {
    let press = 0.8;
    let (a, u) = abdomen_pressed(press)?;
    let view = a.view(&u)?;
    let mesh = view.mesh;
    let von_mises: Vec<f64> = view
        .triangle_stresses()
        .iter()
        .map(|s| s.von_mises())
        .collect();
    let norm = |n: usize| view.displacement(n)[0].hypot(view.displacement(n)[1]);
    let largest = (0..mesh.nodes().len()).map(norm).fold(0.0, f64::max);
    let scale = 0.12 * mesh.extent() / largest;
    let every = (mesh.nodes().len() / 150).max(1);
    plot::mesh_map(
        &report.path("abdomen_stress"),
        &MeshMap {
            title: format!("Abdomen, static press {press} N/mm (arrows × {scale:.2})"),
            nodes: mesh.nodes(),
            triangles: mesh.triangles(),
            values: &von_mises,
            value_label: "von Mises stress (MPa)".into(),
            lines: mesh.lines(),
            arrows: (0..mesh.nodes().len())
                .step_by(every)
                .map(|n| (n, view.displacement(n)))
                .collect(),
            arrow_scale: scale,
        },
    )?;
    report.figure(
        &format!(
            "Abdomen under a static press of {press} N/mm: von Mises stress of the triangles \
             (colour), membranes (black), displacement arrows (red, largest {largest:.1} mm, \
             drawn × {scale:.2})"
        ),
        "abdomen_stress",
    );
    vtu::abdomen(&report.path("abdomen.vtu"), &view)?;
    report.file(
        "abdomen field for ParaView (displacement, stress, tissue)",
        "abdomen.vtu",
    );
    Ok(())
}

/// The default cut block, fully cut and pulled 10 mm, as a VTU file.
fn cutblock(report: &mut Report) -> Result<()> {
    let c = cutblock_pulled(10.0)?;
    let (solid, u) = c.field().context("the cut block is initialized")?;
    vtu::cutblock(&report.path("cutblock.vtu"), solid, u)?;
    report.file(
        "cut block, full cut, 10 mm pull, for ParaView (displacement, von Mises)",
        "cutblock.vtu",
    );
    Ok(())
}
