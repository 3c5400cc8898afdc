//! `synth convert` (scenarios from one format into another) and `synth replay` (scenarios
//! replayed on a machine).

use super::args::TraceArgs;
use super::{exit, Failure};
use crate::pipeline::recordings::machine_and_scenarios;
use crate::scenario::{csvlog, fbsat};
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
pub fn convert(args: &ConvertArgs) -> Result<(), Failure> {
    let mut inputs: Vec<PathBuf> = args.traces.traces.clone();
    inputs.extend(args.traces.input_names.iter().cloned());
    inputs.extend(args.traces.output_names.iter().cloned());
    if let Some((i, o)) = args
        .traces
        .traces
        .first()
        .and_then(|t| crate::scenario::names::default_names_files(t))
    {
        inputs.extend([i, o]);
    }
    let to_stdout = crate::files::is_stdin(&args.output);
    if to_stdout {
        super::data_on_stdout();
    } else {
        super::args::refuse_overwrite(&[&args.output], &inputs)?;
    }
    let set = args.traces.load()?;
    let mut buf = Vec::new();
    match args.to {
        ConvertTo::Fbsat => fbsat::write(&set, &mut buf),
        ConvertTo::Csv => csvlog::write(&set, &mut buf),
    }
    .map_err(Failure::input)?;
    if to_stdout {
        return super::write_data(&buf);
    }
    crate::files::write_atomic(&args.output, &buf).map_err(Failure::input)?;
    out!(
        "wrote {} scenarios ({} steps) to {}",
        set.scenarios.len(),
        set.step_count(),
        args.output.display()
    );
    super::note_written(std::slice::from_ref(&args.output));
    Ok(())
}

/// `synth replay`: replays scenarios on a machine read from JSON and reports the first
/// disagreement.
pub fn replay(args: &ReplayArgs) -> Result<(), Failure> {
    let (ecc, set) = machine_and_scenarios(&args.ecc, &args.traces.recordings())?;
    set.check(&ecc)
        .map_err(|m| Failure::msg(exit::FAILED, format!("not reproduced: {m}")))?;
    out!(
        "replayed {} scenarios ({} steps): all reproduced by {}",
        set.scenarios.len(),
        set.step_count(),
        args.ecc.display()
    );
    Ok(())
}
