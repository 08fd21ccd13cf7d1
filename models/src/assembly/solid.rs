//! Global matrices of a 3D tetrahedral mesh of one material: the closed-form small-strain
//! stiffness and mass of the linear tetrahedron, and a [`Solid`] — linear or quadratic
//! tetrahedra of one material law — whose internal forces and tangent go through the total
//! Lagrangian kernel ([`crate::element::solid`]) for the nonlinear solver.

use nalgebra::{Matrix3, SVector};

use super::plane::Continuum;
use super::Assembler;
use crate::element::solid::{
    deformation_at, internal, small_strain_stiffness, Reference, Shape, Tet10, Tet4,
};
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
            .ok_or_else(|| ModelError::UnknownChoice {
                what: "element",
                value: name.to_string(),
                choices: "tet4 or tet10",
            })
    }
}

/// The elements of a solid, corner nodes first.
#[derive(Debug, Clone)]
pub enum Elements {
    Tet4(Vec<[usize; 4]>),
    Tet10(Vec<[usize; 10]>),
}

/// Tetrahedra of one material law on their nodes, with each element's reference
/// configuration (computed once).
#[derive(Debug, Clone)]
pub struct Solid {
    nodes: Vec<[f64; 3]>,
    elements: Elements,
    reference: Vec<Reference>,
    pub material: Material,
}

impl Solid {
    /// The linear mesh as it is, or with mid-edge nodes for quadratic tetrahedra (the
    /// corner nodes keep their numbers).
    pub fn new(mesh: &Mesh3d, kind: Tetrahedron, material: Material) -> Self {
        match kind {
            Tetrahedron::Tet4 => Self::linear(mesh, material),
            Tetrahedron::Tet10 => Self::quadratic(&QuadraticMesh::new(mesh), material),
        }
    }

    /// Linear tetrahedra on `mesh`.
    pub fn linear(mesh: &Mesh3d, material: Material) -> Self {
        Self::on(
            mesh.nodes().to_vec(),
            Elements::Tet4(mesh.tets().to_vec()),
            material,
        )
    }

    /// Quadratic tetrahedra on `mesh`.
    pub fn quadratic(mesh: &QuadraticMesh, material: Material) -> Self {
        Self::on(
            mesh.nodes().to_vec(),
            Elements::Tet10(mesh.tets().to_vec()),
            material,
        )
    }

    fn on(nodes: Vec<[f64; 3]>, elements: Elements, material: Material) -> Self {
        let mut s = Self {
            nodes,
            elements,
            reference: Vec::new(),
            material,
        };
        s.reference = (0..s.len())
            .map(|e| Reference::new(&s.corners(e).map(|n| s.nodes[n])))
            .collect();
        s
    }

    /// The nodes (corners first).
    pub fn nodes(&self) -> &[[f64; 3]] {
        &self.nodes
    }

    pub fn elements(&self) -> &Elements {
        &self.elements
    }

    /// Which tetrahedron.
    pub fn kind(&self) -> Tetrahedron {
        match self.elements {
            Elements::Tet4(_) => Tetrahedron::Tet4,
            Elements::Tet10(_) => Tetrahedron::Tet10,
        }
    }

    /// The corner nodes of element `e`.
    pub fn corners(&self, e: usize) -> [usize; 4] {
        match &self.elements {
            Elements::Tet4(t) => t[e],
            Elements::Tet10(t) => [t[e][0], t[e][1], t[e][2], t[e][3]],
        }
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        match &self.elements {
            Elements::Tet4(t) => t.len(),
            Elements::Tet10(t) => t.len(),
        }
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The mesh of linear tetrahedra on the corner nodes (which come first), with its
    /// boundary faces: for surfaces, searches and files that need only the corners.
    pub fn corner_mesh(&self) -> Result<Mesh3d, ModelError> {
        let tets: Vec<[usize; 4]> = (0..self.len()).map(|e| self.corners(e)).collect();
        let corners = tets.iter().flatten().max().map_or(0, |&n| n + 1);
        Mesh3d::new(self.nodes[..corners].to_vec(), tets)
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
        let (r, m) = (&self.reference, &self.material);
        match &self.elements {
            Elements::Tet4(e) => add::<Tet4, 4, 12>(r, e, m, asm, u, f, k),
            Elements::Tet10(e) => add::<Tet10, 10, 30>(r, e, m, asm, u, f, k),
        }
    }

    /// Adds the small-strain stiffness of the linear law (λ, μ of the material, whatever
    /// its law) to `k` (values on `asm`'s pattern, whose first elements are these): the
    /// tangent [`Self::add_internal`] gives for the linear law, in closed form
    /// ([`small_strain_stiffness`]).
    pub fn add_stiffness(&self, asm: &Assembler, k: &mut [f64]) -> Result<(), ModelError> {
        let (r, m) = (&self.reference, &self.material);
        let zero = vec![0.0; self.n_dofs()];
        let mut f = zero.clone();
        match &self.elements {
            Elements::Tet4(e) => stiffness_of::<Tet4, 4, 12>(r, e, m, asm, &zero, &mut f, k),
            Elements::Tet10(e) => stiffness_of::<Tet10, 10, 30>(r, e, m, asm, &zero, &mut f, k),
        }
    }

    /// The deformation gradient at each element's centroid and the element's volume, in
    /// element order (computed as iterated: nothing is allocated).
    pub fn centroids<'a>(&'a self, u: &'a [f64]) -> impl Iterator<Item = (Matrix3<f64>, f64)> + 'a {
        (0..self.len()).map(move |e| self.centroid(e, u))
    }

    /// The deformation gradient at element `e`'s centroid and its volume.
    fn centroid(&self, e: usize, u: &[f64]) -> (Matrix3<f64>, f64) {
        let r = &self.reference[e];
        match &self.elements {
            Elements::Tet4(el) => (centroid_gradient::<Tet4, 4, 12>(r, &el[e], u), r.volume),
            Elements::Tet10(el) => (centroid_gradient::<Tet10, 10, 30>(r, &el[e], u), r.volume),
        }
    }
}

fn centroid_gradient<S: Shape<N>, const N: usize, const D: usize>(
    reference: &Reference,
    element: &[usize; N],
    u: &[f64],
) -> Matrix3<f64> {
    let ue = SVector::<f64, D>::from_fn(|row, _| u[3 * element[row / 3] + row % 3]);
    deformation_at::<S, N, D>(reference, &ue, &[0.25; 4])
}

/// A solid on its own pattern is a system of equations for the Newton solver.
pub struct Body<'a> {
    pub solid: &'a Solid,
    pub asm: &'a Assembler,
}

impl Equations for Body<'_> {
    fn add_internal(
        &mut self,
        u: &[f64],
        f: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        self.solid.add_internal(self.asm, u, f, k)
    }
}

fn add<S: Shape<N>, const N: usize, const D: usize>(
    reference: &[Reference],
    elements: &[[usize; N]],
    material: &Material,
    asm: &Assembler,
    u: &[f64],
    f: &mut [f64],
    k: Option<&mut [f64]>,
) -> Result<(), ModelError> {
    super::add_internal(elements, 0, asm, u, f, k, |e, ue, fe, ke| {
        internal::<S, N, D>(&reference[e], ue, material, fe, ke)
    })
}

fn stiffness_of<S: Shape<N>, const N: usize, const D: usize>(
    reference: &[Reference],
    elements: &[[usize; N]],
    material: &Material,
    asm: &Assembler,
    zero: &[f64],
    f: &mut [f64],
    k: &mut [f64],
) -> Result<(), ModelError> {
    super::add_internal(elements, 0, asm, zero, f, Some(k), |e, _, _, ke| {
        if let Some(ke) = ke {
            small_strain_stiffness::<S, N, D>(&reference[e], material, ke);
        }
        Ok(())
    })
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
