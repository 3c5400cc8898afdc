//! The main job: the least machine that reproduces the recordings and that NuSMV verifies in
//! closed loop with the plant, the same for every front end (`synth --ltl`, `synth infer
//! --ltl`).
//!
//! In: the recordings, a [`Check`], what the recordings say about the properties (an
//! [`Explanation`] from [`explain::refuse_violations`]) and [`Options`]. Out: a
//! [`VerifiedMachine`]: the machine, NuSMV's certificate and the [`Summary`] that says how it
//! was found and what is proven; or an [`Error`] whose notes say what is known about why there
//! is none. Progress comes as [`Event`]s, the strategy's own turns as [`Step`]s.
//!
//! # The strategy
//! Several engines, tried in an order that depends on the problem:
//! 1. Where the properties read inputs the recordings never vary, the closed-loop game's guide
//!    ([`guide`]) runs first: the exact loop learns such behaviour one counterexample at a
//!    time, the game answers for every behaviour of the plant at once. Its machine is least
//!    only for the recordings and the guide's own runs; it is made smaller in process
//!    ([`polish`]), and the exact loop gets a turn below it (at most its states; half the
//!    time the guide took, at least 2 s): a smaller verified machine replaces it. No turn
//!    when the machine meets the recordings' own lower bounds, as a turn of the exact loop
//!    reported them ([`Floor`]): then it is least. The guide, the polish and that turn keep
//!    the user's algorithm form and start state.
//! 2. Otherwise the exact loop ([`exact`]). Where the recordings show every value but not
//!    every behaviour the properties need, it can refute candidates one behaviour at a time
//!    for minutes: after [`STALL_ROUNDS`] refuted candidates in a row with the same number of
//!    states, or [`STALL_TIME`] of its own CPU time refuting them ([`STALL_HARD_TIME`] once a
//!    candidate's descent in `T` there has run out of its work budget), it hands over to the
//!    guide, as in 1. When the guide has no machine, the exact loop again for the time left;
//!    when it gives up the error says what the recordings never show and what the game says
//!    of the problem. Both later turns of the loop (below the guide's machine, or alone
//!    again) start from the counterexamples the first one learned.
//! 3. With the search ([`Method::Search`]): its verified machine bounds the exact loop (at
//!    most its states, for as long as the search took, at least 30 s); when that finds no
//!    smaller machine, the search's machine is made small along the closed loop
//!    ([`search::shrink`]) for the time left.
//!
//! "Smaller" is one order everywhere: [`Size::is_smaller_than`] (C, then T, then N).
//!
//! # The time limit
//! One deadline, counted from the start of the run ([`Limit`]), holds for the guide and every
//! exact loop: their SAT calls, NuSMV checks and the game stop there, on this thread
//! ([`super::limit`]). The search keeps its own clock ([`search::Options::time_limit`]) and the
//! shrinking runs to its end, as the exact loop below it then has only what is left.

pub(crate) mod summary;

pub use summary::{BelowGuideSummary, ExactSummary, GuideSummary, SearchSummary, Summary, Turn};

use super::cegis::Stall;
use super::exact::{self, Certificate, Exact};
use super::explain::{self, Explanation};
use super::guide::RepairStart;
use super::limit::Limit;
use super::{guide, polish, search, Check, Class, Error, Event, Events};
use crate::ecc::{Ecc, Size};
use crate::scenario::ScenarioSet;
use std::cell::Cell;
use std::time::Duration;

/// How the main job synthesizes.
#[derive(Debug, Clone)]
pub enum Method {
    /// Exact SAT with counterexample-guided refinement, guided by the closed-loop game where
    /// the recordings never vary what the properties read.
    Sat,
    /// Metaheuristic search with these options; its machine shrunk, and the exact loop below it.
    Search(search::Options),
}

/// Settings of the main job.
#[derive(Debug, Clone)]
pub struct Options {
    /// How it synthesizes.
    pub(crate) method: Method,
    /// The exact loop. Its turns below the guide's and the shrunk machine keep no failed
    /// model and have at most that machine's states.
    pub exact: exact::Options,
    /// The time limit, counted from the start of the run.
    pub(crate) limit: Limit,
}

/// A turn of the strategy, for progress.
#[derive(Debug, Clone)]
pub enum Step {
    /// The guide starts: the recordings never show what some property reads, or the exact
    /// loop stalled.
    GuideStarted,
    /// The exact loop stalled (why): the guide takes over.
    Stalled {
        /// Why.
        why: String,
    },
    /// The guide gave no machine (why); the exact loop goes on.
    GuideDeclined {
        /// Why.
        why: String,
    },
    /// The exact loop looks below the guide's machine.
    BelowGuide {
        /// At most this many states (the guide's machine's).
        states: usize,
        /// For at most this many seconds.
        seconds: f64,
    },
    /// The guide's machine meets the recordings' own lower bounds: it is least, and the exact
    /// loop has no turn below it.
    GuideLeast {
        /// The bounds, in words.
        floor: String,
    },
    /// The exact loop's turn below the guide ended without a smaller machine.
    GuideStands {
        /// What the turn found (as in [`GuideSummary::exact_loop_below_it`]).
        after: String,
    },
    /// The guide's machine being made smaller in process: the smallest so far (at most one
    /// line every [`polish::PROGRESS_EVERY`]).
    Polishing {
        /// Its size.
        size: Size,
        /// Moves judged so far.
        judged: usize,
        /// Seconds since the moves began.
        seconds: f64,
    },
    /// The guide's machine made smaller in process, and NuSMV's word on it (one line).
    Polished {
        /// What was found.
        line: String,
    },
    /// The exact loop gave up: the closed-loop game tells whether any controller exists.
    Realizability,
    /// The search's machine, before it is made small along the closed loop.
    Searched {
        /// Its size.
        size: Size,
    },
    /// The exact loop looks below the search's machine.
    BelowSearched {
        /// At most this many states (the search machine's).
        states: usize,
        /// For at most this many seconds.
        seconds: f64,
    },
    /// The exact loop below the search's machine ended (why) without a smaller machine: the
    /// search's machine is made small along the closed loop.
    BelowSearchedStopped {
        /// Why.
        why: String,
    },
    /// The search's machine shrunk along the closed loop (its own size when the time ran out
    /// first).
    Shrunk {
        /// Its size.
        size: Size,
        /// Whether the shrinking ended before the time limit.
        finished: bool,
    },
}

/// The main job's machine, verified by NuSMV.
#[derive(Debug, Clone)]
pub struct VerifiedMachine {
    /// The machine; it reproduces the recordings.
    pub(crate) ecc: Ecc,
    /// NuSMV's verdicts (all hold) and the closed-loop model it checked.
    pub(crate) certificate: Certificate,
    /// How it was found and what is proven (`summary.json`).
    pub(crate) summary: Summary,
}

/// The main job (module documentation) on `set` with `check`; `explained` is what the
/// recordings say about the properties.
pub fn run(
    set: &ScenarioSet,
    check: &Check,
    explained: &Explanation,
    opts: &Options,
    events: Events<'_>,
) -> Result<VerifiedMachine, Error> {
    let floor = Cell::new(None);
    let events = &mut |e: Event<'_>| {
        if let Event::LowerBounds { c, t, n, .. } = e {
            floor.set(Some(Floor { c, t, n }));
        }
        events(e)
    };
    let job = Job {
        set,
        check,
        explained,
        floor: &floor,
    };
    let mut guide_said = None;
    if guides(opts, explained) {
        // First: a guide that cannot repair the least machine declines at once, and the
        // exact loop has its turn (a machine repaired from the tree's has more states than
        // the loop usually finds).
        match guided(&job, opts, RepairStart::Least, events)? {
            Guided::Machine(m) => return Ok(*m),
            Guided::Declined(why) => guide_said = Some(why),
        }
    }
    match &opts.method {
        Method::Sat if guide_said.is_none() && guide_states(opts) => {
            handing_over(&job, opts, events)
        }
        Method::Sat => exact_loop(set, check, explained, opts, guide_said, events),
        Method::Search(s) => searched(set, check, opts, s, events),
    }
}

/// Whether the guide runs first: properties that read what the recordings never vary, on a
/// problem the guide states ([`guide_states`]).
fn guides(opts: &Options, explained: &Explanation) -> bool {
    !explained.unrecorded.is_empty() && guide_states(opts)
}

/// Whether the guide can take a turn: the exact method and a problem the guide's own
/// synthesis states (no negative scenarios; any algorithm form and start state, which its
/// machine keeps).
fn guide_states(opts: &Options) -> bool {
    matches!(opts.method, Method::Sat) && opts.exact.negatives.is_empty()
}

/// Refuted candidates in a row with the same number of states after which the exact loop,
/// where the recordings show every value the properties read, hands over to the guide: it
/// then converges within a few candidates where the recordings show the behaviours the
/// properties need too, and refutes candidates one behaviour at a time, for minutes, where
/// they do not.
pub(crate) const STALL_ROUNDS: usize = 30;

/// The CPU time of the loop's own work (SAT, in-process checks) after which the exact loop hands
/// over to the guide when its candidates of one number of states keep being refuted (at least
/// 3 of them): there each SAT call can grow to tens of seconds, so that few candidates take
/// minutes. It lies above what a loop that converges spends (Pick-and-Place from four
/// scenarios, `BENCHMARKS.md`): a hand-over there costs the guide's turn and the loop's again.
pub(crate) const STALL_TIME: Duration = Duration::from_secs(60);

/// The CPU time after which the exact loop hands over, as with [`STALL_TIME`], once a
/// candidate's descent in `T` with that many states has run out of its work budget: there the
/// SAT calls can grow from under a second to tens of seconds each (generated stations whose
/// one recorded run serves one request of several), so that [`STALL_TIME`] is reached only
/// after minutes. Loops that converge and run out there have spent at most about 4 s when
/// they do (stations 1 and 8, the distribution station); Pick-and-Place from four scenarios
/// never runs out (its candidates have the proven least `T`).
pub(crate) const STALL_HARD_TIME: Duration = Duration::from_secs(10);

/// The exact loop, handing over to the guide when it stalls ([`STALL_ROUNDS`]); when the
/// guide has no machine, the exact loop again for the time left.
fn handing_over(
    job: &Job<'_>,
    opts: &Options,
    events: Events<'_>,
) -> Result<VerifiedMachine, Error> {
    let Job {
        set,
        check,
        explained,
        ..
    } = *job;
    let mut first = opts.exact.clone();
    first.stall = Some(Stall {
        rounds: STALL_ROUNDS,
        time: STALL_TIME,
        hard_time: STALL_HARD_TIME,
    });
    let (why, learned) = match opts.limit.exact(set, check, &first, events) {
        Ok(r) => {
            let (ecc, certificate, exact) = exact_parts(r, opts)?;
            return Ok(VerifiedMachine {
                ecc,
                certificate,
                summary: Summary::Exact(exact),
            });
        }
        Err(Error::Cegis(e)) => e
            .into_stall()
            .map_err(|e| why_none(set, check, explained, opts, None, Error::Cegis(e), events))?,
        Err(e) => return Err(why_none(set, check, explained, opts, None, e, events)),
    };
    events(Event::MainJob(Step::Stalled { why }));
    // The loop's later turns (below the guide's machine, or alone again) start from what it
    // learned: the same counterexamples would otherwise be found again, one candidate at a time.
    let opts = &Options {
        exact: exact::Options {
            learned,
            ..opts.exact.clone()
        },
        ..opts.clone()
    };
    // The loop has stalled: a larger machine from the guide is better than its going on alone.
    match guided(job, opts, RepairStart::LeastOrTree, events)? {
        Guided::Machine(m) => Ok(*m),
        Guided::Declined(why) => exact_loop(set, check, explained, opts, Some(why), events),
    }
}

/// What every turn of the main job reads.
struct Job<'a> {
    set: &'a ScenarioSet,
    check: &'a Check,
    /// What the recordings say about the properties.
    explained: &'a Explanation,
    /// The recordings' own lower bounds, once a turn of the exact loop has reported them.
    floor: &'a Cell<Option<Floor>>,
}

/// The lower bounds of the recordings alone, as the exact loop reports them
/// ([`Event::LowerBounds`]): the least `C`, the least `T` with `C` states (0: not proven) and
/// the least `N` with both (when proven). They bound every machine in the asked form that
/// reproduces the recordings, verified or not ([`crate::sat::least_tree_exact`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Floor {
    c: usize,
    t: usize,
    n: Option<usize>,
}

impl Floor {
    /// Whether `ecc` meets the bounds in C, T and N: then no machine that reproduces the
    /// recordings is smaller. Only for guards that are conjunctions, the machines the bounds
    /// are proven for.
    fn met_by(&self, ecc: &Ecc) -> bool {
        let size = ecc.size();
        let cubes =
            (ecc.states.iter().flat_map(|s| &s.transitions)).all(|t| t.guard.as_cube().is_some());
        cubes && self.t > 0 && (size.c, size.t, Some(size.n)) == (self.c, self.t, self.n)
    }
}

impl std::fmt::Display for Floor {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the lower bounds of the recordings alone (C >= {}, T >= {}, N >= {})",
            self.c,
            self.t,
            self.n.unwrap_or(0)
        )
    }
}

/// What the guide's turn gives.
enum Guided {
    /// A verified machine (the guide's, or the exact loop's below it).
    Machine(Box<VerifiedMachine>),
    /// No machine, and why.
    Declined(String),
}

/// The guide within the limit, and the exact loop's turn below its machine.
fn guided(
    job: &Job<'_>,
    opts: &Options,
    start: RepairStart,
    events: Events<'_>,
) -> Result<Guided, Error> {
    let (set, check) = (job.set, job.check);
    let started = std::time::Instant::now();
    events(Event::MainJob(Step::GuideStarted));
    let max_states = opts.exact.sat.max_states;
    let conventions = opts.exact.sat.conventions();
    let why = match opts.limit.guide(set, check, conventions, start, events) {
        Ok(guide::Outcome::Verified(g)) if g.size.c <= max_states => {
            let m = below_guide(job, *g, started.elapsed(), opts, events)?;
            return Ok(Guided::Machine(Box::new(m)));
        }
        Ok(guide::Outcome::Verified(g)) => format!(
            "its machine has {} states, more than --max-states {max_states}",
            g.size.c
        ),
        Ok(guide::Outcome::NotHere(why)) => why,
        Err(Error::Interrupted { seconds, .. }) => {
            let limit = Error::NoMachine(format!(
                "time limit of {seconds} s reached before a verified machine (raise --time-limit SECONDS): the closed-loop game's guide had not ended"
            ));
            return Err(noted(
                limit,
                job.explained.unrecorded_line().into_iter().collect(),
            ));
        }
        Err(e) => return Err(e),
    };
    events(Event::MainJob(Step::GuideDeclined { why: why.clone() }));
    Ok(Guided::Declined(why))
}

/// The exact loop's turn below the guide's machine `g`, which took `spent`: its machine if
/// smaller, else `g`, within a quarter of `spent` (at least [`MIN_TURN`]). No turn when `g`,
/// made smaller, meets the recordings' own lower bounds: it is least.
fn below_guide(
    job: &Job<'_>,
    g: guide::Guided,
    spent: Duration,
    opts: &Options,
    events: Events<'_>,
) -> Result<VerifiedMachine, Error> {
    let (set, check) = (job.set, job.check);
    // Where the turn finds a smaller machine, the loop converges within a few candidates;
    // where the recordings are sparse (Pick-and-Place from one or two scenarios, the
    // generated stations) its candidates at the recordings' least C are refuted one
    // behaviour at a time, and a longer turn only delays the result.
    let budget = (opts.limit.left()).min((spent / 4).max(MIN_TURN));
    let mut stages: Vec<String> = g.stages.iter().map(ToString::to_string).collect();
    let g = polished(set, check, opts, g, opts.limit.left(), &mut stages, events)?;
    let budget = budget.min(opts.limit.left());
    if let Some(floor) = job.floor.get().filter(|f| f.met_by(&g.ecc)) {
        let after = format!("not run: the machine meets {floor}");
        events(Event::MainJob(Step::GuideLeast {
            floor: floor.to_string(),
        }));
        return Ok(guide_machine(g, stages, after, true, opts));
    }
    let mut after = "not run: no time left".to_string();
    if !budget.is_zero() {
        events(Event::MainJob(Step::BelowGuide {
            states: g.size.c,
            seconds: budget.as_secs_f64(),
        }));
        let exact = bounded(opts, g.size.c);
        match Limit::from_now(budget).exact(set, check, &exact, events) {
            Ok(r) if r.synthesis.size.is_smaller_than(&g.size) => {
                let (ecc, certificate, exact) = exact_parts(r, opts)?;
                let summary = Summary::Turn(Turn::BelowGuide(BelowGuideSummary {
                    exact,
                    guide_size: g.size,
                    guide: stages,
                }));
                return Ok(VerifiedMachine {
                    ecc,
                    certificate,
                    summary,
                });
            }
            Ok(_) => after = "no smaller machine".into(),
            Err(Error::TimeLimit { so_far, .. }) => {
                let by_nusmv = (so_far.candidates.iter())
                    .filter(|c| c.checked_by == "NuSMV")
                    .count();
                after = format!(
                    "no smaller verified machine within {:.1} s ({} candidates, {by_nusmv} checked by NuSMV)",
                    budget.as_secs_f64(),
                    so_far.candidates.len()
                );
            }
            // A bug stays one; anything else ends the turn, not the verified result.
            Err(e) if e.class() == Class::Bug => return Err(e),
            Err(e) => after = format!("stopped: {e}"),
        }
        events(Event::MainJob(Step::GuideStands {
            after: after.clone(),
        }));
    }
    // The turn computes the recordings' lower bounds when no turn before it did.
    let least = job.floor.get().is_some_and(|f| f.met_by(&g.ecc));
    Ok(guide_machine(g, stages, after, least, opts))
}

/// The shortest turn of the exact loop below the guide's machine.
const MIN_TURN: Duration = Duration::from_secs(2);

/// The guide's machine `g` made smaller by local moves the in-process checker accepts
/// ([`polish`]), in the form `opts` asks (algorithms, start state), within `budget` (the run's
/// time left), when NuSMV verifies the result; else `g`. The outcome is added to `stages`.
fn polished(
    set: &ScenarioSet,
    check: &Check,
    opts: &Options,
    mut g: guide::Guided,
    budget: Duration,
    stages: &mut Vec<String>,
    events: Events<'_>,
) -> Result<guide::Guided, Error> {
    let conventions = opts.exact.sat.conventions();
    let now = std::time::Instant::now();
    // No time limit: a day is as good as none.
    let deadline = (now.checked_add(budget)).unwrap_or(now + Duration::from_secs(86_400));
    let Some(polish::Shrunk {
        ecc: small,
        converged,
    }) = polish::shrink(
        set,
        check,
        &g.ecc,
        conventions,
        deadline,
        &mut |size, judged| {
            events(Event::MainJob(Step::Polishing {
                size,
                judged,
                seconds: now.elapsed().as_secs_f64(),
            }))
        },
    )
    else {
        return Ok(g);
    };
    let ended = match converged {
        true => "no move makes it smaller still",
        false => "stopped at its bound on moves or at the time limit",
    };
    let mut verifier = check.verifier()?;
    let v = verifier.verify_with(&small, crate::nusmv::CheckMode::VerdictsOnly)?;
    g.nusmv_calls += 1;
    g.nusmv_seconds += v.report.nusmv_seconds;
    let (from, to) = (g.size, small.size());
    let line = match v.report.failing().is_empty() {
        true => format!(
            "guide: its machine made smaller by merging states and dropping transitions and literals while every property holds: {to} (from {from}; {ended}; NuSMV verified it)"
        ),
        false => format!(
            "guide: its machine made smaller in process ({to}) fails {} in NuSMV; the guide's machine stays",
            v.report.failing().join(", ")
        ),
    };
    events(Event::MainJob(Step::Polished { line: line.clone() }));
    stages.push(line);
    if v.report.failing().is_empty() {
        g.size = to;
        g.ecc = small;
        g.certificate = Certificate {
            report: v.report,
            model_text: v.model.text,
        };
        g.polished = true;
    }
    Ok(g)
}

/// The guide's machine `g` as the result; `least` when it meets the recordings' own lower
/// bounds ([`Floor::met_by`]).
fn guide_machine(
    g: guide::Guided,
    stages: Vec<String>,
    after: String,
    least: bool,
    opts: &Options,
) -> VerifiedMachine {
    let summary = Summary::Turn(Turn::Guide(GuideSummary {
        exact_loop_below_it: after,
        size: g.size,
        proven_least: least,
        least_for_recordings_and_runs: g.origin == guide::Origin::LeastForRuns,
        for_runs_unproven: g.origin == guide::Origin::ForRuns,
        states_at_least: g.least_states,
        made_smaller: g.polished,
        conventions: opts.exact.sat.conventions().to_string(),
        guide: stages,
        report: g.certificate.report.clone(),
        sat_seconds: g.sat_seconds,
        nusmv_calls: g.nusmv_calls,
        nusmv_seconds: g.nusmv_seconds,
        total_seconds: opts.limit.elapsed(),
    }));
    VerifiedMachine {
        ecc: g.ecc,
        certificate: g.certificate,
        summary,
    }
}

/// The exact loop's options for a turn below a machine of `states` states.
fn bounded(opts: &Options, states: usize) -> exact::Options {
    let mut exact = opts.exact.clone();
    exact.sat.max_states = states;
    exact.keep_failed_model = None;
    exact
}

/// The machine, certificate and summary of the exact loop's result `r`.
fn exact_parts(r: Exact, opts: &Options) -> Result<(Ecc, Certificate, ExactSummary), Error> {
    let Some(certificate) = r.certificate.clone() else {
        return Err(Error::Bug(
            "the exact loop with a check gave no certificate".into(),
        ));
    };
    let summary = ExactSummary::of(&r, &certificate.report, opts.limit.elapsed());
    Ok((r.synthesis.ecc, certificate, summary))
}

/// The exact loop within the limit; when it gives up, the error with what is known.
fn exact_loop(
    set: &ScenarioSet,
    check: &Check,
    explained: &Explanation,
    opts: &Options,
    guide_said: Option<String>,
    events: Events<'_>,
) -> Result<VerifiedMachine, Error> {
    match opts.limit.exact(set, check, &opts.exact, events) {
        Ok(r) => {
            let (ecc, certificate, exact) = exact_parts(r, opts)?;
            Ok(VerifiedMachine {
                ecc,
                certificate,
                summary: Summary::Exact(exact),
            })
        }
        Err(e) => Err(why_none(set, check, explained, opts, guide_said, e, events)),
    }
}

/// The exact loop's error `e` with notes: when it found no machine within the limits, what
/// the recordings never show and what the closed-loop game says (the guide's word if it
/// spoke, else the game solved now); when NuSMV rejected generated code, where the model is.
fn why_none(
    set: &ScenarioSet,
    check: &Check,
    explained: &Explanation,
    opts: &Options,
    guide_said: Option<String>,
    e: Error,
    events: Events<'_>,
) -> Error {
    let mut notes = Vec::new();
    if e.class() == Class::NoMachine {
        notes.extend(explained.unrecorded_line());
        match guide_said {
            Some(said) => notes.push(format!("guide: {said}")),
            None => {
                events(Event::MainJob(Step::Realizability));
                notes.extend(explain::realizability(set, &check.problem));
            }
        }
    }
    let kept =
        (opts.exact.keep_failed_model.as_ref()).filter(|k| e.in_generated_code() && k.is_file());
    if let Some(kept) = kept {
        notes.push(format!(
            "the model NuSMV was given is kept as {}",
            kept.display()
        ));
    }
    noted(e, notes)
}

/// `error` with `notes`, if any.
fn noted(error: Error, notes: Vec<String>) -> Error {
    match notes.is_empty() {
        true => error,
        false => Error::Noted {
            error: Box::new(error),
            notes,
        },
    }
}

/// The search, the exact loop below its machine and, when that finds no smaller machine, the
/// search's machine shrunk along the closed loop.
fn searched(
    set: &ScenarioSet,
    check: &Check,
    opts: &Options,
    s: &search::Options,
    events: Events<'_>,
) -> Result<VerifiedMachine, Error> {
    let r = search::run(set, check, s, None, events)?;
    let found = r.certified(set, s)?.clone();
    events(Event::MainJob(Step::Searched { size: found.size() }));
    let below = below_searched(set, check, opts, &found, events)?;
    let replaced_by_exact_loop = below.is_some();
    let (ecc, certificate, shrunk) = match below {
        Some(b) => {
            let (ecc, certificate, _) = exact_parts(b, opts)?;
            (ecc, certificate, None)
        }
        None => shrunk(set, check, opts, s, &r, &found, events)?,
    };
    let summary = SearchSummary {
        seed: s.seed,
        start: format!("{:?}", s.start).to_lowercase(),
        size: ecc.size(),
        searched_size: found.size(),
        shrunk_size: shrunk.as_ref().map(|(size, _)| *size),
        replaced_by_exact_loop,
        shrink_rounds: shrunk.map(|(_, rounds)| rounds).unwrap_or_default(),
        fitness: r.outcome.fitness,
        search: r.outcome.stats.clone(),
        nusmv_runs: r.nusmv_runs,
        in_process_checks: r.in_process_checks,
        cache_hits: r.cache_hits,
        report: r.verification.report.clone(),
        total_seconds: opts.limit.elapsed(),
    };
    Ok(VerifiedMachine {
        ecc,
        certificate,
        summary: Summary::Turn(Turn::Search(Box::new(summary))),
    })
}

/// The least time the exact loop gets below the search's machine before it is shrunk.
const BELOW_SEARCHED_MIN: Duration = Duration::from_secs(30);

/// The exact loop with at most the search machine's states, for as long as the search took
/// (at least [`BELOW_SEARCHED_MIN`], at most the time left): its machine if it is smaller than
/// `found`. Where the recordings show what the properties need, the exact loop alone converges
/// within seconds; the search's machine bounds it and says a verified machine exists.
fn below_searched(
    set: &ScenarioSet,
    check: &Check,
    opts: &Options,
    found: &Ecc,
    events: Events<'_>,
) -> Result<Option<Exact>, Error> {
    let spent = Duration::from_secs_f64(opts.limit.elapsed());
    let budget = opts.limit.left().min(spent.max(BELOW_SEARCHED_MIN));
    if budget.is_zero() {
        return Ok(None);
    }
    events(Event::MainJob(Step::BelowSearched {
        states: found.states.len(),
        seconds: budget.as_secs_f64(),
    }));
    let exact = bounded(opts, found.states.len());
    let why = match Limit::from_now(budget).exact(set, check, &exact, events) {
        Ok(r) if r.synthesis.size.is_smaller_than(&found.size()) => return Ok(Some(r)),
        Ok(_) => "no smaller machine".to_string(),
        Err(Error::TimeLimit { .. }) => format!(
            "no smaller verified machine within {:.1} s",
            budget.as_secs_f64()
        ),
        Err(e) if e.class() == Class::Bug => return Err(e),
        Err(e) => e.to_string(),
    };
    events(Event::MainJob(Step::BelowSearchedStopped { why }));
    Ok(None)
}

/// The size of a machine made small along the closed loop, and the rounds it took.
type MadeSmall = (Size, Vec<super::follow::Round>);

/// The search's machine `found` (verified in `r`) shrunk along the closed loop within the time
/// left: the shrunk machine, its certificate, size and rounds; when the time runs out first,
/// `found` itself with its certificate and no size.
fn shrunk(
    set: &ScenarioSet,
    check: &Check,
    opts: &Options,
    s: &search::Options,
    r: &search::Searched,
    found: &Ecc,
    events: Events<'_>,
) -> Result<(Ecc, Certificate, Option<MadeSmall>), Error> {
    let shrunk = opts.limit.run(events, |deadline, events| {
        search::shrink_until(set, found, check, s.max_out_degree, deadline, events)
    });
    match shrunk {
        Ok((small, followed)) => {
            events(Event::MainJob(Step::Shrunk {
                size: small.size,
                finished: true,
            }));
            let size = small.size;
            Ok((
                small.ecc,
                followed.certificate,
                Some((size, followed.rounds)),
            ))
        }
        // Out of time: the search's machine, which NuSMV verified, stands.
        Err(Error::Interrupted { .. }) => {
            events(Event::MainJob(Step::Shrunk {
                size: found.size(),
                finished: false,
            }));
            let v = &r.verification;
            let certificate = Certificate {
                report: v.report.clone(),
                model_text: v.model.text.clone(),
            };
            Ok((found.clone(), certificate, None))
        }
        Err(e) => Err(e),
    }
}

#[cfg(test)]
mod tests;
