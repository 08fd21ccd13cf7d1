//! Global matrices of a 3D tetrahedral mesh of one material.

use super::plane::Continuum;
use super::Assembler;
use crate::element::tet4;
use crate::mesh::Mesh3d;

/// Assembler over the tetrahedra of `mesh`, in mesh order.
pub fn assembler(mesh: &Mesh3d) -> Assembler {
    Assembler::new(mesh.nodes().len(), 3, mesh.tets())
}

/// Writes the stiffness matrix into `values` (overwriting).
pub fn stiffness(mesh: &Mesh3d, asm: &Assembler, material: &Continuum, values: &mut [f64]) {
    values.fill(0.0);
    let d = material.elastic.solid();
    for i in 0..mesh.tets().len() {
        asm.add(values, i, &tet4::stiffness(&mesh.tet(i), &d));
    }
}

/// Writes the consistent mass matrix into `values` (overwriting).
pub fn mass(mesh: &Mesh3d, asm: &Assembler, material: &Continuum, values: &mut [f64]) {
    values.fill(0.0);
    for i in 0..mesh.tets().len() {
        asm.add(
            values,
            i,
            &tet4::mass_consistent(&mesh.tet(i), material.density),
        );
    }
}

/// Lumped (row-sum) mass per dof.
pub fn lumped_mass(mesh: &Mesh3d, material: &Continuum) -> Vec<f64> {
    let mut m = vec![0.0; mesh.n_dofs()];
    for i in 0..mesh.tets().len() {
        let lumped = tet4::mass_lumped(&mesh.tet(i), material.density);
        for (k, d) in mesh.tet_dofs(i).into_iter().enumerate() {
            m[d] += lumped[k];
        }
    }
    m
}
