//! The current topology of the cut block: the cut mesh, its solid (linear or quadratic
//! tetrahedra of one material law), the supports, the pattern, the contact of the flanks,
//! the top surface — and its equilibrium solver ([`Equilibrium`]), which solves on them.
//! A topology of the previous one's pattern (the front moved within a cell) shares its
//! pattern and symbolic analysis and starts from its path of equilibria extrapolated
//! ([`super::path`]); another starts from that extrapolation made on the previous mesh slid
//! to the new front and carried onto its mesh ([`super::transfer`]), or from the last
//! equilibrium carried over where there is no path.

use std::sync::Arc;

use super::contact::{FlankContact, PENALTY_FACTOR};
use super::equilibrium::{Equilibrium, On, Spare};
use super::geometry::{Geometry, Strategy, Support};
use super::path::{continue_path, Station};
use super::profiles::TopSurface;
use super::transfer::transfer;
use crate::assembly::tetrahedra::{Solid, Tetrahedron};
use crate::assembly::Assembler;
use crate::element::Material;
use crate::mesh::cut::{self, CutMesh};
use crate::mesh::{Mesh3d, QuadraticMesh};
use crate::scene::SceneError;
use crate::solve::newton::Settings;

/// Everything that depends on the current cut.
#[derive(Debug)]
pub struct Topology {
    /// Where the incision ends (x, mm; 0 uncut).
    pub front: f64,
    pub solid: Solid,
    /// Node pairs facing each other across the cut (front flank, back flank), mid-edge
    /// nodes included.
    pub flank_pairs: Vec<(usize, usize)>,
    /// The pattern, shared with the topologies of the same connectivity.
    pub asm: Arc<Assembler>,
    /// Flank contact, if the scene has a cut and contact is on.
    pub contact: Option<FlankContact>,
    /// The y size of the cell in front of the cut (sets penalty and search tolerance).
    pub layer: f64,
    /// The top surface (undeformed z = size_z).
    pub top: TopSurface,
    /// Nodes of the pulled face.
    pub pulled: Vec<usize>,
    /// The solver and the last equilibrium.
    pub eq: Equilibrium,
    /// The finite-strain laws: equilibria of this pattern at earlier blade positions, the
    /// latest last (at most `PATH_POINTS` − 1; [`Self::start_from`]), the first of them
    /// carried from the previous pattern's mesh after a mesh change ([`Self::carried_path`]).
    pub path: Vec<Station>,
    /// The cut mesh and its quadratic one (tet10): moved, not made anew, for the next
    /// front within the cell ([`Geometry::moved_cut`]).
    cut: CutMesh,
    quadratic: Option<QuadraticMesh>,
}

/// The solid's node sets: the mesh's, with mid-edge nodes for quadratic tetrahedra.
struct Sets<'a> {
    mesh: &'a Mesh3d,
    quadratic: Option<&'a QuadraticMesh>,
}

impl Sets<'_> {
    fn get(&self, name: &str) -> Result<Vec<usize>, SceneError> {
        let corners = self.mesh.node_sets().get(name)?;
        Ok(match self.quadratic {
            Some(q) => q.extend(corners),
            None => corners.to_vec(),
        })
    }
}

/// The constrained dofs of the supports (see [`Support`]).
fn supports(
    g: &Geometry,
    sets: &Sets,
    solid: &Solid,
) -> Result<(Vec<usize>, Vec<usize>), SceneError> {
    let clamped = sets.get("y0")?;
    let pulled = sets.get("y1")?;
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
            let origin = find_node(solid.nodes(), [0.0, 0.0, 0.0])?;
            let corner = find_node(solid.nodes(), [g.size[0], 0.0, 0.0])?;
            fixed.extend([3 * origin, 3 * origin + 2, 3 * corner + 2]);
        }
    }
    Ok((fixed, pulled))
}

/// The flank facets for contact: boundary faces of the cut mesh with every corner on a
/// flank, split into their four sub-triangles for quadratic tetrahedra.
fn flank_facets(
    mesh: &Mesh3d,
    corner_pairs: &[(usize, usize)],
    quadratic: Option<&QuadraticMesh>,
) -> Vec<[usize; 3]> {
    let mut on_flank = vec![false; mesh.nodes().len()];
    for &(f, b) in corner_pairs {
        on_flank[f] = true;
        on_flank[b] = true;
    }
    let faces = mesh
        .boundary()
        .iter()
        .map(|f| f.nodes)
        .filter(|f| f.iter().all(|&n| on_flank[n]));
    match quadratic {
        None => faces.collect(),
        Some(q) => faces
            .flat_map(|f| {
                let [a, b, c, ab, bc, ca] = q.face(f);
                [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
            })
            .collect(),
    }
}

impl Topology {
    /// Meshes the block cut up to `front`, checks that every body is supported, builds the
    /// solid, the pattern and the solver, and factorizes the linear law's stiffness. A
    /// `previous` topology whose mesh has the same connectivity and supports (the front
    /// moved within a cell, [`Geometry::x_planes`]) lends its pattern and symbolic analysis,
    /// and a `spare` solver of that analysis its storage.
    pub fn build(
        g: &Geometry,
        front: f64,
        material: Material,
        kind: Tetrahedron,
        settings: Settings,
        previous: Option<&Topology>,
        spare: Option<Spare>,
    ) -> Result<Self, SceneError> {
        let derive = |mesh: &Mesh3d| (kind == Tetrahedron::Tet10).then(|| QuadraticMesh::new(mesh));
        let moved = previous.and_then(|p| Some((p, g.moved_cut(&p.cut, p.front, front)?)));
        let (cut, quadratic) = match moved {
            // `previous`'s connectivity, supported as it was.
            Some((p, cut)) => {
                let cut = cut?;
                let quadratic = match &p.quadratic {
                    Some(q) if kind == Tetrahedron::Tet10 => Some(q.moved(&cut.mesh)),
                    _ => derive(&cut.mesh),
                };
                (cut, quadratic)
            }
            None => {
                let cut = g.cut(front)?;
                check_supported(&cut.mesh, cut.mesh.node_sets().get("y0")?)?;
                let quadratic = derive(&cut.mesh);
                (cut, quadratic)
            }
        };
        let (mesh, flank_pairs) = (&cut.mesh, &cut.flank_pairs);
        let solid = Solid::on_mesh(mesh, quadratic.as_ref(), material);
        let sets = Sets {
            mesh,
            quadratic: quadratic.as_ref(),
        };
        let (fixed, pulled) = supports(g, &sets, &solid)?;
        let facets = flank_facets(mesh, flank_pairs, quadratic.as_ref());
        let facing = match (&quadratic, g.options.strategy) {
            (Some(q), Strategy::Duplicate) => {
                q.facing_pairs(flank_pairs, &shared_on_cut(mesh, g.y_cut, flank_pairs))
            }
            (Some(q), Strategy::Delete) => q.facing_pairs(flank_pairs, &[]),
            (None, _) => flank_pairs.clone(),
        };
        let contact = if g.options.contact {
            FlankContact::new(solid.nodes(), facets, &facing, solid.len(), g.layer)
        } else {
            None
        };
        let elements = elements_of(&solid, contact.as_ref());
        let fixed = {
            let mut f = fixed;
            f.sort_unstable();
            f.dedup();
            f
        };
        let finite = material.law.finite();
        let same = previous.filter(|p| p.eq.fits(&fixed, finite) && p.elements() == elements);
        let asm = match same {
            Some(p) => Arc::clone(&p.asm),
            None => Arc::new(Assembler::new(solid.nodes().len(), 3, &elements)),
        };
        let eq = Equilibrium::new(
            &asm,
            &fixed,
            (finite, kind),
            settings,
            same.map(|p| &p.eq),
            spare,
        )?;
        let top = TopSurface::new(mesh, g, quadratic.as_ref());
        let mut t = Self {
            front,
            solid,
            flank_pairs: facing,
            asm,
            contact,
            layer: g.layer,
            top,
            pulled,
            eq,
            path: Vec::new(),
            cut,
            quadratic,
        };
        let (on, eq) = t.parts();
        eq.assemble_linear(&on)?;
        Ok(t)
    }

    /// What the equilibrium is solved on, and the equilibrium (borrowed apart).
    pub fn parts(&mut self) -> (On<'_>, &mut Equilibrium) {
        let on = On {
            solid: &self.solid,
            asm: &self.asm,
            contact: self.contact.as_ref(),
            penalty: penalty(&self.solid, self.layer),
            top: &self.top,
            pulled: &self.pulled,
        };
        (on, &mut self.eq)
    }

    /// The solver, for the next topology of `next`'s pattern; `None` if it has another
    /// pattern.
    pub fn into_spare(self, next: &Topology) -> Option<Spare> {
        self.eq.into_spare(&next.eq)
    }

    /// The node lists of the solid's elements and the contact's.
    fn elements(&self) -> Vec<&[usize]> {
        elements_of(&self.solid, self.contact.as_ref())
    }

    /// The material law and its parameters.
    pub fn material(&self) -> Material {
        self.solid.material
    }

    /// Takes new material parameters (the law stays): the linear law reassembles and
    /// refactorizes; a finite-strain law solves the next step with them. With displacement
    /// loading the equilibrium does not depend on E, but on ν it does.
    pub fn set_material(&mut self, material: Material) -> Result<(), SceneError> {
        if material != self.solid.material {
            self.solid.material = material;
            let (on, eq) = self.parts();
            eq.assemble_linear(&on)?;
        }
        Ok(())
    }

    /// Solves this new topology for the pull (mm) and the press force (N) at the scalpel
    /// position ([`Self::solve`]), a finite-strain law started from `from`'s path
    /// extrapolated or its last equilibrium, carried onto this mesh where it changed or a
    /// sliver is left ([`Self::start_from`]), and from the unloaded block if that does not
    /// converge (counted in its work).
    pub fn solve_after(
        &mut self,
        g: &Geometry,
        from: Option<&Topology>,
        pull: f64,
        press: f64,
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        let warm = match from {
            Some(from) => self.start_from(g, from, scalpel_x)?,
            None => false,
        };
        if let Err(e) = self.solve(g, pull, press, scalpel_x) {
            if !warm {
                return Err(e);
            }
            let (on, eq) = self.parts();
            eq.unload(&on, g, scalpel_x)?;
            self.solve(g, pull, press, scalpel_x)?;
            self.eq.work.returns_to_unloaded += 1;
        }
        Ok(())
    }

    /// Starts the next solve, for the finite-strain laws (the linear law solves directly and
    /// needs no start), under `from`'s load: from the equilibria of `from`'s pattern at
    /// earlier blade positions under that load, `from`'s own the latest, extrapolated to
    /// this front ([`continue_path`]) where there are two or three of them — on this
    /// topology's nodes where it has that pattern, else (or where the move leaves a sliver
    /// at an end face, [`Geometry::leaves_a_sliver`]) carried onto this mesh from `from`'s
    /// slid to this front ([`Self::slid`], [`transfer`]); else from `from`'s equilibrium
    /// carried onto this mesh. A topology of another pattern started along the path starts
    /// its own with `from`'s equilibrium ([`Self::carried_path`]). Returns whether it
    /// started from any.
    fn start_from(
        &mut self,
        g: &Geometry,
        from: &Topology,
        scalpel_x: f64,
    ) -> Result<bool, SceneError> {
        if !self.eq.is_newton() {
            return Ok(false);
        }
        let latest = Station {
            front: from.front,
            load: from.eq.load,
            u: from.eq.u.clone(),
            carried: false,
        };
        let (start, path) = continue_path(&from.path, latest, self.front);
        let same_pattern = Arc::ptr_eq(&self.asm, &from.asm);
        let on_nodes = same_pattern && !g.leaves_a_sliver(from.front, self.front);
        let along_path = start.is_some();
        let carried = match start {
            Some(u) if on_nodes => Some(u),
            // The path's extrapolation lies on `from`'s mesh slid to this front (the last
            // equilibrium carried over where that mesh or the transfer cannot be made).
            Some(u) => from
                .slid(g, self.front)
                .ok()
                .and_then(|slid| transfer(&slid, &u, &self.solid, g.y_cut)),
            None => None,
        }
        .or_else(|| transfer(&from.solid, &from.eq.u, &self.solid, g.y_cut));
        self.path = match (same_pattern, along_path) {
            (true, _) => path,
            (false, true) => self.carried_path(g, from),
            // A jump of the blade beyond the path's reach: its mesh slid back that far
            // would read most of the field off an end face.
            (false, false) => Vec::new(),
        };
        let Some(u) = carried else {
            return Ok(false);
        };
        self.eq.u = u;
        let (on, eq) = self.parts();
        let load = from.eq.load;
        eq.set_loads(&on, g, load.0, load.1, scalpel_x);
        let constrained = eq.constrained().to_vec();
        for d in constrained {
            eq.u[d] = eq.prescribed[d];
        }
        eq.restart(&on, g, load, scalpel_x)?;
        Ok(true)
    }

    /// `from`'s equilibrium carried onto this mesh slid back to `from`'s front
    /// ([`Self::slid`], [`transfer`]; a node slid beyond `from`'s mesh reads its end face):
    /// the path this pattern extrapolates along at the next advance, as if its mesh had been
    /// cut there, until it has two equilibria of its own ([`continue_path`]). Only the latest
    /// equilibrium: carrying the two latest (a quadratic at the next advance) took more
    /// Newton iterations along the blade's path (BENCHMARKS.md, "The start of an advance
    /// that changes the mesh"). Empty where it cannot be carried.
    fn carried_path(&self, g: &Geometry, from: &Topology) -> Vec<Station> {
        let carried = self
            .slid(g, from.front)
            .ok()
            .and_then(|slid| transfer(&from.solid, &from.eq.u, &slid, g.y_cut));
        carried
            .map(|u| Station {
                front: from.front,
                load: from.eq.load,
                u,
                carried: true,
            })
            .into_iter()
            .collect()
    }

    /// This topology's solid with its front slid to `front` as its x planes slide within a
    /// cell ([`Geometry::x_planes`]): every node moved along x by `front` − `self.front`
    /// but those on the end face the front moves away from, the other end face too, so that
    /// no cell closes where a plane would cross it (the block then reaches past that end by
    /// the move; the cell at the face left behind widens). Its nodes are where the
    /// equilibria of this pattern extrapolated to `front` ([`continue_path`]) hold, but at
    /// the end faces, which stay put as the planes slide.
    fn slid(&self, g: &Geometry, front: f64) -> Result<Solid, SceneError> {
        let shift = front - self.front;
        let stays = if shift > 0.0 { 0.0 } else { g.size[0] };
        let nodes = self
            .cut
            .mesh
            .nodes()
            .iter()
            .map(|&[x, y, z]| [if x == stays { x } else { x + shift }, y, z])
            .collect();
        let mesh = self.cut.mesh.moved(nodes)?;
        let quadratic = self.quadratic.as_ref().map(|q| q.moved(&mesh));
        Ok(Solid::on_mesh(
            &mesh,
            quadratic.as_ref(),
            self.solid.material,
        ))
    }
}

/// Penalty stiffness k_p = PENALTY_FACTOR · E · h (N/mm) of the contact springs on `solid`
/// with cells of y size `layer` in front of the cut.
fn penalty(solid: &Solid, layer: f64) -> f64 {
    PENALTY_FACTOR * solid.material.elastic.young() * layer
}

/// The node lists of the solid's elements, then the contact's (the assembler's elements).
fn elements_of<'a>(solid: &'a Solid, contact: Option<&'a FlankContact>) -> Vec<&'a [usize]> {
    let mut elements = solid.connectivity();
    if let Some(c) = contact {
        elements.extend(c.elements.iter().map(|e| e.as_slice()));
    }
    elements
}

/// The nodes on the cut plane that the cut left shared (crack front and uncut part).
fn shared_on_cut(mesh: &Mesh3d, y_cut: f64, flank_pairs: &[(usize, usize)]) -> Vec<usize> {
    let on_flank: std::collections::HashSet<usize> =
        flank_pairs.iter().flat_map(|&(a, b)| [a, b]).collect();
    (0..mesh.nodes().len())
        .filter(|n| mesh.nodes()[*n][1] == y_cut && !on_flank.contains(n))
        .collect()
}

fn find_node(nodes: &[[f64; 3]], at: [f64; 3]) -> Result<usize, SceneError> {
    nodes
        .iter()
        .position(|p| (0..3).all(|d| (p[d] - at[d]).abs() <= 1e-9 * (1.0 + at[d].abs())))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::cutblock::variables::MAX_INCREMENT;
    use crate::scene::cutblock::CutBlock;
    use crate::scene::Scene;

    /// ‖f_int(u) − f‖ on the free dofs at the topology's displacements.
    fn residual(t: &Topology) -> f64 {
        let mut r = vec![0.0; t.eq.u.len()];
        t.solid.add_internal(&t.asm, &t.eq.u, &mut r, None).unwrap();
        for (r, f) in r.iter_mut().zip(&t.eq.f) {
            *r -= f;
        }
        for &d in t.eq.constrained() {
            r[d] = 0.0;
        }
        crate::solve::newton::norm_of(&r)
    }

    /// The residuals at the start of an advance of the blade to 38 mm at a 10 mm pull
    /// (neo-Hookean tet4) after equilibria at 38 − 3δ, 38 − 2δ and 38 − δ mm (one cell):
    /// extrapolated from them, and the last carried onto the new mesh.
    fn starts(step: f64) -> (f64, f64) {
        let mut s = CutBlock::new();
        s.initialize(0.0).unwrap();
        s.set("pull", 10.0).unwrap();
        for k in [3.0, 2.0, 1.0] {
            s.set("scalpel_x", 38.0 - k * step).unwrap();
            s.do_step(0.0, 1.0).unwrap();
        }
        let settings =
            super::super::equilibrium::settings(Tetrahedron::Tet4, s.values.real(MAX_INCREMENT));
        let (g, old) = (s.geometry.as_ref().unwrap(), s.topology.as_mut().unwrap());
        assert_eq!(old.path.len(), 2);
        let start = |old: &Topology| {
            let (m, kind) = (old.material(), Tetrahedron::Tet4);
            let mut t = Topology::build(g, 38.0, m, kind, settings, Some(old), None).unwrap();
            assert!(Arc::ptr_eq(&t.asm, &old.asm), "the same pattern");
            assert!(t.start_from(g, old, 38.0).unwrap());
            residual(&t)
        };
        let extrapolated = start(old);
        old.path.clear();
        (extrapolated, start(old))
    }

    /// An advance whose start fails (the previous equilibrium's free displacements reversed
    /// and five times as large under the 10 mm pull) fails in its first iteration, on the
    /// tangent factorized there, and is not cut back (at an unchanged load its halves would
    /// repeat it: 8 times before); the advance goes back to the unloaded block, counts that
    /// return, and reaches what a topology solved from the unloaded block reaches, with that
    /// one failed iteration and factorization counted besides the same work.
    #[test]
    fn an_advance_whose_start_fails_solves_from_the_unloaded_block() {
        let mut s = CutBlock::new();
        s.initialize(0.0).unwrap();
        s.set("pull", 10.0).unwrap();
        s.set("scalpel_x", 37.0).unwrap();
        s.do_step(0.0, 1.0).unwrap();
        let settings =
            super::super::equilibrium::settings(Tetrahedron::Tet4, s.values.real(MAX_INCREMENT));
        let (g, old) = (s.geometry.as_ref().unwrap(), s.topology.as_mut().unwrap());
        old.path.clear();
        old.eq.u.iter_mut().for_each(|u| *u *= -5.0);
        let (m, kind) = (old.material(), Tetrahedron::Tet4);
        let solved = |from: Option<&Topology>| {
            let mut t = Topology::build(g, 38.0, m, kind, settings, from, None).unwrap();
            t.solve_after(g, from, 10.0, 0.0, 38.0).unwrap();
            t
        };
        let (warm, cold) = (solved(Some(old)), solved(None));
        let (w, c) = (warm.eq.work, cold.eq.work);
        assert_eq!((w.returns_to_unloaded, c.returns_to_unloaded), (1, 0));
        assert_eq!(w.iterations, c.iterations);
        assert_eq!(
            (w.failed_iterations, w.factorizations),
            (1, c.factorizations + 1),
            "{w:?} against {c:?}"
        );
        let size = crate::solve::newton::max_abs(&cold.eq.u);
        let diff = warm
            .eq
            .u
            .iter()
            .zip(&cold.eq.u)
            .fold(0.0f64, |a, (x, y)| a.max((x - y).abs()));
        assert!(diff <= 1e-9 * size, "{diff:e} of {size}");
    }

    /// The quadratic through three equilibria follows the path to third order in the step
    /// (the mesh moves affinely with the blade, so each node's displacement is a smooth
    /// function of it), the last equilibrium carried onto the new mesh to first order (it
    /// lags a step behind around the tip): halving δ from 0.5 to 0.25 mm divides the
    /// extrapolated start's residual by about 2³ and the carried one's by about 2.
    #[test]
    fn an_advance_within_a_cell_starts_from_its_path_extrapolated() {
        let (coarse, fine) = (starts(0.5), starts(0.25));
        let order = |a: f64, b: f64| (a / b).log2();
        let (extrapolated, carried) = (order(coarse.0, fine.0), order(coarse.1, fine.1));
        assert!((extrapolated - 3.0).abs() <= 0.5, "order {extrapolated:.2}");
        assert!((carried - 1.0).abs() <= 0.25, "order {carried:.2}");
        let (e, c) = starts(1.0);
        assert!(
            e < 0.1 * c,
            "at 1 mm: extrapolated {e:.3e}, carried {c:.3e}"
        );
    }
}
