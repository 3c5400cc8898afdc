//! A time limit on any pipeline, kept as a deadline inside it.
//!
//! In: the limit the user gave, counted from when the run started ([`Limit`]), and a job that
//! takes the limit's [`Deadline`]. Out: the job's result, or, when the deadline passed first,
//! [`Error::Interrupted`] naming the last step the job reported ([`Limit::run`]) or, for the
//! exact loop, [`Error::TimeLimit`] saying what had been found by then ([`Limit::exact`]).
//!
//! The job runs on the caller's thread. The deadline travels with it: its SAT solvers stop
//! there ([`crate::sat::solver::Solver::until`]), its NuSMV checks are killed there
//! ([`crate::nusmv::Nusmv::deadline`]), the closed-loop game stops exploring there. So the
//! job returns soon after the deadline and leaves no thread or process behind. Whatever it
//! returns then, a machine or an error, was computed on answers cut short: it is discarded,
//! and so are the events it sends after the deadline.

use super::cegis::Iteration;
use super::exact::{self, Exact};
use super::{Check, Error, Event, Events};
use crate::deadline::Deadline;
use crate::scenario::ScenarioSet;
use std::time::{Duration, Instant};

/// What the loop had found when the limit passed.
#[derive(Debug, Clone, Default)]
pub struct SoFar {
    /// Lower bounds on C and T from the recorded inputs alone.
    pub(crate) lower_bounds: Option<(usize, usize)>,
    /// Candidates checked by NuSMV (none verified), the last one last.
    pub(crate) candidates: Vec<Iteration>,
}

impl std::fmt::Display for SoFar {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let bounds = self
            .lower_bounds
            .map(|(c, t)| format!("lower bounds C >= {c}, T >= {t}"));
        match (self.candidates.last(), bounds) {
            (None, None) => write!(f, "no candidate yet, lower bounds not yet known"),
            (None, Some(b)) => write!(f, "no candidate yet ({b})"),
            (Some(last), _) => write!(
                f,
                "{} candidate{}, none verified; the last, C = {} T = {}, fails {}",
                self.candidates.len(),
                if self.candidates.len() == 1 { "" } else { "s" },
                last.c,
                last.t,
                last.failing.join(", ")
            ),
        }
    }
}

/// A time limit: `seconds` as the user gave them, counted from `started`.
#[derive(Debug, Clone, Copy)]
pub struct Limit {
    started: Instant,
    seconds: f64,
    deadline: Deadline,
}

impl Limit {
    /// The limit `seconds` counted from `started` (no deadline when the number is not a time:
    /// [`super::seconds`] checks the user's).
    pub(crate) fn new(started: Instant, seconds: f64) -> Limit {
        let at = Duration::try_from_secs_f64(seconds)
            .ok()
            .and_then(|d| started.checked_add(d));
        let deadline = at.map_or(Deadline::NONE, Deadline::at);
        Limit {
            started,
            seconds,
            deadline,
        }
    }

    /// The limit `budget` from now.
    pub(crate) fn from_now(budget: Duration) -> Limit {
        Limit::new(Instant::now(), budget.as_secs_f64())
    }

    /// Seconds since the run started.
    pub(crate) fn elapsed(&self) -> f64 {
        self.started.elapsed().as_secs_f64()
    }

    /// The time left.
    pub(crate) fn left(&self) -> Duration {
        self.deadline.left().unwrap_or(Duration::MAX)
    }

    /// `job` given the deadline, its events to `events` until the deadline passes; after it,
    /// [`Error::Interrupted`] naming the last solver step it reported (module documentation).
    pub(crate) fn run<T>(
        &self,
        events: Events<'_>,
        job: impl FnOnce(Deadline, Events<'_>) -> Result<T, Error>,
    ) -> Result<T, Error> {
        let mut last: Option<String> = None;
        let result = job(self.deadline, &mut |e| {
            if self.deadline.passed() {
                return;
            }
            if let Event::Solver(s) = &e {
                last = Some(s.to_string());
            }
            events(e)
        });
        if self.deadline.passed() {
            return Err(Error::Interrupted {
                seconds: self.seconds,
                last: last.unwrap_or_else(|| "none yet".into()),
            });
        }
        result
    }

    /// [`exact::run`] with `check`, stopped at the deadline with [`Error::TimeLimit`] saying
    /// what had been found by then.
    pub(crate) fn exact(
        &self,
        set: &ScenarioSet,
        check: &Check,
        opts: &exact::Options,
        events: Events<'_>,
    ) -> Result<Exact, Error> {
        let mut so_far = SoFar::default();
        let result = self.run(
            &mut |e| {
                match &e {
                    Event::LowerBounds { c, t, .. } => so_far.lower_bounds = Some((*c, *t)),
                    Event::Candidate(it) => so_far.candidates.push((*it).clone()),
                    _ => {}
                }
                events(e)
            },
            |deadline, events| {
                let mut opts = opts.clone();
                opts.sat.deadline = deadline;
                exact::run(set, Some(&check.until(deadline)), &opts, events)
            },
        );
        match result {
            Err(Error::Interrupted { seconds, .. }) => Err(Error::TimeLimit { seconds, so_far }),
            r => r,
        }
    }

    /// The closed-loop game's guide ([`super::guide::run`]) with `check`, its machine in
    /// `conventions`, stopped at the deadline with [`Error::Interrupted`].
    pub(crate) fn guide(
        &self,
        set: &ScenarioSet,
        check: &Check,
        conventions: crate::ecc::Conventions,
        start: super::guide::RepairStart,
        events: Events<'_>,
    ) -> Result<super::guide::Outcome, Error> {
        self.run(events, |deadline, events| {
            super::guide::run(set, &check.until(deadline), conventions, start, events)
        })
    }
}

/// `job` within `limit` from now ([`Limit::run`]).
pub(crate) fn within<T>(
    limit: Duration,
    events: Events<'_>,
    job: impl FnOnce(Deadline, Events<'_>) -> Result<T, Error>,
) -> Result<T, Error> {
    Limit::from_now(limit).run(events, job)
}

/// [`exact::run`] with `check` within `limit` from now ([`Limit::exact`]).
pub(crate) fn exact_within(
    set: &ScenarioSet,
    check: &Check,
    opts: &exact::Options,
    limit: Duration,
    events: Events<'_>,
) -> Result<Exact, Error> {
    Limit::from_now(limit).exact(set, check, opts, events)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sat::solver::{pigeons, Solver};

    /// A job that would run for minutes: a SAT call on the pigeonhole formula.
    fn hard_sat(deadline: Deadline) -> Result<bool, Error> {
        let mut s = Solver::until(deadline);
        pigeons(&mut s, 11);
        Ok(s.solve(&[]).is_some())
    }

    #[test]
    fn the_job_stops_at_the_deadline_on_this_thread() {
        let limit = Limit::from_now(Duration::from_millis(200));
        let mut ran_on = None;
        let r = limit.run(&mut |_| {}, |deadline, _| {
            ran_on = Some(std::thread::current().id());
            hard_sat(deadline)
        });
        // The job ran here and returned: nothing of it is left running.
        assert_eq!(ran_on, Some(std::thread::current().id()));
        match r {
            Err(Error::Interrupted { seconds, last }) => {
                assert_eq!(seconds, 0.2);
                assert_eq!(last, "none yet");
            }
            other => panic!("expected the limit, got {:?}", other.map(|_| ())),
        }
    }

    #[test]
    fn a_job_within_the_limit_keeps_its_result_and_events() {
        let mut seen = 0;
        let r = within(
            Duration::from_secs(3600),
            &mut |_| seen += 1,
            |_, events| {
                events(Event::LowerBounds {
                    c: 1,
                    t: 0,
                    n: None,
                    seconds: 0.0,
                });
                Ok(7)
            },
        );
        assert_eq!(r.unwrap(), 7);
        assert_eq!(seen, 1);
    }

    #[test]
    fn events_after_the_deadline_are_dropped() {
        let mut seen = 0;
        let r = within(Duration::ZERO, &mut |_| seen += 1, |_, events| {
            events(Event::LowerBounds {
                c: 1,
                t: 0,
                n: None,
                seconds: 0.0,
            });
            Ok(())
        });
        assert!(matches!(r, Err(Error::Interrupted { .. })));
        assert_eq!(seen, 0);
    }
}
