//! `synth convert` (scenarios from one format into another) and `synth replay` (scenarios
//! replayed on a machine).

use super::args::TraceArgs;
use crate::command::convert::{convert as job, replay as replay_job, To};
use crate::pipeline::Error;
use clap::{Args, ValueEnum};
use std::path::PathBuf;

#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum ConvertTo {
    /// fbSAT scenario text format.
    Fbsat,
    /// CSV log with `in:`/`out:` headers and a `scenario` column.
    Csv,
}

#[derive(Debug, Args)]
pub struct ConvertArgs {
    #[command(flatten)]
    pub traces: TraceArgs,
    /// Format to write.
    #[arg(long, value_enum)]
    pub to: ConvertTo,
    /// File to write (gzip-compressed if it ends in `.gz`; `-`: stdout).
    #[arg(long, short, value_name = "FILE")]
    pub output: PathBuf,
}

#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The machine, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    #[command(flatten)]
    pub traces: TraceArgs,
}

/// `synth convert`.
pub fn convert(args: &ConvertArgs) -> Result<(), Error> {
    let to_stdout = crate::files::is_stdin(&args.output);
    if to_stdout {
        super::data_on_stdout();
    }
    let to = match args.to {
        ConvertTo::Fbsat => To::Fbsat,
        ConvertTo::Csv => To::Csv,
    };
    let output = (!to_stdout).then_some(args.output.as_path());
    let done = job(&args.traces.recordings(), to, output)?;
    if to_stdout {
        return super::write_data(&done.bytes);
    }
    out!("{}", done.line(&args.output));
    super::note_written(std::slice::from_ref(&args.output));
    Ok(())
}

/// `synth replay`: replays scenarios on a machine read from JSON and reports the first
/// disagreement.
pub fn replay(args: &ReplayArgs) -> Result<(), Error> {
    out!("{}", replay_job(&args.ecc, &args.traces.recordings())?);
    Ok(())
}
