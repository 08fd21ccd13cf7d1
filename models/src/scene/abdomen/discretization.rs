//! How the cavity is discretized (issue 12): the seed's 3-node triangles with 2-node
//! membranes (seed 003 §5.4.4), or 6-node triangles ([`tri6`]) with 3-node membranes on the
//! same edge nodes ([`crate::element::line3`]), in the displacement or the mixed P2/P0
//! formulation; at small strain, or at finite strain (issue 26: plane-strain total
//! Lagrangian neo-Hookean cavity in either formulation, the mixed one in the three-field form
//! of [`mixed::internal_mixed`]; membranes at finite strain, [`crate::element::membrane`];
//! Newton's method within each implicit step).
//!
//! The 6-node mesh is derived from the 3-node one: the corners keep their numbers, so node
//! sets, landmarks and the first 2 · corners entries of a displacement mean the same in both.
//! The boundary is the same polyline; supports hold the mid-edge nodes of supported boundary
//! edges too.
//!
//! Where each stops being valid: `tri3` locks as ν → 0.5 (0.15 of the beam deflection at
//! ν = 0.499, `tests/locking.rs`); the displacement `tri6` locks mildly in displacement but
//! its stresses oscillate at ν ≥ 0.499 — use `mixed` there; `linear` kinematics assume small
//! strains and rotations (and give a straight membrane no stiffness across itself).

use std::collections::HashSet;
use std::sync::Arc;

use super::mesher::{Meshed, DIAPHRAGM_REGION};
use crate::assembly::loads;
use crate::assembly::plane::{self, PlaneProperties, Truss};
use crate::assembly::quadratic_plane::{self, scatter, PlaneBody, SharedTension};
use crate::assembly::Assembler;
use crate::element::mixed::Formulation;
use crate::element::recovery;
use crate::element::tri6;
use crate::element::{line2, line3, tri3};
use crate::element::{Law, Material};
use crate::error::ModelError;
use crate::mesh::{plane_dofs, Mesh2d, QuadraticPlaneMesh};
use crate::scene::SceneError;
use crate::stress::{LineStresses, PlaneStress, TriangleStresses};

/// The cavity's element.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Element {
    /// 3-node linear triangles with 2-node membranes (the seed's, `tri3`).
    Tri3,
    /// 6-node quadratic triangles with 3-node membranes on the same edge nodes (`tri6`).
    Tri6,
}

impl Element {
    /// The memory a triangle of the mesh and its assembled system takes, estimated before
    /// meshing. 3-node: half a node of 2 dofs with about 28 stored entries per node, each
    /// an index and eight value copies (stiffness, mass and damping in full and reduced,
    /// effective matrix), plus the 6 × 6 scatter map and the mesher's own vertices and
    /// faces. 6-node: two nodes per triangle (a corner's half and three mid-edge halves),
    /// about 92 stored entries per triangle (a corner couples with about 19 nodes, a
    /// mid-edge node with 9), and the 12 × 12 scatter map. (The scatter maps are counted at
    /// 8 bytes per matrix entry; the assembler keeps 16 bytes per node pair, 144 instead of
    /// 288 bytes for tri3 and 576 instead of 1,152 for tri6: the estimate errs towards
    /// refusing, kept so that the tested refusals stay where they were.)
    pub fn bytes_per_triangle(self) -> usize {
        match self {
            Self::Tri3 => 14 * (8 + 8 * 8) + 36 * 8 + 200,
            Self::Tri6 => 92 * (8 + 8 * 8) + 144 * 8 + 200,
        }
    }
}

/// Parses the `element` parameter.
pub fn element(value: &str) -> Result<Element, SceneError> {
    match value {
        "tri3" => Ok(Element::Tri3),
        "tri6" => Ok(Element::Tri6),
        other => Err(ModelError::unknown("element", other, "tri3 or tri6").into()),
    }
}

/// Parses the `formulation` parameter.
pub fn formulation(value: &str) -> Result<Formulation, SceneError> {
    match value {
        "displacement" => Ok(Formulation::Displacement),
        "mixed" => Ok(Formulation::Mixed),
        other => Err(ModelError::unknown("formulation", other, "displacement or mixed").into()),
    }
}

/// Parses the `kinematics` parameter: whether it is `finite`.
pub fn finite(value: &str) -> Result<bool, SceneError> {
    match value {
        "linear" => Ok(false),
        "finite" => Ok(true),
        other => Err(ModelError::unknown("kinematics", other, "linear or finite").into()),
    }
}

/// The element, formulation and kinematics of a scene, checked together.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Choice {
    /// The cavity's element (the `element` parameter).
    pub element: Element,
    /// Displacement or mixed P2/P0 formulation (the `formulation` parameter).
    pub formulation: Formulation,
    /// Whether the kinematics are finite (total Lagrangian, Newton within each step) rather
    /// than linear (the `kinematics` parameter).
    pub finite: bool,
}

impl Choice {
    /// The choice of the three parameters; combinations the models do not offer are refused
    /// with what to set instead.
    pub fn parse(
        element_value: &str,
        formulation_value: &str,
        kinematics: &str,
    ) -> Result<Self, SceneError> {
        let choice = Self {
            element: element(element_value)?,
            formulation: formulation(formulation_value)?,
            finite: finite(kinematics)?,
        };
        if choice.element == Element::Tri3 && choice.formulation == Formulation::Mixed {
            return Err(SceneError::Config(
                "formulation = `mixed` needs element = `tri6` (the 3-node triangle has no \
                 pressure to condense; it locks as ν → 0.5)"
                    .into(),
            ));
        }
        if choice.finite && choice.element != Element::Tri6 {
            return Err(SceneError::Config(format!(
                "kinematics = `finite` needs element = `tri6` (got `{element_value}`)"
            )));
        }
        Ok(choice)
    }
}

/// The meshed cavity in its chosen discretization, with the assembler of its system.
#[derive(Debug)]
pub struct Discretization {
    /// The 3-node mesh (the corners of a 6-node one) with its quality figures.
    pub meshed: Meshed,
    /// The element, formulation and kinematics.
    pub choice: Choice,
    quadratic: Option<Arc<QuadraticPlaneMesh>>,
    /// The assembler of the system: its sparsity pattern over the dofs of the mesh in use
    /// (the 6-node one for `tri6`).
    pub asm: Arc<Assembler>,
}

impl Discretization {
    /// The discretization of `meshed`; a 6-node mesh has its boundary mid-edge nodes on the
    /// boundary curve ([`Meshed::boundary_mids`]: curved edges, so that a line in tension
    /// presses on its side as a curve does rather than only at its corners).
    pub fn new(meshed: Meshed, choice: Choice) -> Self {
        let quadratic = (choice.element == Element::Tri6).then(|| {
            let mut q = QuadraticPlaneMesh::new(&meshed.mesh);
            for &([a, b], p) in &meshed.boundary_mids {
                q.move_mid(a, b, p);
            }
            Arc::new(q)
        });
        let asm = Arc::new(match &quadratic {
            Some(q) => quadratic_plane::assembler(q),
            None => plane::assembler(&meshed.mesh),
        });
        Self {
            meshed,
            choice,
            quadratic,
            asm,
        }
    }

    /// The 3-node mesh (corners).
    pub fn mesh(&self) -> &Mesh2d {
        &self.meshed.mesh
    }

    /// The 6-node mesh, for `tri6`.
    pub fn quadratic(&self) -> Option<&QuadraticPlaneMesh> {
        self.quadratic.as_deref()
    }

    /// The number of dofs: two (x, y) per node of the mesh in use (the 6-node one for
    /// `tri6`).
    pub fn n_dofs(&self) -> usize {
        self.asm.n_dofs()
    }

    /// Writes the (small-strain) stiffness into `values`.
    pub fn stiffness(&self, props: &PlaneProperties, values: &mut [f64]) {
        match &self.quadratic {
            Some(q) => {
                quadratic_plane::stiffness(q, &self.asm, props, self.choice.formulation, values)
            }
            None => plane::stiffness(self.mesh(), &self.asm, props, values),
        }
    }

    /// Writes the consistent mass into `values`.
    pub fn mass(&self, props: &PlaneProperties, values: &mut [f64]) {
        match &self.quadratic {
            Some(q) => quadratic_plane::mass(q, &self.asm, props, values),
            None => plane::mass(self.mesh(), &self.asm, props, values),
        }
    }

    /// The lumped mass per dof.
    pub fn lumped_mass(&self, props: &PlaneProperties) -> Vec<f64> {
        match &self.quadratic {
            Some(q) => quadratic_plane::lumped_mass(q, props),
            None => plane::lumped_mass(self.mesh(), props),
        }
    }

    /// The dofs of a boundary node set, with the mid-edge nodes of the boundary edges between
    /// its nodes for `tri6`.
    pub fn boundary_dofs(&self, set: &str) -> Result<Vec<usize>, SceneError> {
        let corners = self.mesh().node_sets().get(set)?;
        let nodes = match &self.quadratic {
            Some(q) => boundary_mids(q, corners),
            None => corners.to_vec(),
        };
        Ok(nodes.iter().flat_map(|n| [2 * n, 2 * n + 1]).collect())
    }

    /// The nodal forces (all dofs) that a unit active tension (1 N per mm of depth) in the
    /// contracting line elements ([`crate::assembly::plane::Truss::contracts`]) exerts on
    /// the mesh at rest: −f_int(0) of [`crate::element::membrane`] with T = 1. Along a
    /// polyline of straight elements these are T times the turning of the line at its nodes
    /// (Laplace's law, discrete), pointing to its concave side, plus the pull at its ends —
    /// and T κ₂ times its length where it is curved across the slice.
    pub fn contraction(&self, props: &PlaneProperties) -> Result<Vec<f64>, SceneError> {
        let mesh = self.mesh();
        let mut f = vec![0.0; self.n_dofs()];
        let folded = |e: usize| {
            move |inv: crate::element::total_lagrangian::Inverted| {
                SceneError::Model(ModelError::Inverted {
                    element: e,
                    j: inv.j,
                })
            }
        };
        for (i, &r) in mesh.line_regions().iter().enumerate() {
            let truss = &props.trusses[usize::from(r)];
            if !truss.contracts {
                continue;
            }
            let section = truss.section(1.0);
            match &self.quadratic {
                Some(q) => {
                    let mut fe = line3::Dofs::zeros();
                    let at_rest = line3::Dofs::zeros();
                    line3::membrane(&q.line(i))
                        .internal(&at_rest, section, &mut fe, None)
                        .map_err(folded(i))?;
                    scatter(&mut f, &q.lines()[i], fe.as_slice());
                }
                None => {
                    let mut fe = line2::Dofs::zeros();
                    let at_rest = line2::Dofs::zeros();
                    line2::membrane(&mesh.line(i))
                        .internal(&at_rest, section, &mut fe, None)
                        .map_err(folded(i))?;
                    scatter(&mut f, &mesh.lines()[i], fe.as_slice());
                }
            }
        }
        f.iter_mut().for_each(|x| *x = -*x);
        Ok(f)
    }

    /// The nodal forces (all dofs) of a unit pressure (1 MPa) over the diaphragm's line
    /// elements, normal to them at rest and into the cavity, as consistent nodal loads
    /// ([`crate::assembly::loads::edge_pressure`], its quadratic twin on 3-node lines):
    /// seed 003's press (§5.4.4, "a sinusoidal force acts on the diaphragm"), a dead load
    /// without the contraction's pull at the ends. Each line's cavity side is that of the
    /// triangle on it (the mesher keeps the boundary's edges as triangle edges).
    pub fn diaphragm_pressure(&self) -> Result<Vec<f64>, SceneError> {
        let mesh = self.mesh();
        let mut f = vec![0.0; self.n_dofs()];
        let diaphragm = mesh.line_regions().iter().enumerate();
        let pressed = diaphragm
            .filter(|&(_, &r)| r == DIAPHRAGM_REGION)
            .map(|(i, _)| i);
        for i in pressed {
            let [a, b] = mesh.lines()[i];
            let third = mesh.triangles().iter().find_map(|t| {
                let c = t.iter().find(|&&n| n != a && n != b)?;
                (t.contains(&a) && t.contains(&b)).then_some(*c)
            });
            let Some(c) = third else {
                return Err(SceneError::Config(format!(
                    "the diaphragm's line element {i} borders no triangle of the cavity"
                )));
            };
            // +1 where the cavity lies to the left of a → b (the loads' convention).
            let side = tri3::signed_area(&[a, b, c].map(|n| mesh.nodes()[n])).signum();
            match &self.quadratic {
                Some(q) => loads::quadratic_edge_pressure(q.nodes(), q.lines()[i], side, &mut f),
                None => loads::edge_pressure(mesh.nodes(), [a, b], side, &mut f),
            }
        }
        Ok(f)
    }

    /// The stress recovery for `props`.
    pub fn recovery(&self, props: &PlaneProperties) -> Recovery {
        match &self.quadratic {
            Some(q) => Recovery {
                triangles: TriangleStresses::quadratic(q, props, self.choice.formulation),
                lines: LineStresses::quadratic(q, props),
                finite: self.choice.finite.then(|| Finite {
                    mesh: q.clone(),
                    materials: materials(props).into(),
                    formulation: self.choice.formulation,
                    trusses: props.trusses.clone().into(),
                }),
            },
            None => Recovery {
                triangles: TriangleStresses::new(self.mesh(), props),
                lines: LineStresses::new(self.mesh(), props),
                finite: None,
            },
        }
    }

    /// The finite-strain body for `props` (None for linear kinematics), the contracting lines
    /// carrying the active tension `tension` holds at each evaluation: the internal forces of
    /// a static solve, of the dynamic structure and, element by element, of its
    /// hyper-reduction.
    pub fn body(&self, props: &PlaneProperties, tension: &Arc<SharedTension>) -> Option<PlaneBody> {
        let q = self.quadratic.as_ref().filter(|_| self.choice.finite)?;
        Some(PlaneBody {
            mesh: q.clone(),
            asm: self.asm.clone(),
            materials: materials(props).into(),
            formulation: self.choice.formulation,
            trusses: props.trusses.clone().into(),
            active: Some(tension.clone()),
        })
    }
}

/// The neo-Hookean materials of the triangle regions (finite kinematics).
pub fn materials(props: &PlaneProperties) -> Vec<Material> {
    props
        .continua
        .iter()
        .map(|c| Material::new(Law::NeoHookean, c.elastic))
        .collect()
}

/// `corners` with the mid-edge nodes of the boundary edges (edges of one triangle) between
/// two of them.
fn boundary_mids(q: &QuadraticPlaneMesh, corners: &[usize]) -> Vec<usize> {
    let inside: HashSet<usize> = corners.iter().copied().collect();
    let mut count = std::collections::HashMap::<usize, u8>::new();
    for t in q.triangles() {
        for (k, [a, b]) in tri6::EDGES.iter().enumerate() {
            if inside.contains(&t[*a]) && inside.contains(&t[*b]) {
                *count.entry(t[3 + k]).or_default() += 1;
            }
        }
    }
    let mut mids: Vec<usize> = count
        .into_iter()
        .filter(|&(_, c)| c == 1)
        .map(|(m, _)| m)
        .collect();
    mids.sort_unstable();
    let mut nodes = corners.to_vec();
    nodes.extend(mids);
    nodes
}

/// Stresses from a displacement of all dofs: the membranes' axial stress and the
/// triangles' stress at their centroids — small-strain operators, or at finite strain the
/// Cauchy stress of the neo-Hookean law and the membranes' mean nominal stress
/// ([`crate::element::membrane::Line::mean_stress`]).
#[derive(Debug, Clone)]
pub struct Recovery {
    triangles: TriangleStresses,
    lines: LineStresses,
    finite: Option<Finite>,
}

/// What the stresses at finite strain read: the 6-node mesh, the materials by region, the
/// formulation and the lines' properties.
#[derive(Debug, Clone)]
struct Finite {
    mesh: Arc<QuadraticPlaneMesh>,
    materials: Arc<[Material]>,
    formulation: Formulation,
    trusses: Arc<[Truss]>,
}

impl Recovery {
    /// The stress of triangle `i`; NaN components if it is inverted at finite strain.
    pub fn triangle(&self, i: usize, u: &[f64]) -> PlaneStress {
        let Some(finite) = &self.finite else {
            return self.triangles.stress(i, u);
        };
        let q = &finite.mesh;
        let dofs = plane_dofs::<6, 12>(&q.triangles()[i]);
        let ue = tri6::Dofs::from_fn(|k, _| u[dofs[k]]);
        let material = &finite.materials[usize::from(q.triangle_regions()[i])];
        let centroid = [1.0 / 3.0; 3];
        match recovery::cauchy(finite.formulation, &q.triangle(i), centroid, &ue, material) {
            Ok(s) => PlaneStress {
                xx: s[(0, 0)],
                yy: s[(1, 1)],
                xy: s[(0, 1)],
                zz: s[(2, 2)],
            },
            Err(_) => PlaneStress {
                xx: f64::NAN,
                yy: f64::NAN,
                xy: f64::NAN,
                zz: f64::NAN,
            },
        }
    }

    /// The axial stress of line `i` (MPa, tension > 0): at finite strain its passive mean
    /// nominal stress (without an active tension), NaN if it folded onto itself.
    pub fn line(&self, i: usize, u: &[f64]) -> f64 {
        let Some(finite) = &self.finite else {
            return self.lines.stress(i, u);
        };
        let q = &finite.mesh;
        let dofs = plane_dofs::<3, 6>(&q.lines()[i]);
        let ue = line3::Dofs::from_fn(|k, _| u[dofs[k]]);
        let section = finite.trusses[usize::from(q.line_regions()[i])].section(0.0);
        line3::membrane(&q.line(i))
            .mean_stress(&ue, section)
            .unwrap_or(f64::NAN)
    }
}

/// A displacement of all dofs with the mesh and the stresses it gives, for drawing and
/// export: the 3-node mesh (its nodes are the first nodes of the 6-node one), the 6-node
/// mesh for `tri6`.
#[derive(Debug, Clone, Copy)]
pub struct FieldView<'a> {
    /// The 3-node mesh (mm; the corners of a 6-node one).
    pub mesh: &'a Mesh2d,
    /// The 6-node mesh for `tri6`, `None` for `tri3`.
    pub quadratic: Option<&'a QuadraticPlaneMesh>,
    /// The displacement of all dofs (mm): x and y of node n at 2n and 2n + 1.
    pub u: &'a [f64],
    pub(super) recovery: &'a Recovery,
}

impl FieldView<'_> {
    /// The stress of every triangle (at its centroid).
    pub fn triangle_stresses(&self) -> Vec<PlaneStress> {
        (0..self.mesh.triangles().len())
            .map(|i| self.recovery.triangle(i, self.u))
            .collect()
    }

    /// The axial stress of every line element.
    pub fn line_stresses(&self) -> Vec<f64> {
        (0..self.mesh.lines().len())
            .map(|i| self.recovery.line(i, self.u))
            .collect()
    }

    /// The displacement of node `n` (a corner: valid for both meshes).
    pub fn displacement(&self, n: usize) -> [f64; 2] {
        [self.u[2 * n], self.u[2 * n + 1]]
    }

    /// The largest principal small strain |ε| (ε = sym ∇u) at any triangle's centroid: the
    /// measure the small-strain limit [`crate::scene::SMALL_STRAIN_LIMIT`] is checked on.
    pub fn largest_strain(&self) -> f64 {
        let u = self.u;
        (0..self.mesh.triangles().len())
            .map(|i| match self.quadratic {
                Some(q) => {
                    let dofs = plane_dofs::<6, 12>(&q.triangles()[i]);
                    let ue = tri6::Dofs::from_fn(|k, _| u[dofs[k]]);
                    tri6::b_matrix(&q.triangle(i), [1.0 / 3.0; 3]).0 * ue
                }
                None => {
                    let dofs = self.mesh.triangle_dofs(i);
                    let ue = tri3::Dofs::from_fn(|k, _| u[dofs[k]]);
                    tri3::strain(&self.mesh.triangle(i), &ue)
                }
            })
            .map(|e| {
                // Principal strains c ± r of (ε_xx, ε_yy, γ_xy): the larger magnitude.
                let c = 0.5 * (e[0] + e[1]);
                c.abs() + (0.5 * (e[0] - e[1])).hypot(0.5 * e[2])
            })
            .fold(0.0, f64::max)
    }
}
