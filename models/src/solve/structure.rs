//! The semi-discrete equation of motion M ü + C u̇ + K u = f(t) (seed 003 eq. 2.1) on the free
//! dofs of a mesh: reduced stiffness, consistent mass, damping (all on one pattern) and the
//! lumped mass used by the explicit schemes. Supports are homogeneous (u = 0) in dynamics.
//!
//! At finite strain ([`Structure::with_internal_forces`]) the stiffness term is the internal
//! force f_int(u) with its tangent K_T(u); K is then the tangent at u = 0. The implicit
//! schemes solve each step by Newton's method (`effective`); the explicit schemes and the
//! modal reduction refuse such a structure.

use std::sync::Arc;

use faer::sparse::SparseColMatRef;
use faer::MatRef;

use crate::assembly::{Assembler, Dirichlet, InternalForces};
use crate::error::{non_negative, ModelError};
use crate::linalg::cholesky::{Cholesky, Factorization};
use crate::linalg::product::SymmetricProduct;

/// Rayleigh damping C = α M + β K (α in 1/s, β in s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damping {
    /// The mass-proportional coefficient α (1/s).
    pub alpha: f64,
    /// The stiffness-proportional coefficient β (s).
    pub beta: f64,
}

impl Damping {
    /// No damping.
    pub const NONE: Self = Self {
        alpha: 0.0,
        beta: 0.0,
    };

    fn check(&self) -> Result<(), ModelError> {
        non_negative("rayleigh.alpha", self.alpha)?;
        non_negative("rayleigh.beta", self.beta)?;
        Ok(())
    }
}

/// M, C, K on the free dofs, plus the lumped mass.
#[derive(Clone)]
pub struct Structure {
    bc: Dirichlet,
    k: Vec<f64>,
    m: Vec<f64>,
    c: Vec<f64>,
    lumped: Vec<f64>,
    /// `Some`: C is rebuilt from M and K as Rayleigh damping; `None`: C was assembled by the
    /// caller ([`Structure::set_damping_matrix`]) and is kept as given.
    rayleigh: Option<Damping>,
    /// Whether C has any non-zero entry (the schemes skip its products otherwise).
    damped: bool,
    /// `Some(α)` when C = α M exactly: the history terms then need one product, not two.
    mass_proportional: Option<f64>,
    factorization: Factorization,
    /// The products with K, M and C (all symmetric, on the reduced pattern).
    product: SymmetricProduct,
    /// The internal forces of a finite-strain structure.
    internal: Option<Arc<dyn InternalForces>>,
    /// Newton's iterations stop at a residual of this share of its scale.
    newton_tolerance: f64,
}

impl std::fmt::Debug for Structure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Structure")
            .field("n", &self.n())
            .field("nonlinear", &self.internal.is_some())
            .finish()
    }
}

impl Structure {
    /// Gathers the reduced matrices from full-pattern values `k_full`, `m_full` and the
    /// full-length lumped mass. `factorization` is the Cholesky storage implicit
    /// integrators use.
    pub fn new(
        bc: Dirichlet,
        k_full: &[f64],
        m_full: &[f64],
        lumped_full: &[f64],
        damping: Damping,
        factorization: Factorization,
    ) -> Result<Self, ModelError> {
        damping.check()?;
        let nnz = bc.nnz();
        let mut lumped = vec![0.0; bc.n_free()];
        bc.reduce(lumped_full, &mut lumped);
        if let Some(i) = lumped.iter().position(|&m| !(m > 0.0 && m.is_finite())) {
            return Err(ModelError::InvalidParameter {
                name: format!("lumped mass of equation {i} (dof {})", bc.free()[i]),
                value: lumped[i],
                reason: "every free dof needs a positive mass",
            });
        }
        let mut s = Self {
            product: SymmetricProduct::new(bc.symbolic().as_ref())?,
            internal: None,
            newton_tolerance: NEWTON_TOLERANCE,
            k: vec![0.0; nnz],
            m: vec![0.0; nnz],
            c: vec![0.0; nnz],
            bc,
            lumped,
            rayleigh: Some(damping),
            damped: false,
            mass_proportional: None,
            factorization,
        };
        s.bc.combine(&[(1.0, m_full)], &mut s.m);
        s.set_stiffness(k_full);
        Ok(s)
    }

    /// A structure of small r × r matrices given densely (a reduced model,
    /// [`super::ModalBasis::reduce`]): every equation free, the pattern holding the diagonal
    /// and every entry that is non-zero in K, M or C, the lumped mass M's diagonal, C kept as
    /// given.
    pub fn dense(
        k: MatRef<'_, f64>,
        m: MatRef<'_, f64>,
        c: MatRef<'_, f64>,
    ) -> Result<Self, ModelError> {
        Self::dense_on(k, m, c, |i, j| [k, m, c].iter().any(|a| a[(i, j)] != 0.0))
    }

    /// As [`dense`](Self::dense) on the pattern of every r × r entry: the structure of a
    /// hyper-reduced finite-strain model, whose tangent is dense.
    pub fn dense_full(
        k: MatRef<'_, f64>,
        m: MatRef<'_, f64>,
        c: MatRef<'_, f64>,
    ) -> Result<Self, ModelError> {
        Self::dense_on(k, m, c, |_, _| true)
    }

    /// The dense structure whose pattern holds the diagonal and the entries (i < j) where
    /// `entry(i, j)`.
    fn dense_on(
        k: MatRef<'_, f64>,
        m: MatRef<'_, f64>,
        c: MatRef<'_, f64>,
        entry: impl Fn(usize, usize) -> bool,
    ) -> Result<Self, ModelError> {
        let r = k.nrows();
        let mut elements: Vec<Vec<usize>> = (0..r).map(|i| vec![i]).collect();
        for j in 0..r {
            for i in 0..j {
                if entry(i, j) {
                    elements.push(vec![i, j]);
                }
            }
        }
        let asm = Assembler::new(r, 1, &elements);
        let values = |a: MatRef<'_, f64>| -> Vec<f64> {
            let p = asm.symbolic();
            (0..r)
                .flat_map(|j| {
                    p.row_idx()[p.col_ptr()[j]..p.col_ptr()[j + 1]]
                        .iter()
                        .map(move |&i| a[(i, j)])
                })
                .collect()
        };
        let lumped: Vec<f64> = (0..r).map(|i| m[(i, i)]).collect();
        let bc = Dirichlet::new(&asm, &[])?;
        let (kv, mv, cv) = (values(k), values(m), values(c));
        let mut s = Self::new(
            bc,
            &kv,
            &mv,
            &lumped,
            Damping::NONE,
            Factorization::Simplicial,
        )?;
        s.set_damping_matrix(&cv);
        Ok(s)
    }

    /// Makes the structure finite-strain: the stiffness term becomes `forces` (K stays the
    /// tangent at u = 0, for the first factorization of a step's Newton iterations).
    pub fn with_internal_forces(mut self, forces: Arc<dyn InternalForces>) -> Self {
        self.set_internal_forces(forces);
        self
    }

    /// Newton's iterations in a step stop at a residual of `tolerance` times its scale
    /// (the default [`NEWTON_TOLERANCE`] suits a full model; a reduced one, whose own error
    /// is far larger, may stop sooner).
    pub fn with_newton_tolerance(mut self, tolerance: f64) -> Self {
        self.newton_tolerance = tolerance;
        self
    }

    /// Replaces the internal forces of a finite-strain structure (after a parameter change;
    /// [`set_stiffness`](Self::set_stiffness) gives the matching tangent at u = 0).
    pub fn set_internal_forces(&mut self, forces: Arc<dyn InternalForces>) {
        self.internal = Some(forces);
    }

    /// Whether the stiffness term is nonlinear (finite strain).
    pub fn is_nonlinear(&self) -> bool {
        self.internal.is_some()
    }

    /// Errors with [`ModelError::LinearOnly`] for a finite-strain structure.
    pub fn require_linear(&self, what: &'static str) -> Result<(), ModelError> {
        match self.internal {
            Some(_) => Err(ModelError::LinearOnly { what }),
            None => Ok(()),
        }
    }

    /// Replaces the stiffness (after a parameter change) and rebuilds the damping matrix.
    /// Integrators must be `prepare`d again afterwards.
    pub fn set_stiffness(&mut self, k_full: &[f64]) {
        self.bc.combine(&[(1.0, k_full)], &mut self.k);
        self.rebuild_damping();
    }

    /// Replaces the damping by an assembled damping matrix (full-pattern values), e.g. one
    /// with different Rayleigh coefficients per tissue. It is kept as given when the
    /// stiffness changes. Integrators must be `prepare`d again afterwards.
    pub fn set_damping_matrix(&mut self, c_full: &[f64]) {
        self.rayleigh = None;
        self.bc.combine(&[(1.0, c_full)], &mut self.c);
        self.damped = self.c.iter().any(|&c| c != 0.0);
        self.mass_proportional = self.proportionality();
    }

    /// α if C = α M entry by entry (to round-off), else `None`.
    fn proportionality(&self) -> Option<f64> {
        let k = self.m.iter().position(|&m| m != 0.0)?;
        let alpha = self.c[k] / self.m[k];
        let scale = self.c.iter().fold(0.0f64, |a, c| a.max(c.abs()));
        self.c
            .iter()
            .zip(&self.m)
            .all(|(c, m)| (c - alpha * m).abs() <= 1e-12 * scale)
            .then_some(alpha)
    }

    fn rebuild_damping(&mut self) {
        if let Some(Damping { alpha, beta }) = self.rayleigh {
            for ((c, m), k) in self.c.iter_mut().zip(&self.m).zip(&self.k) {
                *c = alpha * m + beta * k;
            }
            self.damped = alpha != 0.0 || beta != 0.0;
            self.mass_proportional = (beta == 0.0).then_some(alpha);
        }
    }

    /// Number of equations.
    pub fn n(&self) -> usize {
        self.bc.n_free()
    }
    /// The split of the dofs into free and constrained ones.
    pub fn dirichlet(&self) -> &Dirichlet {
        &self.bc
    }
    /// The stiffness K on the free dofs (at finite strain, the tangent at u = 0).
    pub fn stiffness(&self) -> SparseColMatRef<'_, usize, f64> {
        self.bc.matrix(&self.k)
    }
    /// The mass matrix M on the free dofs.
    pub fn mass(&self) -> SparseColMatRef<'_, usize, f64> {
        self.bc.matrix(&self.m)
    }
    /// The damping matrix C on the free dofs.
    pub fn damping_matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        self.bc.matrix(&self.c)
    }
    /// Lumped (diagonal) mass per equation.
    pub fn lumped_mass(&self) -> &[f64] {
        &self.lumped
    }

    /// The internal forces of a finite-strain structure.
    pub fn internal_forces(&self) -> Option<&dyn InternalForces> {
        self.internal.as_deref()
    }

    /// The residual tolerance of a step's Newton iterations.
    pub fn newton_tolerance(&self) -> f64 {
        self.newton_tolerance
    }

    /// The values of M and of C on the reduced pattern.
    pub fn mass_and_damping_values(&self) -> (&[f64], &[f64]) {
        (&self.m, &self.c)
    }

    /// out ← out + c_m M x + c_c C x (no allocation).
    pub fn add_mass_and_damping(&self, x: &[f64], c_m: f64, c_c: f64, out: &mut [f64]) {
        self.product.mul_add(&self.m, x, c_m, out);
        self.product.mul_add(&self.c, x, c_c, out);
    }

    /// Values of the effective matrix c_m M + c_c C + K on the reduced pattern.
    pub fn effective(&self, c_m: f64, c_c: f64, out: &mut [f64]) {
        for (((o, m), c), k) in out.iter_mut().zip(&self.m).zip(&self.c).zip(&self.k) {
            *o = c_m * m + c_c * c + k;
        }
    }

    /// A Cholesky factorization analysed for this structure's reduced pattern.
    pub fn analyze(&self) -> Result<Cholesky, ModelError> {
        Cholesky::analyze(self.bc.symbolic().as_ref(), self.factorization)
    }

    /// out = f − C v − K u (the unbalanced force) with the linear K (for a finite-strain
    /// structure, the tangent at rest). Allocates nothing.
    pub fn residual(&self, f: &[f64], u: &[f64], v: &[f64], out: &mut [f64]) {
        out.copy_from_slice(f);
        self.product.mul_add(&self.k, u, -1.0, out);
        if self.damped {
            self.product.mul_add(&self.c, v, -1.0, out);
        }
    }

    /// out = f − C v − f_int(u): the unbalanced force with the internal forces of a
    /// finite-strain structure (which may load it at rest, e.g. an active tension), else
    /// [`residual`](Self::residual). Allocates at finite strain: for start-up, not for steps.
    pub fn unbalanced(
        &self,
        f: &[f64],
        u: &[f64],
        v: &[f64],
        out: &mut [f64],
    ) -> Result<(), ModelError> {
        self.unbalanced_with(f, u, v, out, &mut self.residual_work())
    }

    /// [`unbalanced`](Self::unbalanced) with `full`, two vectors of all dofs, as the work
    /// space of the internal forces: allocates nothing.
    fn unbalanced_with(
        &self,
        f: &[f64],
        u: &[f64],
        v: &[f64],
        out: &mut [f64],
        [u_full, f_full]: &mut [Vec<f64>; 2],
    ) -> Result<(), ModelError> {
        let Some(forces) = &self.internal else {
            self.residual(f, u, v, out);
            return Ok(());
        };
        self.bc.expand(u, u_full);
        f_full.fill(0.0);
        forces.internal(u_full, f_full, None)?;
        self.bc.reduce(f_full, out);
        for (o, f) in out.iter_mut().zip(f) {
            *o = f - *o;
        }
        if self.damped {
            self.product.mul_add(&self.c, v, -1.0, out);
        }
        Ok(())
    }

    /// The work space of [`equation_residual`](Self::equation_residual): two vectors of
    /// all dofs.
    pub fn residual_work(&self) -> [Vec<f64>; 2] {
        [vec![0.0; self.bc.n_dofs()], vec![0.0; self.bc.n_dofs()]]
    }

    /// Strain energy ½uᵀKu + kinetic energy ½vᵀMv (consistent mass), with the linear K.
    pub fn energy(&self, u: &[f64], v: &[f64], work: &mut [f64]) -> f64 {
        0.5 * (self.quadratic(&self.k, u, work) + self.quadratic(&self.m, v, work))
    }

    /// uᵀKu with the linear K (for a finite-strain structure, the tangent at rest).
    pub fn stiffness_norm_squared(&self, u: &[f64], work: &mut [f64]) -> f64 {
        self.quadratic(&self.k, u, work)
    }

    /// xᵀAx for A given by its values on the reduced pattern.
    fn quadratic(&self, a: &[f64], x: &[f64], work: &mut [f64]) -> f64 {
        work.fill(0.0);
        self.product.mul_add(a, x, 1.0, work);
        work.iter().zip(x).map(|(w, x)| w * x).sum()
    }

    /// out = f − M a − C v − f_int(u): the residual of the equation of motion at the state
    /// (u, v = u̇, a = ü) under the load f ([`unbalanced`](Self::unbalanced) less the
    /// inertia), with `work` from [`residual_work`](Self::residual_work). Allocates nothing.
    pub fn equation_residual(
        &self,
        f: &[f64],
        [u, v, a]: [&[f64]; 3],
        out: &mut [f64],
        work: &mut [Vec<f64>; 2],
    ) -> Result<(), ModelError> {
        self.unbalanced_with(f, u, v, out, work)?;
        self.product.mul_add(&self.m, a, -1.0, out);
        Ok(())
    }
}

/// The history terms of an implicit scheme: out ← out + M Σ_k m_k h_k + C Σ_k c_k h_k over
/// three history vectors h_k (Houbolt: u_n, u_{n−1}, u_{n−2}; Newmark: u_n, u̇_n, ü_n).
#[derive(Debug, Clone, Copy)]
pub struct History<'a> {
    /// The three history vectors h_k.
    pub vectors: [&'a [f64]; 3],
    /// The coefficients m_k of the mass term.
    pub mass: [f64; 3],
    /// The coefficients c_k of the damping term.
    pub damping: [f64; 3],
}

impl Structure {
    /// out ← out + M x_m + C x_c for the history combinations x_m = Σ m_k h_k and
    /// x_c = Σ c_k h_k, built in one pass into the scratch vectors. When C = α M this is one
    /// product, M Σ (m_k + α c_k) h_k.
    pub fn add_history(&self, h: History<'_>, x_m: &mut [f64], x_c: &mut [f64], out: &mut [f64]) {
        let [h0, h1, h2] = h.vectors;
        let [m0, m1, m2] = h.mass;
        let [c0, c1, c2] = h.damping;
        match self.mass_proportional {
            Some(alpha) => {
                let k = [m0 + alpha * c0, m1 + alpha * c1, m2 + alpha * c2];
                for (((x, a), b), c) in x_m.iter_mut().zip(h0).zip(h1).zip(h2) {
                    *x = k[0] * a + k[1] * b + k[2] * c;
                }
                self.product.mul_add(&self.m, x_m, 1.0, out);
            }
            None => {
                for ((((xm, xc), a), b), c) in
                    x_m.iter_mut().zip(x_c.iter_mut()).zip(h0).zip(h1).zip(h2)
                {
                    *xm = m0 * a + m1 * b + m2 * c;
                    *xc = c0 * a + c1 * b + c2 * c;
                }
                self.product.mul_add(&self.m, x_m, 1.0, out);
                self.product.mul_add(&self.c, x_c, 1.0, out);
            }
        }
    }
}

/// A step's Newton iterations converge at a residual of this share of its force scale
/// (the largest norm of the terms that balance: the right-hand side, the internal and the
/// inertia and damping forces), unless the structure sets its own
/// ([`Structure::with_newton_tolerance`]). The assembled internal forces cancel element
/// forces many times larger, so round-off leaves ‖R‖ near 10⁻⁹ of that scale (measured on
/// a tri6 cantilever).
pub const NEWTON_TOLERANCE: f64 = 1e-8;
