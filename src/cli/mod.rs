//! The `synth` command line: argument parsing, progress on stderr, exit codes.
//!
//! In: `std::env::args`. Out: files written by the library and a summary on stdout.
//! Everything that computes lives in the library; this module only wires it to a terminal.

mod bench;
mod conform;
mod events;
mod infer;
mod ingest;
mod modular;
mod noisy;
mod search;
mod verified;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::time::Instant;

/// Exit codes, as documented in `--help`.
pub mod exit {
    /// Success (for the main job and `verify`: every property verified).
    pub const OK: i32 = 0;
    /// Bad input or a failed check: a clear message says what and where.
    pub const INPUT: i32 = 1;
    /// Command-line usage error (clap).
    pub const USAGE: i32 = 2;
    /// No machine exists within the limits given (e.g. --max-states).
    pub const NO_MACHINE: i32 = 3;
    /// An internal error: a bug in synth.
    pub const BUG: i32 = 70;
}

const EXIT_HELP: &str = "\
Exit codes:
  0   success
  1   bad input (file, line and step are named) or a failed check
  2   command-line usage error
  3   no machine exists within the given limits (e.g. --max-states)
  70  internal error: a bug in synth, please report it";

const ABOUT: &str =
    "Rebuild the lost control logic of a legacy PLC as a minimal IEC 61499 basic function block.";

const LONG_ABOUT: &str = "\
Rebuild the lost control logic of a legacy PLC as a minimal IEC 61499 basic function block.

Main job:  synth --ltl specs/pnp.ltl --plant smv/pnp_surrogate.smv
  synthesizes the smallest controller that reproduces the recorded scenarios (by default
  specs/pnp.traces, found beside the --ltl file) and satisfies every LTL property in closed
  loop with the surrogate plant, as checked by the NuSMV model checker. Exit code 0 only
  when NuSMV confirmed every property.

Record the PLC's inputs and outputs while the machine runs (scenario files or CSV logs),
and synth finds the smallest state machine (Execution Control Chart) that reproduces every
recording: fewest states, then fewest transitions, then the shortest guards. It writes the
result as IEC 61499 .fbt (4diac, NxtStudio), Structured Text, SMV, Graphviz and JSON.";

#[derive(Debug, Parser)]
#[command(
    name = "synth",
    version,
    about = ABOUT,
    long_about = LONG_ABOUT,
    after_help = EXIT_HELP,
    args_conflicts_with_subcommands = true
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
    /// The main job: synthesize a controller that reproduces the scenarios and satisfies
    /// every LTL property in closed loop with the plant, verified by NuSMV.
    #[command(flatten)]
    pub main: verified::MainArgs,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Synthesize a minimal ECC that reproduces recorded scenarios.
    Infer(infer::InferArgs),
    /// Monitor a machine in service: replay new recordings, report each trace's first
    /// divergence; with --refine, learn the divergent traces and synthesize again.
    Conform(conform::ConformArgs),
    /// Replay scenarios on a machine (JSON) and report the first step it does not reproduce.
    Replay(infer::ReplayArgs),
    /// Convert scenarios between the fbSAT text format and CSV logs.
    Convert(infer::ConvertArgs),
    /// Check an existing machine (JSON) against LTL properties in closed loop with a plant.
    Verify(verified::VerifyArgs),
    /// Regenerate a shipped case's scenario files from its reference controller and plant
    /// simulation (`pnp`: the Pick-and-Place manipulator).
    Generate(GenerateArgs),
    /// Measure synthesis time on the project's and (when present) fbSAT's scenario sets.
    Bench(bench::BenchArgs),
    /// Turn a raw PLC I/O data-flow log (long or wide CSV, plain or gzip) and an address
    /// mapping into one fbSAT scenario, streaming.
    Ingest(ingest::IngestArgs),
    /// Measure ingestion throughput and peak memory on a generated long-format log.
    BenchIngest(ingest::BenchIngestArgs),
    /// Turn a raw PLC I/O log into an event log (XES and CSV) for process-mining tools,
    /// sliced into traces at a reset activity (seed 002's conversion).
    Events(events::EventsArgs),
    /// Measure modular synthesis (infer --modules) for M = 1..4 on a scenario set.
    BenchModular(modular::BenchModularArgs),
    /// Reproduce a seed paper's experiment (`table1`: seed 001's Table I with the search).
    Experiment(search::ExperimentArgs),
    /// Measure the search's scenario-fitness evaluations per second per thread.
    BenchSearch(search::BenchSearchArgs),
    /// Measure noisy synthesis (--noisy) on generated distribution-station logs.
    BenchNoisy(noisy::BenchNoisyArgs),
}

#[derive(Debug, clap::Args)]
pub struct GenerateArgs {
    /// The case: `pnp`, `tank` (seed 002's tank: scenarios, raw logs, held-out runs) or
    /// `distribution` (the Festo station: clean, noisy and held-out sampled logs).
    #[arg(value_parser = ["pnp", "tank", "distribution"])]
    pub case: String,
    /// Folder to write the scenario and names files into.
    #[arg(long, default_value = "specs", value_name = "DIR")]
    pub out: PathBuf,
}

fn generate(args: &GenerateArgs) -> Result<(), Failure> {
    if args.case == "tank" {
        return events::generate_tank(&args.out);
    }
    if args.case == "distribution" {
        return noisy::generate_distribution(&args.out);
    }
    let files = crate::cases::pnp::write_files(&args.out).map_err(Failure::input)?;
    let set = crate::cases::pnp::generate();
    println!(
        "recorded {} work-piece orders ({} steps) from the reference controller:",
        set.scenarios.len(),
        set.step_count()
    );
    for f in files {
        println!("  {}", f.display());
    }
    Ok(())
}

/// A failure the CLI reports: message, causes, exit code.
pub struct Failure {
    pub code: i32,
    pub message: String,
}

impl Failure {
    pub fn input(e: impl std::error::Error) -> Failure {
        Failure::with_code(exit::INPUT, e)
    }

    pub fn with_code(code: i32, e: impl std::error::Error) -> Failure {
        let mut message = e.to_string();
        let mut source = e.source();
        while let Some(s) = source {
            // Wrappers that only forward their source would repeat the message.
            let text = s.to_string();
            if !message.contains(&text) {
                message.push_str(&format!("\ncaused by: {text}"));
            }
            source = s.source();
        }
        Failure { code, message }
    }

    pub fn msg(code: i32, message: impl Into<String>) -> Failure {
        Failure {
            code,
            message: message.into(),
        }
    }
}

/// Progress lines on stderr, prefixed with the elapsed time.
pub struct Progress {
    start: Instant,
    quiet: bool,
}

impl Progress {
    pub fn new(quiet: bool) -> Progress {
        Progress {
            start: Instant::now(),
            quiet,
        }
    }

    pub fn line(&self, msg: &str) {
        if !self.quiet {
            eprintln!("[{:7.2}s] {msg}", self.start.elapsed().as_secs_f64());
        }
    }

    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }
}

/// Runs the command line; returns the process exit code.
pub fn run() -> i32 {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                exit::USAGE
            } else {
                exit::OK
            };
        }
    };
    let result = match cli.command {
        Some(Command::Infer(a)) => infer::infer(&a),
        Some(Command::Convert(a)) => infer::convert(&a),
        Some(Command::Replay(a)) => infer::replay(&a),
        Some(Command::Conform(a)) => conform::conform(&a),
        Some(Command::Bench(a)) => bench::bench(&a),
        Some(Command::Ingest(a)) => ingest::ingest(&a),
        Some(Command::BenchIngest(a)) => ingest::bench_ingest(&a),
        Some(Command::Events(a)) => events::events(&a),
        Some(Command::BenchModular(a)) => modular::bench_modular(&a),
        Some(Command::Experiment(a)) => search::experiment(&a),
        Some(Command::BenchSearch(a)) => search::bench_search(&a),
        Some(Command::BenchNoisy(a)) => noisy::bench_noisy(&a),
        Some(Command::Verify(a)) => verified::verify(&a),
        Some(Command::Generate(a)) => generate(&a),
        None => verified::main_job(&cli.main),
    };
    match result {
        Ok(()) => exit::OK,
        Err(f) => {
            eprintln!("error: {}", f.message);
            f.code
        }
    }
}

/// Paths given on the command line, for messages.
pub fn show(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| p.display().to_string())
        .collect::<Vec<_>>()
        .join(", ")
}
