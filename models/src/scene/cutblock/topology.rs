//! Geometry (node planes, snapping, supports) and the current topology of the cut block:
//! the cut mesh, its pattern, factorization and last solution.

use super::contact::{FlankContact, PENALTY_FACTOR};
use crate::assembly::plane::Continuum;
use crate::assembly::{loads, solid, Assembler};
use crate::element::Elastic;
use crate::mesh::cut::{self, CutMesh, Incision};
use crate::mesh::{generate, Mesh3d};
use crate::scene::SceneError;
use crate::solve::{Factorization, Statics};

/// How the incision is made (seed 002 §1.4 / §3.4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Strategy {
    Duplicate,
    Delete,
}

impl Strategy {
    pub fn parse(s: &str) -> Result<Self, SceneError> {
        match s {
            "duplicate" => Ok(Self::Duplicate),
            "delete" => Ok(Self::Delete),
            _ => Err(SceneError::Config(format!(
                "cut_strategy `{s}`: use `duplicate` or `delete`"
            ))),
        }
    }
}

/// Supports of the end faces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Support {
    /// The experiment (seed 002 §2.1): y = 0 clamped; y = L u_y prescribed, u_x, u_z free.
    Clamped,
    /// Only u_y on both end faces, plus the three constraints that remove rigid motions
    /// (u_x, u_z at the origin, u_z at (L_x, 0, 0)): a state of exact uniaxial tension.
    Sliding,
    /// Both faces held in rigid grips: y = 0 clamped; y = L moved in y with u_x = u_z = 0.
    Gripped,
}

impl Support {
    pub fn parse(s: &str) -> Result<Self, SceneError> {
        match s {
            "clamped" => Ok(Self::Clamped),
            "sliding" => Ok(Self::Sliding),
            "gripped" => Ok(Self::Gripped),
            _ => Err(SceneError::Config(format!(
                "support `{s}`: use `clamped`, `sliding` or `gripped`"
            ))),
        }
    }
}

/// The choices of how the block is cut, held and kept from interpenetrating.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Options {
    pub strategy: Strategy,
    pub support: Support,
    /// Whether closing flanks are kept apart (penalty contact).
    pub contact: bool,
}

/// The uncut block and where the incision can go.
#[derive(Debug, Clone)]
pub struct Geometry {
    pub size: [f64; 3],
    pub base: Mesh3d,
    pub x_planes: Vec<f64>,
    /// Incision plane and the bottom of the incision (z); `None` for depth 0.
    pub y_cut: f64,
    pub z_cut: Option<f64>,
    /// Thickness of the element layer removed by the deletion strategy.
    pub layer: f64,
    pub press_radius: f64,
    pub options: Options,
}

/// Uniform planes over [0, length]; if `target` lies strictly inside, the nearest interior
/// plane is moved onto it (it moves by at most half a cell, so the order is kept).
fn planes(length: f64, cells: usize, target: Option<f64>) -> Vec<f64> {
    let mut p: Vec<f64> = (0..=cells)
        .map(|i| length * i as f64 / cells as f64)
        .collect();
    if let Some(t) = target.filter(|&t| t > 0.0 && t < length) {
        let nearest = (1..cells).min_by(|&a, &b| (p[a] - t).abs().total_cmp(&(p[b] - t).abs()));
        if let Some(i) = nearest {
            p[i] = t;
        }
    }
    p
}

impl Geometry {
    pub fn new(
        size: [f64; 3],
        cells: [usize; 3],
        y_cut: f64,
        depth: f64,
        press_radius: f64,
        options: Options,
    ) -> Result<Self, SceneError> {
        if !(y_cut > 0.0 && y_cut < size[1]) {
            return Err(SceneError::Config(format!(
                "y_cut = {y_cut} mm must lie inside the block (0, {})",
                size[1]
            )));
        }
        if cells[1] < 2 {
            return Err(SceneError::Config(
                "cells_y must be at least 2 to place a node plane at y_cut".into(),
            ));
        }
        let z_cut = (depth > 0.0).then(|| (size[2] - depth).max(0.0));
        let x_planes = planes(size[0], cells[0], None);
        let y_planes = planes(size[1], cells[1], Some(y_cut));
        let z_planes = planes(size[2], cells[2], z_cut);
        let at = y_planes
            .iter()
            .position(|&y| y == y_cut)
            .expect("snapped above");
        let base = generate::block_on_planes(&[x_planes.clone(), y_planes.clone(), z_planes])?;
        Ok(Self {
            size,
            base,
            x_planes,
            y_cut,
            z_cut,
            layer: y_cut - y_planes[at - 1],
            press_radius,
            options,
        })
    }

    /// Whole x-cells behind the scalpel at `x` (0 without a cut).
    pub fn cut_cells(&self, x: f64) -> usize {
        if self.z_cut.is_none() {
            return 0;
        }
        let tol = 1e-9 * self.size[0];
        self.x_planes[1..]
            .iter()
            .take_while(|&&p| p <= x + tol)
            .count()
    }

    fn cut(&self, cells: usize) -> Result<CutMesh, SceneError> {
        let (Some(z0), true) = (self.z_cut, cells > 0) else {
            return Ok(CutMesh {
                mesh: self.base.clone(),
                flank_pairs: vec![],
            });
        };
        let incision = Incision {
            y: self.y_cut,
            x: (0.0, self.x_planes[cells]),
            z: (z0, self.size[2]),
        };
        Ok(match self.options.strategy {
            Strategy::Duplicate => cut::split(&self.base, &incision)?,
            Strategy::Delete => cut::delete(&self.base, &incision, self.layer)?,
        })
    }
}

/// Largest number of solves per step while the contact set changes.
const CONTACT_ITERATIONS: usize = 25;

/// Everything that depends on the current cut: mesh, pattern, factorization, solution.
#[derive(Debug)]
pub struct Topology {
    pub cut_cells: usize,
    pub mesh: Mesh3d,
    pub flank_pairs: Vec<(usize, usize)>,
    pub asm: Assembler,
    pub statics: Statics,
    /// Stiffness of the tetrahedra alone, and with the active contact springs (factorized).
    pub k_base: Vec<f64>,
    pub k: Vec<f64>,
    pub material: Elastic,
    /// Flank contact, if the scene has a cut and contact is on.
    pub contact: Option<FlankContact>,
    /// The y size of the cell in front of the cut (sets penalty and search tolerance).
    layer: f64,
    /// Top-surface boundary faces (undeformed z = size_z).
    pub top_faces: Vec<[usize; 3]>,
    /// Nodes of the pulled face.
    pub pulled: Vec<usize>,
    pub u: Vec<f64>,
    pub f: Vec<f64>,
    /// Numeric factorizations since this topology was built.
    pub factorizations: u64,
}

impl Topology {
    /// Cuts the base mesh by `cells` x-cells, checks that every body is supported, builds the
    /// pattern and factorizes.
    pub fn build(g: &Geometry, cells: usize, material: Elastic) -> Result<Self, SceneError> {
        let CutMesh { mesh, flank_pairs } = g.cut(cells)?;
        let sets = mesh.node_sets();
        let clamped = sets.get("y0")?;
        check_supported(&mesh, clamped)?;
        let pulled = sets.get("y1")?.to_vec();
        let mut fixed: Vec<usize> = pulled.iter().map(|n| 3 * n + 1).collect();
        let all = |n: &usize| [3 * n, 3 * n + 1, 3 * n + 2];
        match g.options.support {
            Support::Clamped => fixed.extend(clamped.iter().flat_map(all)),
            Support::Gripped => {
                fixed.extend(clamped.iter().flat_map(all));
                fixed.extend(pulled.iter().flat_map(|n| [3 * n, 3 * n + 2]));
            }
            Support::Sliding => {
                fixed.extend(clamped.iter().map(|n| 3 * n + 1));
                let origin = find_node(&mesh, [0.0, 0.0, 0.0])?;
                let corner = find_node(&mesh, [g.size[0], 0.0, 0.0])?;
                fixed.extend([3 * origin, 3 * origin + 2, 3 * corner + 2]);
            }
        }
        let top = g.size[2];
        let tol = 1e-9 * mesh.extent();
        let top_faces = mesh
            .boundary()
            .iter()
            .filter(|f| {
                f.nodes
                    .iter()
                    .all(|&n| (mesh.nodes()[n][2] - top).abs() <= tol)
            })
            .map(|f| f.nodes)
            .collect();
        let contact = if g.options.contact {
            FlankContact::new(&mesh, &flank_pairs, mesh.tets().len(), g.layer)
        } else {
            None
        };
        let asm = match &contact {
            None => solid::assembler(&mesh),
            Some(c) => {
                let mut elements: Vec<&[usize]> =
                    mesh.tets().iter().map(|t| t.as_slice()).collect();
                elements.extend(c.elements.iter().map(|e| e.as_slice()));
                Assembler::new(mesh.nodes().len(), 3, &elements)
            }
        };
        let statics = Statics::new(&asm, &fixed, Factorization::Supernodal)?;
        let n_dofs = mesh.n_dofs();
        let mut t = Self {
            cut_cells: cells,
            k_base: asm.zeros(),
            k: asm.zeros(),
            asm,
            statics,
            material,
            contact,
            layer: g.layer,
            top_faces,
            pulled,
            u: vec![0.0; n_dofs],
            f: vec![0.0; n_dofs],
            mesh,
            flank_pairs,
            factorizations: 0,
        };
        t.assemble()?;
        Ok(t)
    }

    fn assemble(&mut self) -> Result<(), SceneError> {
        let continuum = Continuum {
            elastic: self.material,
            density: 0.0,
        };
        solid::stiffness(&self.mesh, &self.asm, &continuum, &mut self.k_base);
        self.factorize()
    }

    /// Factorizes the tetrahedra plus the active contact springs.
    fn factorize(&mut self) -> Result<(), SceneError> {
        self.k.copy_from_slice(&self.k_base);
        if let Some(c) = &self.contact {
            c.add_stiffness(&self.asm, self.penalty(), &mut self.k);
        }
        self.statics.factorize(&self.k)?;
        self.factorizations += 1;
        Ok(())
    }

    /// Penalty stiffness k_p = PENALTY_FACTOR · E · h (N/mm).
    fn penalty(&self) -> f64 {
        PENALTY_FACTOR * self.material.young() * self.layer
    }

    /// Reassembles and refactorizes if the material changed.
    pub fn set_material(&mut self, material: Elastic) -> Result<(), SceneError> {
        if material != self.material {
            self.material = material;
            self.assemble()?;
        }
        Ok(())
    }

    /// Solves for the pull (mm) and the press force (N) at the scalpel position. With flank
    /// contact: solve, search the flanks, and while the set of penetrating nodes changes,
    /// refactorize with their springs and solve again (at most `CONTACT_ITERATIONS` times).
    pub fn solve(
        &mut self,
        g: &Geometry,
        pull: f64,
        press: f64,
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        for _ in 0..CONTACT_ITERATIONS {
            self.u.fill(0.0);
            for &n in &self.pulled {
                self.u[3 * n + 1] = pull;
            }
            self.f.fill(0.0);
            if press > 0.0 {
                self.press_load(g, press, scalpel_x);
            }
            let penalty = self.penalty();
            if let Some(c) = &self.contact {
                c.add_loads(penalty, &mut self.f);
            }
            self.statics
                .solve(self.asm.matrix(&self.k), &self.f, &mut self.u);
            let Some(c) = &mut self.contact else {
                return Ok(());
            };
            let springs = c.detect(&self.mesh, &self.u);
            if c.same_as_active(&springs) {
                return Ok(());
            }
            c.active = springs;
            self.factorize()?;
        }
        Err(SceneError::NotConverged {
            what: "the flank contact's active set",
            iterations: CONTACT_ITERATIONS,
        })
    }

    /// The press force as a uniform pressure over the top faces whose centroid lies within
    /// `press_radius` of the tip (scalpel_x, y_cut), or over the nearest face if none does;
    /// consistent nodal loads, direction −z, total exactly `force`.
    fn press_load(&mut self, g: &Geometry, force: f64, scalpel_x: f64) {
        let p = self.mesh.nodes();
        let tip = [scalpel_x.min(g.size[0]), g.y_cut];
        let distance = |f: &[usize; 3]| {
            let c = |d: usize| f.iter().map(|&n| p[n][d]).sum::<f64>() / 3.0;
            (c(0) - tip[0]).hypot(c(1) - tip[1])
        };
        let mut patch: Vec<[usize; 3]> = self
            .top_faces
            .iter()
            .filter(|f| distance(f) <= g.press_radius)
            .copied()
            .collect();
        if patch.is_empty() {
            let nearest = self
                .top_faces
                .iter()
                .min_by(|a, b| distance(a).total_cmp(&distance(b)));
            patch.extend(nearest.copied());
        }
        let area = |f: &[usize; 3]| {
            crate::element::tet4::face_area_normal(&p[f[0]], &p[f[1]], &p[f[2]]).norm()
        };
        let total: f64 = patch.iter().map(area).sum();
        for f in &patch {
            loads::face_traction(p, *f, [0.0, 0.0, -force / total], &mut self.f);
        }
    }
}

fn find_node(mesh: &Mesh3d, at: [f64; 3]) -> Result<usize, SceneError> {
    let tol = 1e-9 * mesh.extent();
    mesh.nodes()
        .iter()
        .position(|p| (0..3).all(|d| (p[d] - at[d]).abs() <= tol))
        .ok_or_else(|| SceneError::Config(format!("no node at {at:?}")))
}

/// Every connected body must touch the clamped face, else it would float.
fn check_supported(mesh: &Mesh3d, clamped: &[usize]) -> Result<(), SceneError> {
    let comp = cut::node_components(mesh);
    let supported: std::collections::HashSet<usize> = clamped.iter().map(|&n| comp[n]).collect();
    let mut bodies: Vec<usize> = comp.clone();
    bodies.sort_unstable();
    bodies.dedup();
    if let Some(node) = comp.iter().position(|c| !supported.contains(c)) {
        return Err(SceneError::Separated {
            bodies: bodies.len(),
            node,
            at: mesh.nodes()[node],
        });
    }
    Ok(())
}
