//! `synth infer` and `synth convert`: scenarios in, minimal ECC (or converted scenarios) out.

use super::{exit, Failure, Progress};
use crate::ecc::{Algorithm, AlgorithmKind, Ecc, State};
use crate::export::{self, Format};
use crate::sat::{self, SatError};
use crate::scenario::{csvlog, fbsat, names, tree::ScenarioTree, ScenarioSet};
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// Where scenarios come from: shared by every command that reads them.
#[derive(Debug, Args, Clone)]
pub struct TraceArgs {
    /// Scenario files: fbSAT text format (plain or .gz) or CSV logs (`.csv`, `.csv.gz`).
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

#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum AlgorithmsArg {
    /// One symbol per output from {0, 1, x}: set to 0, set to 1, keep.
    Tri,
    /// fbSAT's form: two bit strings a0/a1 (new value when the old one was 0 / 1).
    Binary,
}

#[derive(Debug, Args)]
pub struct InferArgs {
    #[command(flatten)]
    pub traces: TraceArgs,
    /// Form of the state output algorithms.
    #[arg(long, value_enum, default_value_t = AlgorithmsArg::Tri)]
    pub algorithms: AlgorithmsArg,
    /// Minimize the largest number of transitions of one state (K) before the total (T).
    #[arg(long)]
    pub minimize_k: bool,
    /// Make state 0 a start state that no transition enters, as the fbSAT tool does
    /// (its published minimal sizes count that state).
    #[arg(long)]
    pub start_state: bool,
    /// Give up when more states than this would be needed.
    #[arg(long, default_value_t = 32, value_name = "C")]
    pub max_states: usize,
    /// Seconds for guard minimization; past it the best guards found so far are kept.
    #[arg(long, default_value_t = 10.0, value_name = "SECONDS")]
    pub guard_budget: f64,
    /// Output folder. Default: `out/<stem of the first trace file>`.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Formats to write, comma-separated: json, fbt, smv, dot, st.
    #[arg(long, value_delimiter = ',', default_value = "json,fbt,smv,dot,st")]
    pub format: Vec<String>,
    /// Name of the function block type in the exports.
    #[arg(long, default_value = "SynthesizedFB")]
    pub name: String,
    /// No progress lines on stderr.
    #[arg(long, short)]
    pub quiet: bool,
    /// Modular synthesis: distribute the outputs over M basic FBs wired by a composite FB
    /// (writes <name>.fbt/.smv/.modules.json and <name>_M<i>.fbt/.json/.dot; --format is
    /// ignored).
    #[arg(long, value_name = "M")]
    pub modules: Option<usize>,
    /// With --modules: pin outputs to a module, e.g. `--pin 1=start_led,reset_led`
    /// (modules numbered from 1); repeatable. The solver places the other outputs.
    #[arg(long, value_name = "MODULE=OUTPUTS", requires = "modules")]
    pub pin: Vec<String>,
    /// With --modules: transition slots per state (guards are conjunctions of literals).
    #[arg(long, default_value_t = 3, value_name = "K")]
    pub slots: usize,
    #[command(flatten)]
    pub noisy: super::noisy::NoisyArgs,
}

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
    /// File to write (gzip-compressed if it ends in `.gz`).
    #[arg(long, short, value_name = "FILE")]
    pub output: PathBuf,
}

fn is_csv(path: &Path) -> bool {
    let name = path.to_string_lossy().to_ascii_lowercase();
    name.ends_with(".csv") || name.ends_with(".csv.gz")
}

/// Reads every trace file of `args` into one scenario set.
pub fn load_scenarios(args: &TraceArgs) -> Result<ScenarioSet, Failure> {
    let defaults = names::default_names_files(&args.traces[0]);
    let in_file = args
        .input_names
        .clone()
        .or_else(|| defaults.as_ref().map(|d| d.0.clone()));
    let out_file = args
        .output_names
        .clone()
        .or_else(|| defaults.as_ref().map(|d| d.1.clone()));
    let inputs = in_file
        .as_deref()
        .map(names::read_names)
        .transpose()
        .map_err(Failure::input)?;
    let outputs = out_file
        .as_deref()
        .map(names::read_names)
        .transpose()
        .map_err(Failure::input)?;
    if let (Some(i), Some(o)) = (&inputs, &outputs) {
        if let Some(n) = i.iter().find(|n| o.contains(n)) {
            return Err(Failure::msg(
                exit::INPUT,
                format!("'{n}' is named both as an input and as an output"),
            ));
        }
    }
    let mut set: Option<ScenarioSet> = None;
    for file in &args.traces {
        let s = if is_csv(file) {
            csvlog::read(file, inputs.as_deref(), outputs.as_deref())
        } else {
            fbsat::read(file, inputs.clone(), outputs.clone())
        }
        .map_err(Failure::input)?;
        match &mut set {
            None => set = Some(s),
            Some(all) => all.merge(s).map_err(Failure::input)?,
        }
    }
    Ok(set.expect("at least one trace file"))
}

fn stem(path: &Path) -> String {
    let f = path
        .file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_else(|| "traces".into());
    f.split('.').next().unwrap_or("traces").to_string()
}

/// The progress line saying what was read.
pub fn report_loaded(progress: &Progress, set: &ScenarioSet) {
    progress.line(&format!(
        "read {} scenarios, {} steps ({} active) over {} inputs and {} outputs",
        set.scenarios.len(),
        set.step_count(),
        set.active_count(),
        set.inputs.len(),
        set.outputs.len()
    ));
}

pub fn infer(args: &InferArgs) -> Result<(), Failure> {
    if args.noisy.noisy {
        return super::noisy::infer_noisy(args);
    }
    if let Some(m) = args.modules {
        return super::modular::infer_modular(args, m);
    }
    let progress = Progress::new(args.quiet);
    let set = load_scenarios(&args.traces)?;
    report_loaded(&progress, &set);
    let formats = parse_formats(&args.format)?;
    check_exportable(&set, &args.name, &formats)?;
    let tree = ScenarioTree::build(&set).map_err(Failure::input)?;
    let opts = sat::Options {
        algorithms: match args.algorithms {
            AlgorithmsArg::Tri => AlgorithmKind::Tri,
            AlgorithmsArg::Binary => AlgorithmKind::Binary,
        },
        minimize_k: args.minimize_k,
        max_states: args.max_states,
        start_state: args.start_state,
        cube_slots: None,
        guard_budget: Duration::from_secs_f64(args.guard_budget.max(0.0)),
    };
    let result =
        sat::synthesize(&set, &tree, &opts, &mut |m| progress.line(m)).map_err(|e| match e {
            SatError::TooManyStates { .. } => Failure::with_code(exit::NO_MACHINE, e),
            SatError::Bug(_) => Failure::with_code(exit::BUG, e),
        })?;
    let s = result.size;
    println!(
        "C = {}  K = {}  T = {}  N = {}{}",
        s.c,
        s.k,
        s.t,
        s.n,
        if result.guards_exact {
            ""
        } else {
            " (N not proven minimal)"
        }
    );
    println!(
        "time {:.2} s (SAT {:.2} s, guards {:.2} s); replayed {} scenarios: all reproduced",
        progress.elapsed(),
        result.stats.sat_seconds,
        result.stats.guard_seconds,
        set.scenarios.len()
    );
    let out = out_dir(args)?;
    let files =
        export::write_all(&result.ecc, &out, &args.name, &formats).map_err(Failure::input)?;
    print_written(&files);
    Ok(())
}

/// The output folder of `synth infer` (`--out`, default `out/<stem of the first trace>`),
/// created if missing.
pub fn out_dir(args: &InferArgs) -> Result<PathBuf, Failure> {
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(stem(&args.traces.traces[0])));
    std::fs::create_dir_all(&out)
        .map_err(|e| Failure::msg(exit::INPUT, format!("cannot create {}: {e}", out.display())))?;
    Ok(out)
}

/// The list of files written, on stdout.
pub fn print_written(files: &[PathBuf]) {
    println!("wrote:");
    for f in files {
        println!("  {}", f.display());
    }
}

/// Parses `--format` values.
pub fn parse_formats(list: &[String]) -> Result<Vec<Format>, Failure> {
    list.iter()
        .map(|f| f.trim().parse::<Format>())
        .collect::<Result<Vec<_>, _>>()
        .map_err(|e| Failure::msg(exit::USAGE, format!("--format: {e}")))
}

/// Checks up front, before any search, that the interface names and the block name can be
/// written in every requested format: an empty machine over the interface must export.
pub fn check_exportable(set: &ScenarioSet, name: &str, formats: &[Format]) -> Result<(), Failure> {
    let probe = Ecc {
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        states: vec![State {
            name: "s0".into(),
            algorithm: Algorithm::keep_all(AlgorithmKind::Tri, set.outputs.len()),
            transitions: Vec::new(),
        }],
    };
    let dir = tempfile::tempdir().map_err(Failure::input)?;
    export::write_all(&probe, dir.path(), name, formats)
        .map(|_| ())
        .map_err(Failure::input)
}

pub fn convert(args: &ConvertArgs) -> Result<(), Failure> {
    let set = load_scenarios(&args.traces)?;
    let mut buf = Vec::new();
    match args.to {
        ConvertTo::Fbsat => fbsat::write(&set, &mut buf),
        ConvertTo::Csv => csvlog::write(&set, &mut buf),
    }
    .map_err(Failure::input)?;
    crate::files::write_atomic(&args.output, &buf).map_err(Failure::input)?;
    println!(
        "wrote {} scenarios ({} steps) to {}",
        set.scenarios.len(),
        set.step_count(),
        args.output.display()
    );
    Ok(())
}

#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The machine, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    #[command(flatten)]
    pub traces: TraceArgs,
}

/// Reads a machine from its JSON file.
pub fn read_ecc(path: &Path) -> Result<Ecc, Failure> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| Failure::msg(exit::INPUT, format!("{}: {e}", path.display())))?;
    export::json::read_json(&text, path).map_err(Failure::input)
}

/// Reads a machine and recordings and checks that they share one interface.
pub fn machine_and_scenarios(
    ecc_file: &Path,
    traces: &TraceArgs,
) -> Result<(Ecc, ScenarioSet), Failure> {
    let ecc = read_ecc(ecc_file)?;
    let set = load_scenarios(traces)?;
    if set.inputs != ecc.inputs || set.outputs != ecc.outputs {
        return Err(Failure::msg(
            exit::INPUT,
            format!(
                "{} has inputs [{}] and outputs [{}], the scenarios [{}] and [{}]",
                ecc_file.display(),
                ecc.inputs.join(" "),
                ecc.outputs.join(" "),
                set.inputs.join(" "),
                set.outputs.join(" ")
            ),
        ));
    }
    Ok((ecc, set))
}

/// Replays scenarios on a machine read from JSON and reports the first disagreement.
pub fn replay(args: &ReplayArgs) -> Result<(), Failure> {
    let (ecc, set) = machine_and_scenarios(&args.ecc, &args.traces)?;
    set.check(&ecc)
        .map_err(|m| Failure::msg(exit::INPUT, format!("not reproduced: {m}")))?;
    println!(
        "replayed {} scenarios ({} steps): all reproduced by {}",
        set.scenarios.len(),
        set.step_count(),
        args.ecc.display()
    );
    Ok(())
}
