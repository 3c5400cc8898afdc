//! Search-based synthesis in closed loop: colonies of `(1+λ)` strategies evolve machines
//! against the scenarios (Chivilikhin, Shalyto, Patil and Vyatkin, "Reconstruction of
//! Function Block Logic using Metaheuristic Algorithm: Initial Explorations") and against
//! NuSMV's verdicts with counterexample-weighted mutation (the function-block reconstruction
//! augmented with closed-loop NuSMV verification over a hand-made surrogate plant model); the
//! machine found is checked once more by NuSMV in a fresh session.

use super::{Check, Error, Event, Events};
use crate::ecc::Ecc;
use crate::sat;
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use crate::search::oracle::{Checker, Oracle, Shared};
use crate::search::{self, Machine, Outcome, ScenarioData, Weights};
use crate::verify::Verification;
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Where the colonies start.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Start {
    /// Random machines (the seeds' method).
    Random,
    /// The minimal machine SAT finds for the scenarios alone (verification left to the search).
    Sat,
}

/// Settings of a search run.
#[derive(Debug, Clone)]
pub struct Options {
    /// Seed of every random choice.
    pub seed: u64,
    /// Worker threads (`None`: all cores); the result does not depend on it.
    pub threads: Option<usize>,
    /// Give up after this many seconds.
    pub time_limit: f64,
    /// States of every candidate (`None`: 8, or the SAT machine's with [`Start::Sat`]).
    pub states: Option<usize>,
    /// Colonies sharing their best.
    pub colonies: usize,
    /// Where the colonies start.
    pub start: Start,
    /// Probability of verifying a candidate below the scenario threshold.
    pub verify_probability: f64,
    /// With [`Start::Sat`]: transitions per state of the SAT start.
    pub max_out_degree: usize,
    /// Fitness weights; zero verification weights search on the scenarios alone (NuSMV then
    /// only gives the final verdict).
    pub weights: Weights,
    /// Skip NuSMV for a child that still follows a counterexample of its colony.
    pub replay_counterexamples: bool,
    /// Report every round as [`Event::SearchRound`] (else at most one a second).
    pub every_round: bool,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            seed: 1,
            threads: None,
            time_limit: 600.0,
            states: None,
            colonies: 4,
            start: Start::Sat,
            verify_probability: 0.001,
            max_out_degree: super::exact::DEFAULT_OUT_DEGREE,
            weights: Weights::default(),
            replay_counterexamples: true,
            every_round: false,
        }
    }
}

/// The result of a search: the best machine and NuSMV's final verdict on it.
pub struct Searched {
    /// What the search ended with.
    pub outcome: Outcome,
    /// NuSMV's check of the machine in a fresh session, on every property.
    pub verification: Verification,
    /// NuSMV runs during the search, and answers from its cache.
    pub nusmv_runs: u64,
    pub cache_hits: u64,
    /// States reachable from the initial state.
    pub reachable_states: usize,
}

impl Searched {
    /// The machine, if it is a verified controller: it reproduces every scenario (replayed
    /// here) and NuSMV's final check says every property holds.
    pub fn certified(&self, set: &ScenarioSet, opts: &Options) -> Result<&Ecc, Error> {
        let o = &self.outcome;
        if !o.perfect {
            return Err(Error::NoMachine(format!(
                "no verified controller within --time-limit {} s (seed {}): the best reproduces {}/{} scenarios{}; raise --time-limit or try --start sat",
                opts.time_limit,
                opts.seed,
                o.score.reproduced,
                o.score.scenarios,
                o.verdicts
                    .as_ref()
                    .map(|v| format!(" and satisfies {}/{} properties", v.satisfied, v.total))
                    .unwrap_or_default()
            )));
        }
        if let Err(e) = set.check(&o.ecc) {
            return Err(Error::Bug(format!(
                "the search's machine does not replay the scenarios: {e}"
            )));
        }
        let report = &self.verification.report;
        if !report.all_hold() {
            return Err(Error::Bug(format!(
                "the search's machine fails {} in the final NuSMV check",
                report.failing().join(", ")
            )));
        }
        Ok(&o.ecc)
    }
}

/// The number of worker threads: as given, or every core.
pub fn threads(arg: Option<usize>) -> usize {
    arg.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    })
}

/// The minimal machine SAT finds for the scenarios alone (conjunction guards, at most
/// `out_degree` transitions per state, as in the exact loop), as a search machine.
pub fn sat_start(
    set: &ScenarioSet,
    out_degree: usize,
    events: Events<'_>,
) -> Result<Machine, Error> {
    let t = Instant::now();
    let tree = ScenarioTree::build(set)?;
    let opts = sat::Options {
        cube_slots: Some(out_degree.max(1)),
        ..sat::Options::default()
    };
    let s = sat::synthesize(set, &tree, &opts, &mut |_| {})?;
    events(Event::SatStart {
        size: s.size,
        seconds: t.elapsed().as_secs_f64(),
    });
    Machine::from_ecc(&s.ecc).ok_or_else(|| {
        Error::Bug("the SAT machine has a guard that is not a sum of products".into())
    })
}

/// Searches for a machine that reproduces `set` and satisfies `check`'s properties; NuSMV
/// checks the best machine at the end whatever the search saw. `initial` overrides the start
/// machines (for repeated runs from one SAT start); `None` follows `opts.start`.
pub fn run(
    set: &ScenarioSet,
    check: &Check,
    opts: &Options,
    initial: Option<Vec<Machine>>,
    events: Events<'_>,
) -> Result<Searched, Error> {
    let data = ScenarioData::new(set)?;
    let initial = match (initial, opts.start) {
        (Some(i), _) => i,
        (None, Start::Random) => vec![],
        (None, Start::Sat) => vec![sat_start(set, opts.max_out_degree, events)?],
    };
    let states = opts
        .states
        .map(|s| s.max(initial.first().map_or(1, |m| m.states.len())))
        .or(initial.first().map(|m| m.states.len()))
        .unwrap_or(8);
    let shared = Arc::new(Shared::default());
    let config = search::Config {
        states,
        colonies: opts.colonies.max(1),
        seed: opts.seed,
        threads: threads(opts.threads),
        time_limit: Some(Duration::from_secs_f64(opts.time_limit.max(0.0))),
        verify_probability: opts.verify_probability.clamp(0.0, 1.0),
        weights: opts.weights,
        replay_counterexamples: opts.replay_counterexamples,
        initial,
        ..search::Config::default()
    };
    events(Event::SearchStarted {
        seed: config.seed,
        states: config.states,
        colonies: config.colonies,
        threads: config.threads,
        time_limit: opts.time_limit,
    });
    let searches_properties = opts.weights.sat > 0.0 || opts.weights.ce > 0.0;
    let checkers: Vec<Box<dyn Checker>> = if searches_properties {
        (0..config.colonies)
            .map(|_| {
                Ok(Box::new(Oracle::new(check.verifier()?, shared.clone())) as Box<dyn Checker>)
            })
            .collect::<Result<_, Error>>()?
    } else {
        Vec::new()
    };
    let mut last = Instant::now();
    let outcome = search::run(&data, &config, checkers, &mut |p| {
        if opts.every_round || last.elapsed() >= Duration::from_secs(1) {
            last = Instant::now();
            events(Event::SearchRound(p));
        }
    })?;
    let nusmv_runs = shared.runs.load(Ordering::Relaxed);
    let cache_hits = shared.hits.load(Ordering::Relaxed);
    events(Event::SearchEnded {
        seconds: outcome.stats.seconds,
        evaluations: outcome.stats.evaluations,
        nusmv_runs,
        cache_hits,
    });
    // The claim rests on this check alone: a fresh session, every property.
    let verification = check.verifier()?.verify(&outcome.ecc)?;
    let reachable_states = reachable_states(&outcome.ecc);
    Ok(Searched {
        outcome,
        verification,
        nusmv_runs,
        cache_hits,
        reachable_states,
    })
}

/// States reachable from the initial state along transitions.
fn reachable_states(ecc: &Ecc) -> usize {
    let mut seen = vec![false; ecc.states.len()];
    let mut stack = vec![0usize];
    seen[0] = true;
    while let Some(s) = stack.pop() {
        for t in &ecc.states[s].transitions {
            if !seen[t.target.0] {
                seen[t.target.0] = true;
                stack.push(t.target.0);
            }
        }
    }
    seen.iter().filter(|&&b| b).count()
}
