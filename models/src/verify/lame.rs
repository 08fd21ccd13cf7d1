//! Lamé's thick-walled cylinder under internal pressure, plane strain (Timoshenko & Goodier,
//! Theory of Elasticity, §28): u_r(r) = (1+ν) p a² / (E (b² − a²)) · ((1 − 2ν) r + b²/r).
//! Solved on a quarter annulus with symmetry supports, with linear triangles (L2 displacement
//! error integrated with a 3-point rule of degree 2 per triangle) or 6-node triangles whose
//! mid-edge nodes on the arcs lie on the arcs (errors integrated with the 6-point rule).

use crate::assembly::{loads, plane, quadratic_plane, Assembler};
use crate::element::mixed::Formulation;
use crate::element::quadrature::TRI_6;
use crate::element::recovery;
use crate::element::tri6;
use crate::element::{tri3, Elastic};
use crate::error::ModelError;
use crate::linalg::Factorization;
use crate::mesh::{generate, Mesh2d, QuadraticPlaneMesh};
use crate::solve::Statics;

/// The problem data: radii a < b (mm), pressure p (MPa), material.
#[derive(Debug, Clone, Copy)]
pub struct Lame {
    /// Inner radius a (mm).
    pub a: f64,
    /// Outer radius b (mm).
    pub b: f64,
    /// Internal pressure p (MPa).
    pub p: f64,
    /// Elastic constants of the cylinder.
    pub material: Elastic,
}

/// Result of one FE solution.
#[derive(Debug, Clone, Copy)]
pub struct LameSolution {
    /// Number of triangles of the mesh.
    pub triangles: usize,
    /// Number of free dofs (equations).
    pub dofs: usize,
    /// ‖u_h − u‖_L2 / ‖u‖_L2.
    pub l2_error: f64,
    /// Area-weighted RMS error of the stresses (σxx, σyy, σxy) relative to the RMS of the
    /// exact stress: at the centroid for linear triangles, at the six quadrature points of
    /// [`crate::element::quadrature::TRI_6`] for quadratic ones.
    pub stress_error: f64,
    /// FE radial displacement at (a, 0) and the exact value.
    pub inner_fe: f64,
    /// The exact radial displacement at r = a (mm).
    pub inner_exact: f64,
}

impl Lame {
    /// Exact radial displacement at radius r.
    pub fn radial(&self, r: f64) -> f64 {
        let (e, nu) = (self.material.young(), self.material.poisson());
        (1.0 + nu) * self.p * self.a * self.a / (e * (self.b * self.b - self.a * self.a))
            * ((1.0 - 2.0 * nu) * r + self.b * self.b / r)
    }

    fn exact(&self, x: [f64; 2]) -> [f64; 2] {
        let r = x[0].hypot(x[1]);
        let ur = self.radial(r);
        [ur * x[0] / r, ur * x[1] / r]
    }

    /// Solves on an `nr` × `nt` quarter-annulus mesh.
    pub fn solve(&self, nr: usize, nt: usize) -> Result<LameSolution, ModelError> {
        let mesh = generate::quarter_annulus(self.a, self.b, nr, nt)?;
        let props = plane::PlaneProperties {
            continua: vec![plane::Continuum {
                elastic: self.material,
                density: 1e-9,
            }],
            trusses: vec![],
        };
        let asm: Assembler = plane::assembler(&mesh);
        let mut k = asm.zeros();
        plane::stiffness(&mesh, &asm, &props, &mut k);
        let sets = mesh.node_sets();
        let mut fixed: Vec<usize> = sets.get("x_axis")?.iter().map(|n| 2 * n + 1).collect();
        fixed.extend(sets.get("y_axis")?.iter().map(|n| 2 * n));
        let mut f = vec![0.0; mesh.n_dofs()];
        let inner = sets.get("inner")?;
        for w in inner.windows(2) {
            // Walking from larger to smaller θ keeps the body on the left.
            loads::edge_pressure(mesh.nodes(), [w[1], w[0]], self.p, &mut f);
        }
        let mut statics = Statics::new(&asm, &fixed, Factorization::Simplicial)?;
        statics.factorize(&k)?;
        let mut u = vec![0.0; mesh.n_dofs()];
        statics.solve(asm.matrix(&k), &f, &mut u);
        Ok(LameSolution {
            triangles: mesh.triangles().len(),
            dofs: statics.dirichlet().n_free(),
            l2_error: self.l2_error(&mesh, &u),
            stress_error: self.stress_error(&mesh, &props, &u),
            inner_fe: u[2 * inner[0]],
            inner_exact: self.radial(self.a),
        })
    }

    /// Solves with 6-node triangles in `formulation` on the `nr` × `nt` mesh, the mid-edge
    /// nodes of the arcs moved onto the arcs.
    pub fn solve_quadratic(
        &self,
        nr: usize,
        nt: usize,
        formulation: Formulation,
    ) -> Result<LameSolution, ModelError> {
        let mesh = generate::quarter_annulus(self.a, self.b, nr, nt)?;
        let sets = mesh.node_sets();
        let mut q = QuadraticPlaneMesh::new(&mesh);
        for (set, radius) in [("inner", self.a), ("outer", self.b)] {
            q.curve(sets.get(set)?, |[x, y]| {
                let r = x.hypot(y);
                [x * radius / r, y * radius / r]
            });
        }
        let props = plane::PlaneProperties {
            continua: vec![plane::Continuum {
                elastic: self.material,
                density: 1e-9,
            }],
            trusses: vec![],
        };
        let asm = quadratic_plane::assembler(&q);
        let mut k = asm.zeros();
        quadratic_plane::stiffness(&q, &asm, &props, formulation, &mut k);
        let mut fixed: Vec<usize> = q
            .extend(sets.get("x_axis")?)
            .iter()
            .map(|n| 2 * n + 1)
            .collect();
        fixed.extend(q.extend(sets.get("y_axis")?).iter().map(|n| 2 * n));
        let mut f = vec![0.0; q.n_dofs()];
        let inner = sets.get("inner")?;
        for w in inner.windows(2) {
            let mid = q
                .mid(w[0], w[1])
                .expect("neighbours on the arc share an edge");
            loads::quadratic_edge_pressure(q.nodes(), [w[1], mid, w[0]], self.p, &mut f);
        }
        let mut statics = Statics::new(&asm, &fixed, Factorization::Simplicial)?;
        statics.factorize(&k)?;
        let mut u = vec![0.0; q.n_dofs()];
        statics.solve(asm.matrix(&k), &f, &mut u);
        let (l2_error, stress_error) = self.quadratic_errors(&q, formulation, &u);
        Ok(LameSolution {
            triangles: q.triangles().len(),
            dofs: statics.dirichlet().n_free(),
            l2_error,
            stress_error,
            inner_fe: u[2 * inner[0]],
            inner_exact: self.radial(self.a),
        })
    }

    /// The relative L2 errors of the displacement and the stress of a quadratic solution.
    fn quadratic_errors(
        &self,
        q: &QuadraticPlaneMesh,
        formulation: Formulation,
        u: &[f64],
    ) -> (f64, f64) {
        let mut sums = [0.0; 4]; // displacement error, norm; stress error, norm
        for (i, tri) in q.triangles().iter().enumerate() {
            let p = q.triangle(i);
            let ue = tri6::Dofs::from_fn(|k, _| u[2 * tri[k / 2] + k % 2]);
            for &(l, w) in &TRI_6 {
                let n = tri6::shape(l);
                let interpolate = |v: [f64; 6]| (0..6).map(|k| n[k] * v[k]).sum::<f64>();
                let x = [0, 1].map(|d| interpolate(p.map(|q| q[d])));
                let uh = [0, 1].map(|d| interpolate(std::array::from_fn(|k| ue[2 * k + d])));
                let dx = 0.5 * w * tri6::b_matrix(&p, l).1;
                let exact = self.exact(x);
                sums[0] += dx * ((uh[0] - exact[0]).powi(2) + (uh[1] - exact[1]).powi(2));
                sums[1] += dx * (exact[0].powi(2) + exact[1].powi(2));
                let sh = recovery::stress(formulation, &p, l, &ue, &self.material);
                let se = self.exact_stress(x);
                sums[2] += dx * (0..3).map(|c| (sh[c] - se[c]).powi(2)).sum::<f64>();
                sums[3] += dx * se.iter().map(|s| s * s).sum::<f64>();
            }
        }
        ((sums[0] / sums[1]).sqrt(), (sums[2] / sums[3]).sqrt())
    }

    /// Exact Cartesian stress (σxx, σyy, σxy): σrr = A − B/r², σθθ = A + B/r² with
    /// A = p a²/(b² − a²), B = p a² b²/(b² − a²).
    fn exact_stress(&self, x: [f64; 2]) -> [f64; 3] {
        let (a2, b2) = (self.a * self.a, self.b * self.b);
        let big_a = self.p * a2 / (b2 - a2);
        let big_b = big_a * b2;
        let r2 = x[0] * x[0] + x[1] * x[1];
        let (srr, stt) = (big_a - big_b / r2, big_a + big_b / r2);
        let (c, s) = (x[0] / r2.sqrt(), x[1] / r2.sqrt());
        [
            srr * c * c + stt * s * s,
            srr * s * s + stt * c * c,
            (srr - stt) * s * c,
        ]
    }

    fn stress_error(&self, mesh: &Mesh2d, props: &plane::PlaneProperties, u: &[f64]) -> f64 {
        let stresses = crate::stress::triangle_stresses(mesh, props, u);
        let (mut err, mut norm) = (0.0, 0.0);
        for (i, fe) in stresses.iter().enumerate() {
            let p = mesh.triangle(i);
            let w = tri3::signed_area(&p);
            let c = [0, 1].map(|d| (p[0][d] + p[1][d] + p[2][d]) / 3.0);
            let ex = self.exact_stress(c);
            err +=
                w * ((fe.xx - ex[0]).powi(2) + (fe.yy - ex[1]).powi(2) + (fe.xy - ex[2]).powi(2));
            norm += w * (ex[0].powi(2) + ex[1].powi(2) + ex[2].powi(2));
        }
        (err / norm).sqrt()
    }

    fn l2_error(&self, mesh: &Mesh2d, u: &[f64]) -> f64 {
        // Barycentric points of the degree-2 rule, weight 1/3 each.
        const POINTS: [[f64; 3]; 3] = [
            [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
            [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
            [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
        ];
        let (mut err, mut norm) = (0.0, 0.0);
        for (i, tri) in mesh.triangles().iter().enumerate() {
            let p = mesh.triangle(i);
            let w = tri3::signed_area(&p) / 3.0;
            for l in POINTS {
                let x = [0, 1].map(|d| (0..3).map(|k| l[k] * p[k][d]).sum::<f64>());
                let uh = [0, 1].map(|d| (0..3).map(|k| l[k] * u[2 * tri[k] + d]).sum::<f64>());
                let ue = self.exact(x);
                err += w * ((uh[0] - ue[0]).powi(2) + (uh[1] - ue[1]).powi(2));
                norm += w * (ue[0].powi(2) + ue[1].powi(2));
            }
        }
        (err / norm).sqrt()
    }
}
