//! `synth ingest` and `synth bench-ingest`: raw PLC I/O logs into a scenario file, and the
//! ingestion throughput benchmark.

use super::Failure;
use clap::Args;
use fbsynth::ingest::{self, LogReader, Mapping, ReadStats, RowKind};
use std::io::Write;
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
        fbsynth::files::write_atomic(file, text.as_bytes()).map_err(Failure::input)?;
    }
    report(&written.stats, secs);
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

fn report(stats: &ReadStats, secs: f64) {
    out!("rows:    {}", stats.rows);
    out!("samples: {}", stats.samples);
    for kind in RowKind::ALL {
        let n = stats.skipped(kind);
        if n > 0 {
            out!("skipped: {n} rows ({})", kind.label());
        }
    }
    out!(
        "time:    {secs:.2} s ({:.2} M rows/s)",
        stats.rows as f64 / secs.max(1e-9) / 1e6
    );
}

#[derive(Debug, Args)]
pub struct BenchIngestArgs {
    /// Rows of the generated long-format log.
    #[arg(long, default_value_t = 10_000_000)]
    pub rows: u64,
    /// Input signals of the generated log.
    #[arg(long, default_value_t = 8)]
    pub inputs: usize,
    /// Output signals of the generated log.
    #[arg(long, default_value_t = 8)]
    pub outputs: usize,
    /// Compress the generated log with gzip.
    #[arg(long)]
    pub gzip: bool,
    /// Seed of the random toggles.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

pub fn bench_ingest(args: &BenchIngestArgs) -> Result<(), Failure> {
    let io = |e: std::io::Error| Failure::msg(super::exit::INPUT, format!("temporary log: {e}"));
    let tmp = tempfile::Builder::new()
        .suffix(if args.gzip { ".csv.gz" } else { ".csv" })
        .tempfile()
        .map_err(io)?;
    let start = Instant::now();
    let map = {
        let file = std::io::BufWriter::with_capacity(1 << 16, tmp.as_file());
        if args.gzip {
            let mut gz = flate2::write::GzEncoder::new(file, flate2::Compression::fast());
            let map =
                ingest::write_random_log(&mut gz, args.inputs, args.outputs, args.rows, args.seed)
                    .map_err(io)?;
            gz.finish().map_err(io)?.flush().map_err(io)?;
            map
        } else {
            let mut file = file;
            let map = ingest::write_random_log(
                &mut file,
                args.inputs,
                args.outputs,
                args.rows,
                args.seed,
            )
            .map_err(io)?;
            file.flush().map_err(io)?;
            map
        }
    };
    let size = tmp.as_file().metadata().map_err(io)?.len();
    out!(
        "generated {} rows ({:.1} MB{}) in {:.2} s; peak RSS so far {}",
        args.rows,
        size as f64 / 1e6,
        if args.gzip { ", gzip" } else { "" },
        start.elapsed().as_secs_f64(),
        peak_rss()
    );
    let mapping = Mapping::parse(Path::new("<generated>"), &map).map_err(Failure::input)?;
    let start = Instant::now();
    let reader = LogReader::open(tmp.path(), &mapping, false).map_err(Failure::input)?;
    let mut steps: u64 = 0;
    let mut active: u64 = 0;
    let stats = ingest::convert_log(reader, vec![false; mapping.outputs().len()], |s| {
        steps += 1;
        active += u64::from(s.outputs.is_some());
        Ok::<(), ingest::IngestError>(())
    })
    .map_err(Failure::input)?;
    let secs = start.elapsed().as_secs_f64();
    report(&stats, secs);
    out!("steps:   {steps} ({active} with CNF)");
    out!("peak RSS: {}", peak_rss());
    Ok(())
}

/// Peak resident set size of this process (`VmHWM`), as the kernel reports it.
pub(super) fn peak_rss() -> String {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("VmHWM:").map(|v| v.trim().to_string()))
        })
        .unwrap_or_else(|| "unknown".into())
}
