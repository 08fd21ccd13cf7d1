//! The memory budget of a build. A scene states its limit (its `memory_limit` parameter)
//! for the time it builds a model, with [`within`]; the large allocations — mesh, sparse
//! pattern, matrices, Cholesky factor — are first claimed with [`claim`], which adds their
//! size to what the build has claimed so far and refuses the one that would exceed the
//! limit. A failed allocation aborts a Rust process, and an FMU's host with it; a refused
//! claim is an error that names what was too large and the limit. Outside [`within`]
//! nothing is limited (tests, benchmarks, the core used as a library).

use std::cell::Cell;

use crate::error::ModelError;

thread_local! {
    /// (limit, claimed) in bytes while a build runs on this thread.
    static BUDGET: Cell<Option<(usize, usize)>> = const { Cell::new(None) };
}

/// Runs `build` with a budget of `limit` bytes; the previous budget (if any) is restored
/// afterwards, also on panic.
pub fn within<R>(limit: usize, build: impl FnOnce() -> R) -> R {
    struct Restore(Option<(usize, usize)>);
    impl Drop for Restore {
        fn drop(&mut self) {
            BUDGET.with(|b| b.set(self.0));
        }
    }
    let _restore = Restore(BUDGET.with(|b| b.replace(Some((limit, 0)))));
    build()
}

/// Claims `bytes` for `what` against the current budget.
pub fn claim(what: &'static str, bytes: usize) -> Result<(), ModelError> {
    BUDGET.with(|b| match b.get() {
        None => Ok(()),
        Some((limit, claimed)) => {
            let needed = claimed.saturating_add(bytes);
            if needed > limit {
                return Err(ModelError::MemoryLimit {
                    what,
                    needed,
                    limit,
                });
            }
            b.set(Some((limit, needed)));
            Ok(())
        }
    })
}

/// An equal share, for each of `parts` parallel parts of a build, of what the calling
/// thread's budget has left (None without a budget). The budget is per thread: a part run on
/// another thread claims against its share with [`part`], or is not counted at all.
pub fn shares(parts: usize) -> Option<usize> {
    BUDGET
        .with(Cell::get)
        .map(|(limit, claimed)| limit.saturating_sub(claimed) / parts.max(1))
}

/// Runs `task` (a parallel part of a build, on any thread) within `share` ([`shares`]).
pub fn part<R>(share: Option<usize>, task: impl FnOnce() -> R) -> R {
    match share {
        Some(bytes) => within(bytes, task),
        None => task(),
    }
}

/// Bytes of `n` values of type `T`, saturating.
pub fn bytes_of<T>(n: usize) -> usize {
    n.saturating_mul(std::mem::size_of::<T>())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn claims_add_up_to_the_limit_and_only_inside_a_budget() {
        assert!(claim("anything", usize::MAX).is_ok(), "no budget, no limit");
        within(1000, || {
            claim("a mesh", 600).unwrap();
            let e = claim("a factor", 500).unwrap_err();
            assert!(
                matches!(
                    e,
                    ModelError::MemoryLimit {
                        what: "a factor",
                        needed: 1100,
                        limit: 1000
                    }
                ),
                "{e}"
            );
            within(10, || assert!(claim("inner", 11).is_err()));
            claim("the rest", 400).unwrap();
        });
        assert!(claim("after", usize::MAX).is_ok());
    }

    #[test]
    fn parallel_parts_claim_against_equal_shares_of_what_is_left() {
        use rayon::prelude::*;
        let results: Vec<(bool, bool)> = within(1000, || {
            claim("a mesh", 200).unwrap();
            // 800 left: 200 for each of four parts, wherever rayon runs them.
            let share = shares(4);
            (0..4)
                .into_par_iter()
                .map(|_| {
                    part(share, || {
                        (claim("a part", 200).is_ok(), claim("more", 1).is_ok())
                    })
                })
                .collect()
        });
        assert_eq!(results, vec![(true, false); 4]);
        assert_eq!(shares(4), None, "no budget, no limit");
        assert!(part(None, || claim("anything", usize::MAX).is_ok()));
    }
}
