//! Active learning against a machine that answers: infer, look for a rival, "record" the
//! sequence that tells them apart on the oracle, repeat until the recordings determine the
//! machine; and, for comparison, passive learning from random recordings of the same length.
//!
//! In: initial recordings, the oracle (any [`Ecc`]: a JSON machine or a case's reference
//! controller standing in for the legacy PLC), and [`Options`]. Out: [`Learned`]: the final
//! machine, the recordings it came from, and every round's figures.
//!
//! A "recording" is the oracle run from its initial state on the rival's full sequence (the
//! recorded prefix, then the distinguishing steps): what an engineer does on the machine in
//! service. The recorded steps count both parts.

use super::ambiguity::{self, Verdict};
use super::exact;
use super::Error;
use crate::ecc::{Ecc, Run};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::{Origin, Scenario, ScenarioSet, Step};
use std::path::PathBuf;

/// Settings of the loop.
#[derive(Debug, Clone)]
pub struct Options {
    /// How rivals are looked for each round (bounds, budget, alphabet).
    pub ambiguity: ambiguity::Options,
    /// Rounds at most; the last one ends the loop even if the machine is still ambiguous.
    pub max_rounds: usize,
}

/// One round of the loop.
#[derive(Debug, Clone)]
pub struct Round {
    /// States of the machine inferred in this round.
    pub states: usize,
    /// What the ambiguity check said about this round's machine.
    pub verdict: Verdict,
    /// Steps recorded on the oracle after this round (0 when it ended the loop).
    pub recorded_steps: usize,
}

/// The result of [`learn`].
#[derive(Debug, Clone)]
pub struct Learned {
    /// The machine inferred in the last round.
    pub machine: Ecc,
    /// The initial recordings plus every scenario recorded on the oracle.
    pub recordings: ScenarioSet,
    /// Every round's figures, in order.
    pub rounds: Vec<Round>,
    /// Steps recorded on the oracle in all (beyond the initial recordings).
    pub recorded_steps: usize,
    /// Whether the last round found the machine unique (otherwise the round limit or the
    /// budget ended the loop).
    pub unique: bool,
}

/// The oracle's answers to `inputs` from its initial state, as a scenario.
pub fn record(oracle: &Ecc, inputs: &[Vec<bool>], origin: Origin) -> Scenario {
    let mut run = Run::new(oracle);
    let steps = inputs
        .iter()
        .map(|x| Step {
            inputs: x.clone(),
            outputs: run.step(x).map(|_| run.outputs.clone()),
        })
        .collect();
    Scenario { origin, steps }
}

fn origin(what: &str, k: usize) -> Origin {
    Origin {
        file: PathBuf::from(what),
        line: k,
        rows: None,
    }
}

/// The minimal machine for `set` (tree-exact model, as `synth infer`).
fn infer(set: &ScenarioSet, opts: &Options) -> Result<Ecc, Error> {
    let o = exact::Options {
        sat: exact::SatOptions {
            algorithms: opts.ambiguity.algorithms,
            ..exact::SatOptions::default()
        },
        ..exact::Options::default()
    };
    Ok(exact::run(set, None, &o, &mut |_| {})?.synthesis.ecc)
}

/// Runs the loop from `initial` (which the oracle must reproduce).
pub fn learn(
    initial: &ScenarioSet,
    oracle: &Ecc,
    opts: &Options,
    progress: &mut dyn FnMut(&Round),
) -> Result<Learned, Error> {
    initial.check(oracle).map_err(|m| {
        Error::Input(format!(
            "the oracle does not reproduce the initial recordings: {m}"
        ))
    })?;
    let mut set = initial.clone();
    let mut rounds = Vec::new();
    let mut recorded_steps = 0;
    loop {
        let machine = infer(&set, opts)?;
        let tree = ScenarioTree::build(&set)?;
        let found = ambiguity::check(&set, &tree, &machine, &opts.ambiguity)?;
        let mut round = Round {
            states: machine.states.len(),
            verdict: found.verdict,
            recorded_steps: 0,
        };
        if found.verdict != Verdict::Ambiguous || rounds.len() + 1 >= opts.max_rounds {
            progress(&round);
            rounds.push(round);
            return Ok(Learned {
                machine,
                recordings: set,
                rounds,
                recorded_steps,
                unique: found.verdict == Verdict::Unique,
            });
        }
        for r in &found.rivals {
            let inputs = r.inputs(&set);
            round.recorded_steps += inputs.len();
            let k = set.scenarios.len() + 1;
            set.scenarios
                .push(record(oracle, &inputs, origin("oracle", k)));
        }
        recorded_steps += round.recorded_steps;
        progress(&round);
        rounds.push(round);
    }
}

/// Passive learning for comparison: `initial` plus random recordings on the oracle (input
/// vectors drawn uniformly from `alphabet`, scenarios of `length` steps) until `steps` steps are
/// recorded; the machine inferred from them.
pub fn passive(
    initial: &ScenarioSet,
    oracle: &Ecc,
    alphabet: &[Vec<bool>],
    steps: usize,
    length: usize,
    seed: u64,
    opts: &Options,
) -> Result<Ecc, Error> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand::rngs::StdRng::seed_from_u64(seed);
    let mut set = initial.clone();
    let mut left = steps;
    while left > 0 {
        let n = left.min(length.max(1));
        let inputs: Vec<Vec<bool>> = (0..n)
            .map(|_| alphabet[rng.gen_range(0..alphabet.len())].clone())
            .collect();
        let k = set.scenarios.len() + 1;
        set.scenarios
            .push(record(oracle, &inputs, origin("random", k)));
        left -= n;
    }
    infer(&set, opts)
}
