//! `synth ingest`: a raw PLC I/O log into a scenario file.

use super::show::print_read_stats;
use super::Failure;
use crate::ingest::{self, Mapping};
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;

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

pub fn ingest(args: &IngestArgs) -> Result<(), Failure> {
    let start = Instant::now();
    let (inputs_file, outputs_file) = names_files(&args.output);
    super::args::refuse_overwrite(
        &[&args.output, &inputs_file, &outputs_file],
        &[&args.log, &args.map],
    )?;
    let mapping = Mapping::read(&args.map).map_err(Failure::input)?;
    let written =
        ingest::write_scenario(&args.log, &mapping, args.lenient, &args.output).map_err(|e| {
            let row = matches!(e, ingest::IngestError::Row { .. });
            let mut f = Failure::input(e);
            if row {
                f.message
                    .push_str("\n(--lenient skips bad rows and counts them instead)");
            }
            f
        })?;
    let secs = start.elapsed().as_secs_f64();
    for (file, names) in [
        (&inputs_file, mapping.inputs()),
        (&outputs_file, mapping.outputs()),
    ] {
        let text: String = names.iter().map(|n| format!("{n}\n")).collect();
        crate::files::write_atomic(file, text.as_bytes()).map_err(Failure::input)?;
    }
    print_read_stats(&written.stats, secs);
    out!("steps:   {} ({} with CNF)", written.steps, written.active);
    out!(
        "wrote {}, {}, {}",
        args.output.display(),
        inputs_file.display(),
        outputs_file.display()
    );
    super::note_written(&[
        args.output.clone(),
        inputs_file.clone(),
        outputs_file.clone(),
    ]);
    Ok(())
}

/// `<stem>.inputs` / `<stem>.outputs` beside `out`, where the other commands look for them.
fn names_files(out: &Path) -> (PathBuf, PathBuf) {
    let dir = out.parent().unwrap_or(Path::new(""));
    let file = out
        .file_name()
        .and_then(|f| f.to_str())
        .unwrap_or("scenarios");
    let stem = file.split('.').next().unwrap_or(file);
    (
        dir.join(format!("{stem}.inputs")),
        dir.join(format!("{stem}.outputs")),
    )
}
