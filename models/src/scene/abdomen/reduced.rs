//! The abdomen's reduced orders: a modal basis of the linear model (Ritz vectors of the
//! pressing load or eigenmodes, with the outputs as rows in its coordinates), or the
//! hyper-reduced finite-strain model trained at initialization ([`super::training`]); and
//! the carrying of an integrator's state onto a basis built anew after a parameter change.

use super::build::FullOrder;
use super::outputs::Rows;
use super::parameters::ReducedOrder;
use super::training::{self, HyperReduction, TrainingRange};
use crate::scene::SceneError;
use crate::solve::{Carried, Checkpoint, ModalBasis, Reduction, Structure};

/// The reduced-order system: the basis, the projected matrices, the projected unit load
/// and the output rows.
#[derive(Debug)]
pub struct ReducedSystem {
    pub basis: ModalBasis,
    pub structure: Structure,
    pub unit_load: Vec<f64>,
    /// The outputs as rows in the coordinates (linear kinematics; at finite strain the
    /// outputs are read from the expanded field).
    pub rows: Option<Rows>,
    /// The largest principal strain of each basis vector, for a strain bound without
    /// expansion (linear kinematics).
    pub strains: Vec<f64>,
    /// The hyper-reduction of a finite-strain model.
    pub hyper: Option<HyperReduction>,
    /// The order and the `modes` parameter the basis was built with.
    order: ReducedOrder,
    count: usize,
    /// The state (free dofs, displacement and velocity first) a modal basis was built to
    /// carry at the last stiffness change ([`Carried`]); empty before any. The scene's
    /// state holds it: a restore builds the same basis from it.
    pub carried: Vec<Vec<f64>>,
}

/// What a hyper-reduced model is trained for, and the model's largest step (which bounds
/// the training's, [`training::step`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Training {
    pub range: TrainingRange,
    pub max_step: f64,
}

impl ReducedSystem {
    /// The reduced system of `full` with a basis of (at most) `count` vectors for its
    /// current matrices: for the pressing load's pattern at linear kinematics, by training
    /// over `training` at finite strain ([`ReducedOrder::Hyper`]).
    pub fn new(
        full: &FullOrder,
        order: ReducedOrder,
        count: usize,
        training: Training,
    ) -> Result<Self, SceneError> {
        match order {
            ReducedOrder::Modal(reduction) => Self::modal(full, reduction, count, Vec::new()),
            ReducedOrder::Hyper => Self::hyper_reduced(full, count, training),
        }
    }

    /// The modal system: a basis of `count` vectors for the pressing load's pattern, and
    /// for the state `carried` if there is one ([`Carried`]).
    fn modal(
        full: &FullOrder,
        reduction: Reduction,
        count: usize,
        carried: Vec<Vec<f64>>,
    ) -> Result<Self, SceneError> {
        let state = match &carried[..] {
            [u, v, others @ ..] => Some(Carried {
                vibrating: [u, v],
                others: others.iter().map(Vec::as_slice).collect(),
            }),
            _ => None,
        };
        let s = &full.structure;
        let basis = ModalBasis::new(s, reduction, count, full.unit_load(), state.as_ref())?;
        let bc = full.structure.dirichlet();
        let mut u = vec![0.0; full.disc.n_dofs()];
        let strains = (0..basis.dim())
            .map(|j| {
                bc.expand(basis.column(j), &mut u);
                full.view(&u).largest_strain()
            })
            .collect();
        let at_rest = vec![0.0; full.disc.n_dofs()];
        Ok(Self {
            rows: Some(Rows::new(full.field(&at_rest), &basis, bc)),
            strains,
            structure: basis.reduce(&full.structure)?,
            unit_load: projected_load(full, &basis),
            basis,
            order: ReducedOrder::Modal(reduction),
            count,
            hyper: None,
            carried,
        })
    }

    /// The same modal system built to carry `state` (a restore of [`Self::carried`]).
    pub fn carrying(&self, full: &FullOrder, state: Vec<Vec<f64>>) -> Result<Self, SceneError> {
        match self.order {
            ReducedOrder::Modal(reduction) => Self::modal(full, reduction, self.count, state),
            ReducedOrder::Hyper => Err(SceneError::Config(
                "a hyper-reduced model carries no state in its basis".into(),
            )),
        }
    }

    /// The hyper-reduced finite-strain system ([`training`]).
    fn hyper_reduced(
        full: &FullOrder,
        count: usize,
        Training { range, max_step }: Training,
    ) -> Result<Self, SceneError> {
        let Some(body) = &full.body else {
            // Refused with the scene's words before ([`super::parameters::order_allows`]).
            return Err(SceneError::Config(
                "the hyper-reduced model needs kinematics = \"finite\"".into(),
            ));
        };
        let (basis, hyper) = training::train(full, body, range, max_step, count)?;
        Ok(Self {
            rows: None,
            strains: Vec::new(),
            structure: training::structure(&full.structure, &basis, &hyper.forces)?,
            unit_load: projected_load(full, &basis),
            basis,
            order: ReducedOrder::Hyper,
            count,
            hyper: Some(hyper),
            carried: Vec::new(),
        })
    }

    /// The reduced system of the same order and size for `full`'s current matrices, and
    /// `checkpoint` (of an integrator on this one) carried onto it, each vector projected
    /// (q = Φᵀ M u): the scheme goes on as the full one does, not from a restart. A modal
    /// basis is built to carry the checkpoint's state ([`Carried`]: its vectors exactly,
    /// and the free vibration from its displacement and velocity), so that it has up to
    /// three times `count` vectors after a change.
    pub fn rebuilt(
        &self,
        full: &FullOrder,
        checkpoint: &Checkpoint,
        training: Training,
    ) -> Result<(Self, Checkpoint), SceneError> {
        let mut u = vec![0.0; full.structure.n()];
        let new = match self.order {
            ReducedOrder::Modal(reduction) => {
                let state = checkpoint
                    .vectors()
                    .into_iter()
                    .map(|q| {
                        self.basis.expand(q, &mut u);
                        u.clone()
                    })
                    .collect();
                Self::modal(full, reduction, self.count, state)?
            }
            ReducedOrder::Hyper => Self::hyper_reduced(full, self.count, training)?,
        };
        let mass = full.structure.mass();
        let moved = checkpoint.map(&mut |q| {
            self.basis.expand(q, &mut u);
            let mut projected = vec![0.0; new.basis.dim()];
            new.basis.coordinates(mass, &u, &mut projected);
            projected
        });
        Ok((new, moved))
    }
}

/// Φᵀ f of the unit pressing load.
fn projected_load(full: &FullOrder, basis: &ModalBasis) -> Vec<f64> {
    let mut unit_load = vec![0.0; basis.dim()];
    basis.project(full.unit_load(), &mut unit_load);
    unit_load
}
