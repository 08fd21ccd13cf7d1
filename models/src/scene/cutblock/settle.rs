//! A step's solve with the flank contact settled: solve, search the flanks, and while the
//! set of held nodes changes solve again with the new springs; then linearize the springs
//! again where they hold. A load change whose flanks end through each other, or whose set
//! cycles or does not settle, is taken again from its start in equal parts, halved at
//! each failure ([`Increments::restart`]).
//!
//! The work of one step is bounded for every value in the declared ranges: at most
//! [`MAX_INCREMENTS`] Newton load increments of the pull change (a larger count is refused
//! before any work, naming `max_increment` and the change), each cut back at most 8 times
//! and of at most 25 Newton iterations; with contact, at most [`CONTACT_ITERATIONS`] solves
//! until the contact set repeats and [`RELINEARIZATION_SOLVES`] more while its springs are
//! linearized again (75 per settle), and the change split into at most 2 + 4 + 8 parts
//! ([`CONTACT_HALVINGS`]; 15 settles).

use super::contact::{Held, SLIDING_LIMIT};
use super::equilibrium::Saved;
use super::geometry::Geometry;
use super::topology::Topology;
use crate::scene::SceneError;
use crate::solve::newton::Increments;

/// The most Newton load increments one step may take.
pub const MAX_INCREMENTS: f64 = 1000.0;

/// Largest number of solves of one settle while the contact set changes.
const CONTACT_ITERATIONS: usize = 25;

/// Largest number of solves one settle spends re-linearizing its springs
/// ([`Topology::relinearize`]).
const RELINEARIZATION_SOLVES: usize = 50;

/// Times the parts of a load change whose flanks end through each other, or whose contact
/// set does not settle, are halved: 2, 4 and 8 equal parts.
const CONTACT_HALVINGS: usize = 3;

impl Topology {
    /// Solves for the pull (mm) and the press force (N) at the scalpel position. With flank
    /// contact: solve, search the flanks, and while the set of held nodes changes, solve
    /// again with the new springs (at most `CONTACT_ITERATIONS` solves; a set that comes
    /// back is a cycle and an error), then linearize the springs again where they hold
    /// ([`Self::settle`]; where that fails, the set's first answer stays). A load change
    /// that leaves the flanks through each other (beyond the contact's small-sliding range)
    /// or whose set of held nodes cycles or does not settle is retried from the last
    /// equilibrium in 2, 4 and 8 equal parts ([`Increments::restart`]), the springs
    /// updated after each. On error the last equilibrium stays.
    pub fn solve(
        &mut self,
        g: &Geometry,
        pull: f64,
        press: f64,
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        if let Some(max_increment) = self.eq.max_increment() {
            let change = (pull - self.eq.load.0).abs();
            let increments = (change / max_increment).ceil();
            if increments > MAX_INCREMENTS {
                return Err(SceneError::TooManyIncrements {
                    input: "pull",
                    change,
                    max_increment,
                    increments,
                    limit: MAX_INCREMENTS,
                });
            }
        }
        self.eq.keep(Saved::Solve);
        let (load, held) = (self.eq.load, self.contact.as_ref().map(|c| c.held()));
        let mut increments = Increments::new(1.0, CONTACT_HALVINGS);
        while let Some((_, to)) = increments.next() {
            // The load at the fraction `to` of the change (the target itself at its end).
            let at = |from: f64, target: f64| {
                if to == 1.0 {
                    target
                } else {
                    from + to * (target - from)
                }
            };
            match self.settle(g, at(load.0, pull), at(load.1, press), scalpel_x) {
                Ok(()) => increments.succeeded(),
                Err(SceneError::Slid { .. } | SceneError::NotConverged { .. })
                    if increments.failed() =>
                {
                    // The springs a part leaves depend on its path: the change from its
                    // start, in equal parts of the halved size.
                    increments.restart();
                    self.back(Saved::Solve, g, load, &held, scalpel_x)?;
                }
                Err(e) => {
                    self.back(Saved::Solve, g, load, &held, scalpel_x)?;
                    return Err(e);
                }
            }
        }
        Ok(())
    }

    /// Back to a saved equilibrium with its springs `held` under `load`: displacements,
    /// internal forces, contact, loads and the solver. Undoing a solve also undoes what its
    /// settles fell back to; going back to a settled set is the fallback.
    fn back(
        &mut self,
        saved: Saved,
        g: &Geometry,
        load: (f64, f64),
        held: &Option<Held>,
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        self.eq.go_back(saved);
        if let (Some(c), Some(held)) = (&mut self.contact, held) {
            c.hold(held);
        }
        let (on, eq) = self.parts();
        eq.restart(&on, g, load, scalpel_x)
    }

    /// Equilibrium under (pull, press) with the contact set settled ([`Self::settle_set`])
    /// and its springs linearized where they hold ([`Self::relinearize`]); where that does
    /// not converge, the settled set's answer with the springs linearized where their nodes
    /// were caught stays. A node left deeper than the small-sliding limit is an error.
    fn settle(
        &mut self,
        g: &Geometry,
        pull: f64,
        press: f64,
        scalpel_x: f64,
    ) -> Result<(), SceneError> {
        let (on, eq) = self.parts();
        eq.set_loads(&on, g, pull, press, scalpel_x);
        let mut solves = CONTACT_ITERATIONS;
        self.settle_set(&mut solves)?;
        self.eq.load = (pull, press);
        let Some(c) = &self.contact else {
            return Ok(());
        };
        if !c.active.is_empty() {
            let held = Some(c.held());
            self.eq.keep(Saved::Settled);
            if self.relinearize().is_err() {
                self.back(Saved::Settled, g, (pull, press), &held, scalpel_x)?;
            }
        }
        self.within_sliding()
    }

    /// A node left behind a flank facet deeper than the small-sliding limit is an error.
    fn within_sliding(&self) -> Result<(), SceneError> {
        let Some(c) = &self.contact else {
            return Ok(());
        };
        let limit = SLIDING_LIMIT * self.layer;
        match c.deepest {
            Some(node) if c.penetration > limit => Err(SceneError::Slid {
                node,
                depth: c.penetration,
                limit,
            }),
            _ => Ok(()),
        }
    }

    /// Solves, searches the flanks and re-solves with the springs found until the set of
    /// held nodes repeats, at most `solves` solves (counted down; a set that comes back is
    /// a cycle and an error).
    fn settle_set(&mut self, solves: &mut usize) -> Result<(), SceneError> {
        let mut seen: Vec<Vec<usize>> = Vec::new();
        loop {
            if *solves == 0 {
                return Err(SceneError::NotConverged {
                    what: "the flank contact's active set",
                    iterations: seen.len(),
                });
            }
            *solves -= 1;
            let (on, eq) = self.parts();
            eq.solve(&on)?;
            let Some(c) = &mut self.contact else {
                return Ok(());
            };
            let springs = c.detect(self.solid.nodes(), &self.eq.u);
            if c.same_as_active(&springs) {
                return Ok(());
            }
            let held: Vec<usize> = springs.iter().map(|s| s.node).collect();
            if seen.contains(&held) {
                return Err(SceneError::NotConverged {
                    what: "the flank contact's active set (it cycles)",
                    iterations: seen.len(),
                });
            }
            seen.push(held);
            c.active = springs;
            let (on, eq) = self.parts();
            eq.factorize(&on)?;
        }
    }

    /// Linearizes the held springs again at the present state and settles the set anew,
    /// until the springs are linearized where they hold
    /// ([`super::contact::FlankContact::linearized_alike`]): the answer is then the same
    /// whatever state the springs were first linearized at. At most
    /// [`RELINEARIZATION_SOLVES`] solves in all; a spring on a degenerate facet, or a node
    /// left deeper than the small-sliding limit, is an error too.
    fn relinearize(&mut self) -> Result<(), SceneError> {
        let mut solves = RELINEARIZATION_SOLVES;
        loop {
            let Some(c) = &mut self.contact else {
                return Ok(());
            };
            let springs =
                c.relinearized(self.solid.nodes(), &self.eq.u)
                    .ok_or(SceneError::NotConverged {
                        what: "the flank springs' linearization (a degenerate facet)",
                        iterations: 0,
                    })?;
            if c.linearized_alike(&springs, &self.eq.u) {
                return self.within_sliding();
            }
            c.active = springs;
            let (on, eq) = self.parts();
            eq.factorize(&on)?;
            self.settle_set(&mut solves)
                .map_err(|_| SceneError::NotConverged {
                    what: "the flank springs' linearization",
                    iterations: RELINEARIZATION_SOLVES,
                })?;
        }
    }
}
