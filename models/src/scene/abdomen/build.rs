//! The abdomen's full-order system, as the build makes it from the parameter values: the
//! configuration resolved to an outline, the mesh, the per-tissue properties, the
//! assembled stiffness, mass and damping, the supports, the equation of motion on the
//! free dofs (with the finite-strain body at finite kinematics), the load pattern of the
//! pressing force and the output plan. The integrator and a reduced order sit on top of
//! it (`simulation`).

use std::sync::Arc;

use super::config::PelvisConfig;
use super::discretization::{Choice, Discretization, FieldView, Recovery};
use super::mesher;
use super::outputs::{Field, OutputPlan};
use super::parameters::{self, damping_properties, properties, subdivisions, supports, PressLoad};
use super::variables::{
    CONFIGURATION, COSTAL_MARGIN, ELEMENT, FORMULATION, GRADING, INTEGRATOR, KINEMATICS,
    PRESS_LOAD, TARGET_TRIANGLES, WALL_SUPPORT,
};
use crate::assembly::plane::PlaneProperties;
use crate::assembly::quadratic_plane::{PlaneBody, SharedTension};
use crate::assembly::Dirichlet;
use crate::linalg::Factorization;
use crate::scene::{SceneError, Values};
use crate::solve::{Damping, IntegratorKind, Structure};

/// The full-order abdomen for one set of parameter values.
pub struct FullOrder {
    pub disc: Discretization,
    pub props: PlaneProperties,
    /// The stiffness at rest on all dofs (the assembler's pattern).
    k: Vec<f64>,
    /// The equation of motion on the free dofs.
    pub structure: Structure,
    /// Load vector (free dofs) of a unit pressing force ([`press_pattern`]).
    unit_load: Vec<f64>,
    /// The pressing force per unit active tension of the diaphragm at rest, Θ₀ (N/mm per
    /// N/mm), and the active tension the finite-strain forces read.
    theta: f64,
    tension: Arc<SharedTension>,
    /// The finite-strain body (None at linear kinematics).
    pub body: Option<Arc<PlaneBody>>,
    /// The dofs held fixed, and whether the abdominal wall is among them.
    fixed: Vec<usize>,
    fixed_wall: bool,
    /// Stress recovery for the current properties.
    pub recovery: Recovery,
    /// Which outputs read which elements and nodes.
    pub plan: OutputPlan,
    /// The time integrator the scene steps with.
    kind: IntegratorKind,
}

impl std::fmt::Debug for FullOrder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FullOrder")
            .field("triangles", &self.disc.mesh().triangles().len())
            .field("choice", &self.disc.choice)
            .finish()
    }
}

impl FullOrder {
    /// Builds the full-order system for the current parameter values.
    pub fn build(values: &Values) -> Result<Self, SceneError> {
        let config = PelvisConfig::resolve(values.string(CONFIGURATION)?)?;
        let choice = Choice::parse(
            values.string(ELEMENT)?,
            values.string(FORMULATION)?,
            values.string(KINEMATICS)?,
        )?;
        let target = values.real(TARGET_TRIANGLES) as usize;
        let meshed = mesher::mesh(
            &config.control_points()?,
            target,
            choice.element.bytes_per_triangle(),
            subdivisions(values)?,
            values.real(GRADING),
        )?;
        let disc = Discretization::new(meshed, choice);
        let props = properties(values)?;
        let asm = &disc.asm;
        let (mut k, mut m, mut c) = (asm.zeros(), asm.zeros(), asm.zeros());
        disc.stiffness(&props, &mut k);
        disc.mass(&props, &mut m);
        disc.mass(&damping_properties(values, &props), &mut c);
        let lumped = disc.lumped_mass(&props);
        let fixed = supports(
            &disc,
            values.string(WALL_SUPPORT)?,
            values.string(COSTAL_MARGIN)?,
        )?;
        let bc = Dirichlet::new(asm, &fixed)?;
        let tension = Arc::new(SharedTension::default());
        let body = disc.body(&props, &tension).map(Arc::new);
        let factorization = Factorization::plane(bc.n_free(), body.is_none());
        let mut structure = Structure::new(bc, &k, &m, &lumped, Damping::NONE, factorization)?;
        structure.set_damping_matrix(&c);
        if let Some(body) = &body {
            structure = structure.with_internal_forces(body.clone());
        }
        let load = parameters::press_load(values.string(PRESS_LOAD)?)?;
        let (unit_load, theta) = press_pattern(&disc, &props, load, structure.dirichlet())?;
        Ok(Self {
            recovery: disc.recovery(&props),
            plan: OutputPlan::new(disc.mesh())?,
            kind: IntegratorKind::parse(values.string(INTEGRATOR)?)?,
            fixed_wall: values.string(WALL_SUPPORT)? == "fixed",
            disc,
            props,
            k,
            structure,
            unit_load,
            theta,
            tension,
            body,
            fixed,
        })
    }

    /// Reassembles the stiffness and the finite-strain body for new properties (the
    /// integrator must be prepared again).
    pub fn set_properties(&mut self, props: PlaneProperties) {
        self.disc.stiffness(&props, &mut self.k);
        self.structure.set_stiffness(&self.k);
        self.body = self.disc.body(&props, &self.tension).map(Arc::new);
        if let Some(body) = &self.body {
            self.structure.set_internal_forces(body.clone());
        }
        self.recovery = self.disc.recovery(&props);
        self.props = props;
    }

    /// The displacement `u` (all dofs) with what the outputs need to read it.
    pub fn field<'a>(&'a self, u: &'a [f64]) -> Field<'a> {
        Field {
            plan: &self.plan,
            recovery: &self.recovery,
            u,
        }
    }

    /// The displacement `u` (all dofs) with the meshes and stresses, for drawing.
    pub fn view<'a>(&'a self, u: &'a [f64]) -> FieldView<'a> {
        FieldView {
            mesh: self.disc.mesh(),
            quadratic: self.disc.quadratic(),
            u,
            recovery: &self.recovery,
        }
    }

    /// The load pattern of a unit pressing force (free dofs).
    pub fn unit_load(&self) -> &[f64] {
        &self.unit_load
    }

    /// The stiffness at rest (all dofs, on the assembler's pattern).
    pub fn stiffness(&self) -> &[f64] {
        &self.k
    }

    /// The dofs held fixed.
    pub fn fixed(&self) -> &[usize] {
        &self.fixed
    }

    /// Whether the abdominal wall is held.
    pub fn fixed_wall(&self) -> bool {
        self.fixed_wall
    }

    /// The time integrator the scene steps with.
    pub fn kind(&self) -> IntegratorKind {
        self.kind
    }

    /// Θ₀: the pressing force per unit active tension of the diaphragm at rest.
    pub fn theta(&self) -> f64 {
        self.theta
    }

    /// The diaphragm's active tension of the last step and the one its kept tangent was
    /// taken at (N per mm of depth; 0 at linear kinematics).
    pub fn tension(&self) -> [f64; 2] {
        [self.tension.get(), self.tension.at_tangent()]
    }

    /// Sets the diaphragm's active tension the body reads to `tension` (N per mm of depth).
    pub fn set_tension(&self, tension: f64) {
        self.tension.set(tension);
    }

    /// Sets the diaphragm's active tension of a pressing force `force` (N/mm; none when
    /// drawn out), as the load of a step does.
    pub fn set_press(&self, force: f64) {
        self.tension.set(force.max(0.0) / self.theta);
    }

    /// At finite kinematics, the tension the pressing load of a step sets and Θ₀; None at
    /// linear kinematics.
    pub fn contracting(&self) -> Option<(&SharedTension, f64)> {
        self.disc
            .choice
            .finite
            .then_some((&*self.tension, self.theta))
    }

    /// The full finite-strain structure with a diaphragm tension of its own.
    pub(super) fn detached(&self) -> Result<Detached, SceneError> {
        let tension = Arc::new(SharedTension::default());
        let body = self.body_reading(&tension)?;
        let structure = self.structure.clone().with_internal_forces(body);
        Ok(Detached { structure, tension })
    }

    /// The finite-strain body for the current properties, its diaphragm's active tension
    /// read from `tension`.
    pub(super) fn body_reading(
        &self,
        tension: &Arc<SharedTension>,
    ) -> Result<Arc<PlaneBody>, SceneError> {
        self.disc
            .body(&self.props, tension)
            .map(Arc::new)
            .ok_or_else(|| SceneError::Config("a press run needs finite kinematics".into()))
    }
}

/// The full finite-strain structure with a diaphragm tension of its own
/// ([`FullOrder::detached`]).
pub(super) struct Detached {
    pub structure: Structure,
    pub tension: Arc<SharedTension>,
}

/// The pressing force's load pattern: the forces a contracting diaphragm exerts at rest
/// ([`Discretization::contraction`]), or seed 003's uniform pressure over it
/// ([`Discretization::diaphragm_pressure`]), per unit of their resultant on the free dofs —
/// so that a pressing force F is F times this pattern, a resultant F into the cavity — and
/// that resultant per unit tension, Θ₀ (the turning of the diaphragm between its supports:
/// sin θ₁ + sin θ₂ for a dome leaving its supports at θ₁, θ₂ from the horizontal; for the
/// pressure, its chord less the shares of its held ends).
fn press_pattern(
    disc: &Discretization,
    props: &PlaneProperties,
    load: PressLoad,
    bc: &Dirichlet,
) -> Result<(Vec<f64>, f64), SceneError> {
    let f = match load {
        PressLoad::Contraction => disc.contraction(props)?,
        PressLoad::Pressure => disc.diaphragm_pressure()?,
    };
    let mut reduced = vec![0.0; bc.n_free()];
    bc.reduce(&f, &mut reduced);
    let resultant = bc
        .free()
        .iter()
        .zip(&reduced)
        .fold([0.0; 2], |mut r, (&d, x)| {
            r[d % 2] += x;
            r
        });
    let theta = resultant[0].hypot(resultant[1]);
    if theta.is_nan() || theta <= 0.0 {
        let why = match load {
            PressLoad::Contraction => {
                "the diaphragm is straight between fixed supports: its contraction presses on \
                 nothing (give the dome a rise)"
            }
            PressLoad::Pressure => "the diaphragm has no free node for the pressure to press on",
        };
        return Err(SceneError::Config(why.into()));
    }
    reduced.iter_mut().for_each(|x| *x /= theta);
    Ok((reduced, theta))
}

#[cfg(test)]
mod tests {
    use super::super::variables::{table, ELEMENT, KINEMATICS, PRESS_LOAD, TARGET_TRIANGLES};
    use super::*;

    /// Seed 003's press: a uniform pressure's resultant on any curve is the pressure times
    /// the chord turned by a right angle, so a unit pressure over the diaphragm sums (on all
    /// dofs) to its chord's length, normal to the chord and into the cavity — for the
    /// 2-node and the 3-node (curved) lines alike.
    #[test]
    fn seed_003_s_pressure_sums_to_the_diaphragm_s_chord_turned_into_the_cavity() {
        for element in ["tri3", "tri6"] {
            let mut values = Values::new(table());
            values.set_real(TARGET_TRIANGLES, &[150.0]).unwrap();
            values.set_string(ELEMENT, element).unwrap();
            values.set_string(KINEMATICS, "linear").unwrap();
            values.set_string(PRESS_LOAD, "pressure").unwrap();
            let full = FullOrder::build(&values).unwrap_or_else(|e| panic!("{e}"));
            let f = full.disc.diaphragm_pressure().unwrap();
            let resultant = [0, 1].map(|d| f.iter().skip(d).step_by(2).sum::<f64>());
            let mesh = full.disc.mesh();
            let ends: Vec<usize> = {
                let diaphragm = mesh.node_sets().get("diaphragm").unwrap();
                let mut count = std::collections::BTreeMap::new();
                for (line, &r) in mesh.lines().iter().zip(mesh.line_regions()) {
                    if r == super::super::mesher::DIAPHRAGM_REGION {
                        line.iter().for_each(|n| *count.entry(*n).or_insert(0) += 1);
                    }
                }
                let ends: Vec<usize> = count
                    .into_iter()
                    .filter(|&(_, c)| c == 1)
                    .map(|(n, _)| n)
                    .collect();
                assert!(ends.iter().all(|n| diaphragm.contains(n)));
                ends
            };
            assert_eq!(ends.len(), 2, "{element}");
            let [a, b] = [ends[0], ends[1]].map(|n| mesh.nodes()[n]);
            let chord = [b[0] - a[0], b[1] - a[1]];
            let length = chord[0].hypot(chord[1]);
            let size = resultant[0].hypot(resultant[1]);
            assert!(
                (size - length).abs() < 1e-9 * length,
                "{element}: {size} vs {length}"
            );
            let along = resultant[0] * chord[0] + resultant[1] * chord[1];
            assert!(along.abs() < 1e-9 * length * length, "{element}: {along}");
            // Into the cavity: towards the centroid of its nodes from the chord's middle.
            let n = mesh.nodes().len() as f64;
            let centroid = [0, 1].map(|d| mesh.nodes().iter().map(|p| p[d]).sum::<f64>() / n);
            let inward = [0, 1].map(|d| centroid[d] - 0.5 * (a[d] + b[d]));
            assert!(
                resultant[0] * inward[0] + resultant[1] * inward[1] > 0.0,
                "{element}"
            );
        }
    }
}
