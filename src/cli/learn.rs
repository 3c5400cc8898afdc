//! `synth learn`: the active loop against an oracle (a JSON machine or a shipped case's
//! reference controller), and passive learning from random recordings of the same length.

use super::args::{AlgorithmsArg, AmbiguityArgs, TraceArgs};
use super::progress::Progress;
use crate::command::learn::{run, Request};
use crate::pipeline::{active, Error};
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

/// `synth learn`.
pub fn learn(args: &LearnArgs) -> Result<(), Error> {
    if super::json() {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    let request = Request {
        oracle: args.oracle.clone(),
        recordings: args.traces.recordings(),
        options: active::Options {
            ambiguity: args.ambiguity.options(args.algorithms.into())?,
            max_rounds: args.max_rounds.max(1),
            tour: !args.no_tour,
        },
        passive_runs: args.passive_runs,
        out: args.out.clone(),
    };
    let done = run(&request, &mut |e| progress.event(e))?;
    out!("{done}");
    super::note_written(&done.written.iter().cloned().collect::<Vec<_>>());
    match super::json() {
        true => super::write_json(&done.summary()),
        false => Ok(()),
    }
}
