//! The `synth` command line: argument parsing, progress on stderr, exit codes.
//!
//! In: `std::env::args`. Out: files written by the library and a summary on stdout.
//! Everything that computes lives in the library (one function per command, above the
//! pipelines of [`crate::pipeline`]); each command file here turns its arguments into the
//! library's options, calls it and prints what came back. Command files never import each
//! other: what they share is here, in [`args`], [`progress`] and [`show`]. Every failure is a
//! library [`Error`]; its [`Class`] becomes the exit code in one place, [`code`]. The
//! developer binary `synth-dev` uses this module too, for the same output flags, errors, exit
//! codes, argument groups and progress lines.

/// `println!` for the results on stdout, which survives a reader that went away (`synth ... |
/// head`): the run goes on and finishes its files. A panic there, or death by SIGPIPE (which
/// would also hit synth when NuSMV dies with its input unread), would leave them half-written.
///
/// When the result itself goes to stdout (`--out -`), these lines go to stderr instead
/// ([`data_on_stdout`]).
#[macro_export]
#[doc(hidden)]
macro_rules! out {
    () => {
        $crate::out!("")
    };
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if $crate::cli::stdout_is_data() {
            $crate::cli::capture(&format!("{}\n", format_args!($($arg)*)));
            let _ = writeln!(std::io::stderr(), $($arg)*);
        } else {
            let _ = writeln!(std::io::stdout(), $($arg)*);
        }
    }};
}

/// `print!` likewise ([`out!`]).
#[macro_export]
#[doc(hidden)]
macro_rules! out_raw {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        if $crate::cli::stdout_is_data() {
            $crate::cli::capture(&format!($($arg)*));
            let _ = write!(std::io::stderr(), $($arg)*);
        } else {
            let _ = write!(std::io::stdout(), $($arg)*);
        }
    }};
}

/// One line on stderr, best effort: a closed or full stderr (`2>&1 | head -1`, `2>/dev/full`)
/// loses the line, never the run, its files or its exit code.
pub fn err_line(line: std::fmt::Arguments<'_>) {
    use std::io::Write as _;
    let _ = writeln!(std::io::stderr(), "{line}");
}

/// Set when a command writes its result on stdout: every other line goes to stderr then.
static STDOUT_IS_DATA: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether stdout carries the result only ([`data_on_stdout`]).
pub fn stdout_is_data() -> bool {
    STDOUT_IS_DATA.load(std::sync::atomic::Ordering::Relaxed)
}

/// From now on stdout carries the result only (`--out -`).
pub fn data_on_stdout() {
    STDOUT_IS_DATA.store(true, std::sync::atomic::Ordering::Relaxed);
}

/// The flags every command takes (`-q`, `-v`, `--json`), set once after parsing.
static QUIET: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
static VERBOSE: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
static JSON: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
/// Whether the command wrote its own `--json` summary.
static JSON_WRITTEN: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);
/// With `--json` and no summary of the command's own: what it would have written on stdout,
/// and the files it listed as written, for the generic summary ([`generic_summary`]).
static CAPTURED: std::sync::Mutex<Vec<u8>> = std::sync::Mutex::new(Vec::new());
static WRITTEN: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// `-q`: no progress lines.
pub fn quiet() -> bool {
    QUIET.load(std::sync::atomic::Ordering::Relaxed)
}

/// `-v`: more progress where the command has more to say.
pub fn verbose() -> bool {
    VERBOSE.load(std::sync::atomic::Ordering::Relaxed)
}

/// `--json`: a machine-readable summary on stdout, every other line on stderr.
pub fn json() -> bool {
    JSON.load(std::sync::atomic::Ordering::Relaxed)
}

/// With `--json`: keeps a line the command printed for the generic summary's `output`.
pub fn capture(text: &str) {
    if json() {
        if let Ok(mut c) = CAPTURED.lock() {
            c.extend_from_slice(text.as_bytes());
        }
    }
}

/// Notes files a command wrote (for the generic `--json` summary).
pub fn note_written(files: &[std::path::PathBuf]) {
    if let Ok(mut w) = WRITTEN.lock() {
        w.extend_from_slice(files);
    }
}

/// The flags every command takes.
#[derive(Debug, clap::Args)]
pub struct OutputArgs {
    /// No progress lines on stderr.
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// More progress where the command has more to say (every minimization step, every round).
    #[arg(long, short, global = true)]
    pub verbose: bool,
    /// A machine-readable summary (JSON) on stdout; every other line goes to stderr. Commands
    /// without a summary of their own write `{"command", "exit", "files", "output", "error"}`.
    #[arg(long, global = true)]
    pub json: bool,
    /// Replace files the run reads, or a result another command wrote, in the output (the
    /// output rule refuses that otherwise).
    #[arg(long, global = true)]
    pub force: bool,
}

/// Writes a `--json` summary on stdout (pretty, one value, its keys sorted, a final newline).
pub fn write_json(summary: &impl serde::Serialize) -> Result<(), Error> {
    JSON_WRITTEN.store(true, std::sync::atomic::Ordering::Relaxed);
    let value = summary::to_json(summary);
    write_stdout(format!("{value:#}\n").as_bytes())
}

/// The summary of a command without one of its own, with `--json`: its name, exit code, the
/// files it wrote, what it printed (its result lines, and data it would have written on
/// stdout), and the error.
fn generic_summary(command: &str, exit: i32, error: Option<String>) -> CommandSummary {
    let files = WRITTEN.lock().map(|w| w.clone()).unwrap_or_default();
    let output = CAPTURED
        .lock()
        .map(|c| String::from_utf8_lossy(&c).into_owned())
        .unwrap_or_default();
    CommandSummary {
        format: summary::COMMAND,
        command: command.into(),
        exit,
        files,
        output,
        error,
    }
}

/// Writes the result on stdout (see [`data_on_stdout`]); with `--json` it goes into the
/// generic summary instead, so that stdout holds one JSON value.
pub fn write_data(bytes: &[u8]) -> Result<(), Error> {
    if json() {
        if let Ok(mut c) = CAPTURED.lock() {
            c.extend_from_slice(bytes);
        }
        return Ok(());
    }
    write_stdout(bytes)
}

fn write_stdout(bytes: &[u8]) -> Result<(), Error> {
    use std::io::Write as _;
    let mut out = std::io::stdout().lock();
    match out.write_all(bytes).and_then(|()| out.flush()) {
        Ok(()) => Ok(()),
        // A reader that went away (`| head`) took what it wanted.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Error::Input(format!("cannot write to stdout: {e}"))),
    }
}

mod ambiguity;
pub mod args;
mod batch;
mod conform;
mod convert;
mod diff;
mod docs;
mod events;
mod export;
mod infer;
mod ingest;
mod learn;
mod learn_plant;
mod live;
mod main_job;
pub mod progress;
pub mod show;
mod verify;

use crate::pipeline::summary::{self, CommandSummary};
pub use crate::pipeline::{Class, Error};
use clap::{Parser, Subcommand};

/// Exit codes, as documented in `--help`.
pub mod exit {
    /// Success (for the main job and `verify`: every property verified).
    pub const OK: i32 = 0;
    /// The check asked for came out negative: `verify` found a violated property, `diff` a
    /// difference, `replay` or `conform` a step the machine does not reproduce; the main job
    /// and `verify` were given a plant that allows no behaviour, or a closed loop deadlocks
    /// (nothing can be verified).
    pub const FAILED: i32 = 1;
    /// Command-line usage error (clap).
    pub const USAGE: i32 = 2;
    /// No machine exists within the limits given (e.g. --max-states).
    pub const NO_MACHINE: i32 = 3;
    /// Bad input or a failed tool: a clear message says what and where (file, line, step;
    /// NuSMV missing, crashed or out of time).
    pub const INPUT: i32 = 4;
    /// An internal error: a bug in synth.
    pub const BUG: i32 = 70;
}

const EXIT_HELP: &str = "\
Exit codes:
  0   success
  1   the check came out negative: a violated property (verify), a difference (diff), a
      step not reproduced (replay, conform), a plant with no behaviour (main job, verify)
  2   command-line usage error
  3   no machine exists within the given limits (--max-states, --max-iterations,
      --time-limit)
  4   bad input (file, line and step are named), an output that would replace an input or
      another command's result (--force allows it), a busy output folder, or a failed tool
      (NuSMV missing, crashed or out of time)
  70  internal error: a bug in synth, please report it
  130 ended by SIGINT, SIGTERM or SIGHUP";

const ABOUT: &str =
    "Rebuild the lost control logic of a legacy PLC as a minimal IEC 61499 basic function block.";

const LONG_ABOUT: &str = "\
Rebuild the lost control logic of a legacy PLC as a minimal IEC 61499 basic function block.

Main job:  synth --ltl specs/pnp.ltl --plant smv/pnp_surrogate.smv
  synthesizes the smallest controller that reproduces the recorded scenarios (by default
  specs/pnp.traces, found beside the --ltl file) and satisfies every LTL property in closed
  loop with the surrogate plant, as checked by the NuSMV model checker. Exit code 0 only
  when NuSMV confirmed every property. With --learn-plant (and --observe FILE) instead of
  --plant, the plant is learned from the recordings and kept as plant.smv with the result.

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
    // The main job's options cannot go with a subcommand; the flags every command takes
    // (`-q`, `-v`, `--json`) may stand before it too. [`parse`] checks the first.
    subcommand_negates_reqs = true
)]
pub(crate) struct Cli {
    #[command(flatten)]
    pub output: OutputArgs,
    #[command(subcommand)]
    pub command: Option<Command>,
    /// The main job: synthesize a controller that reproduces the scenarios and satisfies
    /// every LTL property in closed loop with the plant, verified by NuSMV.
    #[command(flatten)]
    pub main: main_job::MainArgs,
}

#[derive(Debug, Subcommand)]
pub(crate) enum Command {
    /// Synthesize a minimal ECC that reproduces recorded scenarios.
    Infer(Box<infer::InferArgs>),
    /// Monitor a machine in service: replay new recordings, report each trace's first
    /// divergence; with --refine, learn the divergent traces and synthesize again.
    Conform(conform::ConformArgs),
    /// Replay scenarios on a machine (JSON) and report the first step it does not reproduce.
    Replay(convert::ReplayArgs),
    /// Compare two machines (JSON): "equivalent", or the shortest input sequence on which
    /// they answer differently (exit 1).
    Diff(diff::DiffArgs),
    /// What to record next: input sequences (from the initial state or a recorded prefix) on
    /// which the machines that fit the recordings answer differently, as a plan.
    NextRecording(ambiguity::NextRecordingArgs),
    /// Learn the surrogate plant from the recordings: a plant file for the main job and
    /// verify, checked to produce every recorded step.
    LearnPlant(learn_plant::LearnPlantArgs),
    /// Compare two plants on random closed-loop runs of a machine: how many runs of each
    /// the other admits.
    ComparePlants(learn_plant::ComparePlantsArgs),
    /// Active learning against a machine that answers (JSON, or a case's reference): infer,
    /// find a rival, record the sequence that tells them apart, until unique; compared with
    /// random recordings of the same length.
    Learn(learn::LearnArgs),
    /// Print a shell completion script (bash, zsh, fish, elvish, powershell).
    Completions(docs::CompletionsArgs),
    /// Print the manual page (roff), or write one page per command with --out.
    Man(docs::ManArgs),
    /// Print the JSON Schema of the machine contract (the JSON files synth writes and reads),
    /// or with --summary of the summaries (summary.json, --json).
    Schema(docs::SchemaArgs),
    /// Write a machine (JSON, also a hand-edited one) in every format: fbt, st, smv, dot, pnml,
    /// PLCopen XML.
    Export(export::ExportArgs),
    /// Convert scenarios between the fbSAT text format and CSV logs.
    Convert(convert::ConvertArgs),
    /// Check an existing machine (JSON) against LTL properties in closed loop with a plant.
    Verify(verify::VerifyArgs),
    /// Turn a raw PLC I/O data-flow log (long or wide CSV, plain or gzip) and an address
    /// mapping into one fbSAT scenario, streaming.
    Ingest(ingest::IngestArgs),
    /// Record a running PLC's inputs and outputs over OPC UA as a CSV log (for infer).
    Record(live::RecordArgs),
    /// Run a machine beside a running PLC over OPC UA, scan by scan: the first divergence
    /// (exit 1) and the stretch up to it as a recording (for conform --refine).
    Monitor(live::MonitorArgs),
    /// One reconstruction per PLC over a folder of logs (CSV, Parquet, or raw logs with
    /// --map), on all cores; each machine in its folder, and a summary table (CSV, JSON).
    Batch(batch::BatchArgs),
    /// Turn a raw PLC I/O log into an event log (XES and CSV) for process-mining tools,
    /// sliced into traces at a reset activity (the process-mining paper's conversion).
    Events(events::EventsArgs),
}

/// The exit code of each class of failure: the one place where a failure becomes a code.
pub fn code(class: Class) -> i32 {
    match class {
        Class::Input => exit::INPUT,
        Class::Vacuous | Class::Negative => exit::FAILED,
        Class::Usage => exit::USAGE,
        Class::NoMachine => exit::NO_MACHINE,
        Class::Bug => exit::BUG,
    }
}

/// What the command line says of a failure: the error, a `caused by:` line per source
/// (unless the error already says it), then its notes, one a line.
pub fn message(e: &Error) -> String {
    if let Error::Noted { error, notes } = e {
        let notes: String = notes.iter().map(|n| format!("\n({n})")).collect();
        return message(error) + &notes;
    }
    let mut message = e.to_string();
    let mut source = std::error::Error::source(e);
    while let Some(s) = source {
        // Wrappers that only forward their source would repeat the message.
        let text = s.to_string();
        if !message.contains(&text) {
            message.push_str(&format!("\ncaused by: {text}"));
        }
        source = s.source();
    }
    message
}

/// Prints an error of clap (or the help it stands for); the exit code.
pub fn clap_error(e: clap::Error) -> i32 {
    let _ = e.print();
    match e.use_stderr() {
        true => code(Class::Usage),
        false => exit::OK,
    }
}

/// Parses the command line, refusing the main job's options beside a subcommand.
fn parse() -> Result<Cli, clap::Error> {
    use clap::{CommandFactory, FromArgMatches};
    let mut cmd = Cli::command();
    let matches = cmd.try_get_matches_from_mut(std::env::args_os())?;
    if let Some((name, _)) = matches.subcommand() {
        let main_arg = cmd
            .get_arguments()
            .filter(|a| !a.is_global_set())
            .find(|a| {
                matches.value_source(a.get_id().as_str())
                    == Some(clap::parser::ValueSource::CommandLine)
            });
        if let Some(a) = main_arg {
            let flag = a
                .get_long()
                .map_or_else(|| a.get_id().to_string(), |l| format!("--{l}"));
            return Err(cmd.error(
                clap::error::ErrorKind::ArgumentConflict,
                format!("the subcommand '{name}' cannot be used with '{flag}' (an option of the main job)"),
            ));
        }
    }
    Cli::from_arg_matches(&matches).map_err(|e| e.format(&mut cmd))
}

/// Runs the command line; returns the process exit code.
pub fn run() -> i32 {
    let cli = match parse() {
        Ok(c) => c,
        Err(e) => return clap_error(e),
    };
    start(&cli.output);
    let command = std::env::args()
        .skip(1)
        .find(|a| !a.starts_with('-'))
        .filter(|_| cli.command.is_some())
        .unwrap_or_else(|| "main".into());
    let result = match cli.command {
        Some(Command::Infer(a)) => infer::infer(&a),
        Some(Command::NextRecording(a)) => ambiguity::next_recording(&a),
        Some(Command::Learn(a)) => learn::learn(&a),
        Some(Command::LearnPlant(a)) => learn_plant::learn_plant(&a),
        Some(Command::ComparePlants(a)) => learn_plant::compare_plants(&a),
        Some(Command::Export(a)) => export::export(&a),
        Some(Command::Completions(a)) => docs::completions(&a),
        Some(Command::Man(a)) => docs::man(&a),
        Some(Command::Schema(a)) => docs::schema(&a),
        Some(Command::Convert(a)) => convert::convert(&a),
        Some(Command::Replay(a)) => convert::replay(&a),
        Some(Command::Diff(a)) => diff::diff(&a),
        Some(Command::Conform(a)) => conform::conform(&a),
        Some(Command::Ingest(a)) => ingest::ingest(&a),
        Some(Command::Batch(a)) => batch::batch(&a),
        Some(Command::Record(a)) => live::record_cmd(&a),
        Some(Command::Monitor(a)) => live::monitor_cmd(&a),
        Some(Command::Events(a)) => events::events(&a),
        Some(Command::Verify(a)) => verify::verify(&a),
        None => main_job::main_job(&cli.main),
    };
    finish(&command, result)
}

/// Sets the flags every command takes (`-q`, `-v`, `--json`).
pub fn start(o: &OutputArgs) {
    QUIET.store(o.quiet, std::sync::atomic::Ordering::Relaxed);
    VERBOSE.store(o.verbose, std::sync::atomic::Ordering::Relaxed);
    JSON.store(o.json, std::sync::atomic::Ordering::Relaxed);
    crate::files::allow_replacing(o.force);
    // Before any work: a signal ends every phase alike (exit 130), reading included.
    crate::signals::install();
    if o.json {
        data_on_stdout();
    }
}

/// Reports the result of `command` (`error: ...`; with `--json` the generic summary when the
/// command wrote none); returns the exit code.
pub fn finish(command: &str, result: Result<(), Error>) -> i32 {
    let (code, error) = match &result {
        Ok(()) => (exit::OK, None),
        Err(e) => {
            let message = message(e);
            err_line(format_args!("error: {message}"));
            (code(e.class()), Some(message))
        }
    };
    if json() && !JSON_WRITTEN.load(std::sync::atomic::Ordering::Relaxed) {
        let _ = write_json(&generic_summary(command, code, error));
    }
    code
}
