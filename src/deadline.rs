//! The moment a computation gives up: the time limit of a run, carried to every place that
//! may take long (SAT calls, NuSMV checks, the game's exploration).
//!
//! In: an instant, or none. Out: whether it has passed and how much time is left. A
//! [`Deadline`] is a plain value (`Copy`): options structs and NuSMV handles carry it, each
//! layer checks it where it waits or loops, and no thread is left running when it passes. The
//! caller that set it ([`crate::pipeline::limit`]) then discards whatever the computation
//! returned and reports the limit: a SAT call stopped at the deadline answers "no model", which
//! is not a proof of anything.

use std::time::{Duration, Instant};

/// A point in time after which work stops; [`Deadline::NONE`] never passes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Hash)]
pub struct Deadline(Option<Instant>);

impl Deadline {
    /// No deadline: the work runs to its end.
    pub const NONE: Deadline = Deadline(None);

    /// The deadline at `at`.
    pub(crate) fn at(at: Instant) -> Deadline {
        Deadline(Some(at))
    }

    /// The deadline `limit` from now (none if that instant is out of the clock's range).
    pub(crate) fn after(limit: Duration) -> Deadline {
        Deadline(Instant::now().checked_add(limit))
    }

    /// The instant, if there is a deadline.
    pub(crate) fn instant(self) -> Option<Instant> {
        self.0
    }

    /// Whether the deadline has passed (never for [`Deadline::NONE`]).
    pub(crate) fn passed(self) -> bool {
        self.0.is_some_and(|at| Instant::now() >= at)
    }

    /// The time left (`None`: no deadline; zero once passed).
    pub(crate) fn left(self) -> Option<Duration> {
        self.0
            .map(|at| at.saturating_duration_since(Instant::now()))
    }

    /// The earlier of the two.
    pub(crate) fn min(self, other: Deadline) -> Deadline {
        match (self.0, other.0) {
            (Some(a), Some(b)) => Deadline(Some(a.min(b))),
            (a, b) => Deadline(a.or(b)),
        }
    }

    /// `at`, or this deadline when it comes first: a budget that may not outlive the deadline.
    pub(crate) fn cap(self, at: Instant) -> Instant {
        self.0.map_or(at, |d| d.min(at))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn none_never_passes_and_caps_nothing() {
        let later = Instant::now() + Duration::from_secs(5);
        assert!(!Deadline::NONE.passed());
        assert_eq!(Deadline::NONE.left(), None);
        assert_eq!(Deadline::NONE.cap(later), later);
        assert_eq!(Deadline::NONE.min(Deadline::at(later)), Deadline::at(later));
    }

    #[test]
    fn a_past_deadline_has_passed_and_leaves_no_time() {
        let d = Deadline::after(Duration::ZERO);
        assert!(d.passed());
        assert_eq!(d.left(), Some(Duration::ZERO));
        let later = Instant::now() + Duration::from_secs(5);
        assert_eq!(d.cap(later), d.instant().unwrap());
        assert_eq!(d.min(Deadline::at(later)), d);
    }

    #[test]
    fn a_deadline_beyond_the_clock_is_none() {
        assert_eq!(Deadline::after(Duration::MAX), Deadline::NONE);
    }
}
