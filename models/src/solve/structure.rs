//! The semi-discrete equation of motion M ü + C u̇ + K u = f(t) (seed 003 eq. 2.1) on the free
//! dofs of a mesh: reduced stiffness, consistent mass, damping (all on one pattern) and the
//! lumped mass used by the explicit schemes. Supports are homogeneous (u = 0) in dynamics.
//!
//! At finite strain ([`Structure::with_internal_forces`]) the stiffness term is the internal
//! force f_int(u) with its tangent K_T(u); K is then the tangent at u = 0. The implicit
//! schemes solve each step by Newton's method ([`Effective::solve`]); the explicit schemes
//! and the modal reduction refuse such a structure.

use std::sync::Arc;

use faer::sparse::SparseColMatRef;
use faer::MatRef;

use super::cholesky::{Cholesky, Factorization};
use super::newton::{max_abs, norm_of};
use super::product::SymmetricProduct;
use crate::assembly::{Assembler, Dirichlet};
use crate::error::{non_negative, ModelError};

/// Rayleigh damping C = α M + β K (α in 1/s, β in s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damping {
    pub alpha: f64,
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

/// The internal forces of a finite-strain structure: `forces(u, f, k)` writes f_int(u) (u and
/// f on all dofs, the constrained ones of u zero) into `f` and, when given, the tangent values
/// on the full pattern into `k`; an inverted element is an error.
pub type InternalForces =
    dyn Fn(&[f64], &mut [f64], Option<&mut [f64]>) -> Result<(), ModelError> + Send + Sync;

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
    internal: Option<Arc<InternalForces>>,
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
    pub fn with_internal_forces(mut self, forces: Arc<InternalForces>) -> Self {
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
    pub fn set_internal_forces(&mut self, forces: Arc<InternalForces>) {
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
    pub fn dirichlet(&self) -> &Dirichlet {
        &self.bc
    }
    pub fn stiffness(&self) -> SparseColMatRef<'_, usize, f64> {
        self.bc.matrix(&self.k)
    }
    pub fn mass(&self) -> SparseColMatRef<'_, usize, f64> {
        self.bc.matrix(&self.m)
    }
    pub fn damping_matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        self.bc.matrix(&self.c)
    }
    /// Lumped (diagonal) mass per equation.
    pub fn lumped_mass(&self) -> &[f64] {
        &self.lumped
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
        forces(u_full, f_full, None)?;
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
    pub vectors: [&'a [f64]; 3],
    pub mass: [f64; 3],
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

/// Newton iterations a finite-strain step may take. Most steps take 2–7; the steps in
/// which the abdomen's membranes go slack at the end of a press took up to 93 on the mixed
/// element (measured before 2026-11-27, with the membranes' tension-field tangent: default
/// scene, ν = 0.4999, 10 ms steps).
const MAX_NEWTON_ITERATIONS: usize = 100;
/// A step has converged when ‖R‖ ≤ this fraction of the step's force scale (the largest
/// norm of the terms that balance: the right-hand side, the internal and the inertia and
/// damping forces). The assembled internal forces cancel element forces many times larger,
/// so round-off leaves ‖R‖ near 10⁻⁹ of that scale (measured on a tri6 cantilever).
pub const NEWTON_TOLERANCE: f64 = 1e-8;
/// A step has also converged when Newton's correction is below this fraction of the
/// displacement (‖Δu‖∞ ≤ 10⁻¹⁰ max(‖u‖∞, [`DISPLACEMENT_FLOOR`])).
const ROUND_OFF_CORRECTION: f64 = 1e-10;
/// Displacements (mm) below which the correction is measured against this instead: at
/// strains near zero the finite-strain stress P(I + ∇u) loses the digits of ∇u it shares
/// with the identity (10⁻¹⁶/|∇u| of itself), so a load that starts from zero (a press
/// rising as 1 − cos) gives corrections no iteration can make relatively small; 10⁻¹³ mm is
/// far below anything an output resolves.
const DISPLACEMENT_FLOOR: f64 = 1e-3;
/// A fresh Newton correction below this fraction of the displacement that gives no descent,
/// or that (unshifted, taken in full) does not halve the residual, is round-off (stiff
/// membranes on soft contents, a contrast of 10⁶, reach about 10⁻⁹).
const STALLED_CORRECTION: f64 = 1e-8;
/// Shifts towards the mass tried when a tangent is not positive definite
/// ([`Effective::factorize_tangent`]).
const SHIFTS: usize = 12;
/// Times a Newton correction is halved when it takes an element past inversion.
const BACKTRACKS: usize = 10;
/// A fresh tangent's correction that does not reduce a residual below this fraction of the
/// force scale has met the round-off of the stresses (the neo-Hookean stress at strains of
/// 10⁻⁷ carries a round-off of 10⁻⁹ of itself).
const STALL: f64 = 1e-6;
/// The factorization is kept while every iteration reduces ‖R‖ at least by this factor; a
/// slower iteration refactorizes the tangent at the current iterate (modified Newton).
const KEEP_FACTOR_CONTRACTION: f64 = 0.25;

/// The factorized effective matrix c_m M + c_c C + K of an implicit scheme, and for a
/// finite-strain structure the Newton iteration of a step. The symbolic analysis is done on
/// first use and kept; later calls refactorize numerically only.
#[derive(Debug, Default)]
pub(crate) struct Effective {
    chol: Option<Cholesky>,
    values: Vec<f64>,
    coefficients: (f64, f64),
    newton: NewtonWork,
    /// Finite strain: the displacement at which the kept tangent was factorized, when it is
    /// not the prepared matrix (a checkpoint refactorizes there to continue bit for bit).
    tangent_at: Vec<f64>,
    has_tangent: bool,
    /// The mass coefficient added to the kept tangent to make it positive definite (0
    /// unless the tangent at `tangent_at` was not).
    shift: f64,
}

/// The work vectors of the Newton iterations (sized when the matrix is first factorized for
/// a finite-strain structure; nothing is allocated per step).
#[derive(Debug, Default)]
struct NewtonWork {
    target: Vec<f64>,
    residual: Vec<f64>,
    /// (c_m M + c_c C) u.
    inertia: Vec<f64>,
    u_full: Vec<f64>,
    f_full: Vec<f64>,
    k_full: Vec<f64>,
    k_reduced: Vec<f64>,
    /// The last Newton correction and the line search's trial state.
    correction: Vec<f64>,
    trial: Vec<f64>,
    /// Iterations and tangent factorizations of the last step (0 for a linear structure).
    iterations: usize,
    factorizations: usize,
}

impl Effective {
    /// Forms and factorizes c_m M + c_c C + K.
    pub(crate) fn factorize(
        &mut self,
        s: &Structure,
        c_m: f64,
        c_c: f64,
    ) -> Result<(), ModelError> {
        let chol = match &mut self.chol {
            Some(c) if c.n() == s.n() => c,
            slot => {
                self.values = vec![0.0; s.dirichlet().nnz()];
                slot.insert(s.analyze()?)
            }
        };
        if s.is_nonlinear() && self.newton.target.len() != s.n() {
            let bc = s.dirichlet();
            self.newton = NewtonWork {
                target: vec![0.0; s.n()],
                residual: vec![0.0; s.n()],
                inertia: vec![0.0; s.n()],
                u_full: vec![0.0; bc.n_dofs()],
                f_full: vec![0.0; bc.n_dofs()],
                k_full: vec![0.0; bc.full_nnz()],
                k_reduced: vec![0.0; bc.nnz()],
                correction: vec![0.0; s.n()],
                trial: vec![0.0; s.n()],
                iterations: 0,
                factorizations: 0,
            };
        }
        self.coefficients = (c_m, c_c);
        self.has_tangent = false;
        self.tangent_at.resize(s.n(), 0.0);
        s.effective(c_m, c_c, &mut self.values);
        chol.factorize(s.dirichlet().matrix(&self.values))
    }

    /// Where the kept factor's tangent was taken and its shift, if it is not the prepared
    /// matrix.
    pub(crate) fn kept_tangent(&self) -> Option<(Vec<f64>, f64)> {
        self.has_tangent
            .then(|| (self.tangent_at.clone(), self.shift))
    }

    /// Refactorizes (c_m + `shift`) M + c_c C + K_T(x) with the prepared coefficients, as a
    /// step's Newton iteration at `x` did (to resume from a checkpoint).
    pub(crate) fn refactorize_at(
        &mut self,
        s: &Structure,
        x: &[f64],
        shift: f64,
    ) -> Result<(), ModelError> {
        let (Some(forces), Some(chol)) = (&s.internal, self.chol.as_mut()) else {
            return Err(ModelError::LinearAlgebra(
                "a kept tangent needs a prepared finite-strain structure".into(),
            ));
        };
        let w = &mut self.newton;
        let (c_m, c_c) = self.coefficients;
        w.residual(s, forces.as_ref(), self.coefficients, x)?;
        w.tangent(s, forces.as_ref())?;
        w.combine(s, c_m + shift, c_c, &mut self.values);
        chol.factorize(s.dirichlet().matrix(&self.values))?;
        self.tangent_at.copy_from_slice(x);
        self.has_tangent = true;
        self.shift = shift;
        Ok(())
    }

    /// Factorizes (c_m + σ) M + c_c C + K_T at `x` (the last residual's state): σ = 0, or
    /// where that is not positive definite (the contents near an instability, an iterate
    /// beyond the solution, or slack membranes, whose exact tangent is negative across
    /// them) the smallest of 10⁻⁴, 10⁻³, … times trace K_T / trace M that
    /// makes it so — a shift towards the mass that keeps Newton's corrections descent
    /// directions (pseudo-transient continuation).
    fn factorize_tangent(
        &mut self,
        s: &Structure,
        forces: &InternalForces,
        x: &[f64],
    ) -> Result<(), ModelError> {
        let chol = self.chol.as_mut().expect("prepared");
        let w = &mut self.newton;
        let (c_m, c_c) = self.coefficients;
        w.tangent(s, forces)?;
        w.factorizations += 1;
        let ratio = diagonal_sum(s, &w.k_reduced).abs() / diagonal_sum(s, &s.m);
        let mut shift = 0.0;
        let mut attempt = 0;
        loop {
            w.combine(s, c_m + shift, c_c, &mut self.values);
            match chol.factorize(s.dirichlet().matrix(&self.values)) {
                Err(ModelError::Singular { .. }) if attempt < SHIFTS => {
                    shift = ratio * 10f64.powi(attempt as i32 - 4);
                    attempt += 1;
                }
                result => {
                    result?;
                    self.tangent_at.copy_from_slice(x);
                    self.has_tangent = true;
                    self.shift = shift;
                    return Ok(());
                }
            }
        }
    }

    /// Solves a step: on entry `x` holds the right-hand side (load and history terms), on
    /// return the new displacement. Linear: one solve with the factor. Finite strain:
    /// Newton's method on R(u) = c_m M u + c_c C u + f_int(u) − rhs from `guess` (the last
    /// displacement). Each iteration solves with the kept factorization while the previous
    /// one reduced ‖R‖ by [`KEEP_FACTOR_CONTRACTION`], else refactorizes
    /// c_m M + c_c C + K_T(u) (shifted towards the mass where it is not positive definite,
    /// [`Self::factorize_tangent`]), and steps along the correction by the line search of
    /// [`NewtonWork::line_search`]; a kept factorization whose full step is too short is
    /// replaced by a fresh tangent at once. Allocates nothing (but the error).
    pub(crate) fn solve(
        &mut self,
        s: &Structure,
        x: &mut [f64],
        guess: &[f64],
    ) -> Result<(), ModelError> {
        let Some(forces) = &s.internal else {
            self.chol
                .as_mut()
                .expect("an integrator is prepared before it steps")
                .solve_in_place(x);
            return Ok(());
        };
        let forces = forces.as_ref();
        let coefficients = self.coefficients;
        self.newton.target.copy_from_slice(x);
        self.newton.factorizations = 0;
        x.copy_from_slice(guess);
        let (mut r, mut scale) = self.newton.residual(s, forces, coefficients, x)?;
        let mut previous = f64::INFINITY;
        for iteration in 1..=MAX_NEWTON_ITERATIONS {
            if r <= s.newton_tolerance * scale || r == 0.0 {
                self.newton.iterations = iteration - 1;
                return Ok(());
            }
            let mut fresh = r > KEEP_FACTOR_CONTRACTION * previous;
            let (alpha, next, next_scale) = loop {
                if fresh {
                    self.factorize_tangent(s, forces, x)?;
                }
                let w = &mut self.newton;
                w.correction.copy_from_slice(&w.residual);
                self.chol
                    .as_mut()
                    .expect("prepared")
                    .solve_in_place(&mut w.correction);
                match w.line_search(s, forces, coefficients, x, fresh)? {
                    Some(found) => break found,
                    // A kept factorization without descent: a fresh tangent at x.
                    None if !fresh => {
                        w.residual(s, forces, coefficients, x)?;
                        fresh = true;
                    }
                    // Round-off: a fresh correction finds no descent from a residual the
                    // cancelling element forces leave, or is itself within round-off of u.
                    None if r <= STALL * scale
                        || max_abs(&w.correction)
                            <= STALLED_CORRECTION * max_abs(x).max(DISPLACEMENT_FLOOR) =>
                    {
                        w.iterations = iteration;
                        return Ok(());
                    }
                    None => {
                        return Err(ModelError::NotConverged {
                            reached: 0.0,
                            reason: format!(
                                "Newton's method found no descent from a residual of {r:e} \
                                 in iteration {iteration} of one time step"
                            ),
                        })
                    }
                }
            };
            let w = &mut self.newton;
            x.copy_from_slice(&w.trial);
            let size = alpha * max_abs(&w.correction);
            let magnitude = max_abs(x).max(DISPLACEMENT_FLOOR);
            // Converged: a correction within round-off of u; or the full step along an
            // unshifted fresh tangent's correction (Newton's estimate of the error in u)
            // below STALLED_CORRECTION of u that does not halve the residual — the residual
            // is the stresses' round-off (stiff lines at strains of 10⁻⁹ leave corrections
            // of 10⁻¹² mm that wander without end; measured 2026-11-27: 50–99 iterations
            // per step on a 10⁶ stiffness contrast). Not bounded by the residual: its scale
            // there is itself of the round-off's size.
            let stalled = fresh
                && self.shift == 0.0
                && alpha == 1.0
                && next > 0.5 * r
                && size <= STALLED_CORRECTION * magnitude;
            (previous, r, scale) = (r, next, next_scale);
            if size <= ROUND_OFF_CORRECTION * magnitude || stalled {
                w.iterations = iteration;
                return Ok(());
            }
        }
        Err(ModelError::NotConverged {
            reached: 0.0,
            reason: format!(
                "Newton's method left a residual of {r:e} after \
                 {MAX_NEWTON_ITERATIONS} iterations of one time step"
            ),
        })
    }

    /// Newton iterations of the last step (0 for a linear structure).
    pub(crate) fn iterations(&self) -> usize {
        self.newton.iterations
    }

    /// Tangent factorizations of the last step (0 for a linear structure).
    pub(crate) fn factorizations(&self) -> usize {
        self.newton.factorizations
    }
}

/// The sum of the diagonal of a matrix on the structure's reduced pattern.
fn diagonal_sum(s: &Structure, values: &[f64]) -> f64 {
    let p = s.dirichlet().symbolic();
    let a = faer::sparse::SparseColMatRef::new(p.as_ref(), values);
    (0..p.ncols())
        .map(|j| super::cholesky::diagonal(a, j))
        .sum()
}

impl NewtonWork {
    /// The line search along the correction d (in `correction`) from `x`, whose residual is
    /// in `residual`: the step x − α d is the minimizer of the step's energy along the line
    /// when its slope there vanishes, η(α) = d·R(x − α d) / d·R(x) = 0 (η(0) = 1 for any
    /// positive definite matrix d came from). α = 1 is taken when |η| ≤ 0.8 (Crisfield,
    /// Non-linear Finite Element Analysis of Solids and Structures, vol. 1, §9.3), or when
    /// the energy still falls there after a fresh tangent; an overshoot (η < −0.8) shortens
    /// the step by the secant α / (1 − η), an inverted element halves it, up to
    /// [`BACKTRACKS`] times. The trial (in `trial`, its residual in `residual`) is returned
    /// as (α, ‖R‖, scale); None when a kept factorization's full step is too short
    /// (η > 0.8: refactorize).
    fn line_search(
        &mut self,
        s: &Structure,
        forces: &InternalForces,
        coefficients: (f64, f64),
        x: &[f64],
        fresh: bool,
    ) -> Result<Option<(f64, f64, f64)>, ModelError> {
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        let slope = dot(&self.correction, &self.residual);
        let mut alpha = 1.0;
        for _ in 0..=BACKTRACKS {
            for ((t, u), d) in self.trial.iter_mut().zip(x).zip(&self.correction) {
                *t = u - alpha * d;
            }
            let trial = std::mem::take(&mut self.trial);
            let result = self.residual(s, forces, coefficients, &trial);
            self.trial = trial;
            let (r, scale) = match result {
                Ok(found) => found,
                Err(ModelError::Inverted { .. }) => {
                    alpha *= 0.5;
                    continue;
                }
                Err(e) => return Err(e),
            };
            let eta = dot(&self.correction, &self.residual) / slope;
            if eta.abs() <= 0.8 || (eta > 0.0 && (fresh || alpha < 1.0)) {
                return Ok(Some((alpha, r, scale)));
            }
            if eta > 0.0 {
                return Ok(None);
            }
            alpha *= (1.0 / (1.0 - eta)).max(0.1);
        }
        Ok(None)
    }

    /// R(u) = (c_m M + c_c C) u + f_int(u) − rhs into `residual`; returns ‖R‖ and the force
    /// scale (the largest norm of the terms that balance).
    fn residual(
        &mut self,
        s: &Structure,
        forces: &InternalForces,
        (c_m, c_c): (f64, f64),
        x: &[f64],
    ) -> Result<(f64, f64), ModelError> {
        let bc = s.dirichlet();
        bc.expand(x, &mut self.u_full);
        forces(&self.u_full, &mut self.f_full, None)?;
        bc.reduce(&self.f_full, &mut self.residual);
        self.inertia.fill(0.0);
        s.product.mul_add(&s.m, x, c_m, &mut self.inertia);
        s.product.mul_add(&s.c, x, c_c, &mut self.inertia);
        let scale = [&self.target, &self.residual, &self.inertia]
            .map(|v| norm_of(v))
            .into_iter()
            .fold(0.0, f64::max);
        for ((r, i), t) in self
            .residual
            .iter_mut()
            .zip(&self.inertia)
            .zip(&self.target)
        {
            *r += i - t;
        }
        Ok((norm_of(&self.residual), scale))
    }

    /// K_T(u) at the last residual's u, reduced, into `k_reduced`.
    fn tangent(&mut self, s: &Structure, forces: &InternalForces) -> Result<(), ModelError> {
        forces(&self.u_full, &mut self.f_full, Some(&mut self.k_full))?;
        s.dirichlet()
            .combine(&[(1.0, &self.k_full)], &mut self.k_reduced);
        Ok(())
    }

    /// c_m M + c_c C + K_T (the last [`tangent`](Self::tangent)) into `values`.
    fn combine(&self, s: &Structure, c_m: f64, c_c: f64, values: &mut [f64]) {
        for (((v, m), c), k) in values.iter_mut().zip(&s.m).zip(&s.c).zip(&self.k_reduced) {
            *v = c_m * m + c_c * c + k;
        }
    }
}
