//! `synth learn`: the active loop against an oracle (a JSON machine or a shipped case's
//! reference controller), and passive learning from random recordings of the same length.

use super::args::{AlgorithmsArg, AmbiguityArgs, TraceArgs};
use super::progress::Progress;
use super::{exit, Failure};
use crate::cases::reference;
use crate::ecc::Ecc;
use crate::pipeline::active::{self, Comparison, Learned, Options, Round};
use crate::pipeline::ambiguity::Uniqueness;
use crate::scenario::ScenarioSet;
use clap::Args;
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
            let known: Vec<String> = reference::NAMES
                .iter()
                .map(|n| format!("case:{n}"))
                .collect();
            let (last, rest) = known.split_last().expect("at least one case");
            let message = format!("unknown case {name:?}: {} or {last}", rest.join(", "));
            Failure::msg(exit::USAGE, message)
        });
    }
    let path = PathBuf::from(name);
    let text = crate::files::read_text(&path, None).map_err(Failure::input)?;
    crate::export::json::read_json(&text, &path).map_err(Failure::input)
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
    let mut round = 0;
    let learned = active::learn(
        &initial,
        &oracle,
        &opts,
        &mut |r| {
            round += 1;
            progress.line(&round_line(round, r));
        },
        &mut |e| progress.event(e),
    )?;
    let comparison = Comparison::new(&initial, &oracle, &learned, &opts)?;
    let agreement = comparison.agreement(&learned.machine);
    out!("{}", active_line(&learned, &initial, &agreement));
    let mut passive = Vec::new();
    for seed in 1..=args.passive_runs as u64 {
        let m = comparison.passive(seed)?;
        let a = comparison.agreement(&m);
        out!(
            "passive (seed {seed}): {} random steps in scenarios of {}; C = {}; {a}",
            learned.recorded_steps,
            comparison.length(),
            m.states.len()
        );
        passive.push((seed, m.states.len(), a.equivalent()));
    }
    if args.passive_runs > 0 {
        out!(
            "passive: {} of {} random recordings of equal length give a machine equivalent to the oracle",
            passive.iter().filter(|p| p.2).count(),
            args.passive_runs
        );
    }
    if let Some(out) = &args.out {
        crate::files::write_atomic(
            out,
            crate::export::json::to_string(&learned.machine).as_bytes(),
        )
        .map_err(Failure::input)?;
        out!("wrote {}", out.display());
        super::note_written(std::slice::from_ref(out));
    }
    if super::json() {
        return super::write_json(&summary(
            &learned,
            &initial,
            agreement.equivalent(),
            &passive,
        ));
    }
    Ok(())
}

/// The progress line of round `number`.
fn round_line(number: usize, r: &Round) -> String {
    let verdict = match r.verdict {
        Some(Uniqueness::Unique) => "unique",
        Some(Uniqueness::Ambiguous) => "ambiguous",
        Some(Uniqueness::Unknown) => "unknown",
        None => r.asked.name(),
    };
    let widened = if r.widened {
        " over the recorded combinations; now over every input vector"
    } else {
        ""
    };
    format!(
        "round {number}: C = {}, {verdict}{widened}; {} steps recorded",
        r.states, r.recorded_steps
    )
}

/// The line of the active loop's result.
fn active_line(learned: &Learned, initial: &ScenarioSet, agreement: &active::Agreement) -> String {
    format!(
        "active: {} rounds, {} steps recorded beyond the initial {}; C = {}; {}; {agreement}",
        learned.rounds.len(),
        learned.recorded_steps,
        initial.step_count(),
        learned.machine.states.len(),
        match learned.rounds.last().and_then(|r| r.verdict) {
            Some(Uniqueness::Unique) => "unique",
            Some(Uniqueness::Ambiguous) => "still ambiguous (round limit)",
            _ => "no verdict within the budget",
        },
    )
}

/// The `--json` summary: every round, the result, and each passive run as `(seed, C,
/// equivalent)`.
fn summary(
    learned: &Learned,
    initial: &ScenarioSet,
    equivalent: bool,
    passive: &[(u64, usize, bool)],
) -> serde_json::Value {
    serde_json::json!({
        "rounds": learned.rounds.iter().map(|r| serde_json::json!({
            "states": r.states,
            "asked": r.asked,
            "verdict": r.verdict,
            "recorded_steps": r.recorded_steps,
            "widened": r.widened,
        })).collect::<Vec<_>>(),
        "recorded_steps": learned.recorded_steps,
        "initial_steps": initial.step_count(),
        "unique": learned.unique,
        "states": learned.machine.states.len(),
        "equivalent": equivalent,
        "passive": passive.iter().map(|(seed, states, equivalent)| serde_json::json!({
            "seed": seed,
            "states": states,
            "equivalent": equivalent,
        })).collect::<Vec<_>>(),
    })
}
