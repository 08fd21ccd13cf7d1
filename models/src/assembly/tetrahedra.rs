//! Global matrices of a 3D tetrahedral mesh of one material: the closed-form small-strain
//! stiffness and mass of the linear tetrahedron, and a [`Solid`] — linear or quadratic
//! tetrahedra of one material law — whose internal forces and tangent go through the total
//! Lagrangian kernel ([`crate::element::total_lagrangian`]) for the nonlinear solver.

use nalgebra::{Matrix3, SVector};

use super::forces::{self, InternalForces};
use super::plane::Continuum;
use super::Assembler;
use crate::element::total_lagrangian::{
    deformation_at, internal, small_strain_stiffness, Shape, Tet10, Tet4, TetReference,
};
use crate::element::{tet4, Material};
use crate::error::ModelError;
use crate::mesh::{Mesh3d, QuadraticMesh};

/// Which tetrahedron (the scenes' `element` parameter).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Tetrahedron {
    /// The 4-node linear tetrahedron (`tet4`): constant strain.
    Tet4,
    /// The 10-node quadratic tetrahedron (`tet10`): corners and mid-edge nodes.
    Tet10,
}

impl Tetrahedron {
    /// Both tetrahedra ([`parse`](Self::parse) searches them).
    pub const ALL: [Self; 2] = [Self::Tet4, Self::Tet10];

    /// The name used by the scenes' `element` parameter.
    pub fn name(self) -> &'static str {
        match self {
            Self::Tet4 => "tet4",
            Self::Tet10 => "tet10",
        }
    }

    /// Parses a name as given by [`name`](Self::name).
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
    /// Linear tetrahedra: four corner nodes each.
    Tet4(Vec<[usize; 4]>),
    /// Quadratic tetrahedra: four corners, then six mid-edge nodes (node order as
    /// [`crate::element::tet10`]).
    Tet10(Vec<[usize; 10]>),
}

/// Tetrahedra of one material law on their nodes, with each element's reference
/// configuration (computed once).
#[derive(Debug, Clone)]
pub struct Solid {
    nodes: Vec<[f64; 3]>,
    elements: Elements,
    reference: Vec<TetReference>,
    /// The material law and elastic constants of every element.
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

    /// Quadratic tetrahedra on `quadratic` (`mesh` with its mid-edge nodes) where it is
    /// given, else linear ones on `mesh`.
    pub fn on_mesh(mesh: &Mesh3d, quadratic: Option<&QuadraticMesh>, material: Material) -> Self {
        match quadratic {
            Some(q) => Self::quadratic(q, material),
            None => Self::linear(mesh, material),
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
            .map(|e| TetReference::new(&s.corners(e).map(|n| s.nodes[n])))
            .collect();
        s
    }

    /// The nodes (corners first).
    pub fn nodes(&self) -> &[[f64; 3]] {
        &self.nodes
    }

    /// The elements' node lists.
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

    /// Whether the solid has no elements.
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

    /// Number of degrees of freedom (3 per node).
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
        self.add_internal_of(&self.material, asm, u, f, k)
    }

    /// Adds ∂f_int/∂ν at fixed `u` (all dofs) to `f`: the internal forces of the material's
    /// derivative in Poisson's ratio ([`Material::poisson_derivative`]).
    pub fn add_poisson_derivative(
        &self,
        asm: &Assembler,
        u: &[f64],
        f: &mut [f64],
    ) -> Result<(), ModelError> {
        self.add_internal_of(&self.material.poisson_derivative(), asm, u, f, None)
    }

    fn add_internal_of(
        &self,
        m: &Material,
        asm: &Assembler,
        u: &[f64],
        f: &mut [f64],
        k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        let r = &self.reference;
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

fn centroid_gradient<
    S: Shape<N, 3, Reference = TetReference, At = [f64; 4]>,
    const N: usize,
    const D: usize,
>(
    reference: &TetReference,
    element: &[usize; N],
    u: &[f64],
) -> Matrix3<f64> {
    let ue = SVector::<f64, D>::from_fn(|row, _| u[3 * element[row / 3] + row % 3]);
    deformation_at::<S, N, 3, D>(reference, &ue, &[0.25; 4])
}

/// A solid on its own pattern: the internal forces the Newton solver iterates on.
pub struct Body<'a> {
    /// The solid whose internal forces are evaluated.
    pub solid: &'a Solid,
    /// The pattern the tangent is written on (its first elements are the solid's).
    pub asm: &'a Assembler,
}

impl InternalForces for Body<'_> {
    fn internal(
        &self,
        u: &[f64],
        f: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        forces::clear(f, k.as_deref_mut());
        self.solid.add_internal(self.asm, u, f, k)
    }
}

fn add<S: Shape<N, 3, Reference = TetReference, At = [f64; 4]>, const N: usize, const D: usize>(
    reference: &[TetReference],
    elements: &[[usize; N]],
    material: &Material,
    asm: &Assembler,
    u: &[f64],
    f: &mut [f64],
    k: Option<&mut [f64]>,
) -> Result<(), ModelError> {
    super::add_internal(elements, 0, asm, u, f, k, |e, ue, fe, ke| {
        internal::<S, N, 3, D>(&reference[e], ue, material, fe, ke)
    })
}

fn stiffness_of<
    S: Shape<N, 3, Reference = TetReference, At = [f64; 4]>,
    const N: usize,
    const D: usize,
>(
    reference: &[TetReference],
    elements: &[[usize; N]],
    material: &Material,
    asm: &Assembler,
    zero: &[f64],
    f: &mut [f64],
    k: &mut [f64],
) -> Result<(), ModelError> {
    super::add_internal(elements, 0, asm, zero, f, Some(k), |e, _, _, ke| {
        if let Some(ke) = ke {
            small_strain_stiffness::<S, N, 3, D>(&reference[e], material, ke);
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
        let lumped = tet4::lumped_mass(&mesh.tet(i), material.density);
        for (k, d) in mesh.tet_dofs(i).into_iter().enumerate() {
            m[d] += lumped[k];
        }
    }
    m
}
