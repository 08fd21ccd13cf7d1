//! Global matrices of a 3D tetrahedral mesh of one material: the closed-form small-strain
//! stiffness and mass of the linear tetrahedron, and a [`Solid`] — linear or quadratic
//! tetrahedra of one material law — whose internal forces and tangent go through the total
//! Lagrangian kernel ([`crate::element::solid`]) for the nonlinear solver.

use nalgebra::{SMatrix, SVector};

use super::plane::Continuum;
use super::Assembler;
use crate::element::solid::{internal, Shape, Tet10, Tet4};
use crate::element::{tet4, Material};
use crate::error::ModelError;
use crate::mesh::{Mesh3d, QuadraticMesh};
use crate::solve::newton::Equations;

/// Which tetrahedron (the scenes' `element` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tetrahedron {
    Tet4,
    Tet10,
}

impl Tetrahedron {
    pub const ALL: [Self; 2] = [Self::Tet4, Self::Tet10];

    pub fn name(self) -> &'static str {
        match self {
            Self::Tet4 => "tet4",
            Self::Tet10 => "tet10",
        }
    }

    pub fn parse(name: &str) -> Result<Self, ModelError> {
        Self::ALL
            .into_iter()
            .find(|t| t.name() == name)
            .ok_or_else(|| ModelError::InvalidParameter {
                name: format!("element `{name}`"),
                value: f64::NAN,
                reason: "unknown; use tet4 or tet10",
            })
    }
}

/// The elements of a solid, corner nodes first.
#[derive(Debug, Clone)]
pub enum Elements {
    Tet4(Vec<[usize; 4]>),
    Tet10(Vec<[usize; 10]>),
}

/// Tetrahedra of one material law on their nodes.
#[derive(Debug, Clone)]
pub struct Solid {
    pub nodes: Vec<[f64; 3]>,
    pub elements: Elements,
    pub material: Material,
}

impl Solid {
    /// The linear mesh as it is, or with mid-edge nodes for quadratic tetrahedra (the
    /// corner nodes keep their numbers).
    pub fn new(mesh: &Mesh3d, kind: Tetrahedron, material: Material) -> Self {
        match kind {
            Tetrahedron::Tet4 => Self {
                nodes: mesh.nodes().to_vec(),
                elements: Elements::Tet4(mesh.tets().to_vec()),
                material,
            },
            Tetrahedron::Tet10 => {
                let q = QuadraticMesh::new(mesh);
                Self {
                    nodes: q.nodes().to_vec(),
                    elements: Elements::Tet10(q.tets().to_vec()),
                    material,
                }
            }
        }
    }

    pub fn n_dofs(&self) -> usize {
        3 * self.nodes.len()
    }

    /// The element node lists, for building an assembler's pattern.
    pub fn connectivity(&self) -> Vec<&[usize]> {
        match &self.elements {
            Elements::Tet4(e) => e.iter().map(|t| t.as_slice()).collect(),
            Elements::Tet10(e) => e.iter().map(|t| t.as_slice()).collect(),
        }
    }

    /// Adds the internal forces at `u` (all dofs) to `f` and the tangent to `k` (values on
    /// `asm`'s pattern, whose first elements are these), without zeroing either.
    pub fn add_internal(
        &self,
        asm: &Assembler,
        u: &[f64],
        f: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        match &self.elements {
            Elements::Tet4(e) => add::<Tet4, 4, 12>(&self.nodes, e, &self.material, asm, u, f, k),
            Elements::Tet10(e) => {
                add::<Tet10, 10, 30>(&self.nodes, e, &self.material, asm, u, f, k)
            }
        }
    }
}

/// A solid on its own pattern is a system of equations for the Newton solver.
pub struct Body<'a> {
    pub solid: &'a Solid,
    pub asm: &'a Assembler,
}

impl Equations for Body<'_> {
    fn internal(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        f.fill(0.0);
        if let Some(k) = k.as_deref_mut() {
            k.fill(0.0);
        }
        self.solid.add_internal(self.asm, u, f, k)
    }
}

fn add<S: Shape<N>, const N: usize, const D: usize>(
    nodes: &[[f64; 3]],
    elements: &[[usize; N]],
    material: &Material,
    asm: &Assembler,
    u: &[f64],
    f: &mut [f64],
    mut k: Option<&mut [f64]>,
) -> Result<(), ModelError> {
    let mut ke = SMatrix::<f64, D, D>::zeros();
    for (e, el) in elements.iter().enumerate() {
        let corners = [0, 1, 2, 3].map(|i| nodes[el[i]]);
        let ue = SVector::<f64, D>::from_fn(|r, _| u[3 * el[r / 3] + r % 3]);
        let mut fe = SVector::<f64, D>::zeros();
        ke.fill(0.0);
        let tangent = k.is_some().then_some(&mut ke);
        internal::<S, N, D>(&corners, &ue, material, &mut fe, tangent).map_err(|inv| {
            ModelError::Inverted {
                element: e,
                j: inv.j,
            }
        })?;
        for (a, &n) in el.iter().enumerate() {
            for i in 0..3 {
                f[3 * n + i] += fe[3 * a + i];
            }
        }
        if let Some(k) = k.as_deref_mut() {
            asm.add(k, e, &ke);
        }
    }
    Ok(())
}

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
