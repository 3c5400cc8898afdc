//! `synth next-recording`: what to record next so that the rivals found are told apart.

use super::args::{AlgorithmsArg, AmbiguityArgs, TraceArgs};
use super::progress::Progress;
use super::show::print_written;
use crate::command::ambiguity::{next_recording as job, Request};
use crate::pipeline::summary::{NextRecordingSummary, NEXT_RECORDING};
use crate::pipeline::Error;
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct NextRecordingArgs {
    #[command(flatten)]
    pub traces: TraceArgs,
    /// The machine inferred from the recordings (JSON, as `synth infer` wrote it); default:
    /// infer it now.
    #[arg(long, value_name = "FILE")]
    pub ecc: Option<PathBuf>,
    /// Form of the state output algorithms.
    #[arg(long, value_enum, default_value_t = AlgorithmsArg::Tri)]
    pub algorithms: AlgorithmsArg,
    #[command(flatten)]
    pub ambiguity: AmbiguityArgs,
    /// Output folder for `plan.csv`, `plan.txt`, the rivals and the machine they rival
    /// (`machine.json`). Default: `out/<stem of the first trace file>-next`.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `synth next-recording`: the sequences that tell the rivals apart, as a plan.
pub fn next_recording(args: &NextRecordingArgs) -> Result<(), Error> {
    if super::json() {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    let request = Request {
        recordings: args.traces.recordings(),
        ecc: args.ecc.clone(),
        algorithms: args.algorithms.into(),
        ambiguity: args.ambiguity.options(args.algorithms.into())?,
        out: args.out.clone(),
    };
    let plan = job(&request, &mut |e| progress.event(e))?;
    out!("{plan}");
    print_written(&plan.files);
    if super::json() {
        return super::write_json(&NextRecordingSummary {
            format: NEXT_RECORDING,
            ambiguity: plan.report.summary(&plan.set, &plan.machine),
            files: plan.files.clone(),
        });
    }
    Ok(())
}
