//! `synth infer`: the least machine that reproduces the recordings, exact, noisy, modular
//! or distributed; with `--ltl` the main job's method. Its arguments, the call to the library
//! for the mode asked, and what it prints.

use super::args::{parse_formats, time_limit, AlgorithmsArg, AmbiguityArgs, NusmvArgs, TraceArgs};
use super::progress::Progress;
use super::show::print_written;
use crate::command::infer::{self as job, Inferred, Request};
use crate::command::modular::{self, Modules};
use crate::command::noisy;
use crate::pipeline::{self, exact, Error};
use clap::{Args, ValueEnum};
use std::path::PathBuf;

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

/// `synth infer`.
pub fn infer(args: &InferArgs) -> Result<(), Error> {
    let to_stdout = args.out.as_deref().is_some_and(crate::files::is_stdin);
    refuse_combinations(args, to_stdout)?;
    // With --json, --out -, --noisy and --modules give the generic summary (their files and
    // lines; the machine of --out - in its `output`).
    if to_stdout {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    let events: pipeline::Events = &mut |e| progress.event(e);
    let r = request(args, to_stdout, &progress)?;
    let modules = modules(args);
    if args.noisy.noisy {
        let settings = noisy::Settings {
            max_errors: args.noisy.max_errors,
            enumerate: args.noisy.enumerate,
        };
        let done = noisy::run(&r, &settings, args.modules.map(|_| &modules), events)?;
        out_raw!("{done}");
        if !done.files.is_empty() {
            print_written(&done.files);
        }
        out!("results in {}", crate::quote::path(&done.out));
        return done.failure.map_or(Ok(()), Err);
    }
    if args.distributed.is_some() || args.topology == TopologyArg::Arbitrary {
        let done = modular::network(&r, &modules, args.distributed.as_deref(), events)?;
        out!("{done}");
        print_written(&done.files);
        return Ok(());
    }
    if args.modules.is_some() {
        let done = modular::modules(&r, &modules, events)?;
        out!("{done}");
        print_written(&done.files);
        return Ok(());
    }
    match job::run(&r, events)? {
        Inferred::Verified(v) => {
            out!("{v}");
            print_written(&v.files);
            json(&v.summary())
        }
        Inferred::Least(l) => {
            out!("{l}");
            if !l.dumped.is_empty() {
                print_written(&l.dumped);
            }
            if let Some(a) = &l.ambiguity {
                out_raw!("{a}");
            }
            if let Some(text) = &l.text {
                return super::write_data(text.as_bytes());
            }
            print_written(&l.files);
            json(&l.summary())
        }
    }
}

/// With `--json`: the summary.
fn json(summary: &impl serde::Serialize) -> Result<(), Error> {
    match super::json() {
        true => super::write_json(summary),
        false => Ok(()),
    }
}

/// Combinations of options no mode takes.
fn refuse_combinations(args: &InferArgs, to_stdout: bool) -> Result<(), Error> {
    let modes = args.noisy.noisy || args.modules.is_some() || args.distributed.is_some();
    let refused = if to_stdout && modes {
        "--out - (the machine on stdout) is for one machine: --noisy, --modules and --distributed write result folders"
    } else if to_stdout && args.ltl.is_some() && !args.noisy.noisy {
        "--out - (the machine on stdout) is for one machine without --ltl: a verified machine comes with its report in a result folder"
    } else if args.topology == TopologyArg::Arbitrary
        && args.distributed.is_none()
        && !args.noisy.noisy
        && args.ltl.is_some()
    {
        "--topology arbitrary is for recordings alone: not with --ltl or --noisy"
    } else {
        return Ok(());
    };
    Err(Error::Usage(refused.into()))
}

/// What the arguments ask of every mode.
fn request(args: &InferArgs, to_stdout: bool, progress: &Progress) -> Result<Request, Error> {
    let f = &args.fixed;
    Ok(Request {
        recordings: args.traces.recordings(),
        formats: parse_formats(&args.format)?,
        name: args.name.clone(),
        out: args.out.clone(),
        to_stdout,
        sat: exact::SatOptions {
            algorithms: args.algorithms.into(),
            minimize_k: args.minimize_k,
            max_states: args.max_states,
            start_state: args.start_state,
            guard_budget: pipeline::seconds("--guard-budget", args.guard_budget, false)?,
            fixed: crate::sat::Fixed {
                states: f.states,
                max_out_degree: f.out_degree,
                transitions: f.transitions,
            },
            ..exact::SatOptions::default()
        },
        plateau: f.plateau,
        limit: time_limit(args.time_limit, progress)?,
        spec: args.nusmv.spec(&args.ltl, &args.plant),
        max_iterations: args.max_iterations,
        negatives: args.negative.clone(),
        ambiguity: match args.no_ambiguity {
            true => None,
            false => Some(args.ambiguity.options(args.algorithms.into())?),
        },
        dump_cnf: args.dump_cnf.clone(),
    })
}

/// The modules `--modules`, `--slots`, `--pin` and `--topology` ask for (one module for
/// `--distributed`).
fn modules(args: &InferArgs) -> Modules {
    Modules {
        count: args.modules.unwrap_or(1),
        slots: args.slots,
        pins: args.pin.clone(),
        topology: match args.topology {
            // An arbitrary network is a parallel composite over the extended inputs.
            TopologyArg::Parallel | TopologyArg::Arbitrary => pipeline::modular::Topology::Parallel,
            TopologyArg::Consecutive => pipeline::modular::Topology::Consecutive,
        },
        arbitrary: args.topology == TopologyArg::Arbitrary,
    }
}
