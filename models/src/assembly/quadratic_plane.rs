//! Global matrices of a mesh of 6-node plane-strain triangles ([`crate::element::tri6`]),
//! properties per region tag as for the linear mesh ([`super::plane::PlaneProperties`]), in
//! the displacement or the mixed P2/P0 formulation; and at finite strain ([`PlaneBody`], for
//! the Newton solver).

use std::sync::Arc;

use super::plane::PlaneProperties;
use super::Assembler;
pub use crate::element::tri6::Formulation;
use crate::element::{tri6, Material};
use crate::error::ModelError;
use crate::mesh::QuadraticPlaneMesh;
use crate::solve::newton::Equations;
use crate::solve::structure::InternalForces;

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

/// Lumped (HRZ) mass per dof.
pub fn lumped_mass(mesh: &QuadraticPlaneMesh, props: &PlaneProperties) -> Vec<f64> {
    let mut m = vec![0.0; mesh.n_dofs()];
    for (i, (el, &r)) in mesh
        .triangles()
        .iter()
        .zip(mesh.triangle_regions())
        .enumerate()
    {
        let lumped = tri6::mass_lumped(&mesh.triangle(i), props.continua[usize::from(r)].density);
        for (a, &n) in el.iter().enumerate() {
            m[2 * n] += lumped[2 * a];
            m[2 * n + 1] += lumped[2 * a + 1];
        }
    }
    m
}

/// A mesh of 6-node triangles at finite strain (plane strain, total Lagrangian), one
/// material per region: the internal forces and tangent for [`crate::solve::Newton`].
pub struct PlaneBody<'a> {
    pub mesh: &'a QuadraticPlaneMesh,
    pub asm: &'a Assembler,
    pub materials: &'a [Material],
}

impl Equations for PlaneBody<'_> {
    fn add_internal(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        let mesh = self.mesh;
        let materials = self.materials;
        super::add_internal(mesh.triangles(), self.asm, u, f, k, |e, ue, fe, ke| {
            let material = &materials[usize::from(mesh.triangle_regions()[e])];
            tri6::internal(&mesh.triangle(e), ue, material, fe, ke)
        })
    }
}

/// The internal forces of the body as a finite-strain structure's
/// ([`crate::solve::Structure::with_internal_forces`]), owning what it reads.
pub fn internal_forces(
    mesh: Arc<QuadraticPlaneMesh>,
    asm: Arc<Assembler>,
    materials: Arc<[Material]>,
) -> Arc<InternalForces> {
    Arc::new(move |u, f, k| {
        PlaneBody {
            mesh: &mesh,
            asm: &asm,
            materials: &materials,
        }
        .internal(u, f, k)
    })
}
