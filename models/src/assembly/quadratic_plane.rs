//! Global matrices of a mesh of 6-node plane-strain triangles ([`crate::element::tri6`]),
//! properties per region tag as for the linear mesh ([`super::plane::PlaneProperties`]), in
//! the displacement or the mixed P2/P0 formulation; and at finite strain ([`PlaneBody`], for
//! the Newton solver).

use std::sync::Arc;

use nalgebra::SMatrix;

use super::plane::{PlaneProperties, Truss};
use super::Assembler;
pub use crate::element::tri6::Formulation;
use crate::element::{line3, tri6, Material};
use crate::error::ModelError;
use crate::mesh::QuadraticPlaneMesh;
use crate::solve::newton::Equations;
use crate::solve::structure::InternalForces;

/// Element order for the assembler: all triangles, then all lines.
pub fn assembler(mesh: &QuadraticPlaneMesh) -> Assembler {
    let mut elements: Vec<&[usize]> = mesh.triangles().iter().map(|t| t.as_slice()).collect();
    elements.extend(mesh.lines().iter().map(|l| l.as_slice()));
    Assembler::new(mesh.nodes().len(), 2, &elements)
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
    add_lines(mesh, asm, props, values, |p, t| {
        line3::stiffness(p, t.young, t.area)
    });
}

/// Adds each line's matrix `matrix(points, truss)` to `values`.
fn add_lines(
    mesh: &QuadraticPlaneMesh,
    asm: &Assembler,
    props: &PlaneProperties,
    values: &mut [f64],
    matrix: impl Fn(&[[f64; 2]; 3], &Truss) -> SMatrix<f64, 6, 6>,
) {
    let first = mesh.triangles().len();
    for (i, &r) in mesh.line_regions().iter().enumerate() {
        let t = &props.trusses[usize::from(r)];
        asm.add(values, first + i, &matrix(&mesh.line(i), t));
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
    add_lines(mesh, asm, props, values, |p, t| {
        line3::mass_consistent(p, t.density, t.area)
    });
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
        scatter(&mut m, el, lumped.as_slice());
    }
    for (i, (el, &r)) in mesh.lines().iter().zip(mesh.line_regions()).enumerate() {
        let t = &props.trusses[usize::from(r)];
        scatter(
            &mut m,
            el,
            line3::mass_lumped(&mesh.line(i), t.density, t.area).as_slice(),
        );
    }
    m
}

/// Adds an element's per-dof values to the global vector.
fn scatter(global: &mut [f64], nodes: &[usize], values: &[f64]) {
    for (a, &n) in nodes.iter().enumerate() {
        global[2 * n] += values[2 * a];
        global[2 * n + 1] += values[2 * a + 1];
    }
}

/// A mesh of 6-node triangles at finite strain (plane strain, total Lagrangian), one
/// material per region: the internal forces and tangent for [`crate::solve::Newton`].
pub struct PlaneBody<'a> {
    pub mesh: &'a QuadraticPlaneMesh,
    pub asm: &'a Assembler,
    pub materials: &'a [Material],
    /// The lines' properties (by line region); the lines stay small-strain (linear axial
    /// stiffness), valid while they rotate little.
    pub trusses: &'a [Truss],
}

impl Equations for PlaneBody<'_> {
    fn add_internal(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        let (mesh, materials, trusses) = (self.mesh, self.materials, self.trusses);
        super::add_internal(
            mesh.triangles(),
            0,
            self.asm,
            u,
            f,
            k.as_deref_mut(),
            |e, ue, fe, ke| {
                let material = &materials[usize::from(mesh.triangle_regions()[e])];
                tri6::internal(&mesh.triangle(e), ue, material, fe, ke)
            },
        )?;
        // The lines stay small-strain: f = K u with their linear axial stiffness.
        let first = mesh.triangles().len();
        super::add_internal(mesh.lines(), first, self.asm, u, f, k, |e, ue, fe, ke| {
            let t = &trusses[usize::from(mesh.line_regions()[e])];
            let kl = line3::stiffness(&mesh.line(e), t.young, t.area);
            *fe += kl * ue;
            if let Some(ke) = ke {
                *ke += kl;
            }
            Ok(())
        })
    }
}

/// The internal forces of the body as a finite-strain structure's
/// ([`crate::solve::Structure::with_internal_forces`]), owning what it reads.
pub fn internal_forces(
    mesh: Arc<QuadraticPlaneMesh>,
    asm: Arc<Assembler>,
    materials: Arc<[Material]>,
    trusses: Arc<[Truss]>,
) -> Arc<InternalForces> {
    Arc::new(move |u, f, k| {
        PlaneBody {
            mesh: &mesh,
            asm: &asm,
            materials: &materials,
            trusses: &trusses,
        }
        .internal(u, f, k)
    })
}
