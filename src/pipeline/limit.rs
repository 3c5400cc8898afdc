//! A time limit on exact synthesis with NuSMV in the loop ([`exact::run`]), and on any other
//! pipeline ([`within`]).
//!
//! In: what [`exact::run`] takes, and a limit. Out: its result, or, when the limit passes
//! first, [`Error::TimeLimit`] saying what had been found by then (the lower bounds, the
//! candidates and what the last one failed).
//!
//! The loop runs on a thread of its own and sends its events here; this thread forwards them
//! to the caller and waits for the result until the deadline. So the limit holds whatever the
//! loop is doing, a SAT call or a NuSMV check, without a check inside either. When the limit
//! passes the loop's thread is left to end with the process: a command line that gives up
//! exits (after killing NuSMV, [`crate::nusmv::kill_all_children`]); a long-lived caller
//! should know that the thread still computes until its current SAT call returns.

use super::cegis::Iteration;
use super::exact::{self, Exact};
use super::{Check, Error, Event, Events};
use crate::scenario::ScenarioSet;
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// What the loop had found when the limit passed.
#[derive(Debug, Clone, Default)]
pub struct SoFar {
    /// Lower bounds on C and T from the recorded inputs alone.
    pub lower_bounds: Option<(usize, usize)>,
    /// Candidates checked by NuSMV (none verified), the last one last.
    pub candidates: Vec<Iteration>,
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

/// [`exact::run`] with `check`, given up after `limit` ([`within`]) with
/// [`Error::TimeLimit`] saying what had been found by then.
pub fn exact_within(
    set: &ScenarioSet,
    check: &Check,
    opts: &exact::Options,
    limit: Duration,
    events: Events<'_>,
) -> Result<Exact, Error> {
    let mut so_far = SoFar::default();
    let (set, check, opts) = (set.clone(), check.clone(), opts.clone());
    let result = within(
        limit,
        &mut |e| {
            match &e {
                Event::LowerBounds { c, t, .. } => so_far.lower_bounds = Some((*c, *t)),
                Event::Candidate(it) => so_far.candidates.push((*it).clone()),
                _ => {}
            }
            events(e)
        },
        move |events| exact::run(&set, Some(&check), &opts, events),
    );
    match result {
        Err(Error::Interrupted { seconds, .. }) => Err(Error::TimeLimit { seconds, so_far }),
        r => r,
    }
}

/// The closed-loop game's guide ([`super::guide::run`]) with `check`, given up after `limit`
/// ([`within`]) with [`Error::Interrupted`].
pub fn guide_within(
    set: &ScenarioSet,
    check: &Check,
    limit: Duration,
    events: Events<'_>,
) -> Result<super::guide::Outcome, Error> {
    let (set, check) = (set.clone(), check.clone());
    within(limit, events, move |events| {
        super::guide::run(&set, &check, events)
    })
}

/// An event of any pipeline, owned so that it can cross threads ([`within`]).
enum Owned {
    Solver(crate::sat::Step),
    LowerBounds {
        c: usize,
        t: usize,
        seconds: f64,
    },
    Candidate(Iteration),
    CandidateVerdict(Vec<String>),
    ClosedLoopOf {
        candidate: usize,
        errors: usize,
    },
    Followed(super::follow::Round),
    NoisyPart(super::lazy_noisy::PartRound),
    NoisyBound(super::lazy_noisy::Bounds),
    Guide(super::guide::Stage),
    Lazy {
        round: usize,
        encoded: usize,
        total: usize,
        diverging: usize,
    },
}

impl Owned {
    fn of(e: Event<'_>) -> Option<Owned> {
        Some(match e {
            Event::Solver(s) => Owned::Solver(s),
            Event::LowerBounds { c, t, seconds } => Owned::LowerBounds { c, t, seconds },
            Event::Candidate(it) => Owned::Candidate(it.clone()),
            Event::CandidateVerdict { failing } => Owned::CandidateVerdict(failing.to_vec()),
            Event::ClosedLoopOf { candidate, errors } => Owned::ClosedLoopOf { candidate, errors },
            Event::Followed(r) => Owned::Followed(r.clone()),
            Event::NoisyPart(r) => Owned::NoisyPart(r),
            Event::NoisyBound(b) => Owned::NoisyBound(b),
            Event::Guide(s) => Owned::Guide(s),
            Event::Lazy {
                round,
                encoded,
                total,
                diverging,
            } => Owned::Lazy {
                round,
                encoded,
                total,
                diverging,
            },
            // The search has its own clock.
            _ => return None,
        })
    }

    fn emit(&self, events: Events<'_>) {
        match self {
            Owned::Solver(s) => events(Event::Solver(s.clone())),
            &Owned::LowerBounds { c, t, seconds } => events(Event::LowerBounds { c, t, seconds }),
            Owned::Candidate(it) => events(Event::Candidate(it)),
            Owned::CandidateVerdict(f) => events(Event::CandidateVerdict { failing: f }),
            &Owned::ClosedLoopOf { candidate, errors } => {
                events(Event::ClosedLoopOf { candidate, errors })
            }
            Owned::Followed(r) => events(Event::Followed(r)),
            &Owned::NoisyPart(r) => events(Event::NoisyPart(r)),
            &Owned::NoisyBound(b) => events(Event::NoisyBound(b)),
            Owned::Guide(s) => events(Event::Guide(s.clone())),
            &Owned::Lazy {
                round,
                encoded,
                total,
                diverging,
            } => events(Event::Lazy {
                round,
                encoded,
                total,
                diverging,
            }),
        }
    }
}

/// `job` (any pipeline: plain, noisy or modular synthesis, with or without NuSMV), given up
/// after `limit` with [`Error::Interrupted`] naming the last step it reported. The job runs on
/// a thread of its own and its events reach `events` from here ([`exact_within`] is this with
/// what the exact loop had found when the limit passed).
pub fn within<T: Send + 'static>(
    limit: Duration,
    events: Events<'_>,
    job: impl FnOnce(Events<'_>) -> Result<T, Error> + Send + 'static,
) -> Result<T, Error> {
    let deadline = Instant::now() + limit;
    let (tx, rx) = mpsc::channel::<Result<Owned, Box<Result<T, Error>>>>();
    {
        let forward = tx.clone();
        std::thread::spawn(move || {
            let result = job(&mut |e| {
                if let Some(m) = Owned::of(e) {
                    // The receiver is gone once the limit passed: nobody listens any more.
                    let _ = forward.send(Ok(m));
                }
            });
            let _ = tx.send(Err(Box::new(result)));
        });
    }
    let mut last: Option<String> = None;
    loop {
        let wait = deadline.saturating_duration_since(Instant::now());
        match rx.recv_timeout(wait) {
            Ok(Ok(m)) => {
                if let Owned::Solver(s) = &m {
                    last = Some(s.to_string());
                }
                m.emit(events);
            }
            Ok(Err(result)) => return *result,
            Err(mpsc::RecvTimeoutError::Timeout) => {
                return Err(Error::Interrupted {
                    seconds: limit.as_secs_f64(),
                    last: last.unwrap_or_else(|| "none yet".into()),
                })
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                return Err(Error::Bug(
                    "the synthesis thread ended without a result".into(),
                ))
            }
        }
    }
}
