//! The increment/cut-back policy of every load or time change the crate takes in parts: a
//! static solve's load increments ([`super::Newton`]), the abdomen's time step where Newton's
//! method fails in it, the cut block's load change whose flank contact does not settle
//! (taken again from its start in equal parts: [`Increments::restart`]).

/// A change from fraction 0 to 1 taken in increments of at most `base`: an increment that
/// fails is cut back to half its size and taken again from the last success; one that
/// succeeds lets the next grow back (doubled) up to `base`. An increment smaller than
/// `base` halved `max_cutbacks` times fails the change.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Increments {
    reached: f64,
    size: f64,
    base: f64,
    smallest: f64,
    cutbacks: usize,
}

impl Increments {
    /// The change in increments of `base` (0 < base ≤ 1), each halved at most
    /// `max_cutbacks` times.
    pub fn new(base: f64, max_cutbacks: usize) -> Self {
        Self {
            reached: 0.0,
            size: base,
            base,
            smallest: base / f64::from(1u32 << max_cutbacks.min(30)),
            cutbacks: 0,
        }
    }

    /// The next increment, from the fraction reached to the fraction it aims at; None once
    /// the change is complete.
    pub fn next(&self) -> Option<(f64, f64)> {
        (self.reached < 1.0).then(|| (self.reached, (self.reached + self.size).min(1.0)))
    }

    /// The increment [`next`](Self::next) gave succeeded.
    pub fn succeeded(&mut self) {
        if let Some((_, to)) = self.next() {
            self.reached = to;
            self.size = (2.0 * self.size).min(self.base);
        }
    }

    /// The increment [`next`](Self::next) gave failed: cut back (true) or, below the
    /// smallest increment, give up (false).
    pub fn failed(&mut self) -> bool {
        if 0.5 * self.size < self.smallest {
            return false;
        }
        self.size *= 0.5;
        self.cutbacks += 1;
        true
    }

    /// Takes the change again from its start, in increments of the present size that no
    /// longer grow: for changes whose answer depends on the path (a part's success can leave
    /// a state the next part fails from), retried in equal parts.
    pub fn restart(&mut self) {
        self.reached = 0.0;
        self.base = self.size;
    }

    /// The fraction of the change reached.
    pub fn reached(&self) -> f64 {
        self.reached
    }

    /// The present increment's size.
    pub fn size(&self) -> f64 {
        self.size
    }

    /// The cut-backs so far.
    pub fn cutbacks(&self) -> usize {
        self.cutbacks
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Increments of a quarter, one failure at the second: the change goes 0, ¼, then ⅛
    /// (the cut-back size), then a quarter again; a change that keeps failing
    /// gives up after its cut-backs, having reached what succeeded.
    #[test]
    fn a_failed_increment_is_halved_and_the_next_ones_grow_back() {
        let mut steps = Vec::new();
        let mut inc = Increments::new(0.25, 2);
        let mut failures = 1;
        while let Some((from, to)) = inc.next() {
            if from == 0.25 && failures > 0 {
                failures -= 1;
                assert!(inc.failed());
                continue;
            }
            steps.push((from, to));
            inc.succeeded();
        }
        assert_eq!(
            steps,
            [
                (0.0, 0.25),
                (0.25, 0.375),
                (0.375, 0.625),
                (0.625, 0.875),
                (0.875, 1.0)
            ]
        );
        assert_eq!(inc.cutbacks(), 1);
        // Restarted after each failure (the last part failing above a quarter): equal parts
        // of the halved size from the start.
        let mut parts = Vec::new();
        let mut equal = Increments::new(1.0, 3);
        while let Some((from, to)) = equal.next() {
            if to == 1.0 && equal.size() > 0.25 {
                assert!(equal.failed());
                equal.restart();
                parts.clear();
                continue;
            }
            parts.push((from, to));
            equal.succeeded();
        }
        assert_eq!(parts, [(0.0, 0.25), (0.25, 0.5), (0.5, 0.75), (0.75, 1.0)]);
        let mut stuck = Increments::new(1.0, 3);
        assert!(stuck.failed() && stuck.failed() && stuck.failed() && !stuck.failed());
        assert_eq!((stuck.size(), stuck.reached()), (0.125, 0.0));
    }
}
