//! The line elements at finite strain (issue 26): diaphragm, abdominal wall and pelvic floor
//! as total Lagrangian membranes in the plane (a sheet of unit depth seen edge-on), for the
//! 2-node (`line2`) and 3-node (`line3`) lines alike.
//!
//! **Kinematics.** A reference line X(ξ) = Σ N_a(ξ) X_a, ξ ∈ [−1, 1], with arc length dS =
//! |X'(ξ)| dξ, deforms to x = Σ N_a (X_a + u_a). The stretch is λ = |dx/dS| and the unit
//! tangent t = (dx/dS)/λ; rigid motions leave λ = 1 whatever the rotation.
//!
//! **Law.** Muscle sheets carry tension, not compression: their passive force is zero below
//! their slack length (Zajac, Crit Rev Biomed Eng 17 (1989) 359–411), and a sheet without
//! bending stiffness that were made to carry compression would wrinkle at the scale of its
//! elements: pressed into a soft solid of modulus E_s it is unstable for every wavelength
//! shorter than 2π N / E_s (measured: a passive diaphragm that carried the press as an arch
//! wrinkled element by element at a fifth of the default press of the abdomen, and the
//! diaphragm compressed by a fraction of a kilopascal at the end of a press made the
//! tangent indefinite on a graded mesh). The law is therefore slack in compression — the
//! relaxed energy of a membrane, whose wrinkles it smears out (tension-field theory;
//! Pipkin, IMA J Appl Math 36 (1986) 85–99) — made smooth, and in tension one of two
//! ([`Law`]): with x = ln λ,
//!
//! P(λ) = E s(x) / λ,  s(x) = x for x ≥ 0,  s(x) = −δ (1 − e^{x/δ}) for x < 0
//!
//! (Hencky's, logarithmic strain, the default), or in tension (λ ≥ 1) the incompressible
//! neo-Hookean sheet in plane strain (the stretches λ, 1, 1/λ; energy (μ/2)(I₁ − 3) with
//! μ = E/4, so that E is the slope at rest as in Hencky's law):
//!
//! P(λ) = (E/4) (λ − λ⁻³),  dP/dλ = (E/4) (1 + 3 λ⁻⁴).
//!
//! In plane strain I₁ = I₂, so this is also the Mooney–Rivlin law (c₁ + c₂ = E/8) with which
//! Noakes et al. (J Biomech 41 (2008) 3060–3065) loaded the levator ani by 4 kPa. Both are E ε
//! at small strain (s'(0) = 1 from both sides: at rest the tangent is the linear element's)
//! with a continuous tangent; the compressive stress saturates at E δ, with tangent
//! dP/dλ = E (s'(x) − s(x)) / λ². Hencky's nominal stress peaks at E/e at λ = e, where a
//! pressed sheet necks; the neo-Hookean one rises without bound (its tangent never below
//! E/4). δ = [`SLACK`] = 10⁻³: the exact kink made Newton's method cycle, a tenth of it
//! failed on the mixed element, ten times it let the slack diaphragm carry enough
//! compression to make the tangent indefinite (BENCHMARKS.md, "The membranes' slack
//! smoothing").
//!
//! **Active tension.** A muscle sheet may add a tension T (N per mm of depth, its
//! contraction) to the passive force A P(λ), the same at every stretch: the line then pulls
//! on its nodes along its current tangent, and a curved one presses on what lies on its
//! concave side with T times its curvature (Laplace's law).
//!
//! **Transverse curvature.** The slice sees a sheet edge-on; a real muscle sheet is also
//! curved across the slice (the diaphragm's dome from side to side, the abdominal wall
//! round the waist, the levator bowl), with curvature κ₂ there, positive where it is
//! concave towards the line's left (the cavity's side: the abdomen's lines run
//! counter-clockwise around it). Across the slice it carries what a strip of a surface of
//! that curvature carries (Laplace's law of a doubly curved membrane, p = N₁ κ₁ + N₂ κ₂):
//!
//! - its **active tension** T, contracting both ways: a follower pressure q = T κ₂ on its
//!   current left side: the internal force gains f_a += q ∫ N_a J x' dξ with J = [[0, 1],
//!   [−1, 0]] (J x' the right normal times |x'|, so that the pressure on the mesh points to
//!   the left); the tangent is the symmetric part of the derivative, q D_ab J with D_ab =
//!   ½ ∫ (N_a N_b' − N_b N_a') dξ — the antisymmetric rest sums to end terms of the chain,
//!   which cancel between neighbouring lines of the same q and vanish where the chain's ends
//!   are held (the pressure on a fixed-ended membrane is conservative); where q jumps at a
//!   free junction (a contracting diaphragm meeting a free, passive wall) the dropped term
//!   slows Newton's convergence there, it does not change the solution;
//! - its **passive transverse stretch** λ₂ = 1 − κ₂ u·n₀ (n₀ the reference left normal: a
//!   strip of a surface moved by w towards its centre of curvature shortens by κ₂ w),
//!   carried by the same law as along the line, with energy A ∫ W(λ₂) dS: f_a −= κ₂ ∫ A
//!   P(λ₂) N_a n₀ dS, K_ab += κ₂² ∫ A P'(λ₂) N_a N_b n₀ n₀ᵀ dS — an elastic foundation of
//!   stiffness E A κ₂² at rest, slack where the sheet is pushed towards its centre, so that
//!   a floor or wall bulging out of the cavity is held by its hoop tension as a bowl or a
//!   cylinder is.
//!
//! **Forces and tangent** (A the reference cross-section per mm of depth, N = A P + T the
//! force the line carries):
//!
//! f_a = ∫ N t N_a,S dS,
//! K_ab = ∫ N_a,S N_b,S [A P'(λ) t tᵀ + (N/λ)(I − t tᵀ)] dS,
//!
//! the material part along the line and the geometric part across it: a membrane in tension
//! resists transverse motion (a string under pressure takes a circular arc with tension
//! p R), a straight one at rest does not (at λ = 1 without T the tangent is the linear
//! element's). A slack line's geometric part is negative, N/λ ≥ −E A δ/λ, and the tangent
//! keeps it: it is the force's exact derivative, so Newton's method converges quadratically
//! near slack lines too. Where that makes a system matrix indefinite, the time step's
//! Newton iteration shifts it towards the mass and the static one cuts its increment back.
//! The tension-field tangent (N replaced by max(N, 0), never indefinite) was used before;
//! the exact one steps the default press faster, the outputs the same to 10⁻⁹ of their
//! peaks (BENCHMARKS.md, "The membranes' exact tangent").

use nalgebra::{Matrix2, SMatrix, SVector, Vector2};

use super::quadrature::Rule;
use super::total_lagrangian::Inverted;

/// The compressive log strain δ at which a slack line's stress saturates (see the module
/// documentation).
pub const SLACK: f64 = 1e-3;

/// s(x) and s'(x) of the slack-smoothed Hencky law (see the module documentation).
fn slack(x: f64) -> (f64, f64) {
    if x >= 0.0 {
        return (x, 1.0);
    }
    let e = (x / SLACK).exp();
    (-SLACK * (1.0 - e), e)
}

/// A sheet's law in tension (see the module documentation); in compression both are slack.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Law {
    /// Hencky's: P = E ln λ / λ, peaking at E/e at λ = e.
    #[default]
    Hencky,
    /// The incompressible neo-Hookean sheet in plane strain: P = (E/4)(λ − λ⁻³).
    NeoHookean,
}

impl Law {
    /// Nominal stress P(λ) (MPa) of Young's modulus `young` at stretch `stretch`.
    pub fn stress(self, young: f64, stretch: f64) -> f64 {
        match self {
            Law::NeoHookean if stretch >= 1.0 => 0.25 * young * (stretch - stretch.powi(-3)),
            _ => young * slack(stretch.ln()).0 / stretch,
        }
    }

    /// dP/dλ at stretch `stretch`.
    pub fn tangent(self, young: f64, stretch: f64) -> f64 {
        match self {
            Law::NeoHookean if stretch >= 1.0 => 0.25 * young * (1.0 + 3.0 * stretch.powi(-4)),
            _ => {
                let (s, ds) = slack(stretch.ln());
                young * (ds - s) / (stretch * stretch)
            }
        }
    }
}

/// What a line is made of: its law, Young's modulus `young` (MPa), reference cross-section
/// `area` (mm² per mm of depth), active tension `tension` (N per mm of depth) and transverse
/// curvature (1/mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Section {
    /// The law in tension.
    pub law: Law,
    /// Young's modulus E (MPa).
    pub young: f64,
    /// Reference cross-section A (mm² per mm of depth).
    pub area: f64,
    /// Active tension T (N per mm of depth).
    pub tension: f64,
    /// Curvature κ₂ across the slice (1/mm), positive where the sheet is concave towards the
    /// left of the line's direction: the active tension presses there with T κ₂.
    pub transverse_curvature: f64,
}

impl Section {
    /// The force the line carries at stretch λ, N = A P(λ) + T (N per mm of depth).
    pub fn force(&self, stretch: f64) -> f64 {
        self.area * self.law.stress(self.young, stretch) + self.tension
    }
}

/// A line element: its reference nodes, its shape functions and their derivatives dN/dξ,
/// and its quadrature rule.
pub struct Line<'a, const N: usize, const Q: usize> {
    /// The reference positions of the nodes (mm).
    pub nodes: &'a [[f64; 2]; N],
    /// The shape functions N_a at ξ.
    pub shapes: fn(f64) -> [f64; N],
    /// The shape-function derivatives dN_a/dξ at ξ.
    pub derivatives: fn(f64) -> [f64; N],
    /// The Gauss rule on ξ ∈ [−1, 1].
    pub rule: &'a Rule<Q>,
}

/// What a quadrature point of a deformed line gives: dN_a/dS, the weight times dS/dξ, the
/// stretch and the unit tangent.
struct Point<const N: usize> {
    gradients: [f64; N],
    weight: f64,
    stretch: f64,
    tangent: Vector2<f64>,
}

impl<const N: usize, const Q: usize> Line<'_, N, Q> {
    /// The quadrature points for node-major displacements `u` (2 dofs per node); a point
    /// whose stretch is not positive (the line folded onto itself) is an error.
    fn points<const D: usize>(&self, u: &SVector<f64, D>) -> Result<[Point<N>; Q], Inverted> {
        debug_assert_eq!(D, 2 * N);
        let mut out = [(); Q].map(|_| Point {
            gradients: [0.0; N],
            weight: 0.0,
            stretch: 1.0,
            tangent: Vector2::zeros(),
        });
        for (point, &(xi, w)) in out.iter_mut().zip(self.rule) {
            let dn = (self.derivatives)(xi);
            let (mut reference, mut current) = (Vector2::zeros(), Vector2::zeros());
            for (a, d) in dn.iter().enumerate() {
                let x = Vector2::from(self.nodes[a]);
                reference += x * *d;
                current += (x + Vector2::new(u[2 * a], u[2 * a + 1])) * *d;
            }
            let jacobian = reference.norm();
            let stretch = Inverted::check(current.norm() / jacobian)?;
            *point = Point {
                gradients: dn.map(|d| d / jacobian),
                weight: w * jacobian,
                stretch,
                tangent: current / current.norm(),
            };
        }
        Ok(out)
    }

    /// Adds the internal force of the line of `section` to `force` and, when asked, its
    /// exact tangent to `tangent` (see the module documentation).
    pub fn internal<const D: usize>(
        &self,
        u: &SVector<f64, D>,
        section: Section,
        force: &mut SVector<f64, D>,
        mut tangent: Option<&mut SMatrix<f64, D, D>>,
    ) -> Result<(), Inverted> {
        for p in self.points(u)? {
            let carried = section.force(p.stretch);
            for (a, ga) in p.gradients.iter().enumerate() {
                for i in 0..2 {
                    force[2 * a + i] += p.weight * carried * p.tangent[i] * ga;
                }
            }
            let Some(k) = tangent.as_deref_mut() else {
                continue;
            };
            let tt = p.tangent * p.tangent.transpose();
            let block = tt * (section.area * section.law.tangent(section.young, p.stretch))
                + (Matrix2::identity() - tt) * (carried / p.stretch);
            for (a, ga) in p.gradients.iter().enumerate() {
                for (b, gb) in p.gradients.iter().enumerate() {
                    let mut view = k.fixed_view_mut::<2, 2>(2 * a, 2 * b);
                    view += block * (p.weight * ga * gb);
                }
            }
        }
        if section.transverse_curvature != 0.0 {
            self.transverse(u, section, force, tangent)?;
        }
        Ok(())
    }

    /// Adds the internal force of the sheet's curvature across the slice and, when asked,
    /// its tangent (see the module documentation): the active tension's follower pressure
    /// T κ₂ on the line's left, and the passive transverse stretch λ₂ = 1 − κ₂ u·n₀.
    fn transverse<const D: usize>(
        &self,
        u: &SVector<f64, D>,
        section: Section,
        force: &mut SVector<f64, D>,
        mut tangent: Option<&mut SMatrix<f64, D, D>>,
    ) -> Result<(), Inverted> {
        let kappa = section.transverse_curvature;
        let q = section.tension * kappa;
        let turn = Matrix2::new(0.0, 1.0, -1.0, 0.0);
        for &(xi, w) in self.rule {
            let (n, dn) = ((self.shapes)(xi), (self.derivatives)(xi));
            let (mut reference, mut rate, mut moved) =
                (Vector2::zeros(), Vector2::zeros(), Vector2::zeros());
            for a in 0..N {
                let ua = Vector2::new(u[2 * a], u[2 * a + 1]);
                reference += Vector2::from(self.nodes[a]) * dn[a];
                rate += (Vector2::from(self.nodes[a]) + ua) * dn[a];
                moved += ua * n[a];
            }
            // The reference normal to the left, n₀, times dS/dξ.
            let left = -(turn * reference);
            let jacobian = reference.norm();
            let normal = left / jacobian;
            let stretch = Inverted::check(1.0 - kappa * moved.dot(&normal))?;
            let passive = section.area * section.law.stress(section.young, stretch) * kappa;
            let push = turn * rate * q - left * passive;
            for a in 0..N {
                for i in 0..2 {
                    force[2 * a + i] += w * n[a] * push[i];
                }
            }
            let Some(k) = tangent.as_deref_mut() else {
                continue;
            };
            let foundation = normal
                * normal.transpose()
                * (section.area
                    * section.law.tangent(section.young, stretch)
                    * kappa
                    * kappa
                    * jacobian);
            for a in 0..N {
                for b in 0..N {
                    let d = 0.5 * (n[a] * dn[b] - n[b] * dn[a]);
                    let mut view = k.fixed_view_mut::<2, 2>(2 * a, 2 * b);
                    view += (turn * (q * d) + foundation * (n[a] * n[b])) * w;
                }
            }
        }
        Ok(())
    }

    /// The mean stress over the reference length, (1/L) ∫ N(λ) / A dS (MPa, tension > 0):
    /// the force per unit reference section the line carries on average, active tension
    /// included. At small strain without T it is E times the mean strain, the linear
    /// elements' axial stress.
    pub fn mean_stress<const D: usize>(
        &self,
        u: &SVector<f64, D>,
        section: Section,
    ) -> Result<f64, Inverted> {
        let (mut integral, mut length) = (0.0, 0.0);
        for p in self.points(u)? {
            integral += section.force(p.stretch) * p.weight;
            length += p.weight;
        }
        Ok(integral / (length * section.area))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::element::{line2, line3};

    const E: f64 = 0.2;
    const AREA: f64 = 4.0;
    const PASSIVE: Section = Section {
        law: Law::Hencky,
        young: E,
        area: AREA,
        tension: 0.0,
        transverse_curvature: 0.0,
    };

    /// A 3-node line along 30° from (1, 2), length 3, and its 2-node chord.
    fn line() -> [[f64; 2]; 3] {
        let c = [30f64.to_radians().cos(), 30f64.to_radians().sin()];
        [0.0, 1.5, 3.0].map(|s| [1.0 + s * c[0], 2.0 + s * c[1]])
    }

    fn chord() -> [[f64; 2]; 2] {
        let p = line();
        [p[0], p[2]]
    }

    /// A displacement with stretch (1.1 to 1.4 along the line), bending and rotation.
    fn some_u<const D: usize>() -> SVector<f64, D> {
        let n = D / 2;
        let p = line();
        let (a, b) = (p[0], p[2]);
        SVector::from_fn(|r, _| {
            let s = (r / 2) as f64 / (n - 1) as f64;
            let x = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1])];
            let shear = 0.3 * ((r * 7919 + 13) % 97) as f64 / 97.0;
            (0.25 + 0.05 * s) * (x[r % 2] - a[r % 2]) + shear
        })
    }

    fn forces_of<const N: usize, const Q: usize, const D: usize>(
        line: &Line<'_, N, Q>,
        u: &SVector<f64, D>,
        section: Section,
    ) -> (SVector<f64, D>, SMatrix<f64, D, D>) {
        let (mut f, mut k) = (SVector::zeros(), SMatrix::zeros());
        line.internal(u, section, &mut f, Some(&mut k)).unwrap();
        (f, k)
    }

    fn forces<const N: usize, const Q: usize, const D: usize>(
        line: &Line<'_, N, Q>,
        u: &SVector<f64, D>,
    ) -> (SVector<f64, D>, SMatrix<f64, D, D>) {
        forces_of(line, u, PASSIVE)
    }

    /// The tangent against central differences of the force (to 1e-6 of its largest entry),
    /// passive, with an active tension and with a passive transverse curvature, in either law.
    fn check_tangent<const N: usize, const Q: usize, const D: usize>(line: &Line<'_, N, Q>) {
        let u = some_u::<D>();
        // Passive, active, and passive curved across the slice (its foundation conservative).
        let cases = [(0.0, 0.0), (0.3, 0.0), (0.0, 0.05)];
        for ((tension, transverse_curvature), law) in cases
            .into_iter()
            .flat_map(|c| [(c, Law::Hencky), (c, Law::NeoHookean)])
        {
            let section = Section {
                law,
                tension,
                transverse_curvature,
                ..PASSIVE
            };
            let (_, k) = forces_of(line, &u, section);
            let h = 1e-6;
            for c in 0..D {
                let (mut up, mut um) = (u, u);
                up[c] += h;
                um[c] -= h;
                let column =
                    (forces_of(line, &up, section).0 - forces_of(line, &um, section).0) / (2.0 * h);
                let gap = (column - k.column(c)).amax() / k.amax();
                assert!(gap < 1e-6, "{law:?}, T = {tension}, column {c}: {gap:e}");
            }
            assert!((k - k.transpose()).amax() < 1e-14 * k.amax(), "symmetric");
        }
    }

    /// With a transverse curvature the tangent is the symmetric part of the force's
    /// derivative (to 1e-6 of its largest entry) and, on a chain of two lines whose ends are
    /// held, the derivative itself at the free nodes.
    #[test]
    fn a_transverse_pressure_has_the_symmetric_tangent_exact_on_a_held_chain() {
        let p = line();
        let section = Section {
            tension: 0.3,
            transverse_curvature: 0.05,
            ..PASSIVE
        };
        let element = line3::membrane(&p);
        let u = some_u::<6>();
        let (_, k) = forces_of(&element, &u, section);
        let h = 1e-6;
        let fd = SMatrix::<f64, 6, 6>::from_fn(|r, c| {
            let (mut up, mut um) = (u, u);
            up[c] += h;
            um[c] -= h;
            (forces_of(&element, &up, section).0[r] - forces_of(&element, &um, section).0[r])
                / (2.0 * h)
        });
        let symmetric = (fd + fd.transpose()) / 2.0;
        assert!((symmetric - k).amax() < 1e-6 * k.amax());
        assert!(
            (fd - k).amax() > 1e-3 * k.amax(),
            "one line's derivative is not symmetric"
        );
        // Two lines end to end, nodes 0..5: the second the first turned by 40° about node 2.
        let r = nalgebra::Rotation2::new(40f64.to_radians());
        let second = [0, 1, 2].map(|i| {
            let d = r * (Vector2::from(p[i]) - Vector2::from(p[0]));
            [p[2][0] + d[0], p[2][1] + d[1]]
        });
        let chain = |u: &SVector<f64, 10>| {
            let (mut f, mut k) = (SVector::<f64, 10>::zeros(), SMatrix::<f64, 10, 10>::zeros());
            for (nodes, first) in [(&p, 0), (&second, 4)] {
                let ue = SVector::<f64, 6>::from_fn(|i, _| u[first + i]);
                let (fe, ke) = forces_of(&line3::membrane(nodes), &ue, section);
                for i in 0..6 {
                    f[first + i] += fe[i];
                    for j in 0..6 {
                        k[(first + i, first + j)] += ke[(i, j)];
                    }
                }
            }
            (f, k)
        };
        let u = SVector::<f64, 10>::from_fn(|i, _| {
            if (2..8).contains(&i) {
                0.4 * ((i * 37 % 11) as f64 / 11.0 - 0.5)
            } else {
                0.0
            }
        });
        let (_, k) = chain(&u);
        for c in 2..8 {
            let (mut up, mut um) = (u, u);
            up[c] += h;
            um[c] -= h;
            let column = (chain(&up).0 - chain(&um).0) / (2.0 * h);
            for r in 2..8 {
                let gap = (column[r] - k[(r, c)]).abs() / k.amax();
                assert!(gap < 1e-6, "({r}, {c}): {gap:e}");
            }
        }
    }

    /// A straight line of length L with active tension T and transverse curvature κ₂ at rest
    /// pushes its left side with the resultant T κ₂ L, shared L/6, 2L/3, L/6 by its nodes
    /// (the consistent load of a uniform pressure on a 3-node line), besides pulling its ends
    /// together with T.
    #[test]
    fn a_transversely_curved_sheet_presses_its_left_side_with_t_kappa() {
        let p = line();
        let (tension, kappa, length) = (0.7, 1.0 / 150.0, 3.0);
        let section = Section {
            tension,
            transverse_curvature: kappa,
            ..PASSIVE
        };
        let (f, _) = forces_of(&line3::membrane(&p), &line3::Dofs::zeros(), section);
        let t = (Vector2::from(p[2]) - Vector2::from(p[0])).normalize();
        let left = Vector2::new(-t[1], t[0]);
        let q = tension * kappa;
        let on_mesh = |a: usize| -Vector2::new(f[2 * a], f[2 * a + 1]);
        for (a, share, pull) in [
            (0, 1.0 / 6.0, 1.0),
            (1, 2.0 / 3.0, 0.0),
            (2, 1.0 / 6.0, -1.0),
        ] {
            let expected = left * (q * length * share) + t * (tension * pull);
            assert!((on_mesh(a) - expected).norm() < 1e-14, "node {a}");
        }
        let (f2, _) = forces_of(&line2::membrane(&chord()), &line2::Dofs::zeros(), section);
        let on_chord = -Vector2::new(f2[0] + f2[2], f2[1] + f2[3]);
        assert!((on_chord - left * (q * length)).norm() < 1e-14);
    }

    /// A straight passive line of length L moved by w along its normal: away from its
    /// centre of transverse curvature (to its right) it is held by the foundation E A κ₂² w L
    /// (to first order: w of 1e-4 κ₂⁻¹), towards it it goes slack (E A δ κ₂ L / λ₂).
    #[test]
    fn a_sheet_curved_across_resists_bulging_out_and_goes_slack_bulging_in() {
        let p = chord();
        let (kappa, length) = (1.0 / 60.0, 3.0);
        let section = Section {
            transverse_curvature: kappa,
            ..PASSIVE
        };
        let t = (Vector2::from(p[1]) - Vector2::from(p[0])).normalize();
        let left = Vector2::new(-t[1], t[0]);
        let resultant = |w: f64| {
            let u = line2::Dofs::from_fn(|r, _| -w * left[r % 2]);
            let (f, _) = forces_of(&line2::membrane(&p), &u, section);
            Vector2::new(f[0] + f[2], f[1] + f[3])
        };
        let w = 1e-4 / kappa;
        let out = resultant(w);
        let foundation = E * AREA * kappa * kappa * w * length;
        assert!(
            (out + left * foundation).norm() < 1e-3 * foundation,
            "{out}"
        );
        // Moved in by 0.05/κ₂: λ₂ = 0.95, far beyond δ, where the nominal stress is −E δ / λ₂.
        let inward = resultant(-0.05 / kappa);
        let slack = E * AREA * SLACK / 0.95 * kappa * length;
        assert!((inward.norm() / slack - 1.0).abs() < 1e-9, "{inward}");
        assert!(
            inward.dot(&left) > 0.0,
            "a slack sheet still pushes a little, outwards"
        );
    }

    #[test]
    fn the_tangents_are_the_derivatives_of_the_forces() {
        check_tangent::<2, 1, 4>(&line2::membrane(&chord()));
        check_tangent::<3, 3, 6>(&line3::membrane(&line()));
    }

    /// An active tension on a straight line at rest pulls its ends together along the line
    /// with T and leaves its middle alone.
    #[test]
    fn an_active_tension_pulls_the_ends_of_a_straight_line() {
        let p = line();
        let section = Section {
            tension: 0.7,
            ..PASSIVE
        };
        let (f, _) = forces_of(&line3::membrane(&p), &line3::Dofs::zeros(), section);
        let t = (Vector2::from(p[2]) - Vector2::from(p[0])).normalize();
        let end = |a: usize| Vector2::new(f[2 * a], f[2 * a + 1]);
        assert!((end(0) + t * 0.7).norm() < 1e-14 && (end(2) - t * 0.7).norm() < 1e-14);
        assert!(end(1).norm() < 1e-14);
        let mean = line3::membrane(&p)
            .mean_stress(&line3::Dofs::zeros(), section)
            .unwrap();
        assert!((mean - 0.7 / AREA).abs() < 1e-15);
    }

    /// At rest the tangent is the small-strain element's stiffness, and a small displacement
    /// gives its force to second order.
    #[test]
    fn at_small_strain_the_lines_are_the_linear_elements() {
        let (p3, p2) = (line(), chord());
        let (k3, k2) = (
            line3::stiffness(&p3, PASSIVE),
            line2::stiffness(&p2, E, AREA),
        );
        let at_rest3 = forces(&line3::membrane(&p3), &line3::Dofs::zeros()).1;
        let at_rest2 = forces(&line2::membrane(&p2), &line2::Dofs::zeros()).1;
        assert!((at_rest3 - k3).amax() < 1e-14 * k3.amax());
        assert!((at_rest2 - k2).amax() < 1e-14 * k2.amax());
        let gap = |scale: f64| {
            let u = some_u::<6>() * scale;
            let f = forces(&line3::membrane(&p3), &u).0;
            (f - k3 * u).amax() / (k3 * u).amax()
        };
        let (coarse, fine) = (gap(1e-3), gap(1e-4));
        assert!(
            coarse < 1e-2 && (fine / coarse - 0.1).abs() < 0.01,
            "{coarse:e} {fine:e}"
        );
        let u = some_u::<6>() * 1e-7;
        let mean = line3::membrane(&p3).mean_stress(&u, PASSIVE).unwrap();
        let linear = line3::axial_stress(&p3, E, &u);
        assert!(
            (mean - linear).abs() < 1e-6 * linear.abs(),
            "{mean:e} {linear:e}"
        );
    }

    /// A prestressed line turned rigidly keeps its stress; its nodal forces turn with it.
    #[test]
    fn a_rigid_rotation_of_a_prestressed_line_leaves_its_force_unchanged() {
        let p = line();
        let stretched = line3::Dofs::from_fn(|r, _| 0.2 * (p[r / 2][r % 2] - p[0][r % 2]));
        let element = line3::membrane(&p);
        let (f0, _) = forces(&element, &stretched);
        let s0 = element.mean_stress(&stretched, PASSIVE).unwrap();
        assert!(
            (s0 - Law::Hencky.stress(E, 1.2)).abs() < 1e-14,
            "uniform stretch 1.2: {s0}"
        );
        for angle in [0.3, 1.7, -2.9] {
            let r = nalgebra::Rotation2::new(angle).into_inner();
            let turned = line3::Dofs::from_fn(|row, _| {
                let a = row / 2;
                let x = Vector2::from(p[a]) + Vector2::new(stretched[2 * a], stretched[2 * a + 1]);
                (r * x)[row % 2] - p[a][row % 2]
            });
            let (f, _) = forces(&element, &turned);
            let s = element.mean_stress(&turned, PASSIVE).unwrap();
            assert!((s - s0).abs() < 1e-14 * s0, "{angle}: {s} vs {s0}");
            for a in 0..3 {
                let expected = r * Vector2::new(f0[2 * a], f0[2 * a + 1]);
                let got = Vector2::new(f[2 * a], f[2 * a + 1]);
                assert!(
                    (got - expected).norm() < 1e-13 * f0.amax(),
                    "{angle}: node {a}"
                );
            }
        }
    }

    /// A compressed (slack) line: the tangent is the force's derivative, negative geometric
    /// part included, so it is indefinite across the line.
    #[test]
    fn a_slack_line_has_the_consistent_tangent() {
        let p = line();
        let element = line3::membrane(&p);
        // Shortened to 0.9 of its length and bent.
        let u = line3::Dofs::from_fn(|r, _| {
            let a = r / 2;
            -0.1 * (p[a][r % 2] - p[0][r % 2]) + if r == 3 { 0.2 } else { 0.0 }
        });
        let (f, k) = forces(&element, &u);
        assert!(f.iter().all(|x| x.is_finite()));
        let eigen = k.symmetric_eigenvalues();
        assert!(eigen.min() < -1e-6 * eigen.max(), "{eigen}");
        let h = 1e-7;
        for c in 0..6 {
            let direction = line3::Dofs::from_fn(|r, _| if r == c { 1.0 } else { 0.0 });
            let fd = (forces(&element, &(u + direction * h)).0
                - forces(&element, &(u - direction * h)).0)
                / (2.0 * h);
            let gap = (fd - k * direction).amax() / k.amax();
            assert!(gap < 1e-6, "column {c}: {gap:e}");
        }
    }

    #[test]
    fn a_line_folded_onto_itself_is_refused() {
        let p = chord();
        let folded = line2::Dofs::new(0.0, 0.0, p[0][0] - p[1][0], p[0][1] - p[1][1]);
        let mut f = line2::Dofs::zeros();
        assert!(line2::membrane(&p)
            .internal(&folded, PASSIVE, &mut f, None)
            .is_err());
    }

    #[test]
    fn the_law_is_hencky_in_tension_slack_in_compression_and_smooth() {
        let e = 0.3;
        assert_eq!(
            (Law::Hencky.stress(e, 1.0), Law::Hencky.tangent(e, 1.0)),
            (0.0, e)
        );
        for stretch in [1.0 - 3.0 * SLACK, 1.0 - 1e-5, 1.0 + 1e-5, 1.3, 2.5] {
            let h = 1e-8;
            let fd = (Law::Hencky.stress(e, stretch + h) - Law::Hencky.stress(e, stretch - h))
                / (2.0 * h);
            let tangent = Law::Hencky.tangent(e, stretch);
            assert!((fd - tangent).abs() < 1e-6 * e, "{stretch}: {fd} {tangent}");
        }
        for stretch in [1.3, 2.5] {
            // Kirchhoff stress τ = λ P = E ln λ in tension.
            assert!((stretch * Law::Hencky.stress(e, stretch) - e * stretch.ln()).abs() < 1e-15);
        }
        // Compressed well beyond δ the stress is −E δ / λ: what is left of the stiffness is
        // E δ / λ², from the 1/λ of a nominal stress.
        for stretch in [0.9, 0.5] {
            let p = Law::Hencky.stress(e, stretch);
            assert!(
                (p * stretch + e * SLACK).abs() < 1e-12 * e,
                "{stretch}: {p}"
            );
            let rest = e * SLACK / (stretch * stretch);
            assert!(
                (Law::Hencky.tangent(e, stretch) - rest).abs() < 1e-12 * e,
                "{stretch}"
            );
        }
        // At small strain, E ε on both sides to first order.
        for eps in [-1e-6, 1e-6] {
            let p = Law::Hencky.stress(e, 1.0 + eps);
            assert!((p / (e * eps) - 1.0).abs() < 2e-3, "{eps}: {p}");
        }
    }

    /// The neo-Hookean law is the derivative of the plane-strain incompressible energy
    /// (μ/2)(λ² + 1 + λ⁻² − 3) with μ = E/4 (central differences, to 1e-7 of E), Hencky's
    /// at small strain and in compression, and keeps rising where Hencky's peaks (E/e at e).
    #[test]
    fn the_neo_hookean_law_is_its_energy_s_derivative_and_does_not_peak() {
        let e = 0.3;
        let law = Law::NeoHookean;
        let energy = |l: f64| 0.5 * (e / 4.0) * (l * l + 1.0 + 1.0 / (l * l) - 3.0);
        for stretch in [1.0 + 1e-5, 1.3, std::f64::consts::E, 4.0] {
            let h = 1e-6;
            let fd = (energy(stretch + h) - energy(stretch - h)) / (2.0 * h);
            let p = law.stress(e, stretch);
            assert!((fd - p).abs() < 1e-7 * e, "{stretch}: {fd} {p}");
            let fd = (law.stress(e, stretch + h) - law.stress(e, stretch - h)) / (2.0 * h);
            assert!((fd - law.tangent(e, stretch)).abs() < 1e-7 * e, "{stretch}");
            assert!(law.tangent(e, stretch) > 0.25 * e, "{stretch}");
        }
        for stretch in [0.5, 0.9, 1.0 - 3.0 * SLACK, 1.0] {
            assert_eq!(law.stress(e, stretch), Law::Hencky.stress(e, stretch));
            assert_eq!(law.tangent(e, stretch), Law::Hencky.tangent(e, stretch));
        }
        assert_eq!(law.tangent(e, 1.0), e);
        // Past Hencky's peak: at λ = 4 Hencky's stress has fallen to 0.94 of its peak (ln 4 · e
        // / 4), the neo-Hookean one is 0.996 E, 2.7 times that peak.
        let peak = e / std::f64::consts::E;
        assert!(Law::Hencky.stress(e, 4.0) < 0.95 * peak);
        assert!(law.stress(e, 4.0) > 2.7 * peak);
    }
}
