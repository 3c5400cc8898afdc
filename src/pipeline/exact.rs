//! Exact synthesis: the smallest ECC (least C, then K if asked, then T, then N) that
//! reproduces the scenarios and, given a [`Check`], satisfies every property in closed loop
//! as NuSMV certifies (counterexample-guided refinement, [`super::cegis`]).
//!
//! In: a [`ScenarioSet`], [`Options`] and optionally a [`Check`] (plant, coupling, properties
//! and the NuSMV binary). Out: an [`Exact`]: the machine with its size and, when checked, the
//! iterations of the loop and NuSMV's report on the machine returned. `synth infer` runs it
//! without a check, the main job with one.
//!
//! # Scenarios only
//! The scenarios are merged into a [`ScenarioTree`]; passive steps become marks saying "no
//! transition fires here". The encoding ([`crate::sat`], varisat) colours the tree nodes with
//! states, one function per constraint family, so that the colouring is a deterministic ECC
//! that reproduces every step; BFS symmetry breaking removes renamings of the states. The
//! minimization is Algorithm 1 of the SAT reconstruction paper (Chivilikhin et al.): least C,
//! then, with `--minimize-k`, least K, then least T. All of it runs on one incremental solver:
//! the encoding is built for a window of states with "state in use" variables, and every bound
//! is a solver assumption on those or on totalizer outputs, so nothing is re-encoded between
//! bounds. Without a check the guard model is tree-exact: transitions exist only on recorded
//! inputs, and each guard is minimized by SAT afterwards (fewest literals, the priority order
//! chosen too), unrecorded inputs being don't-cares.
//!
//! # Verification in the loop
//! With a check the guards are part of the encoding: conjunctions of literals with first-fire
//! priority, as in the modular synthesis of the same paper. The solver's machine is then the
//! machine on *every* input vector, not only on the recorded ones, which the loop needs:
//! counterexamples run on inputs nobody recorded. The loop starts at the tree-exact minimum,
//! a proven lower bound on C and T in this model. Each
//! candidate is composed with the plant and checked by one long-lived `NuSMV -int` dialogue
//! ([`crate::verify::Verifier`]). A violated safety property `G p` yields the finite prefix up
//! to the first state where `p` fails; any other property yields a lasso, whose loop point is
//! chosen by evaluating the property on each of NuSMV's `-- Loop starts here` markers. Each
//! counterexample becomes a negative scenario the machine must leave somewhere
//! ([`crate::sat::negative`]), and the loop goes on on the same solver. Every "verified" comes
//! from NuSMV.
//!
//! # Results
//! - Pick-and-Place, main job: C 8, K 5, T 13, N 18 in three candidates. The first fails
//!   liveness properties; the in-process checker's lasso becomes a negative scenario, NuSMV
//!   verifies the next one, and the final pass finds nothing smaller.
//! - fbSAT's Pick-and-Place scenario sets with `binary` algorithms: with `--start-state` the
//!   published minimal sizes come out exactly (tests-1: C 6, T 8; tests-10: C 8, T 15). Without
//!   it one state fewer is enough (tests-1: C 5, T 7; tests-10: C 7, T 12): fbSAT's initial
//!   state is a dedicated start state that emits `INITO` and is never re-entered, while here
//!   state 0 is an ordinary state that transitions may return to.
//!
//! Times, and the commands that reproduce them, are in `BENCHMARKS.md`.

use super::cegis;
pub use super::cegis::{Iteration, UNCHANGED};
use super::{Check, Error, Event, Events};
use crate::sat::{self, Synthesis};
use crate::scenario::negative::{self, NegativeScenario};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use crate::verify::Report;
use std::path::PathBuf;

pub use crate::sat::Options as SatOptions;

/// Settings of exact synthesis.
#[derive(Debug, Clone)]
pub struct Options {
    /// The SAT synthesis: algorithms, bounds, guard model. With a [`Check`] the cube guard
    /// model is always used (at most [`DEFAULT_MAX_OUT_DEGREE`] transitions per state unless
    /// set), so the machine is defined on every input: counterexamples run on inputs nobody
    /// recorded.
    pub sat: SatOptions,
    /// With a check: give up after this many candidates.
    pub max_iterations: usize,
    /// Report every step of every minimization as [`Event::Solver`].
    pub verbose: bool,
    /// With a check: where to keep the closed-loop model of the last candidate when the
    /// loop fails (so the user can read what NuSMV choked on).
    pub keep_failed_model: Option<PathBuf>,
    /// With a check and the properties inside the encoding: the time the final machine's `T`
    /// and `N` may take to be proven minimal (past it they are reported as not proven).
    pub proof_budget: std::time::Duration,
    /// Behaviours the machine must not show (the user's `--negative` scenarios), beside those
    /// the loop learns from NuSMV.
    pub negatives: Vec<NegativeScenario>,
    /// With a check: when to stop with [`super::CegisError::Stalled`] (the loop learning one
    /// behaviour at a time: another engine's turn); `None`: never.
    pub stall: Option<super::Stall>,
    /// With a check: counterexamples an earlier turn of the loop on the same problem learned
    /// ([`super::CegisError::Stalled`]).
    pub learned: super::Learned,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            sat: SatOptions::default(),
            max_iterations: 500,
            verbose: false,
            keep_failed_model: None,
            proof_budget: DEFAULT_PROOF_BUDGET,
            negatives: Vec::new(),
            stall: None,
            learned: Default::default(),
        }
    }
}

/// The default of [`Options::proof_budget`].
/// Proving the literal count minimal in closed loop usually takes far longer than the whole
/// synthesis, so by default the final pass only looks briefly for a smaller machine.
pub(crate) const DEFAULT_PROOF_BUDGET: std::time::Duration = std::time::Duration::from_millis(500);

/// The out-degree bound of the closed-loop guard model when none is given.
pub(crate) const DEFAULT_MAX_OUT_DEGREE: usize = 6;

impl Options {
    fn sat(&self, verified: bool) -> SatOptions {
        let mut sat = self.sat.clone();
        if verified && sat.max_out_degree.is_none() {
            sat.max_out_degree = Some(DEFAULT_MAX_OUT_DEGREE);
        }
        sat
    }
}

/// NuSMV's word that a machine is correct in closed loop.
#[derive(Debug, Clone)]
pub struct Certificate {
    /// The verdict on every property (all hold).
    pub report: Report,
    /// The closed-loop model NuSMV verified.
    pub model_text: String,
}

/// The result of exact synthesis.
#[derive(Debug, Clone)]
pub struct Exact {
    /// The machine, its size and figures (replayed on every scenario).
    pub synthesis: Synthesis,
    /// With a check: NuSMV's certificate.
    pub certificate: Option<Certificate>,
    /// With a check: every candidate of the loop.
    pub iterations: Vec<Iteration>,
}

/// Synthesizes the smallest machine for `set`; with `check`, the smallest that NuSMV also
/// verifies.
pub fn run(
    set: &ScenarioSet,
    check: Option<&Check>,
    opts: &Options,
    events: Events<'_>,
) -> Result<Exact, Error> {
    if check.is_none() && opts.negatives.is_empty() {
        return Ok(unverified(by_parts(set, opts, events)?));
    }
    let tree = ScenarioTree::build(set)?;
    negative::check_not_recorded(set, &tree, &opts.negatives)?;
    let Some(check) = check else {
        let mut synth = sat::Synthesizer::new(set, &tree, &opts.sat(false));
        for neg in &opts.negatives {
            synth.add_negative(neg.clone());
        }
        return Ok(unverified(
            synth.minimize(&mut |m| events(Event::Solver(m)))?,
        ));
    };
    let mut verifier = check.verifier()?;
    let config = cegis::Config {
        sat: opts.sat(true),
        max_iterations: opts.max_iterations,
        verbose: opts.verbose,
        proof_budget: opts.proof_budget,
        negatives: opts.negatives.clone(),
        stall: opts.stall,
        learned: opts.learned.clone(),
    };
    let closed = match super::loop_encoding::LoopEncoding::new(
        &check.problem,
        set,
        super::loop_encoding::DEFAULT_RESPONSE_BOUND,
    ) {
        Ok(closed) => Some(closed),
        Err(why) => {
            events(Event::InProcessRefused { why });
            None
        }
    };
    match cegis::run(set, &tree, &mut verifier, closed.as_ref(), &config, events) {
        Ok(v) => Ok(Exact {
            synthesis: v.synthesis,
            certificate: Some(Certificate {
                report: v.report,
                model_text: v.model_text,
            }),
            iterations: v.iterations,
        }),
        // Past the deadline the loop was cut short: nothing it failed on is worth keeping.
        Err(e) if opts.sat.deadline.passed() => Err(e.into()),
        Err(e) => {
            keep_failed_model(opts, &verifier);
            Err(e.into())
        }
    }
}

/// The least machine for `set` alone, long recordings encoded a part at a time (the same
/// answer, see `lazy`).
fn by_parts(set: &ScenarioSet, opts: &Options, events: Events<'_>) -> Result<Synthesis, Error> {
    let sat = opts.sat(false);
    super::lazy::synthesize(
        set,
        &mut |part, tree, events| {
            let mut synth = sat::Synthesizer::new(part, tree, &sat);
            Ok(synth.minimize(&mut |m| events(Event::Solver(m)))?)
        },
        events,
    )
}

/// A machine no model checker judged.
fn unverified(synthesis: Synthesis) -> Exact {
    Exact {
        synthesis,
        certificate: None,
        iterations: Vec::new(),
    }
}

/// The last closed-loop model NuSMV judged, copied where `--keep-failed-model` asks, on a
/// best effort: the loop's error is what the user needs first.
fn keep_failed_model(opts: &Options, verifier: &crate::verify::Verifier) {
    let (Some(keep), Some(model)) = (&opts.keep_failed_model, verifier.last_model()) else {
        return;
    };
    if let Some(dir) = keep.parent() {
        let _ = std::fs::create_dir_all(dir);
    }
    if let Ok(text) = std::fs::read(model) {
        let _ = crate::files::write_atomic(keep, &text);
    }
}

/// The plateau search on the guard size (after fbSAT's extended-min-ub): from `first`, the
/// least machine for `set`, the least machine with at most one state more (least T, then N),
/// and so on, until `width` such steps in a row bring no fewer guard literals, or
/// `max_states`. Returns the machine with the fewest literals (on a tie the one found first,
/// with fewer states). Without a check only.
pub(crate) fn plateau(
    set: &ScenarioSet,
    opts: &Options,
    first: Synthesis,
    width: usize,
    events: Events<'_>,
) -> Result<Synthesis, Error> {
    let mut best = first;
    let (mut misses, mut c) = (0, best.size.c);
    while misses < width.max(1) && c < opts.sat.max_states {
        c += 1;
        let mut o = opts.clone();
        o.sat.fixed.states = Some(c);
        let found = run(set, None, &o, &mut |_| {})?.synthesis;
        events(Event::Solver(sat::Step::Plateau {
            states: c,
            n: found.size.n,
            best: best.size.n.min(found.size.n),
        }));
        if found.size.n < best.size.n {
            best = found;
            misses = 0;
        } else {
            misses += 1;
        }
    }
    Ok(best)
}
