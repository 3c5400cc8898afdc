//! Argument groups shared by several commands, and their conversion to library settings.

use super::progress::Progress;
use crate::command::{Spec, Tool};
use crate::ecc::AlgorithmKind;
use crate::export::Format;
use crate::pipeline::{self, search, Error, Nusmv, Recordings};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

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
    /// Couples a plant signal with a controller signal of another name: `plant.SIGNAL=NAME`,
    /// SIGNAL a parameter of MODULE plant (NAME an output) or a name it declares (NAME an
    /// input). Repeatable.
    #[arg(long, value_name = "plant.SIGNAL=NAME")]
    pub couple: Vec<crate::smv::composition::Couple>,
    /// A file of `--couple` pairs, one `plant.SIGNAL=NAME` per line (`--` comments); added to
    /// those of `--couple`.
    #[arg(long, value_name = "FILE", value_parser = couple_file)]
    pub couple_file: Option<CoupleFile>,
}

/// The pairs read from a `--couple-file`.
#[derive(Debug, Clone)]
pub struct CoupleFile(pub Vec<crate::smv::composition::Couple>);

/// Reads a `--couple-file` when the command line is parsed, so that a bad line is a usage
/// error naming the file and line.
fn couple_file(path: &str) -> Result<CoupleFile, String> {
    crate::smv::composition::read_couples(std::path::Path::new(path)).map(CoupleFile)
}

impl NusmvArgs {
    /// Locates NuSMV; fails early with the install hint.
    pub fn nusmv(&self) -> Result<Nusmv, Error> {
        pipeline::nusmv(self.nusmv.as_deref(), self.timeout)
    }

    /// NuSMV, located when the command needs it.
    pub(crate) fn tool(&self) -> Tool {
        Tool {
            path: self.nusmv.clone(),
            timeout: self.timeout,
        }
    }

    /// The pairs of `--couple`, then those of `--couple-file`.
    pub(crate) fn couples(&self) -> Vec<crate::smv::composition::Couple> {
        let file = self.couple_file.iter().flat_map(|f| &f.0);
        self.couple.iter().chain(file).cloned().collect()
    }

    /// With both `--ltl` and `--plant`: the properties, the plant and this NuSMV.
    pub(crate) fn spec(&self, ltl: &Option<PathBuf>, plant: &Option<PathBuf>) -> Option<Spec> {
        Some(Spec {
            ltl: ltl.clone()?,
            plant: plant.clone()?,
            nusmv: self.tool(),
            couple: self.couples(),
            learned: None,
        })
    }
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
    #[arg(long, default_value_t = 20.0, value_name = "SECONDS", value_parser = seconds)]
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
    ) -> Result<crate::pipeline::ambiguity::Options, Error> {
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

/// A number of seconds, 0 to a year, refused when parsed (not after the work it limits).
pub fn seconds(text: &str) -> Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|e| format!("{e}"))?;
    crate::pipeline::seconds("the option", value, false).map_err(|e| e.to_string())?;
    Ok(value)
}

/// `--verify-probability`: a probability, 0 to 1.
pub fn probability(text: &str) -> Result<f64, String> {
    let value: f64 = text.trim().parse().map_err(|e| format!("{e}"))?;
    match (0.0..=1.0).contains(&value) {
        true => Ok(value),
        false => Err(format!(
            "a probability is a number from 0 to 1, not {value}"
        )),
    }
}

/// Repetitions of a benchmark or an experiment: 0 to 10,000.
pub fn repetitions() -> clap::builder::RangedU64ValueParser<usize> {
    clap::builder::RangedU64ValueParser::new().range(0..=10_000)
}

/// `--name`: a block name every export can use ([`crate::ecc::ident::check_block_name`]),
/// refused before anything is read.
pub fn block_name(name: &str) -> Result<String, String> {
    crate::ecc::ident::check_block_name(name).map(|()| name.to_string())
}

/// Parses `--format` values.
pub fn parse_formats(list: &[String]) -> Result<Vec<Format>, Error> {
    list.iter()
        .map(|f| f.trim().parse::<Format>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| Error::Usage(format!("--format: {e}")))
}

/// Where the colonies start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Start {
    /// Random machines, as in Chivilikhin et al.'s metaheuristic reconstruction.
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

/// The time limit `--time-limit` names, counted from the start of the run.
pub fn time_limit(seconds: f64, progress: &Progress) -> Result<pipeline::limit::Limit, Error> {
    pipeline::seconds("--time-limit", seconds, true)?;
    Ok(pipeline::limit::Limit::new(progress.started(), seconds))
}
