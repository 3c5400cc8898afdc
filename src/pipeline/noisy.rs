//! Synthesis from noisy sampled logs: the scan-cycle error model of Chivilikhin, Patil,
//! Chukharev, Cordonnier and Vyatkin, "Automatic state machine reconstruction from legacy
//! PLC using data collection and SAT solver". Minimal machines are enumerated by number of corrected
//! errors ε; with a [`Check`] every candidate is verified by NuSMV and the enumeration stops at
//! the first one that satisfies every property.
//!
//! In: a [`ScenarioSet`] read from sampled logs, [`Options`] (above all the bound on ε and
//! the number of candidates) and optionally a [`Check`]. Out: a [`Noisy`]: the least C, K and
//! T, and the distinct minimal machines in order of increasing ε, each with its corrected,
//! error-free traces and, when checked, NuSMV's verdict. `synth infer --noisy` writes them with
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
//!   from 0, which spent one UNSAT proof per value below it: on the 10^4-sample benchmark log
//!   enumeration went from 48.8 s (98.8 s wall, 60.5 CPU s in all) to 1.9 s.
//! - Every candidate is replayed by the simulator on its corrected traces before it is
//!   written. With a check, each is verified as it is found; the first verified one ends the
//!   enumeration (`synth infer` exits 3 if none is).
//!
//! # Bound the errors
//! Without a bound, Algorithm 1 minimizes C with ε free, and the solver happily explains real
//! transitions as errors to save states: on the shipped distribution-station log (2 errors
//! injected) it returns C = 8 with ε = 24, where the reference controller has 9 states. With
//! `--max-errors` at or a little above the expected error count the size is right, and the
//! error totalizer stays small (its size grows with alternatives times bound).
//!
//! # Measured: `synth bench-noisy`
//! Distribution-station logs of random use cases (seed 1; 1 to 3 rounds of loading 1 to 8
//! pieces, start, sometimes emergency, stop; one log per use case, the last one cut so the
//! total is exact), skew injected at rate 0.02 (seeded per log), `--max-errors` = the number
//! injected (`--error-bound` scales it), one candidate. Release build, 2026-11-22, on the 2-core
//! machine shared with three other builders (wall times inflated by up to 2x):
//!
//! | samples | steps | graph nodes | alternatives | injected | C K T | least ε | clauses | C, K, T s | enumerate s | total s (wall) |
//! |---|---|---|---|---|---|---|---|---|---|---|
//! | 10^3 | 434 | 253 | 252 | 4 | 9 3 12 | 4 | 0.45 M | 9.3 | 3.7 | 13.0 |
//! | 10^4 | 4 676 | 2 554 | 2 553 | 36 | 9 3 12 | 36 | 4.6 M | 70.6 | 1.9 | 72.5 |
//! | 10^5 | n/a | 24 102 | 24 101 | n/a | 9 3 12 | not reached | n/a | 833.9 | not reached | killed at 840 |
//!
//! The first two rows ran in one process (47.6 CPU s, 1:25.6 wall, peak RSS 107 MB). The 10^5
//! run was stopped by `timeout 840` (766.9 CPU s, peak RSS 1.39 GB) right after C = 9 (at
//! 410 s), K = 3 and T = 12 (at 833.9 s) had been proven; the least ε and the candidate did not
//! fit. The encoding is linear in the log (one node per active step, about 1.8 k clauses per
//! node for this 10-input, 7-output station at C = 9; variables and clauses grow 8-10x per 10x
//! samples), the solving is not: from 10^3 to 10^4 samples time grows about 6x, and from 10^4
//! to 10^5 the minimization of C, K, T alone grows 12x (70.6 s to 833.9 s) and memory 13x.
//! Most of the time goes into the UNSAT proofs of the minimization (no machine with C-1
//! states, K-1, T-1), each over the whole log. Noisy synthesis is therefore for logs of
//! up to about 10^4 samples (a minute); cut longer recordings into use cases, synthesize from
//! a representative subset (distinct traces are deduplicated, repeated cycles are not) and
//! check the rest with `synth replay` or `synth conform`.

use super::{Check, Error, Event, Events};
use crate::sat::noisy::{synthesize_noisy, Candidate, Flow, NoisySynthesis};
use crate::scenario::ScenarioSet;

pub use crate::sat::noisy::NoisyOptions as Options;

/// The candidates and, with a check, NuSMV's verdict on each.
pub struct Noisy {
    /// Minimal machines by ε, with the least C, K and T.
    pub synthesis: NoisySynthesis,
    /// Per candidate: `Some(true)` every property holds, `Some(false)` one fails, `None`
    /// not checked.
    pub verdicts: Vec<Option<bool>>,
}

impl Noisy {
    /// The 1-based number of the first candidate NuSMV verified.
    pub fn first_verified(&self) -> Option<usize> {
        self.verdicts
            .iter()
            .position(|v| *v == Some(true))
            .map(|k| k + 1)
    }
}

/// Enumerates minimal machines for the noisy `set`; with `check`, verifies each one.
pub fn run(
    set: &ScenarioSet,
    check: Option<&Check>,
    opts: &Options,
    events: Events<'_>,
) -> Result<Noisy, Error> {
    let mut verifier = check.map(Check::verifier).transpose()?;
    let mut verdicts: Vec<Option<bool>> = Vec::new();
    let mut check_error: Option<Error> = None;
    // Both closures report progress: share the sink through a cell.
    let events = std::cell::RefCell::new(events);
    let mut accept = |c: &Candidate| -> Flow {
        let Some(verifier) = verifier.as_mut() else {
            verdicts.push(None);
            return Flow::Continue;
        };
        match verifier.verify(&c.ecc) {
            Ok(v) => {
                let failing: Vec<String> =
                    v.report.failing().iter().map(|s| s.to_string()).collect();
                (events.borrow_mut())(Event::CandidateVerdict { failing: &failing });
                let holds = v.report.all_hold();
                verdicts.push(Some(holds));
                if holds {
                    Flow::Stop
                } else {
                    Flow::Continue
                }
            }
            Err(e) => {
                check_error = Some(e.into());
                Flow::Stop
            }
        }
    };
    let synthesis = synthesize_noisy(
        set,
        opts,
        &mut |m| (events.borrow_mut())(Event::Solver(m)),
        &mut accept,
    )?;
    if let Some(e) = check_error {
        return Err(e);
    }
    verdicts.resize(synthesis.candidates.len(), None);
    Ok(Noisy {
        synthesis,
        verdicts,
    })
}
