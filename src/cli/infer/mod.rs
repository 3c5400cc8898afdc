//! `synth infer`: the least machine that reproduces the recordings, exact, noisy
//! ([`noisy`]), modular or distributed ([`modular`]); with `--ltl` the main job's method
//! ([`crate::pipeline::main_job`]). Its arguments, the calls to the library and what it
//! prints, one file per mode.

// Jobs handed to `Limit::run` return `pipeline::Error` (128 bytes) by value; an error ends
// the run, so its size costs nothing that matters.
#![allow(clippy::result_large_err)]

mod least;
mod modular;
mod noisy;

use super::args::{
    optional_check, out_dir, parse_formats, read_negatives, time_limit, AlgorithmsArg,
    AmbiguityArgs, NusmvArgs, TraceArgs,
};
use super::progress::Progress;
use super::show::{closing, explained, print_written, size_line, verified_line};
use super::{exit, Failure};
use crate::export;
use crate::files::ResultSet;
use crate::pipeline::explain::{self, Explanation};
use crate::pipeline::main_job::{self, Summary, VerifiedMachine};
use crate::pipeline::output::{check_exportable, write_verified, Provenance};
use crate::pipeline::{self, exact, Check};
use crate::scenario::negative::NegativeScenario;
use crate::scenario::ScenarioSet;
use clap::{Args, ValueEnum};
use std::path::{Path, PathBuf};

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
    #[arg(long, default_value_t = 32, value_name = "C", value_parser = super::args::states())]
    pub max_states: usize,
    #[command(flatten)]
    pub fixed: FixedArgs,
    /// Seconds for guard minimization; past it the best guards found so far are kept.
    #[arg(long, default_value_t = 10.0, value_name = "SECONDS")]
    pub guard_budget: f64,
    /// Output folder. Default: `out/<stem of the first trace file>`. `-`: the machine on
    /// stdout (the one format --format names, JSON when it names several), every other line
    /// on stderr.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Formats to write, comma-separated: json, fbt, smv, dot, st, pnml, plcopen
    /// (PLCopen TC6 XML, written as .xml).
    #[arg(long, value_delimiter = ',', default_value = "json,fbt,smv,dot,st")]
    pub format: Vec<String>,
    /// Name of the function block type in the exports (an identifier, no keyword of SMV or
    /// IEC 61131-3, none of main, ECC, plant, REQ, CNF, state).
    #[arg(long, default_value = "SynthesizedFB", value_parser = super::args::block_name)]
    pub name: String,
    /// Modular synthesis: distribute the outputs over M basic FBs wired by a composite FB
    /// (writes `<name>.fbt/.smv/.st/.xml/.dot/.modules.json` and
    /// `<name>_M<i>.fbt/.json/.dot`; --format is ignored).
    #[arg(long, value_name = "M", value_parser = super::args::modules())]
    pub modules: Option<usize>,
    /// Distributed synthesis: several controllers, each with the interface FILE gives it
    /// (JSON: `{"controllers": [{"name": "Feeder", "inputs": ["start", "busy"], "outputs":
    /// ["feed"]}, ...]}`; an input is a recorded input or another controller's output, read as
    /// it was before the scan), synthesized together from recordings of the whole network.
    /// Writes each controller's block and the network (`<name>.smv/.st/.dot/.network.json`).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["noisy", "modules", "ltl", "negative", "dump_cnf"])]
    pub distributed: Option<PathBuf>,
    /// With --modules: how the modules are wired. parallel: every module gets REQ and writes
    /// the outputs it owns; consecutive: a chain, REQ to module 1, each module's CNF to the
    /// next, each module rewrites every output in turn and the last one's are the composite's;
    /// arbitrary: a network the solver wires, each block reading recorded inputs and other
    /// blocks' outputs (from before the scan), written as for --distributed.
    #[arg(long, value_enum, default_value_t = TopologyArg::Parallel, requires = "modules")]
    pub topology: TopologyArg,
    /// With --modules: pin outputs to a module, e.g. `--pin 1=start_led,reset_led`
    /// (modules numbered from 1); repeatable. The solver places the other outputs.
    #[arg(long, value_name = "MODULE=OUTPUTS", requires = "modules")]
    pub pin: Vec<String>,
    /// With --modules: transition slots per state (guards are conjunctions of literals), fixed.
    /// Default: 3, widened one at a time while too few (when no modules as small as the least
    /// single machine fit, more slots are what is missing).
    #[arg(long, value_name = "K", value_parser = super::args::per_state())]
    pub slots: Option<usize>,
    #[command(flatten)]
    pub noisy: NoisyArgs,
    /// LTL properties the result must satisfy in closed loop with --plant, as NuSMV verifies:
    /// the least machine that reproduces the recordings and satisfies them (as the main job);
    /// with --noisy the least verified machine over the candidates' corrected traces; with
    /// --modules a composite that NuSMV verifies too.
    #[arg(long, value_name = "FILE", requires = "plant")]
    pub ltl: Option<PathBuf>,
    /// Surrogate plant for --ltl (SMV).
    #[arg(long, value_name = "FILE", requires = "ltl")]
    pub plant: Option<PathBuf>,
    /// With --ltl: give up after this many candidates (each loop: the machine's, the
    /// composite's).
    #[arg(long, default_value_t = 500, value_name = "N", requires = "ltl")]
    pub max_iterations: usize,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
    /// Give up after this many seconds of synthesis (and verification, with --ltl), whatever
    /// the method: plain, --noisy, --modules (exit 3, naming the last step reached).
    #[arg(long, default_value_t = 600.0, value_name = "SECONDS")]
    pub time_limit: f64,
    /// Skip the check whether another machine with as many states fits the recordings.
    #[arg(long)]
    pub no_ambiguity: bool,
    /// Write the SAT questions that prove the sizes minimal as DIMACS CNF files into DIR, for
    /// any other solver: at most C states (satisfiable) and C - 1 (not), and with C states at
    /// most T transitions (satisfiable) and T - 1 (not); `verdicts.txt` lists varisat's answer
    /// to each file.
    #[arg(long, value_name = "DIR")]
    pub dump_cnf: Option<PathBuf>,
    #[command(flatten)]
    pub ambiguity: AmbiguityArgs,
    /// Negative scenarios: behaviours the machine must not show, in the scenario syntax
    /// (fbSAT's complete synthesis); repeatable. A machine shows one when its outputs after
    /// every step equal the scenario's (a step without `out=` keeps the outputs).
    #[arg(long, value_name = "FILE", conflicts_with_all = ["noisy", "modules", "dump_cnf"])]
    pub negative: Vec<PathBuf>,
}

/// Fixed bounds of `synth infer` (fbSAT's `-C`, `-K`, `-T`): a machine within them is asked
/// for, the sizes not fixed are still minimized.
#[derive(Debug, Args, Clone)]
pub struct FixedArgs {
    /// At most C states, and no search for fewer (exit 3 when no machine has at most C states
    /// within the other bounds). More states may allow fewer transitions or guard literals.
    #[arg(long = "states", value_name = "C", value_parser = super::args::states(), conflicts_with_all = ["noisy", "modules", "ltl"])]
    pub states: Option<usize>,
    /// At most K transitions in any state.
    #[arg(long = "out-degree", value_name = "K", value_parser = super::args::per_state(), conflicts_with_all = ["noisy", "modules", "ltl"])]
    pub out_degree: Option<usize>,
    /// After the least machine, look for fewer guard literals with more states (fbSAT's
    /// extended-min-ub): one state more at a time, the least T then N there, until W steps in a
    /// row bring no fewer literals; the machine with the fewest is the result.
    #[arg(long = "plateau", value_name = "W", value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=64), conflicts_with_all = ["noisy", "modules", "ltl", "states"])]
    pub plateau: Option<usize>,
    /// At most T transitions in all.
    #[arg(long = "transitions", value_name = "T", value_parser = super::args::transitions(), conflicts_with_all = ["noisy", "modules", "ltl"])]
    pub transitions: Option<usize>,
}

impl FixedArgs {
    pub fn bounds(&self) -> crate::sat::Fixed {
        crate::sat::Fixed {
            states: self.states,
            max_out_degree: self.out_degree,
            transitions: self.transitions,
        }
    }
}

/// The options of `synth infer` that only `--noisy` reads.
#[derive(Debug, Args, Clone)]
pub struct NoisyArgs {
    /// Read the traces as noisy (scan-cycle skew between PLC and data collector): correct up
    /// to --max-errors recorded output changes and list the minimal machines by errors.
    #[arg(long)]
    pub noisy: bool,
    /// With --noisy: at most this many corrected errors (default: no bound).
    #[arg(long, value_name = "E", requires = "noisy")]
    pub max_errors: Option<usize>,
    /// With --noisy: stop after this many distinct candidate machines.
    #[arg(long, default_value_t = 5, value_name = "N", requires = "noisy")]
    pub enumerate: usize,
}

/// `--topology`.
#[derive(Debug, Clone, Copy, ValueEnum, PartialEq, Eq)]
pub enum TopologyArg {
    /// Every module gets REQ and owns some outputs.
    Parallel,
    /// A chain of modules, each rewriting every output.
    Consecutive,
    /// Modules wired as the solver chooses: each reads recorded inputs and other modules'
    /// outputs (before the scan) and writes some outputs.
    Arbitrary,
}

impl From<TopologyArg> for crate::pipeline::modular::Topology {
    fn from(t: TopologyArg) -> Self {
        match t {
            // An arbitrary network is a parallel composite over the extended inputs.
            TopologyArg::Parallel | TopologyArg::Arbitrary => Self::Parallel,
            TopologyArg::Consecutive => Self::Consecutive,
        }
    }
}

/// `synth infer`.
pub fn infer(args: &InferArgs) -> Result<(), Failure> {
    let to_stdout = args.out.as_deref().is_some_and(crate::files::is_stdin);
    // With --json, --out -, --noisy and --modules give the generic summary (their files and
    // lines; the machine of --out - in its `output`).
    if to_stdout {
        if args.noisy.noisy || args.modules.is_some() || args.distributed.is_some() {
            return Err(Failure::msg(
                exit::USAGE,
                "--out - (the machine on stdout) is for one machine: --noisy, --modules and --distributed write result folders",
            ));
        }
        super::data_on_stdout();
    }
    if args.noisy.noisy {
        return noisy::infer_noisy(args);
    }
    if to_stdout && args.ltl.is_some() {
        return Err(Failure::msg(
            exit::USAGE,
            "--out - (the machine on stdout) is for one machine without --ltl: a verified machine comes with its report in a result folder",
        ));
    }
    if let Some(file) = &args.distributed {
        return modular::infer_network(args, Some(file));
    }
    if args.topology == TopologyArg::Arbitrary {
        if args.ltl.is_some() || args.noisy.noisy {
            return Err(Failure::msg(
                exit::USAGE,
                "--topology arbitrary is for recordings alone: not with --ltl or --noisy",
            ));
        }
        return modular::infer_network(args, None);
    }
    if let Some(m) = args.modules {
        return modular::infer_modules(args, m);
    }
    infer_one(args, to_stdout)
}

/// `synth infer` of one machine: the least for the recordings, or with `--ltl` the main
/// job's verified machine.
fn infer_one(args: &InferArgs, to_stdout: bool) -> Result<(), Failure> {
    let progress = Progress::new(super::quiet());
    let set = load(args, &progress)?;
    let formats = parse_formats(&args.format)?;
    check_exportable(&set, &args.name, &formats, &args.traces.recordings())?;
    let check = loop_check(args, &set, &progress)?;
    let negatives = read_negatives(&args.negative, &set, &progress)?;
    // Rivals are searched without the negative scenarios, so they could be machines the user
    // ruled out: no verdict rather than a wrong one.
    let ambiguity = !args.no_ambiguity && negatives.is_empty();
    if !args.no_ambiguity && !ambiguity {
        progress.line("ambiguity check skipped: it does not take negative scenarios");
    }
    let results = match to_stdout {
        true => None,
        false => Some(infer_out(args)?),
    };
    if let Some((check, found)) = &check {
        let results = results.expect("--out - with --ltl is refused above");
        let v = verified(args, &set, check, found, negatives, &progress)?;
        let staged = write_verified(
            results.staging(),
            &formats,
            &v.ecc,
            &v.certificate,
            &provenance(args),
            &v.summary,
        )?;
        let files = publish(results, &staged)?;
        print_written(&files);
        if super::json() {
            let mut summary = v.summary.to_json();
            summary["files"] = serde_json::json!(files);
            return super::write_json(&summary);
        }
        return Ok(());
    }
    let (opts, result) = least::least(args, &set, negatives, &progress)?;
    let Some(results) = results else {
        let format = super::args::stdout_format(&formats);
        let text = export::text(&result.ecc, &args.name, format).map_err(Failure::input)?;
        if ambiguity {
            super::ambiguity::report(
                &set,
                &result.ecc,
                &args.ambiguity,
                args.algorithms,
                &progress,
                None,
            )?;
        }
        return super::write_data(text.as_bytes());
    };
    if let Some(dir) = &args.dump_cnf {
        least::dump_cnf(&set, &opts.sat, &result, dir)?;
    }
    least::write_least(args, &set, &result, &formats, ambiguity, results, &progress)
}

/// The progress line saying what was read.
pub(super) fn report_loaded(progress: &Progress, set: &ScenarioSet) {
    progress.line(&format!(
        "read {} scenarios, {} steps ({} active) over {} inputs and {} outputs",
        set.scenarios.len(),
        set.step_count(),
        set.active_count(),
        set.inputs.len(),
        set.outputs.len()
    ));
}

/// The recordings, read, with the progress line.
pub(super) fn load(args: &InferArgs, progress: &Progress) -> Result<ScenarioSet, Failure> {
    let set = args.traces.load()?;
    report_loaded(progress, &set);
    Ok(set)
}

/// The output folder (`--out`, default `out/<stem of the first trace>`), taken for this run
/// before the search, so that a second run into it stops at once.
pub(super) fn infer_out(args: &InferArgs) -> Result<ResultSet, Failure> {
    let out = out_dir(&args.out, &args.traces.recordings().stem());
    ResultSet::open(&out).map_err(Failure::input)
}

/// Publishes the staged results; the published paths of `staged`.
pub(super) fn publish(results: ResultSet, staged: &[PathBuf]) -> Result<Vec<PathBuf>, Failure> {
    let files = staged.iter().map(|f| results.published(f)).collect();
    results
        .publish()
        .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
    Ok(files)
}

/// With --ltl/--plant: the check, after the recordings were checked against the properties
/// (recordings that violate one leave no machine to find), with what they say about them.
pub(super) fn loop_check(
    args: &InferArgs,
    set: &ScenarioSet,
    progress: &Progress,
) -> Result<Option<(Check, Explanation)>, Failure> {
    let check = optional_check(&args.ltl, &args.plant, set, &args.nusmv)?;
    let (Some(check), Some(ltl)) = (check, &args.ltl) else {
        return Ok(None);
    };
    let props = &check.problem.props;
    let found = explain::refuse_violations(set, props, ltl).map_err(pipeline::Error::from)?;
    explained(progress, &found, props.len());
    Ok(Some((check, found)))
}

/// Who made a verified machine, for its `verification.txt`.
pub(super) fn provenance(args: &InferArgs) -> Provenance<'_> {
    Provenance {
        name: &args.name,
        plant_file: args.plant.as_deref().unwrap_or(Path::new("")),
        spec_file: args.ltl.as_deref().unwrap_or(Path::new("")),
    }
}

/// The exact loop's options for `infer --ltl` (also the closed loop of `--noisy --ltl`).
pub(super) fn loop_options(args: &InferArgs, negatives: Vec<NegativeScenario>) -> exact::Options {
    exact::Options {
        sat: exact::SatOptions {
            algorithms: args.algorithms.into(),
            max_states: args.max_states,
            start_state: args.start_state,
            ..exact::SatOptions::default()
        },
        max_iterations: args.max_iterations,
        negatives,
        ..exact::Options::default()
    }
}

/// With --ltl/--plant: the main job's verified machine for `set`, printed.
pub(super) fn verified(
    args: &InferArgs,
    set: &ScenarioSet,
    check: &Check,
    found: &Explanation,
    negatives: Vec<NegativeScenario>,
    progress: &Progress,
) -> Result<VerifiedMachine, Failure> {
    let opts = main_job::Options {
        method: main_job::Method::Sat,
        exact: loop_options(args, negatives),
        limit: time_limit(args.time_limit, progress)?,
    };
    let v = main_job::run(set, check, found, &opts, &mut |e| progress.event(e))?;
    let report = &v.certificate.report;
    out!(
        "{}",
        verified_line(report.properties.len(), set.scenarios.len())
    );
    match &v.summary {
        Summary::Exact(e) => out!("{}; {} candidates", size_line(&e.size), e.iterations.len()),
        s => {
            out!("{}", size_line(&s.size()));
            out!("{}", closing(s));
        }
    }
    Ok(v)
}
