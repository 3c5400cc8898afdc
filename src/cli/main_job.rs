//! The main job (`synth --ltl SPEC --plant PLANT`, by exact SAT or by search): its
//! arguments, the call to the library and what it prints. With `--learn-plant [--observe
//! FILE] [--slack N]` instead of `--plant`, the plant is learned from the same recordings, as
//! `synth learn-plant` learns it, and published with the machine as `plant.smv`.

use super::args::{parse_formats, time_limit, AlgorithmsArg, Judge, NusmvArgs, Start, TraceArgs};
use super::learn_plant::LearningArgs;
use super::progress::Progress;
use super::show::print_files;
use crate::command::main_job::{self as job, Request};
use crate::pipeline::{self, exact, main_job, search, Error};
use clap::{ArgGroup, Args, ValueEnum};
use std::path::PathBuf;
/// The help heading of the options that say how the plant is learned.
const LEARNING: &str = "With --learn-plant";

/// Arguments of the main job (no subcommand).
#[derive(Debug, Args, Clone)]
// The plant is read (`--plant`) or learned (`--learn-plant`): exactly one of them.
#[command(group(ArgGroup::new("plant_source").args(["plant", "learn_plant"])))]
// How the plant is learned applies only when it is learned.
#[command(
    mut_arg("observe", |a| a
        .requires("learn_plant")
        .conflicts_with("plant")
        .help_heading(LEARNING)),
    mut_arg("slack", |a| a
        .requires("learn_plant")
        .conflicts_with("plant")
        .help_heading(LEARNING)),
    mut_arg("assume", |a| a
        .requires("learn_plant")
        .conflicts_with("plant")
        .help_heading(LEARNING))
)]
pub struct MainArgs {
    /// LTL properties, one per line (NuSMV syntax over bare names; `--` comments; `name:`).
    #[arg(long, value_name = "FILE")]
    pub ltl: Option<PathBuf>,
    /// Surrogate plant model: an SMV file defining `MODULE plant(<controller outputs>)`.
    #[arg(long, value_name = "FILE")]
    pub plant: Option<PathBuf>,
    /// Learn the surrogate plant from the recordings instead (as `synth learn-plant` does;
    /// recordings it cannot learn from are refused with their file and step), and keep it as
    /// `plant.smv` in the output folder, its figures under `learned_plant` in `summary.json`.
    #[arg(long)]
    pub learn_plant: bool,
    #[command(flatten)]
    pub learning: LearningArgs,
    /// Scenario files. Default: `<stem>.traces` beside the --ltl file (specs/pnp.ltl ->
    /// specs/pnp.traces), with names from `<stem>.inputs` / `<stem>.outputs`.
    #[arg(long = "traces", value_name = "FILE", num_args = 1..)]
    pub traces: Vec<PathBuf>,
    /// Input names file (default: beside the first trace file).
    #[arg(long, value_name = "FILE")]
    pub input_names: Option<PathBuf>,
    /// Output names file (default: beside the first trace file).
    #[arg(long, value_name = "FILE")]
    pub output_names: Option<PathBuf>,
    /// Output folder. Default: `out/<stem of the --ltl file>`.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// After synthesis: look for rivals (machines with as many states that reproduce the
    /// recordings but answer differently) and check each with NuSMV.
    #[arg(long)]
    pub ambiguity: bool,
    /// Negative scenarios: behaviours the machine must not show, in the scenario syntax
    /// (fbSAT's complete synthesis); repeatable. A machine shows one when its outputs after
    /// every step equal the scenario's (a step without `out=` keeps the outputs).
    #[arg(long, value_name = "FILE", conflicts_with = "ambiguity")]
    pub negative: Vec<PathBuf>,
    #[command(flatten)]
    pub ambiguity_args: super::args::AmbiguityArgs,
    /// Form of the state output algorithms.
    #[arg(long, value_enum, default_value_t = AlgorithmsArg::Tri)]
    pub algorithms: AlgorithmsArg,
    /// Make state 0 a start state that no transition enters, as the fbSAT tool does
    /// (its published minimal sizes count that state).
    #[arg(long)]
    pub start_state: bool,
    /// Give up when more states than this would be needed.
    #[arg(long, default_value_t = 32, value_name = "C", value_parser = super::args::states())]
    pub max_states: usize,
    /// Transitions per state at most (each guarded by a conjunction of input literals).
    #[arg(long, default_value_t = exact::DEFAULT_MAX_OUT_DEGREE, value_name = "K", value_parser = super::args::per_state())]
    pub max_out_degree: usize,
    /// Give up after this many candidate controllers.
    #[arg(long, default_value_t = 500, value_name = "N")]
    pub max_iterations: usize,
    /// Give up after this many seconds of synthesis and verification, with either method
    /// (exit 3, saying what was found by then).
    #[arg(long, default_value_t = 600.0, value_name = "SECONDS")]
    pub time_limit: f64,
    /// Seconds the final machine's transition and literal counts may take to be proven
    /// minimal once it is verified; past it the result says "not proven minimal". 0 skips the
    /// proof.
    #[arg(long, default_value_t = exact::DEFAULT_PROOF_BUDGET.as_secs_f64(), value_name = "SECONDS")]
    pub proof_budget: f64,
    /// Formats to write, comma-separated: json, fbt, smv, dot, st, pnml, plcopen
    /// (PLCopen TC6 XML, written as .xml).
    #[arg(long, value_delimiter = ',', default_value = "json,fbt,smv,dot,st")]
    pub format: Vec<String>,
    /// Name of the function block type in the exports (an identifier, no keyword of SMV or
    /// IEC 61131-3, none of main, ECC, plant, REQ, CNF, state).
    #[arg(long, default_value = "SynthesizedFB", value_parser = super::args::block_name)]
    pub name: String,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
    /// How to synthesize: exact SAT with counterexample-guided refinement (default), or
    /// metaheuristic search (options under "Search").
    #[arg(long, value_enum, default_value_t = Method::Sat)]
    pub method: Method,
    #[command(flatten)]
    pub search: SearchArgs,
}

/// Synthesis method of the main job.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Method {
    /// Exact SAT synthesis, minimal, with CEGIS against NuSMV.
    Sat,
    /// Metaheuristic search with verification-aware fitness.
    Search,
}

/// Options of the search (`--method search`).
#[derive(Debug, Args, Clone)]
#[command(next_help_heading = "Search (--method search)")]
pub struct SearchArgs {
    /// Seed of every random choice: the same seed gives the same machine (when the run stops
    /// on a solution, not on the clock).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores). The result does not depend on it.
    #[arg(long, value_parser = super::args::workers())]
    pub threads: Option<usize>,
    /// States of every candidate (default: 10 with --start random, the SAT machine's with
    /// --start sat).
    #[arg(long, value_name = "C", value_parser = super::args::states())]
    pub states: Option<usize>,
    /// Colonies ((1+λ) strategies sharing their best).
    #[arg(long, default_value_t = 4, value_parser = super::args::workers())]
    pub colonies: usize,
    /// Where the colonies start. `random`: random machines; the search first reconstructs the
    /// scenarios (seconds on Pick-and-Place, where the published search took hours), then
    /// looks for the properties from that machine. `sat` (default): SAT's machine for the
    /// scenarios, leaving only the properties to the search.
    #[arg(long, value_enum, default_value_t = Start::Sat)]
    pub start: Start,
    /// Probability of verifying a candidate whose scenario fitness is below 99% of the maximum
    /// (above it every candidate is verified). Default: 0.01 with --judge in-process, 0.001
    /// with --judge nusmv.
    #[arg(long, value_name = "P", value_parser = super::args::probability)]
    pub verify_probability: Option<f64>,
    /// Who judges the candidates during the search; NuSMV checks the machine it ends with.
    #[arg(long, value_enum, default_value_t = Judge::InProcess)]
    pub judge: Judge,
}

/// `synth --ltl SPEC --plant PLANT`.
pub fn main_job(args: &MainArgs) -> Result<(), Error> {
    if super::json() {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    refuse_search_conventions(args)?;
    // A learned plant is named after the file it is published as, in the output folder.
    let plant = match args.learn_plant {
        true => Some(PathBuf::from(job::LEARNED_PLANT)),
        false => args.plant.clone(),
    };
    let Some(spec) = args.nusmv.spec(&args.ltl, &plant) else {
        return Err(Error::Usage(
            "the main job needs --ltl FILE and --plant FILE, or --learn-plant to learn the plant from the recordings (or use a subcommand: synth --help)".into(),
        ));
    };
    let request = Request {
        spec,
        learn_plant: args.learn_plant.then(|| args.learning.options()),
        recordings: TraceArgs {
            traces: args.traces.clone(),
            input_names: args.input_names.clone(),
            output_names: args.output_names.clone(),
        }
        .recordings(),
        negatives: args.negative.clone(),
        out: args.out.clone(),
        limit: time_limit(args.time_limit, &progress)?,
        exact: exact_options(args)?,
        formats: parse_formats(&args.format)?,
        name: args.name.clone(),
        method: method(args),
        ambiguity: match args.ambiguity {
            true => Some(args.ambiguity_args.options(args.algorithms.into())?),
            false => None,
        },
    };
    let done = job::run(&request, &mut |e| progress.event(e))?;
    out!("{done}");
    print_files(&done.out, &done.files);
    match super::json() {
        true => super::write_json(&done.summary()),
        false => Ok(()),
    }
}

/// The search builds three-valued machines without a start state: fbSAT's conventions are the
/// exact method's, and asking the search for them is refused rather than ignored.
fn refuse_search_conventions(args: &MainArgs) -> Result<(), Error> {
    let asked = [
        (
            matches!(args.algorithms, AlgorithmsArg::Binary),
            "--algorithms binary",
        ),
        (args.start_state, "--start-state"),
    ];
    match asked.iter().find(|(on, _)| *on && args.method == Method::Search) {
        Some((_, flag)) => Err(Error::Usage(format!(
            "{flag} works with the exact method only: the search (--method search) builds machines with three-valued algorithms and no start state"
        ))),
        None => Ok(()),
    }
}

/// The method the arguments ask for.
fn method(args: &MainArgs) -> main_job::Method {
    let s = &args.search;
    match args.method {
        Method::Sat => main_job::Method::Sat,
        Method::Search => main_job::Method::Search(search::Options {
            seed: s.seed,
            threads: s.threads,
            time_limit: args.time_limit,
            states: s.states,
            colonies: s.colonies,
            start: s.start.into(),
            verify_probability: s.verify_probability,
            judge: s.judge.into(),
            max_out_degree: args.max_out_degree,
            ..search::Options::default()
        }),
    }
}

/// The exact loop's settings from the command line.
fn exact_options(args: &MainArgs) -> Result<exact::Options, Error> {
    Ok(exact::Options {
        sat: exact::SatOptions {
            algorithms: args.algorithms.into(),
            start_state: args.start_state,
            max_states: args.max_states,
            max_out_degree: Some(args.max_out_degree),
            ..exact::SatOptions::default()
        },
        max_iterations: args.max_iterations,
        verbose: super::verbose(),
        proof_budget: pipeline::seconds("--proof-budget", args.proof_budget, false)?,
        ..exact::Options::default()
    })
}
