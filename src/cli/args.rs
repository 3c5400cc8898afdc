//! Argument groups shared by several commands, and their conversion to library settings.

use super::{exit, Failure};
use crate::ecc::AlgorithmKind;
use crate::export::Format;
use crate::pipeline::{self, search, Check, Nusmv, Problem, Recordings};
use crate::scenario::ScenarioSet;
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};

/// Where scenarios come from: shared by every command that reads them.
#[derive(Debug, Args, Clone)]
pub struct TraceArgs {
    /// Scenario files: fbSAT text format (plain or .gz), CSV logs (`.csv`, `.csv.gz`) or
    /// Parquet logs (`.parquet`, the CSV log's columns); a folder stands for the logs in it and
    /// its subfolders (a partitioned data set); `-` reads stdin (told apart by content: fbSAT
    /// scenarios hold `REQ[`).
    #[arg(long = "traces", visible_alias = "log", value_name = "FILE", num_args = 1.., required = true)]
    pub traces: Vec<PathBuf>,
    /// Input names, separated by whitespace or newlines, in bit order.
    /// Default: `<stem>.inputs` or `input-names` beside the first trace file.
    #[arg(long, value_name = "FILE")]
    pub input_names: Option<PathBuf>,
    /// Output names, in bit order. Default: `<stem>.outputs` or `output-names` beside the
    /// first trace file.
    #[arg(long, value_name = "FILE")]
    pub output_names: Option<PathBuf>,
}

impl TraceArgs {
    /// The recordings these arguments name.
    pub fn recordings(&self) -> Recordings {
        Recordings {
            traces: self.traces.clone(),
            input_names: self.input_names.clone(),
            output_names: self.output_names.clone(),
        }
    }

    /// Reads every trace file into one scenario set.
    pub fn load(&self) -> Result<ScenarioSet, Failure> {
        Ok(self.recordings().load()?)
    }
}

/// Form of the state output algorithms.
#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum AlgorithmsArg {
    /// One symbol per output from {0, 1, x}: set to 0, set to 1, keep.
    Tri,
    /// fbSAT's form: two bit strings a0/a1 (new value when the old one was 0 / 1).
    Binary,
}

impl From<AlgorithmsArg> for AlgorithmKind {
    fn from(a: AlgorithmsArg) -> AlgorithmKind {
        match a {
            AlgorithmsArg::Tri => AlgorithmKind::Tri,
            AlgorithmsArg::Binary => AlgorithmKind::Binary,
        }
    }
}

/// NuSMV options shared by the commands that run it.
#[derive(Debug, Args, Clone)]
pub struct NusmvArgs {
    /// The NuSMV binary. Default: $NUSMV, then NuSMV on PATH, then the install script's cache.
    #[arg(long, value_name = "PATH")]
    pub nusmv: Option<PathBuf>,
    /// Seconds NuSMV may spend on one closed-loop model before it is killed.
    #[arg(long, default_value_t = 60.0, value_name = "SECONDS")]
    pub timeout: f64,
}

impl NusmvArgs {
    /// Locates NuSMV; fails early with the install hint.
    pub fn nusmv(&self) -> Result<Nusmv, Failure> {
        Ok(pipeline::nusmv(self.nusmv.as_deref(), self.timeout)?)
    }
}

/// Reads and checks the spec, the plant and the coupling with the controller interface.
pub fn problem(
    ltl: &Path,
    plant: &Path,
    inputs: &[String],
    outputs: &[String],
) -> Result<Problem, Failure> {
    Problem::load(ltl, plant, inputs, outputs).map_err(|e| Failure::from(pipeline::Error::from(e)))
}

/// With both `--ltl` and `--plant`: the problem they state over the interface of `set`, and
/// the NuSMV that checks it.
pub fn optional_check(
    ltl: &Option<PathBuf>,
    plant: &Option<PathBuf>,
    set: &ScenarioSet,
    nusmv: &NusmvArgs,
) -> Result<Option<Check>, Failure> {
    match (ltl, plant) {
        (Some(ltl), Some(plant)) => Ok(Some(check(
            problem(ltl, plant, &set.inputs, &set.outputs)?,
            nusmv,
        )?)),
        _ => Ok(None),
    }
}

/// A problem and the NuSMV that checks it.
pub fn check(problem: Problem, nusmv: &NusmvArgs) -> Result<Check, Failure> {
    Ok(Check::new(problem, nusmv.nusmv()?))
}

/// Refuses to run when an output path names one of the input files (the atomic rename
/// would replace the input with the result), or a folder (found only when the first files
/// of the result were already written).
pub fn refuse_overwrite<P: AsRef<Path>, Q: AsRef<Path>>(
    outputs: &[P],
    inputs: &[Q],
) -> Result<(), Failure> {
    for out in outputs {
        if out.as_ref().is_dir() {
            return Err(Failure::msg(
                exit::INPUT,
                format!(
                    "the output {} is a folder; give a file name (or move the folder away)",
                    out.as_ref().display()
                ),
            ));
        }
        for input in inputs {
            if crate::files::same_file(out.as_ref(), input.as_ref()) {
                return Err(Failure::msg(
                    exit::INPUT,
                    format!(
                        "the output {} would overwrite the input {}; choose another output path",
                        out.as_ref().display(),
                        input.as_ref().display()
                    ),
                ));
            }
        }
    }
    Ok(())
}

// Bounds of the size options: far above any controller the tool is for, and below what makes
// an encoding or a thread pool exhaust the machine (a thousand transition slots per state
// took gigabytes).
/// `--max-states`, `--states`: 1 to 256.
pub fn states() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=256)
}

/// `--max-out-degree`, `--slots`: 1 to 64 transitions per state.
pub fn per_state() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=64)
}

/// `--transitions`: 0 to 65536 transitions in all.
pub fn transitions() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(0..=65536)
}

/// `--rivals`: 1 to 100 rival machines.
pub fn rivals() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=100)
}

/// `--passive-runs`: 0 to 100.
pub fn runs() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(0..=100)
}

/// `--ambiguity-depth`: 1 to 1000 steps.
pub fn depth() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=1000)
}

/// The ambiguity check after synthesis (`synth infer`, `synth next-recording`, `synth learn`,
/// the main job with `--ambiguity`).
#[derive(Debug, clap::Args, Clone)]
pub struct AmbiguityArgs {
    /// Rival machines to list at most (each answers some sequence differently from the
    /// machine and from the rivals before it).
    #[arg(long, default_value_t = 1, value_name = "N", value_parser = rivals())]
    pub rivals: usize,
    /// The longest distinguishing sequence looked for, in steps (default: the number
    /// of states).
    #[arg(long, value_name = "STEPS", value_parser = depth())]
    pub ambiguity_depth: Option<usize>,
    /// Seconds for each rival's search; past it the verdict is "unknown".
    #[arg(long, default_value_t = 20.0, value_name = "SECONDS")]
    pub ambiguity_budget: f64,
    /// Distinguishing sequences over every input vector (at most 10 inputs), not only the
    /// input combinations the recordings show.
    #[arg(long)]
    pub all_inputs: bool,
    /// States a rival may have beyond the machine's (0: exactly as many); a machine in service
    /// may need more states than the recordings show.
    #[arg(long, default_value_t = 0, value_name = "E", value_parser = runs())]
    pub extra_states: usize,
}

impl AmbiguityArgs {
    /// The pipeline's options.
    pub fn options(
        &self,
        algorithms: crate::ecc::AlgorithmKind,
    ) -> Result<crate::pipeline::ambiguity::Options, super::Failure> {
        Ok(crate::pipeline::ambiguity::Options {
            algorithms,
            rivals: self.rivals,
            depth: self.ambiguity_depth,
            all_inputs: self.all_inputs,
            polish: std::time::Duration::from_secs(1),
            extra_states: self.extra_states,
            budget: crate::pipeline::seconds("--ambiguity-budget", self.ambiguity_budget, false)?,
        })
    }
}

/// `--modules`: 1 to 64.
pub fn modules() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=64)
}

/// `--threads`, `--colonies`: 1 to 1024.
pub fn workers() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(1..=1024)
}

/// `--name`: a block name every export can use ([`crate::ecc::ident::check_block_name`]),
/// refused before anything is read.
pub fn block_name(name: &str) -> Result<String, String> {
    crate::ecc::ident::check_block_name(name).map(|()| name.to_string())
}

/// Parses `--format` values.
pub fn parse_formats(list: &[String]) -> Result<Vec<Format>, Failure> {
    list.iter()
        .map(|f| f.trim().parse::<Format>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| Failure::msg(exit::USAGE, format!("--format: {e}")))
}

/// The one format written on stdout (`--out -`): the one `--format` names, JSON when it
/// names several.
pub fn stdout_format(formats: &[Format]) -> Format {
    match formats {
        [one] => *one,
        _ => Format::Json,
    }
}

/// `--out`, or `out/<stem>`.
pub fn out_dir(out: &Option<PathBuf>, stem: &str) -> PathBuf {
    out.clone()
        .unwrap_or_else(|| PathBuf::from("out").join(stem))
}

/// Where the colonies start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Start {
    /// Random machines (the seeds' method).
    Random,
    /// The minimal machine SAT finds for the scenarios alone (verification left to the search).
    Sat,
}

/// Who judges the search's candidates (NuSMV always judges the machine it ends with).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Judge {
    /// The in-process checker (about a millisecond a candidate; NuSMV where it cannot decide).
    InProcess,
    /// NuSMV on every candidate judged, as the verification-in-the-loop paper does.
    Nusmv,
}

impl From<Judge> for search::Judge {
    fn from(j: Judge) -> search::Judge {
        match j {
            Judge::InProcess => search::Judge::InProcess,
            Judge::Nusmv => search::Judge::Nusmv,
        }
    }
}

impl From<Start> for search::Start {
    fn from(s: Start) -> search::Start {
        match s {
            Start::Random => search::Start::Random,
            Start::Sat => search::Start::Sat,
        }
    }
}

/// The `--negative` files, read over the recordings' interface (a progress line each).
pub fn read_negatives(
    files: &[PathBuf],
    set: &ScenarioSet,
    progress: &super::progress::Progress,
) -> Result<Vec<crate::scenario::negative::NegativeScenario>, Failure> {
    use crate::scenario::negative;
    let mut all = Vec::new();
    for file in files {
        let negs = negative::read(file, &set.inputs, &set.outputs, &set.initial_outputs)
            .map_err(pipeline::Error::from)?;
        progress.line(&format!(
            "read {} negative scenario{} from {}",
            negs.len(),
            if negs.len() == 1 { "" } else { "s" },
            file.display()
        ));
        all.extend(negs);
    }
    Ok(all)
}

/// The time limit `--time-limit` names, counted from the start of the run.
pub fn time_limit(
    seconds: f64,
    progress: &super::progress::Progress,
) -> Result<pipeline::limit::Limit, Failure> {
    pipeline::seconds("--time-limit", seconds, true)?;
    Ok(pipeline::limit::Limit::new(progress.started(), seconds))
}
