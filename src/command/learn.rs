//! `synth learn`: the active loop against an oracle (a JSON machine or a shipped case's
//! reference controller), and passive learning from random recordings of the same length.

use super::refuse_overwrite;
use crate::cases::reference;
use crate::ecc::Ecc;
use crate::pipeline::active::{self, Agreement, Comparison, Learned};
use crate::pipeline::ambiguity::Uniqueness;
use crate::pipeline::summary::{LearnSummary, PassiveSummary, RoundSummary, LEARN};
use crate::pipeline::{recordings, Error, Events, Recordings};
use std::fmt;
use std::path::{Path, PathBuf};

/// What `synth learn` is asked.
pub(crate) struct Request {
    /// A JSON machine, or `case:NAME`.
    pub oracle: String,
    /// The initial recordings (the oracle must reproduce them).
    pub recordings: Recordings,
    /// The loop's settings.
    pub options: active::Options,
    /// Random recordings for the passive comparison (seeds 1..=N).
    pub passive_runs: usize,
    /// Where to write the final machine (JSON).
    pub out: Option<PathBuf>,
}

/// A machine passive learning inferred.
pub(crate) struct Passive {
    /// The seed of its recordings.
    pub seed: u64,
    /// C.
    pub states: usize,
    /// How it compares with the oracle.
    pub agreement: Agreement,
}

/// What the loop learned, beside passive learning.
pub(crate) struct Done {
    /// The loop's result.
    pub learned: Learned,
    /// Steps of the initial recordings.
    pub initial_steps: usize,
    /// How the loop's machine compares with the oracle.
    pub agreement: Agreement,
    /// Steps of each random scenario.
    pub length: usize,
    /// Each passive run.
    pub passive: Vec<Passive>,
    /// The file written, when asked.
    pub written: Option<PathBuf>,
}

impl fmt::Display for Done {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let l = &self.learned;
        write!(
            f,
            "active: {} rounds, {} steps recorded beyond the initial {}; C = {}; {}; {}",
            l.rounds.len(),
            l.recorded_steps,
            self.initial_steps,
            l.machine.states.len(),
            match l.rounds.last().and_then(|r| r.verdict) {
                Some(Uniqueness::Unique) => "unique",
                Some(Uniqueness::Ambiguous) => "still ambiguous (round limit)",
                _ => "no verdict within the budget",
            },
            self.agreement
        )?;
        for p in &self.passive {
            write!(
                f,
                "\npassive (seed {}): {} random steps in scenarios of {}; C = {}; {}",
                p.seed, l.recorded_steps, self.length, p.states, p.agreement
            )?;
        }
        if !self.passive.is_empty() {
            write!(
                f,
                "\npassive: {} of {} random recordings of equal length give a machine equivalent to the oracle",
                self.passive.iter().filter(|p| p.agreement.equivalent()).count(),
                self.passive.len()
            )?;
        }
        match &self.written {
            Some(out) => write!(f, "\nwrote {}", crate::quote::path(out)),
            None => Ok(()),
        }
    }
}

impl Done {
    /// The `--json` summary.
    pub fn summary(&self) -> LearnSummary {
        let l = &self.learned;
        LearnSummary {
            format: LEARN,
            rounds: (l.rounds.iter())
                .map(|r| RoundSummary {
                    states: r.states,
                    asked: r.asked,
                    verdict: r.verdict,
                    recorded_steps: r.recorded_steps,
                    widened: r.widened,
                })
                .collect(),
            recorded_steps: l.recorded_steps,
            initial_steps: self.initial_steps,
            unique: l.unique,
            states: l.machine.states.len(),
            equivalent: self.agreement.equivalent(),
            passive: (self.passive.iter())
                .map(|p| PassiveSummary {
                    seed: p.seed,
                    states: p.states,
                    equivalent: p.agreement.equivalent(),
                })
                .collect(),
        }
    }
}

/// The oracle named by `--oracle`.
fn oracle(name: &str) -> Result<Ecc, Error> {
    let Some(case) = name.strip_prefix("case:") else {
        return recordings::read_ecc(&PathBuf::from(name));
    };
    reference::named(case).ok_or_else(|| {
        let known: Vec<String> = (reference::NAMES.iter())
            .map(|n| format!("case:{n}"))
            .collect();
        let (last, rest) = known.split_last().expect("at least one case");
        Error::Usage(format!(
            "unknown case {name:?}: {} or {last}",
            rest.join(", ")
        ))
    })
}

/// `synth learn`: the loop, the passive runs, and the machine written when asked.
pub(crate) fn run(r: &Request, events: Events<'_>) -> Result<Done, Error> {
    let oracle = oracle(&r.oracle)?;
    let initial = r.recordings.load()?;
    if initial.inputs != oracle.inputs || initial.outputs != oracle.outputs {
        return Err(Error::Input(format!(
            "the oracle's interface ({} / {}) is not the recordings' ({} / {})",
            oracle.inputs.join(" "),
            oracle.outputs.join(" "),
            initial.inputs.join(" "),
            initial.outputs.join(" ")
        )));
    }
    if let Some(out) = &r.out {
        // The oracle is a file unless it names a shipped case.
        let oracle = Path::new(&r.oracle);
        let reads = (r.recordings.paths().into_iter())
            .chain(oracle.is_file().then(|| oracle.to_path_buf()));
        refuse_overwrite(&[out], &reads.collect::<Vec<_>>())?;
    }
    let learned = active::learn(&initial, &oracle, &r.options, events)?;
    let comparison = Comparison::new(&initial, &oracle, &learned, &r.options)?;
    let mut passive = Vec::new();
    for seed in 1..=r.passive_runs as u64 {
        let m = comparison.passive(seed)?;
        passive.push(Passive {
            seed,
            states: m.states.len(),
            agreement: comparison.agreement(&m),
        });
    }
    if let Some(out) = &r.out {
        let json = crate::export::json::to_string(&learned.machine);
        crate::files::write_atomic(out, json.as_bytes())?;
    }
    Ok(Done {
        agreement: comparison.agreement(&learned.machine),
        initial_steps: initial.step_count(),
        length: comparison.length(),
        learned,
        passive,
        written: r.out.clone(),
    })
}
