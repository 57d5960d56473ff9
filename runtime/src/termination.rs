//! When a long search must stop: OMPL's `PlannerTerminationCondition`, reduced to what
//! cellc needs.
//!
//! A [`Termination`] is a deadline (from a request's time budget) and an optional cancel
//! flag another thread may raise. It is made once per request and passed down by
//! reference into every long loop: the restarts of inverse kinematics
//! ([`crate::kinematics::solve_ik`]) and of the closed-chain solver
//! ([`crate::kinematics::closed_chain::solve_handoff`]), and the iterations of RRT-Connect and its
//! shortcutting ([`crate::motion::RrtConnect`]). Each checks it once per pass, which costs
//! a clock read (tens of nanoseconds) against the microseconds a pass takes.
//!
//! A search that stops early returns its own error (`Terminated`), never "unreachable" or
//! "no path": being cut short says nothing about the problem. [`Termination::fired`]
//! remembers that something was cut short, so a caller can refuse a result built around
//! a shortened search (the planner answers [`crate::plan::PlanError::TimeBudget`] rather
//! than a plan that differs from the unhurried one).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// A deadline and a cancel flag, checked inside long loops. The default never stops.
#[derive(Debug, Default)]
pub struct Termination {
    deadline: Option<Instant>,
    cancel: Option<Arc<AtomicBool>>,
    /// Set the first time [`Termination::should_stop`] answers yes.
    fired: AtomicBool,
}

impl Clone for Termination {
    fn clone(&self) -> Termination {
        Termination {
            deadline: self.deadline,
            cancel: self.cancel.clone(),
            fired: AtomicBool::new(self.fired()),
        }
    }
}

impl Termination {
    /// Never stops (verification, tests, requests without a budget).
    pub fn never() -> Termination {
        Termination::default()
    }

    /// Stops at `deadline`.
    pub fn at(deadline: Instant) -> Termination {
        Termination {
            deadline: Some(deadline),
            ..Termination::default()
        }
    }

    /// Stops `budget` from now; `None` never stops (a budget too large to represent is
    /// no limit either).
    pub fn after(budget: Option<Duration>) -> Termination {
        Termination {
            deadline: budget.and_then(|b| Instant::now().checked_add(b)),
            ..Termination::default()
        }
    }

    /// Also stops once `flag` is raised (by any thread).
    pub fn with_cancel(mut self, flag: Arc<AtomicBool>) -> Termination {
        self.cancel = Some(flag);
        self
    }

    /// Whether the search should stop now: the flag is raised or the deadline passed.
    /// Once it has answered yes, [`Termination::fired`] is true.
    pub fn should_stop(&self) -> bool {
        let cancelled = self
            .cancel
            .as_ref()
            .is_some_and(|flag| flag.load(Ordering::Relaxed));
        let late = self.deadline.is_some_and(|d| Instant::now() >= d);
        if cancelled || late {
            self.fired.store(true, Ordering::Relaxed);
        }
        cancelled || late
    }

    /// Whether some search was stopped by this condition (its result is not the one an
    /// unhurried search would have given).
    pub fn fired(&self) -> bool {
        self.fired.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn never_stops_without_a_deadline_or_flag() {
        let stop = Termination::never();
        assert!(!stop.should_stop());
        assert!(!stop.fired());
        assert!(!Termination::after(None).should_stop());
    }

    #[test]
    fn a_past_deadline_stops_and_is_remembered() {
        let stop = Termination::at(Instant::now());
        assert!(!stop.fired());
        assert!(stop.should_stop());
        assert!(stop.fired());
        assert!(stop.clone().fired());
    }

    #[test]
    fn the_flag_stops_from_outside() {
        let flag = Arc::new(AtomicBool::new(false));
        let stop = Termination::never().with_cancel(flag.clone());
        assert!(!stop.should_stop());
        flag.store(true, Ordering::Relaxed);
        assert!(stop.should_stop());
    }
}
