//! `synth ingest`: a raw PLC I/O log into a scenario file.

use crate::command::ingest::run;
use crate::pipeline::Error;
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct IngestArgs {
    /// Data-flow log: long (`timestamp,address,value`) or wide (`timestamp,<signal>,...`)
    /// CSV, plain or gzip, or Parquet (`.parquet`) with the same columns.
    #[arg(long, value_name = "FILE")]
    pub log: PathBuf,
    /// Mapping file: one `ADDRESS in|out NAME` per line.
    #[arg(long, value_name = "FILE")]
    pub map: PathBuf,
    /// Skip bad rows (unparsable value, unknown address, time going backwards, wrong cell
    /// count) and count them, instead of stopping at the first.
    #[arg(long)]
    pub lenient: bool,
    /// fbSAT scenario file to write (`.gz` compresses); `<stem>.inputs` and `<stem>.outputs`
    /// are written beside it.
    #[arg(short = 'o', long = "output", value_name = "OUT")]
    pub output: PathBuf,
}

/// `synth ingest`.
pub fn ingest(args: &IngestArgs) -> Result<(), Error> {
    let done = run(&args.log, &args.map, args.lenient, &args.output)?;
    out!("{done}");
    super::note_written(&done.files);
    Ok(())
}
