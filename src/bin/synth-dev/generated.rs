//! The benchmarks on generated data: logs and runs of the distribution station, and raw
//! data-flow logs, of any length; each row also shows the peak memory.
//!
//! - `bench-noisy`: noisy synthesis on generated distribution-station logs;
//! - `bench-long`: exact synthesis on one long generated run (lazy synthesis);
//! - `bench-ingest`: ingestion throughput and peak memory on a generated long-format log.

use crate::cli::progress::Progress;
use clap::Args;
use fbsynth::cases::distribution;
use fbsynth::ingest::Throughput;
use fbsynth::ingest::{self, LogReader, Mapping};
use fbsynth::out;
use fbsynth::pipeline::Error;
use fbsynth::pipeline::{exact, noisy};
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub struct BenchNoisyArgs {
    /// Log lengths in samples, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1000,10000,100000")]
    pub samples: Vec<usize>,
    /// Probability that an output change is recorded one sample early.
    #[arg(long, default_value_t = 0.02)]
    pub rate: f64,
    /// Seed of the use cases and of the injected errors.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Candidates to enumerate after minimization.
    #[arg(long, default_value_t = 1)]
    pub enumerate: usize,
    /// Bound on corrected errors, as a multiple of the number injected (0: no bound).
    #[arg(long, default_value_t = 1.0)]
    pub error_bound: f64,
    /// Also write each size's logs as `DIR/noisy-<samples>.csv` and `DIR/clean-<samples>.csv`
    /// (the format of `specs/distribution_noisy.csv`), to time `synth infer --noisy` on them.
    #[arg(long, value_name = "DIR")]
    pub save: Option<PathBuf>,
}

/// `synth-dev bench-noisy`: times noisy synthesis on generated distribution-station logs
/// ([`distribution::random_logs`], skew injected per log).
pub fn bench_noisy(args: &BenchNoisyArgs) -> Result<(), Error> {
    out!(
        "samples  steps    nodes   traces  injected  C  K  T   ε      rounds  encoded  vars      clauses    sizes_s  epsilon_s  total_s  clean  peak_rss"
    );
    for &len in &args.samples {
        let mut injected = 0;
        let clean = distribution::random_logs(len, args.seed);
        let noisy: Vec<_> = clean
            .iter()
            .enumerate()
            .map(|(k, log)| {
                let (n, i) = distribution::inject_skew(log, args.rate, args.seed + k as u64);
                injected += i;
                n
            })
            .collect();
        if let Some(dir) = &args.save {
            save_logs(dir, &format!("noisy-{len}.csv"), &noisy)?;
            save_logs(dir, &format!("clean-{len}.csv"), &clean)?;
        }
        let set = distribution::to_scenarios(&noisy, "<generated>");
        let opts = noisy::Options {
            enumerate: args.enumerate.max(1),
            max_errors: (args.error_bound > 0.0)
                .then(|| (injected as f64 * args.error_bound).ceil() as usize),
            ..noisy::Options::default()
        };
        let t = Instant::now();
        let progress = Progress::new(!crate::cli::verbose());
        let r = noisy::run(&set, None, &opts, &mut |e| progress.event(e))
            .map_err(|e| Error::Bug(crate::cli::message(&e)))?
            .synthesis;
        let total = t.elapsed().as_secs_f64();
        let first = r.candidates.first();
        // The candidate has been replayed on its corrected traces; the logs before the
        // injected errors are the ground truth it should reproduce as well.
        let replays_clean = first.is_some_and(|c| {
            distribution::to_scenarios(&clean, "<clean>")
                .check(&c.ecc)
                .is_ok()
        });
        out!(
            "{:<8} {:<8} {:<7} {:<7} {:<9} {:<2} {:<2} {:<3} {:<6} {:<7} {:<8} {:<9} {:<10} {:<8.2} {:<10.2} {:<8.2} {:<6} {}",
            len,
            set.step_count(),
            r.stats.graph_nodes,
            r.stats.distinct_traces,
            injected,
            r.n,
            r.k,
            r.r,
            first.map_or(0, |c| c.errors),
            r.stats.rounds,
            if r.stats.rounds == 0 { r.stats.graph_nodes } else { r.stats.encoded_nodes },
            r.stats.variables,
            r.stats.clauses,
            r.stats.minimize_seconds,
            r.stats.enumerate_seconds,
            total,
            if replays_clean { "yes" } else { "no" },
            peak_rss()
        );
    }
    Ok(())
}

fn save_logs(
    dir: &Path,
    name: &str,
    logs: &[Vec<fbsynth::scenario::csvlog::Sample>],
) -> Result<(), Error> {
    std::fs::create_dir_all(dir).map_err(Error::from)?;
    let mut text = Vec::new();
    distribution::write_csv(logs, &mut text).map_err(Error::from)?;
    fbsynth::files::write_atomic(&dir.join(name), &text).map_err(Error::from)
}

#[derive(Debug, Args)]
pub struct BenchLongArgs {
    /// Lengths of the run in steps, comma-separated; one row each, in this order.
    #[arg(long, value_delimiter = ',', default_value = "10000,100000,1000000")]
    pub steps: Vec<usize>,
    /// Seed of the operator's rounds.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Also write each run as a scenario file `DIR/long-<steps>.traces` (names in
    /// `DIR/long.inputs`, `DIR/long.outputs`), to time `synth infer` on it on its own.
    #[arg(long, value_name = "DIR")]
    pub save: Option<PathBuf>,
}

/// `synth-dev bench-long`: exact synthesis (no properties) on one long run of the distribution
/// station ([`distribution::long_run`]); every machine is replayed on the whole run.
pub fn bench_long(args: &BenchLongArgs) -> Result<(), Error> {
    out!("steps     C  K  T   N   rounds  encoded  generate_s  synth_s  peak_rss");
    for &steps in &args.steps {
        let t = Instant::now();
        let set = distribution::long_run(steps, args.seed);
        let generate = t.elapsed().as_secs_f64();
        if let Some(dir) = &args.save {
            save_run(&set, dir, steps)?;
        }
        let t = Instant::now();
        let progress = Progress::new(!crate::cli::verbose());
        let r = exact::run(&set, None, &exact::Options::default(), &mut |e| {
            progress.event(e)
        })
        .map_err(|e| Error::Bug(crate::cli::message(&e)))?
        .synthesis;
        // The pipeline has replayed the machine on every step of the run.
        let seconds = t.elapsed().as_secs_f64();
        out!(
            "{:<9} {:<2} {:<2} {:<3} {:<3} {:<7} {:<8} {:<11.2} {:<8.2} {}",
            steps,
            r.size.c,
            r.size.k,
            r.size.t,
            r.size.n,
            r.stats.rounds,
            r.stats.steps_encoded,
            generate,
            seconds,
            peak_rss()
        );
    }
    Ok(())
}

fn save_run(set: &fbsynth::scenario::ScenarioSet, dir: &Path, steps: usize) -> Result<(), Error> {
    use fbsynth::files::write_atomic;
    std::fs::create_dir_all(dir).map_err(Error::from)?;
    let mut text = Vec::new();
    fbsynth::scenario::fbsat::write(set, &mut text).map_err(Error::from)?;
    write_atomic(&dir.join(format!("long-{steps}.traces")), &text).map_err(Error::from)?;
    let names = |n: &[String]| format!("{}\n", n.join("\n"));
    write_atomic(&dir.join("long.inputs"), names(&set.inputs).as_bytes()).map_err(Error::from)?;
    write_atomic(&dir.join("long.outputs"), names(&set.outputs).as_bytes()).map_err(Error::from)?;
    Ok(())
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

/// `synth-dev bench-ingest`: writes a random long-format log (gzip with `--gzip`) into a
/// temporary file, then reads it through the ingestion as `synth ingest` does.
pub fn bench_ingest(args: &BenchIngestArgs) -> Result<(), Error> {
    let io = |e: std::io::Error| Error::Input(format!("temporary log: {e}"));
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
    let mapping = Mapping::parse(Path::new("<generated>"), &map).map_err(Error::from)?;
    let start = Instant::now();
    let reader = LogReader::open(tmp.path(), &mapping, false).map_err(Error::from)?;
    let mut steps: u64 = 0;
    let mut active: u64 = 0;
    let stats = ingest::convert_log(reader, vec![false; mapping.outputs().len()], |s| {
        steps += 1;
        active += u64::from(s.outputs.is_some());
        Ok::<(), ingest::IngestError>(())
    })
    .map_err(Error::from)?;
    let secs = start.elapsed().as_secs_f64();
    out!(
        "{}",
        Throughput {
            stats: &stats,
            seconds: secs
        }
    );
    out!("steps:   {steps} ({active} with CNF)");
    out!("peak RSS: {}", peak_rss());
    Ok(())
}

/// Peak resident set size of this process (`VmHWM`), as the kernel reports it.
fn peak_rss() -> String {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find_map(|l| l.strip_prefix("VmHWM:").map(|v| v.trim().to_string()))
        })
        .unwrap_or_else(|| "unknown".into())
}
