//! `synth learn`: the active loop against an oracle (a JSON machine or a shipped case's
//! reference controller), and passive learning from random recordings of the same length.

use super::args::{AlgorithmsArg, AmbiguityArgs, TraceArgs};
use super::progress::Progress;
use super::{exit, Failure};
use clap::Args;
use fbsynth::cases::reference;
use fbsynth::ecc::diff::{difference, difference_from};
use fbsynth::ecc::{Ecc, StateId};
use fbsynth::pipeline::active::{self, Options};
use fbsynth::pipeline::ambiguity::{alphabet, Verdict};
use fbsynth::scenario::tree::ScenarioTree;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct LearnArgs {
    /// The machine that answers: a JSON machine, or a shipped case's reference controller
    /// (`case:pnp`, `case:distribution`, `case:tank1`, `case:tank2`).
    #[arg(long, value_name = "FILE|case:NAME")]
    pub oracle: String,
    /// The initial recordings (the oracle must reproduce them).
    #[command(flatten)]
    pub traces: TraceArgs,
    /// Form of the state output algorithms.
    #[arg(long, value_enum, default_value_t = AlgorithmsArg::Tri)]
    pub algorithms: AlgorithmsArg,
    #[command(flatten)]
    pub ambiguity: AmbiguityArgs,
    /// Stop after this many rounds.
    #[arg(long, default_value_t = 50, value_name = "N", value_parser = super::args::rivals())]
    pub max_rounds: usize,
    /// Random recordings for the passive comparison (seeds 1..=N; 0: no comparison).
    #[arg(long, default_value_t = 5, value_name = "N", value_parser = super::args::runs())]
    pub passive_runs: usize,
    /// Only look for rivals: do not first record a tour trying every letter of the alphabet
    /// in every configuration of the machine.
    #[arg(long)]
    pub no_tour: bool,
    /// Write the final machine here (JSON).
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// The oracle named by `--oracle`.
fn oracle(name: &str) -> Result<Ecc, Failure> {
    if let Some(case) = name.strip_prefix("case:") {
        return reference::named(case).ok_or_else(|| {
            let names: Vec<String> = reference::NAMES
                .iter()
                .map(|n| format!("case:{n}"))
                .collect();
            Failure::msg(
                exit::USAGE,
                format!(
                    "unknown case {name:?}: {} or {}",
                    names[..names.len() - 1].join(", "),
                    names[names.len() - 1]
                ),
            )
        });
    }
    let path = PathBuf::from(name);
    let text = fbsynth::files::read_text(&path, None).map_err(Failure::input)?;
    fbsynth::export::json::read_json(&text, &path).map_err(Failure::input)
}

/// `synth learn`.
pub fn learn(args: &LearnArgs) -> Result<(), Failure> {
    if super::json() {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    let oracle = oracle(&args.oracle)?;
    let initial = args.traces.load()?;
    if initial.inputs != oracle.inputs || initial.outputs != oracle.outputs {
        return Err(Failure::msg(
            exit::INPUT,
            format!(
                "the oracle's interface ({} / {}) is not the recordings' ({} / {})",
                oracle.inputs.join(" "),
                oracle.outputs.join(" "),
                initial.inputs.join(" "),
                initial.outputs.join(" ")
            ),
        ));
    }
    if let Some(out) = &args.out {
        super::args::refuse_overwrite(&[out], &args.traces.traces)?;
    }
    let opts = Options {
        ambiguity: args.ambiguity.options(args.algorithms.into())?,
        max_rounds: args.max_rounds.max(1),
        tour: !args.no_tour,
    };
    let initial_steps = initial.step_count();
    let mut round = 0;
    let learned = active::learn(
        &initial,
        &oracle,
        &opts,
        &mut |r| {
            round += 1;
            let verdict = match r.verdict {
                Some(Verdict::Unique) => "unique",
                Some(Verdict::Ambiguous) => "ambiguous",
                Some(Verdict::Unknown) => "unknown",
                None => r.asked.name(),
            };
            let widened = if r.widened {
                " over the recorded combinations; now over every input vector"
            } else {
                ""
            };
            progress.line(&format!(
                "round {round}: C = {}, {verdict}{widened}; {} steps recorded",
                r.states, r.recorded_steps
            ));
        },
        &mut |e| progress.event(e),
    )?;
    let tree = ScenarioTree::build(&learned.recordings).map_err(fbsynth::pipeline::Error::from)?;
    let letters = alphabet(&tree, initial.inputs.len(), opts.ambiguity.all_inputs)?;
    // Whether `m` is equivalent to the oracle, and the words for it.
    let verdict = |m: &Ecc| -> (bool, String) {
        let found = difference(m, &oracle);
        let equivalent = matches!(found, Ok(None));
        let full = match found {
            Ok(None) => "equivalent to the oracle".to_string(),
            Ok(Some(d)) => format!("differs from the oracle after {} steps", d.inputs.len()),
            Err(e) => format!("not compared on every input vector ({e})"),
        };
        let start = (
            (StateId(0), m.initial_outputs.clone()),
            (StateId(0), oracle.initial_outputs.clone()),
        );
        let over = match difference_from(m, &oracle, &[start], &letters) {
            None => "agrees on every sequence of the alphabet",
            Some(_) => "disagrees on some sequence of the alphabet",
        };
        (equivalent, format!("{full}; {over}"))
    };
    out!(
        "active: {} rounds, {} steps recorded beyond the initial {}; C = {}; {}; {}",
        learned.rounds.len(),
        learned.recorded_steps,
        initial_steps,
        learned.machine.states.len(),
        match learned.rounds.last().and_then(|r| r.verdict) {
            Some(Verdict::Unique) => "unique",
            Some(Verdict::Ambiguous) => "still ambiguous (round limit)",
            _ => "no verdict within the budget",
        },
        verdict(&learned.machine).1
    );
    let length = learned
        .recordings
        .scenarios
        .iter()
        .skip(initial.scenarios.len())
        .map(|s| s.steps.len())
        .max()
        .unwrap_or(1);
    let mut equivalent = 0;
    let mut passive = Vec::new();
    for seed in 1..=args.passive_runs as u64 {
        let m = active::passive(
            &initial,
            &oracle,
            &letters,
            learned.recorded_steps,
            length,
            seed,
            &opts,
        )?;
        let (same, v) = verdict(&m);
        equivalent += usize::from(same);
        passive.push(serde_json::json!({
            "seed": seed,
            "states": m.states.len(),
            "equivalent": same,
        }));
        out!(
            "passive (seed {seed}): {} random steps in scenarios of {length}; C = {}; {v}",
            learned.recorded_steps,
            m.states.len()
        );
    }
    if args.passive_runs > 0 {
        out!(
            "passive: {equivalent} of {} random recordings of equal length give a machine equivalent to the oracle",
            args.passive_runs
        );
    }
    if let Some(out) = &args.out {
        fbsynth::files::write_atomic(
            out,
            fbsynth::export::json::to_string(&learned.machine).as_bytes(),
        )
        .map_err(Failure::input)?;
        out!("wrote {}", out.display());
        super::note_written(std::slice::from_ref(out));
    }
    if super::json() {
        let summary = serde_json::json!({
            "rounds": learned.rounds.iter().map(|r| serde_json::json!({
                "states": r.states,
                "asked": r.asked,
                "verdict": r.verdict,
                "recorded_steps": r.recorded_steps,
                "widened": r.widened,
            })).collect::<Vec<_>>(),
            "recorded_steps": learned.recorded_steps,
            "initial_steps": initial_steps,
            "unique": learned.unique,
            "states": learned.machine.states.len(),
            "equivalent": verdict(&learned.machine).0,
            "passive": passive,
        });
        return super::write_json(&summary);
    }
    Ok(())
}
