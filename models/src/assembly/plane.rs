//! Global matrices of a 2D mesh: plane-strain triangles plus axial line elements, with
//! properties per region tag (tissue).

use super::Assembler;
use crate::element::membrane::{Law, Section};
use crate::element::{line2, tri3, Elastic};
use crate::error::{positive, ModelError};
use crate::mesh::Mesh2d;

/// Properties of a triangle region: elastic constants and density (t/mm³).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Continuum {
    /// Elastic constants: Young's modulus (MPa) and Poisson's ratio.
    pub elastic: Elastic,
    /// Density (t/mm³).
    pub density: f64,
}

/// Properties of a line-element region: Young's modulus (MPa), cross-section (mm² per mm
/// of out-of-plane depth), density (t/mm³) and, for a muscle sheet, whether it contracts
/// (carries the press's active tension at finite strain) and its curvature across the slice.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Truss {
    /// Young's modulus (MPa).
    pub young: f64,
    /// Cross-section (mm² per mm of out-of-plane depth).
    pub area: f64,
    /// Density (t/mm³).
    pub density: f64,
    /// Whether the line contracts: the press's active tension acts in it.
    pub contracts: bool,
    /// Its curvature across the slice (1/mm; [`Section::transverse_curvature`]).
    pub transverse_curvature: f64,
    /// Its law in tension at finite strain.
    pub law: Law,
}

impl Truss {
    /// Validated constructor; `name` prefixes the variable names in errors.
    pub fn new(name: &str, young: f64, area: f64, density: f64) -> Result<Self, ModelError> {
        Ok(Self {
            young: positive(&format!("{name}.E"), young)?,
            area: positive(&format!("{name}.area"), area)?,
            density: crate::error::non_negative(&format!("{name}.density"), density)?,
            contracts: false,
            transverse_curvature: 0.0,
            law: Law::default(),
        })
    }

    /// The section of the lines at finite strain with active tension `tension` (N per mm of
    /// depth) where the line contracts, none where it does not.
    pub fn section(&self, tension: f64) -> Section {
        Section {
            law: self.law,
            young: self.young,
            area: self.area,
            tension: if self.contracts { tension } else { 0.0 },
            transverse_curvature: self.transverse_curvature,
        }
    }
}

/// Properties indexed by region tag.
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneProperties {
    /// The triangles' properties, indexed by triangle region tag.
    pub continua: Vec<Continuum>,
    /// The line elements' properties, indexed by line region tag.
    pub trusses: Vec<Truss>,
}

impl PlaneProperties {
    /// Checks that every region tag of `mesh` has properties.
    pub fn check(&self, mesh: &Mesh2d) -> Result<(), ModelError> {
        let missing = |tags: &[u16], n: usize, what: &'static str| match tags
            .iter()
            .find(|&&t| usize::from(t) >= n)
        {
            Some(&t) => Err(ModelError::InvalidParameter {
                name: what.into(),
                value: f64::from(t),
                reason: "region tag has no properties",
            }),
            None => Ok(()),
        };
        missing(
            mesh.triangle_regions(),
            self.continua.len(),
            "triangle region",
        )?;
        missing(mesh.line_regions(), self.trusses.len(), "line region")
    }
}

/// Element order for the assembler: all triangles, then all line elements.
pub fn assembler(mesh: &Mesh2d) -> Assembler {
    let mut elements: Vec<&[usize]> = mesh.triangles().iter().map(|t| t.as_slice()).collect();
    elements.extend(mesh.lines().iter().map(|l| l.as_slice()));
    Assembler::new(mesh.nodes().len(), 2, &elements)
}

/// Writes the stiffness matrix into `values` (overwriting).
pub fn stiffness(mesh: &Mesh2d, asm: &Assembler, props: &PlaneProperties, values: &mut [f64]) {
    values.fill(0.0);
    let n_tri = mesh.triangles().len();
    let d: Vec<_> = props
        .continua
        .iter()
        .map(|c| c.elastic.plane_strain())
        .collect();
    for (i, &r) in mesh.triangle_regions().iter().enumerate() {
        asm.add(
            values,
            i,
            &tri3::stiffness(&mesh.triangle(i), &d[usize::from(r)]),
        );
    }
    for (i, &r) in mesh.line_regions().iter().enumerate() {
        let t = &props.trusses[usize::from(r)];
        asm.add(
            values,
            n_tri + i,
            &line2::stiffness(&mesh.line(i), t.young, t.area),
        );
    }
}

/// Writes the consistent mass matrix into `values` (overwriting).
pub fn mass(mesh: &Mesh2d, asm: &Assembler, props: &PlaneProperties, values: &mut [f64]) {
    values.fill(0.0);
    let n_tri = mesh.triangles().len();
    for (i, &r) in mesh.triangle_regions().iter().enumerate() {
        let rho = props.continua[usize::from(r)].density;
        asm.add(values, i, &tri3::mass_consistent(&mesh.triangle(i), rho));
    }
    for (i, &r) in mesh.line_regions().iter().enumerate() {
        let t = &props.trusses[usize::from(r)];
        asm.add(
            values,
            n_tri + i,
            &line2::mass_consistent(&mesh.line(i), t.density, t.area),
        );
    }
}

/// Lumped (row-sum) mass per dof.
pub fn lumped_mass(mesh: &Mesh2d, props: &PlaneProperties) -> Vec<f64> {
    let mut m = vec![0.0; mesh.n_dofs()];
    for (i, &r) in mesh.triangle_regions().iter().enumerate() {
        let lumped = tri3::lumped_mass(&mesh.triangle(i), props.continua[usize::from(r)].density);
        for (k, d) in mesh.triangle_dofs(i).into_iter().enumerate() {
            m[d] += lumped[k];
        }
    }
    for (i, &r) in mesh.line_regions().iter().enumerate() {
        let t = &props.trusses[usize::from(r)];
        let lumped = line2::lumped_mass(&mesh.line(i), t.density, t.area);
        for (k, d) in mesh.line_dofs(i).into_iter().enumerate() {
            m[d] += lumped[k];
        }
    }
    m
}
