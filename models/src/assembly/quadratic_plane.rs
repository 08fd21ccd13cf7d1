//! Global matrices of a mesh of 6-node plane-strain triangles ([`crate::element::tri6`]),
//! properties per region tag as for the linear mesh ([`super::plane::PlaneProperties`]), in
//! the displacement or the mixed P2/P0 formulation.

use super::plane::PlaneProperties;
use super::Assembler;
use crate::element::tri6;
pub use crate::element::tri6::Formulation;
use crate::mesh::QuadraticPlaneMesh;

/// The assembler of the mesh's triangles.
pub fn assembler(mesh: &QuadraticPlaneMesh) -> Assembler {
    Assembler::new(mesh.nodes().len(), 2, mesh.triangles())
}

/// Writes the stiffness matrix into `values` (overwriting).
pub fn stiffness(
    mesh: &QuadraticPlaneMesh,
    asm: &Assembler,
    props: &PlaneProperties,
    formulation: Formulation,
    values: &mut [f64],
) {
    values.fill(0.0);
    for (i, &r) in mesh.triangle_regions().iter().enumerate() {
        let elastic = &props.continua[usize::from(r)].elastic;
        let k = tri6::stiffness_in(formulation, &mesh.triangle(i), elastic);
        asm.add(values, i, &k);
    }
}

/// Writes the consistent mass matrix into `values` (overwriting).
pub fn mass(
    mesh: &QuadraticPlaneMesh,
    asm: &Assembler,
    props: &PlaneProperties,
    values: &mut [f64],
) {
    values.fill(0.0);
    for (i, &r) in mesh.triangle_regions().iter().enumerate() {
        let rho = props.continua[usize::from(r)].density;
        asm.add(values, i, &tri6::mass_consistent(&mesh.triangle(i), rho));
    }
}
