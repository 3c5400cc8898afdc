//! Synthesis from noisy sampled logs: the scan-cycle error model of Chivilikhin, Patil,
//! Chukharev, Cordonnier and Vyatkin, "Automatic state machine reconstruction from legacy
//! PLC using data collection and SAT solver". Minimal machines are enumerated by number of corrected
//! errors ε; with a [`Check`] the closed loop ([`super::exact`] with the check) runs on the
//! candidates' corrected traces, in the order given at [`run`], until one gives a machine
//! NuSMV verifies.
//!
//! In: a [`ScenarioSet`] read from sampled logs, [`Options`] (above all the bound on ε and
//! the number of candidates) and optionally a [`Check`]. Out: a [`Noisy`]: the least C, K and
//! T, and the distinct minimal machines in order of increasing ε, each with its corrected,
//! error-free traces and, when checked, the closed loop's result for those tried.
//! `synth infer --noisy` writes them with
//! [`super::output::write_noisy`]: `candidate_<k>/` per candidate (the machine in every
//! format, `corrected.txt`, `corrected.csv`, `candidate.json`), `summary.txt` and
//! `summary.json`.
//!
//! # Why
//! A data collector and a PLC scan asynchronously, so an output change can be recorded one
//! sample *before* the input change that caused it. Read as they are, such logs contradict
//! each other (one input history answered in two ways) and plain synthesis stops with
//! "contradictory scenarios".
//!
//! # How
//! - The log is preprocessed as any CSV log
//!   ([`crate::scenario::csvlog::samples_to_steps`]), so the noise shows as an active step on
//!   the *old* inputs followed by a passive step on the inputs that really caused it.
//! - [`crate::scenario::trace_graph`]: one chain per distinct scenario, all hanging from one
//!   shared root (every trace starts in state 0), no other merging. Every active step that
//!   changed the outputs and has a next step gets an *alternative edge* between the same
//!   nodes, labelled with the next step's inputs.
//! - [`crate::sat::noisy`]: the colouring encoding of clean synthesis plus one selection
//!   variable per alternative (the recorded edge or the alternative, exactly one),
//!   transitions only on selected edges, and a totalizer over the selections that bounds ε.
//! - The paper's Algorithm 1 (its N, K, R are C, K, T here): least C, then least K, then least
//!   T (one minimized guard per transition), then every distinct minimal machine by
//!   increasing ε, each edge choice blocked once found. The least ε is found by descending
//!   from a model's error count (a few SAT calls and one UNSAT proof) rather than by climbing
//!   from 0, which would cost one UNSAT proof per value below it.
//! - Every candidate is replayed by the simulator on its corrected traces before it is
//!   written. With a check, the verified machine is replayed on its corrected traces too
//!   (the loop replays every machine it returns); `synth infer` exits 3 if no correction has
//!   one.
//!
//! # Bound the errors
//! Without a bound, Algorithm 1 minimizes C with ε free, and the solver happily explains real
//! transitions as errors to save states: on the shipped distribution-station log (2 errors
//! injected) it returns C = 8 with ε = 24, where the reference controller has 9 states. With
//! `--max-errors` at or a little above the expected error count the size is right, and the
//! error totalizer stays small (its size grows with alternatives times bound).
//!
//! # Large logs
//! The encoding is linear in the log (one node per active step, about 1.8 k clauses per node
//! for the 10-input, 7-output distribution station at C = 9); the solving is not. Most of the
//! time goes into the UNSAT proofs of the minimization (no machine with C-1 states, K-1, T-1),
//! each over the whole log, and they grow faster than the log: whole, 10^5 samples do not get
//! past the sizes within minutes. That is why logs of [`lazy_noisy::LAZY_FROM_NODES`] graph
//! nodes or more are taken in parts ([`lazy_noisy`]): the proofs run on a few traces and on
//! one segment per correction, with the same C, K, T and least ε. `synth bench-noisy`
//! measures it on generated distribution-station logs; its figures are in `BENCHMARKS.md`.

use super::exact::{self, Exact};
use super::lazy_noisy;
use super::{Check, Class, Error, Event, Events};
use crate::sat::noisy::NoisySynthesis;
use crate::scenario::ScenarioSet;

pub use crate::sat::noisy::NoisyOptions as Options;

/// The candidates and, with a check, the closed loop of each one tried.
pub struct Noisy {
    /// Minimal machines by ε, with the least C, K and T.
    pub synthesis: NoisySynthesis,
    /// Per candidate, with a check: `None` if its closed loop was not tried (an earlier one
    /// gave the result), else the verified machine for its corrected traces or why there is
    /// none. Empty without a check.
    pub closed: Vec<Option<InLoop>>,
    /// Per candidate, with a check: the properties NuSMV finds violated by the candidate as
    /// found (before any closed loop), so the engineer sees which raw machines fail and why.
    /// Empty without a check.
    pub(crate) as_found: Vec<Vec<String>>,
}

/// What the closed loop made of one candidate's corrected traces.
pub enum InLoop {
    /// The verified machine found for the candidate's corrected traces.
    Verified(Box<Exact>),
    /// No verified machine within the limits: the reason.
    None(String),
}

impl Noisy {
    /// The 1-based number of the candidate whose verified machine is the result.
    pub fn chosen(&self) -> Option<usize> {
        (1..=self.closed.len()).find(|&k| self.verified(k).is_some())
    }

    /// The verified machine of candidate `k` (1-based), if any.
    pub(crate) fn verified(&self, k: usize) -> Option<&Exact> {
        match self.closed.get(k.checked_sub(1)?)? {
            Some(InLoop::Verified(e)) => Some(e),
            _ => None,
        }
    }
}

/// Enumerates minimal machines for the noisy `set`; with `check`, runs the closed loop on the
/// candidates' corrected traces until one gives a verified machine.
///
/// # Which correction
/// The log alone does not say which correction is right: on the shipped distribution log the
/// ε = 1 correction reads a real transition as a glitch, and its closed loop still finds a
/// verified machine (one that diverges on a held-out recording). The corrections are tried
/// in the order of the SAT reconstruction paper's Algorithm 1, sizes first and errors last,
/// with the guards' literal count among the sizes: least C, K, T, then N of the correction's
/// own minimal machine, then least ε. The first whose closed loop gives a verified machine is
/// the result.
/// On that log it is the ε = 2 correction whose machine needs 13 literals where the others
/// need 14 and 15, the right one. The order depends on the recordings only (every size is
/// proven), not on the closed loop's timing.
///
/// Everything stops at `opts.deadline`: the SAT calls, NuSMV and the closed loop's.
pub fn run(
    set: &ScenarioSet,
    check: Option<(&Check, &exact::Options)>,
    opts: &Options,
    events: Events<'_>,
) -> Result<Noisy, Error> {
    let check = check.map(|(check, exact_opts)| {
        let mut exact_opts = exact_opts.clone();
        exact_opts.sat.deadline = opts.deadline;
        (check.until(opts.deadline), exact_opts)
    });
    let check = check.as_ref().map(|(c, o)| (c, o));
    let synthesis = lazy_noisy::synthesize(set, opts, lazy_noisy::Parts::default(), events)?;
    let mut closed: Vec<Option<InLoop>> = Vec::new();
    let mut as_found = Vec::new();
    if let Some((check, _)) = check {
        let mut verifier = check.verifier()?;
        for c in &synthesis.candidates {
            let v = verifier.verify_with(&c.ecc, crate::nusmv::CheckMode::VerdictsOnly)?;
            let failing: Vec<String> = v.report.failing().iter().map(|s| s.to_string()).collect();
            events(Event::CandidateVerdict { failing: &failing });
            as_found.push(failing);
        }
    }
    if let Some((check, exact_opts)) = check {
        closed.resize_with(synthesis.candidates.len(), || None);
        for k in trial_order(&synthesis) {
            let c = &synthesis.candidates[k];
            events(Event::ClosedLoopOf {
                candidate: k + 1,
                errors: c.errors,
            });
            let found = match exact::run(&c.corrected, Some(check), exact_opts, events) {
                Ok(e) => InLoop::Verified(Box::new(e)),
                Err(e) if e.class() == Class::NoMachine => InLoop::None(e.to_string()),
                Err(e) => return Err(e),
            };
            let done = matches!(found, InLoop::Verified(_));
            closed[k] = Some(found);
            if done {
                break;
            }
        }
    }
    Ok(Noisy {
        synthesis,
        closed,
        as_found,
    })
}

/// The candidates' indices by the size of their own machine (C, K, T, N), then ε.
fn trial_order(s: &NoisySynthesis) -> Vec<usize> {
    let mut order: Vec<usize> = (0..s.candidates.len()).collect();
    order.sort_by_key(|&k| {
        let c = &s.candidates[k];
        (c.size.c, c.size.k, c.size.t, c.size.n, c.errors, k)
    });
    order
}
