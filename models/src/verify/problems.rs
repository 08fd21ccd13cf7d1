//! The benchmark-sized problems of the FE-core issue: a 2D mesh of about 6,000 triangles
//! with 170 line elements (the size of seed 003's abdomen model) and the cut block's
//! 6 × 16 × 14 cubes × 5 tetrahedra (seed 002 §3.1), both with soft-tissue properties.

use crate::assembly::plane::{self, Continuum, PlaneProperties, Truss};
use crate::assembly::{tetrahedra, Assembler, Dirichlet};
use crate::element::Elastic;
use crate::error::ModelError;
use crate::linalg::Factorization;
use crate::mesh::{generate, Mesh2d, Mesh3d};
use crate::solve::{Damping, Structure};

/// A 2D problem: mesh, properties, constrained dofs.
#[derive(Debug, Clone)]
pub struct PlaneProblem {
    /// The mesh: triangles and line elements.
    pub mesh: Mesh2d,
    /// Properties of the triangle and line regions.
    pub props: PlaneProperties,
    /// The constrained dofs (held at zero).
    pub fixed: Vec<usize>,
}

/// Assembled global matrices on the full pattern.
#[derive(Debug, Clone)]
pub struct Assembled {
    /// The pattern and scatter map over all dofs.
    pub asm: Assembler,
    /// Stiffness values on the full pattern (N/mm; in 2D per mm of depth).
    pub k: Vec<f64>,
    /// Consistent mass values on the full pattern (t; in 2D per mm of depth).
    pub m: Vec<f64>,
    /// Lumped mass per dof (t; in 2D per mm of depth).
    pub lumped: Vec<f64>,
}

impl Assembled {
    /// The dynamic system on the free dofs (all but `fixed`).
    pub fn structure(
        &self,
        fixed: &[usize],
        damping: Damping,
        factorization: Factorization,
    ) -> Result<Structure, ModelError> {
        let bc = Dirichlet::new(&self.asm, fixed)?;
        Structure::new(bc, &self.k, &self.m, &self.lumped, damping, factorization)
    }
}

impl PlaneProblem {
    /// Pattern, stiffness, consistent and lumped mass.
    pub fn assemble(&self) -> Assembled {
        let asm = plane::assembler(&self.mesh);
        let (mut k, mut m) = (asm.zeros(), asm.zeros());
        plane::stiffness(&self.mesh, &asm, &self.props, &mut k);
        plane::mass(&self.mesh, &asm, &self.props, &mut m);
        let lumped = plane::lumped_mass(&self.mesh, &self.props);
        Assembled { asm, k, m, lumped }
    }
}

/// A 300 × 250 mm rectangle of `nx` × `ny` cells (2 triangles each; 60 × 50 gives 6,000),
/// line elements along the top, right and bottom edges, the left edge fixed. Cavity
/// E = 5 kPa, ν = 0.45; line elements E = 0.5 MPa, 1 mm²/mm; density 1e-9 t/mm³.
pub fn plane(nx: usize, ny: usize) -> Result<PlaneProblem, ModelError> {
    let rect = generate::rectangle(300.0, 250.0, nx, ny)?;
    let sets = rect.node_sets();
    let mut lines = Vec::new();
    for set in ["top", "right", "bottom"] {
        let nodes = sets.get(set)?;
        lines.extend(nodes.windows(2).map(|w| [w[0], w[1]]));
    }
    let fixed = sets
        .get("left")?
        .iter()
        .flat_map(|n| [2 * n, 2 * n + 1])
        .collect();
    let n_lines = lines.len();
    let mesh = rect.with_lines(lines, vec![0; n_lines])?;
    let props = PlaneProperties {
        continua: vec![Continuum {
            elastic: Elastic::new("cavity", 0.005, 0.45)?,
            density: 1e-9,
        }],
        trusses: vec![Truss::new("wall", 0.5, 1.0, 1e-9)?],
    };
    Ok(PlaneProblem { mesh, props, fixed })
}

/// A 3D problem: mesh, material, constrained dofs and their prescribed values.
#[derive(Debug, Clone)]
pub struct BlockProblem {
    /// The tetrahedral block.
    pub mesh: Mesh3d,
    /// Elastic constants and density of the block.
    pub material: Continuum,
    /// The constrained dofs.
    pub fixed: Vec<usize>,
    /// Full-length vector holding the prescribed displacement at constrained dofs.
    pub prescribed: Vec<f64>,
}

impl BlockProblem {
    /// Pattern, stiffness, consistent and lumped mass.
    pub fn assemble(&self) -> Assembled {
        let asm = tetrahedra::assembler(&self.mesh);
        let (mut k, mut m) = (asm.zeros(), asm.zeros());
        tetrahedra::stiffness(&self.mesh, &asm, &self.material, &mut k);
        tetrahedra::mass(&self.mesh, &asm, &self.material, &mut m);
        let lumped = tetrahedra::lumped_mass(&self.mesh, &self.material);
        Assembled { asm, k, m, lumped }
    }
}

/// Seed 002's block: 100 × 80 × 17 mm, `cells` cubes (default 6 × 16 × 14), face y = 0
/// clamped, face y = 80 pulled by `pull` mm in y (x, z free); E = 0.0385 MPa, ν = 0.43
/// (seed 002 Table 4.1).
pub fn block(cells: [usize; 3], pull: f64) -> Result<BlockProblem, ModelError> {
    let mesh = generate::block([100.0, 80.0, 17.0], cells)?;
    let sets = mesh.node_sets();
    let mut fixed: Vec<usize> = sets
        .get("y0")?
        .iter()
        .flat_map(|n| [3 * n, 3 * n + 1, 3 * n + 2])
        .collect();
    let mut prescribed = vec![0.0; mesh.n_dofs()];
    for n in sets.get("y1")? {
        fixed.push(3 * n + 1);
        prescribed[3 * n + 1] = pull;
    }
    Ok(BlockProblem {
        material: Continuum {
            elastic: Elastic::new("silicone", 0.0385, 0.43)?,
            density: 1.1e-9,
        },
        mesh,
        fixed,
        prescribed,
    })
}
