//! What the cut block has done: its rebuilds, analyses, factorizations and solves, and for
//! the finite-strain laws the returns to the unloaded block and the Newton increments and
//! iterations, those of failed increments apart ([`Work`], part of the scene's state), and
//! where the Newton solves' time went ([`Timing`], a measurement: neither saved nor
//! compared, so that the states of identical runs are identical bytes).

use std::time::Duration;

/// What the scene has done so far: how often it rebuilt the topology (and of those, made a
/// new pattern and symbolic analysis), refactorized and solved, and for the finite-strain
/// laws how often a solve went back to the unloaded block, and the Newton increments and
/// iterations.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Work {
    /// Topologies (cut mesh, pattern and solver) built: at initialization and each time the
    /// mesh's incision ends at a new crack front.
    pub topology_builds: u64,
    /// Of those builds, the ones that made a new sparsity pattern and symbolic analysis
    /// (the others reused the previous topology's).
    pub analyses: u64,
    /// Numeric factorizations of the stiffness matrix (for the finite-strain laws, those of
    /// the Newton increments that failed included: cut back, or of a start given up for the
    /// unloaded block).
    pub factorizations: u64,
    /// Solves of the scene for its current loads: one per initialization and step that
    /// succeeded.
    pub solves: u64,
    /// Solves of a new topology that went back to the unloaded block after the start from
    /// the previous one's equilibria did not converge (finite-strain laws).
    pub returns_to_unloaded: u64,
    /// Newton load increments that converged (finite-strain laws).
    pub increments: u64,
    /// Newton iterations (corrections Δu) of the converged increments, summed (finite-strain
    /// laws).
    pub iterations: u64,
    /// Newton iterations of the increments that failed (cut back, or of a start given up),
    /// summed (finite-strain laws).
    pub failed_iterations: u64,
}

/// Where the Newton solves' time went so far (finite-strain laws).
#[derive(Debug, Clone, Copy, Default)]
pub struct Timing {
    /// Time spent assembling in the Newton solves (finite-strain laws).
    pub assembly: Duration,
    /// Time spent factorizing in the Newton solves (finite-strain laws).
    pub factorization: Duration,
    /// Time spent solving with the factorized tangent in the Newton solves (finite-strain
    /// laws).
    pub solve: Duration,
}

impl std::ops::Add for Work {
    type Output = Work;

    /// The sum of two counts.
    fn add(self, other: Work) -> Work {
        Work {
            topology_builds: self.topology_builds + other.topology_builds,
            analyses: self.analyses + other.analyses,
            factorizations: self.factorizations + other.factorizations,
            solves: self.solves + other.solves,
            returns_to_unloaded: self.returns_to_unloaded + other.returns_to_unloaded,
            increments: self.increments + other.increments,
            iterations: self.iterations + other.iterations,
            failed_iterations: self.failed_iterations + other.failed_iterations,
        }
    }
}

impl std::ops::Add for Timing {
    type Output = Timing;

    /// The sum of two timings.
    fn add(self, other: Timing) -> Timing {
        Timing {
            assembly: self.assembly + other.assembly,
            factorization: self.factorization + other.factorization,
            solve: self.solve + other.solve,
        }
    }
}
