//! `synth infer` without `--ltl`: the least machine for the recordings, its files, and the
//! size questions around it (`--dump-cnf`).

use super::{publish, InferArgs};
use crate::cli::args::time_limit;
use crate::cli::progress::Progress;
use crate::cli::show::{print_written, size_line};
use crate::cli::{exit, Failure};
use crate::export;
use crate::files::ResultSet;
use crate::pipeline::{self, exact, output};
use crate::sat::Synthesis;
use crate::scenario::negative::NegativeScenario;
use crate::scenario::ScenarioSet;
use std::path::Path;

/// Said when exact synthesis fails on a contradiction, or climbs to
/// [`GLITCH_HINT_STATES`] states.
const NOISY_HINT: &str = "hint: if the recording has scan-cycle glitches (outputs logged a scan early or late), `synth infer --noisy --max-errors N` corrects up to N samples";

/// The number of states from which exact synthesis hints at `--noisy`: more than the
/// controllers of the shipped cases need (at most 9), and where each further C starts to take
/// long.
const GLITCH_HINT_STATES: usize = 10;

/// A contradiction in recordings read as exact: most often a scan-cycle glitch of the logger,
/// which `--noisy` corrects, so the message says so.
fn suggest_noisy(e: pipeline::Error) -> Failure {
    use crate::scenario::ScenarioError;
    match e {
        pipeline::Error::Scenario(ScenarioError::Contradiction(_)) => {
            Failure::msg(exit::INPUT, format!("{e}\n{NOISY_HINT}"))
        }
        e => e.into(),
    }
}

/// The least machine for the recordings (and `--plateau`'s search on the guard size), within
/// the time limit, with the hint at `--noisy` where the recordings look glitchy; the options
/// it was found with.
pub(super) fn least(
    args: &InferArgs,
    set: &ScenarioSet,
    negatives: Vec<NegativeScenario>,
    progress: &Progress,
) -> Result<(exact::Options, Synthesis), Failure> {
    let opts = options(args, negatives)?;
    let limit = time_limit(args.time_limit, progress)?;
    let until = |deadline| {
        let mut o = opts.clone();
        o.sat.deadline = deadline;
        o
    };
    let first = limit
        .run(&mut glitch_hint(progress), |d, events| {
            exact::run(set, None, &until(d), events)
        })
        .map_err(suggest_noisy)?
        .synthesis;
    let result = match args.fixed.plateau {
        Some(width) => limit.run(&mut |e| progress.event(e), |d, events| {
            exact::plateau(set, &until(d), first, width, events)
        })?,
        None => first,
    };
    out!(
        "{}{}",
        size_line(&result.size),
        if result.guards_exact {
            ""
        } else {
            " (N not proven minimal)"
        }
    );
    out!(
        "time {:.2} s (SAT {:.2} s, guards {:.2} s); replayed {} scenarios: all reproduced",
        progress.elapsed(),
        result.stats.sat_seconds,
        result.stats.guard_seconds,
        set.scenarios.len()
    );
    Ok((opts, result))
}

/// The exact synthesis the arguments ask for.
fn options(args: &InferArgs, negatives: Vec<NegativeScenario>) -> Result<exact::Options, Failure> {
    Ok(exact::Options {
        sat: exact::SatOptions {
            algorithms: args.algorithms.into(),
            minimize_k: args.minimize_k,
            max_states: args.max_states,
            start_state: args.start_state,
            guard_budget: pipeline::seconds("--guard-budget", args.guard_budget, false)?,
            fixed: args.fixed.bounds(),
            ..exact::SatOptions::default()
        },
        negatives,
        ..exact::Options::default()
    })
}

/// Shows every event, and once the search climbs to [`GLITCH_HINT_STATES`] states the hint at
/// `--noisy`: glitches in a log read as exact each cost states, so a climb this high is the
/// sign.
fn glitch_hint(progress: &Progress) -> impl FnMut(pipeline::Event<'_>) + '_ {
    use crate::sat::{Bound, Step};
    let mut hinted = false;
    move |e| {
        let c = match &e {
            pipeline::Event::Solver(Step::TryingStates { c, .. }) => Some(*c),
            pipeline::Event::Solver(Step::Trying {
                bound: Bound::C,
                value,
            }) => Some(*value),
            _ => None,
        };
        progress.event(e);
        if c.is_some_and(|c| c >= GLITCH_HINT_STATES) && !hinted {
            hinted = true;
            progress.line(NOISY_HINT);
        }
    }
}

/// Writes the least machine into `results` (its exports, and the ambiguity report), prints
/// the files and, with `--json`, the summary.
pub(super) fn write_least(
    args: &InferArgs,
    set: &ScenarioSet,
    result: &Synthesis,
    formats: &[export::Format],
    ambiguity: bool,
    results: ResultSet,
    progress: &Progress,
) -> Result<(), Failure> {
    let mut staged = export::write_all(&result.ecc, results.staging(), &args.name, formats)
        .map_err(Failure::input)?;
    let mut ambiguity_json = serde_json::Value::Null;
    if ambiguity {
        let (found, files) = crate::cli::ambiguity::report(
            set,
            &result.ecc,
            &args.ambiguity,
            args.algorithms,
            progress,
            Some(results.staging()),
        )?;
        ambiguity_json = found.to_json(set, &result.ecc);
        staged.extend(files);
    }
    let files = publish(results, &staged)?;
    print_written(&files);
    if crate::cli::json() {
        let summary = serde_json::json!({
            "size": result.size,
            "guards_proven_minimal": result.guards_exact,
            "transitions_proven_minimal": result.transitions_exact,
            "scenarios": set.scenarios.len(),
            "seconds": progress.elapsed(),
            "stats": result.stats,
            "files": files,
            "ambiguity": ambiguity_json,
        });
        return crate::cli::write_json(&summary);
    }
    Ok(())
}

/// `--dump-cnf DIR`: the size questions around the minimum as DIMACS files, each answered by
/// a fresh solver on exactly the formula written (`verdicts.txt`).
pub(super) fn dump_cnf(
    set: &ScenarioSet,
    sat: &exact::SatOptions,
    result: &Synthesis,
    dir: &Path,
) -> Result<(), Failure> {
    let results = ResultSet::open(dir).map_err(Failure::input)?;
    let staged = output::write_size_questions(results.staging(), set, sat, &result.size)?;
    print_written(&publish(results, &staged)?);
    Ok(())
}
