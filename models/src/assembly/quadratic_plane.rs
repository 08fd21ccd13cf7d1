//! Global matrices of a mesh of 6-node plane-strain triangles ([`crate::element::tri6`]),
//! properties per region tag as for the linear mesh ([`super::plane::PlaneProperties`]), in
//! the displacement or the mixed P2/P0 formulation; and at finite strain ([`PlaneBody`]:
//! triangles in either formulation, lines as membranes, [`crate::element::membrane`]).

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use nalgebra::{SMatrix, SVector};

use super::forces::{self, ElementForces, InternalForces};
use super::plane::{PlaneProperties, Truss};
use super::Assembler;
use crate::element::mixed;
pub use crate::element::mixed::Formulation;
use crate::element::total_lagrangian::Inverted;
use crate::element::{line3, tri6, Material};
use crate::error::ModelError;
use crate::mesh::QuadraticPlaneMesh;

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
        let k = mixed::stiffness_in(formulation, &mesh.triangle(i), elastic);
        asm.add(values, i, &k);
    }
    add_lines(mesh, asm, props, values, |p, t| {
        line3::stiffness(p, t.section(0.0))
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
        let lumped = tri6::lumped_mass(&mesh.triangle(i), props.continua[usize::from(r)].density);
        scatter(&mut m, el, lumped.as_slice());
    }
    for (i, (el, &r)) in mesh.lines().iter().zip(mesh.line_regions()).enumerate() {
        let t = &props.trusses[usize::from(r)];
        scatter(
            &mut m,
            el,
            line3::lumped_mass(&mesh.line(i), t.density, t.area).as_slice(),
        );
    }
    m
}

/// Adds an element's per-dof values to the global vector.
pub(crate) fn scatter(global: &mut [f64], nodes: &[usize], values: &[f64]) {
    for (a, &n) in nodes.iter().enumerate() {
        global[2 * n] += values[2 * a];
        global[2 * n + 1] += values[2 * a + 1];
    }
}

/// An active tension shared between whoever drives the steps, which sets it (the abdomen's
/// load, at each step's time; a static ramp, at each load fraction), and a [`PlaneBody`],
/// which reads it at every evaluation and notes the value its last tangent was taken at (a
/// checkpoint must refactorize a kept tangent at that value).
#[derive(Debug, Default)]
pub struct SharedTension {
    now: AtomicU64,
    at_tangent: AtomicU64,
}

impl SharedTension {
    /// Sets the tension (N per mm of depth) the next evaluations read.
    pub fn set(&self, tension: f64) {
        self.now.store(tension.to_bits(), Ordering::Relaxed);
    }

    /// The tension the next evaluations read.
    pub fn get(&self) -> f64 {
        f64::from_bits(self.now.load(Ordering::Relaxed))
    }

    /// The tension the last tangent was evaluated at.
    pub fn at_tangent(&self) -> f64 {
        f64::from_bits(self.at_tangent.load(Ordering::Relaxed))
    }

    fn tangent_taken(&self) {
        self.at_tangent
            .store(self.now.load(Ordering::Relaxed), Ordering::Relaxed);
    }
}

/// A mesh of 6-node triangles at finite strain (plane strain, total Lagrangian), one
/// material per region, in `formulation`, with its 3-node lines as membranes at finite
/// strain ([`crate::element::membrane`]); the lines whose truss contracts
/// ([`Truss::contracts`]: the muscle sheets of a press) carry the tension `active` holds at
/// each evaluation. Its internal forces serve the
/// static Newton solver, a dynamic structure and, element by element, its hyper-reduction.
pub struct PlaneBody {
    /// The mesh of 6-node triangles and 3-node lines.
    pub mesh: Arc<QuadraticPlaneMesh>,
    /// The pattern over the mesh's elements: all triangles, then all lines.
    pub asm: Arc<Assembler>,
    /// The material of the triangles (by triangle region).
    pub materials: Arc<[Material]>,
    /// The triangles' formulation: displacement or mixed P2/P0.
    pub formulation: Formulation,
    /// The lines' properties (by line region).
    pub trusses: Arc<[Truss]>,
    /// The active tension of the contracting lines.
    pub active: Option<Arc<SharedTension>>,
}

impl PlaneBody {
    /// A body of triangles alone (no membranes, no active tension).
    pub fn triangles(
        mesh: Arc<QuadraticPlaneMesh>,
        asm: Arc<Assembler>,
        materials: Arc<[Material]>,
        formulation: Formulation,
    ) -> Self {
        Self {
            mesh,
            asm,
            materials,
            formulation,
            trusses: Arc::from([]),
            active: None,
        }
    }

    /// Triangle `e`'s internal force and tangent at its nodal displacement (total
    /// Lagrangian, plane strain, in the body's formulation).
    fn triangle(
        &self,
        e: usize,
        ue: &SVector<f64, 12>,
        fe: &mut SVector<f64, 12>,
        ke: Option<&mut SMatrix<f64, 12, 12>>,
    ) -> Result<(), Inverted> {
        let material = &self.materials[usize::from(self.mesh.triangle_regions()[e])];
        mixed::internal_in(
            self.formulation,
            &self.mesh.triangle(e),
            ue,
            material,
            fe,
            ke,
        )
    }

    /// Line `e` as a membrane, carrying the active tension `tension` if its truss contracts.
    fn line(
        &self,
        e: usize,
        tension: f64,
        ue: &SVector<f64, 6>,
        fe: &mut SVector<f64, 6>,
        ke: Option<&mut SMatrix<f64, 6, 6>>,
    ) -> Result<(), Inverted> {
        let region = self.mesh.line_regions()[e];
        let section = self.trusses[usize::from(region)].section(tension);
        line3::membrane(&self.mesh.line(e)).internal::<6>(ue, section, fe, ke)
    }

    /// The active tension now (0 without one); noted as the tangent's when `tangent`.
    fn tension(&self, tangent: bool) -> f64 {
        self.active.as_ref().map_or(0.0, |t| {
            if tangent {
                t.tangent_taken();
            }
            t.get()
        })
    }

    /// The nodes of element `e` in the assembler's order: the triangles, then the lines.
    fn nodes(&self, e: usize) -> &[usize] {
        let triangles = self.mesh.triangles();
        match triangles.get(e) {
            Some(t) => t,
            None => &self.mesh.lines()[e - triangles.len()],
        }
    }
}

impl InternalForces for PlaneBody {
    fn internal(
        &self,
        u: &[f64],
        f: &mut [f64],
        mut k: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        forces::clear(f, k.as_deref_mut());
        let tension = self.tension(k.is_some());
        let mesh = &self.mesh;
        super::add_internal(
            mesh.triangles(),
            0,
            &self.asm,
            u,
            f,
            k.as_deref_mut(),
            |e, ue, fe, ke| self.triangle(e, ue, fe, ke),
        )?;
        let first = mesh.triangles().len();
        super::add_internal(mesh.lines(), first, &self.asm, u, f, k, |e, ue, fe, ke| {
            self.line(e, tension, ue, fe, ke)
        })
    }
}

impl ElementForces for PlaneBody {
    fn count(&self) -> usize {
        self.mesh.triangles().len() + self.mesh.lines().len()
    }

    fn dofs(&self, e: usize, dofs: &mut Vec<usize>) {
        dofs.clear();
        dofs.extend(self.nodes(e).iter().flat_map(|n| [2 * n, 2 * n + 1]));
    }

    fn evaluate(
        &self,
        e: usize,
        ue: &[f64],
        fe: &mut [f64],
        ke: Option<&mut [f64]>,
    ) -> Result<(), ModelError> {
        let tension = self.tension(ke.is_some());
        let triangles = self.mesh.triangles().len();
        // Numbered within its kind, as the full assembly names an inverted element.
        let inverted =
            |element: usize| move |inv: Inverted| ModelError::Inverted { element, j: inv.j };
        if e < triangles {
            kernel::<12>(ue, fe, ke, |u, f, k| self.triangle(e, u, f, k)).map_err(inverted(e))
        } else {
            let line = e - triangles;
            kernel::<6>(ue, fe, ke, |u, f, k| self.line(line, tension, u, f, k))
                .map_err(inverted(line))
        }
    }
}

/// An element kernel on fixed-size vectors called with slices (`ke` column-major).
fn kernel<const D: usize>(
    ue: &[f64],
    fe: &mut [f64],
    ke: Option<&mut [f64]>,
    f: impl FnOnce(
        &SVector<f64, D>,
        &mut SVector<f64, D>,
        Option<&mut SMatrix<f64, D, D>>,
    ) -> Result<(), Inverted>,
) -> Result<(), Inverted> {
    let u = SVector::<f64, D>::from_column_slice(ue);
    let mut force = SVector::<f64, D>::zeros();
    let mut tangent = ke.as_ref().map(|_| SMatrix::<f64, D, D>::zeros());
    f(&u, &mut force, tangent.as_mut())?;
    fe.copy_from_slice(force.as_slice());
    if let (Some(ke), Some(t)) = (ke, tangent) {
        ke.copy_from_slice(t.as_slice());
    }
    Ok(())
}
