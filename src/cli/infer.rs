//! `synth infer` (exact, noisy or modular synthesis from recordings), `synth convert` and
//! `synth replay`.

// Jobs handed to `limit::within` return `pipeline::Error` (128 bytes) by value; an error ends
// the run, so its size costs nothing that matters.
#![allow(clippy::result_large_err)]

use super::args::{
    optional_check, out_dir, parse_formats, AlgorithmsArg, AmbiguityArgs, NusmvArgs, TraceArgs,
};
use super::progress::Progress;
use super::show::{describe_modules, print_written};
use super::{exit, Failure};
use clap::{Args, ValueEnum};
use fbsynth::export;
use fbsynth::files::ResultSet;
use fbsynth::pipeline::output::{
    self, check_exportable, check_exportable_modular, write_verified, Provenance,
};
use fbsynth::pipeline::recordings::machine_and_scenarios;
use fbsynth::pipeline::{self, exact, limit, modular, noisy};
use fbsynth::scenario::negative::{self, NegativeScenario};
use fbsynth::scenario::{csvlog, fbsat, ScenarioSet};
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
    pub fn bounds(&self) -> fbsynth::sat::Fixed {
        fbsynth::sat::Fixed {
            states: self.states,
            out_degree: self.out_degree,
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

impl From<TopologyArg> for modular::Topology {
    fn from(t: TopologyArg) -> Self {
        match t {
            // An arbitrary network is a parallel composite over the extended inputs.
            TopologyArg::Parallel | TopologyArg::Arbitrary => modular::Topology::Parallel,
            TopologyArg::Consecutive => modular::Topology::Consecutive,
        }
    }
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
    /// File to write (gzip-compressed if it ends in `.gz`; `-`: stdout).
    #[arg(long, short, value_name = "FILE")]
    pub output: PathBuf,
}

#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// The machine, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    #[command(flatten)]
    pub traces: TraceArgs,
}

/// The progress line saying what was read.
fn report_loaded(progress: &Progress, set: &ScenarioSet) {
    progress.line(&format!(
        "read {} scenarios, {} steps ({} active) over {} inputs and {} outputs",
        set.scenarios.len(),
        set.step_count(),
        set.active_count(),
        set.inputs.len(),
        set.outputs.len()
    ));
}

/// The output folder (`--out`, default `out/<stem of the first trace>`), taken for this run
/// before the search, so that a second run into it stops at once.
fn infer_out(args: &InferArgs) -> Result<ResultSet, Failure> {
    let out = out_dir(&args.out, &args.traces.recordings().stem());
    ResultSet::open(&out).map_err(Failure::input)
}

/// Publishes the staged results; the published paths of `staged`.
fn publish(results: ResultSet, staged: &[PathBuf]) -> Result<Vec<PathBuf>, Failure> {
    let files = staged.iter().map(|f| results.published(f)).collect();
    results
        .publish()
        .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
    Ok(files)
}

/// Said when exact synthesis fails on a contradiction, or climbs to
/// [`GLITCH_HINT_STATES`] states.
const NOISY_HINT: &str = "hint: if the recording has scan-cycle glitches (outputs logged a scan early or late), `synth infer --noisy --max-errors N` corrects up to N samples";

/// The number of states from which exact synthesis hints at `--noisy`: more than the
/// controllers of the shipped cases need (at most 9), and where each further C starts to take
/// long.
const GLITCH_HINT_STATES: usize = 10;

/// A contradiction in recordings read as exact: most often a scan-cycle glitch of the logger,
/// which `--noisy` corrects, so the message says so.
fn suggest_noisy(e: pipeline::Error) -> Failure {
    use fbsynth::scenario::ScenarioError;
    match e {
        pipeline::Error::Scenario(ScenarioError::Contradiction(_)) => {
            Failure::msg(exit::INPUT, format!("{e}\n{NOISY_HINT}"))
        }
        e => e.into(),
    }
}

/// `synth infer`.
pub fn infer(args: &InferArgs) -> Result<(), Failure> {
    let to_stdout = args.out.as_deref().is_some_and(fbsynth::files::is_stdin);
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
        return infer_noisy(args);
    }
    if to_stdout && args.ltl.is_some() {
        return Err(Failure::msg(
            exit::USAGE,
            "--out - (the machine on stdout) is for one machine without --ltl: a verified machine comes with its report in a result folder",
        ));
    }
    if let Some(file) = &args.distributed {
        return infer_network(args, Some(file));
    }
    if args.topology == TopologyArg::Arbitrary {
        if args.ltl.is_some() || args.noisy.noisy {
            return Err(Failure::msg(
                exit::USAGE,
                "--topology arbitrary is for recordings alone: not with --ltl or --noisy",
            ));
        }
        return infer_network(args, None);
    }
    if let Some(m) = args.modules {
        let progress = Progress::new(super::quiet());
        let set = args.traces.load()?;
        report_loaded(&progress, &set);
        let check = loop_check(args, &set, &progress)?;
        let results = infer_out(args)?;
        let staged = match &check {
            None => distribute(args, m, &set, results.staging(), &progress)?,
            Some(check) => {
                // --negative conflicts with --modules.
                let single = verified_exact(args, &set, check, Vec::new(), &progress)?;
                let staging = results.staging();
                let mut files =
                    distribute_verified(args, m, &set, &single, check, staging, &progress)?;
                let summary = loop_summary(&single, &progress);
                let formats = parse_formats(&args.format)?;
                let dir = staging.join("single");
                files.extend(write_single(args, &dir, &formats, &single, &summary)?);
                files
            }
        };
        print_written(&publish(results, &staged)?);
        return Ok(());
    }
    let progress = Progress::new(super::quiet());
    let set = args.traces.load()?;
    report_loaded(&progress, &set);
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
    if let Some(check) = &check {
        let results = results.expect("--out - with --ltl is refused above");
        let r = verified_exact(args, &set, check, negatives, &progress)?;
        let summary = loop_summary(&r, &progress);
        let staged = write_single(args, results.staging(), &formats, &r, &summary)?;
        let files = publish(results, &staged)?;
        print_written(&files);
        if super::json() {
            let mut summary = summary;
            summary["files"] = serde_json::json!(files);
            return super::write_json(&summary);
        }
        return Ok(());
    }
    let opts = exact::Options {
        sat: exact::SatOptions {
            algorithms: args.algorithms.into(),
            minimize_k: args.minimize_k,
            max_states: args.max_states,
            start_state: args.start_state,
            guard_budget: pipeline::seconds("--guard-budget", args.guard_budget, false)?,
            fixed: args.fixed.bounds(),
            ..exact::SatOptions::default()
        },
        negatives,
        ..exact::Options::default()
    };
    let mut hinted = false;
    let (job_set, job_opts) = (set.clone(), opts.clone());
    let job = move |events: pipeline::Events<'_>| exact::run(&job_set, None, &job_opts, events);
    let result = limited(args, &progress, job, &mut |e| {
        let c = match &e {
            pipeline::Event::Solver(fbsynth::sat::Step::TryingStates { c, .. }) => Some(*c),
            pipeline::Event::Solver(fbsynth::sat::Step::Trying {
                bound: fbsynth::sat::Bound::C,
                value,
            }) => Some(*value),
            _ => None,
        };
        progress.event(e);
        // Glitches in a log read as exact each cost states: a climb this high is the sign.
        if c.is_some_and(|c| c >= GLITCH_HINT_STATES) && !hinted {
            hinted = true;
            progress.line(NOISY_HINT);
        }
    })
    .map_err(suggest_noisy)?
    .synthesis;
    let result = match args.fixed.plateau {
        Some(width) => {
            let (job_set, job_opts) = (set.clone(), opts.clone());
            let job = move |events: pipeline::Events<'_>| {
                exact::plateau(&job_set, &job_opts, result, width, events)
            };
            limited(args, &progress, job, &mut |e| progress.event(e))?
        }
        None => result,
    };
    let s = result.size;
    out!(
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
    out!(
        "time {:.2} s (SAT {:.2} s, guards {:.2} s); replayed {} scenarios: all reproduced",
        progress.elapsed(),
        result.stats.sat_seconds,
        result.stats.guard_seconds,
        set.scenarios.len()
    );
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
        dump_cnf(&set, &opts.sat, &s, dir)?;
    }
    let mut staged = export::write_all(&result.ecc, results.staging(), &args.name, &formats)
        .map_err(Failure::input)?;
    let mut ambiguity_json = serde_json::Value::Null;
    if ambiguity {
        let (found, files) = super::ambiguity::report(
            &set,
            &result.ecc,
            &args.ambiguity,
            args.algorithms,
            &progress,
            Some(results.staging()),
        )?;
        ambiguity_json = found.to_json(&set, &result.ecc);
        staged.extend(files);
    }
    let files = publish(results, &staged)?;
    print_written(&files);
    if super::json() {
        let summary = serde_json::json!({
            "size": s,
            "guards_proven_minimal": result.guards_exact,
            "transitions_proven_minimal": result.transitions_exact,
            "scenarios": set.scenarios.len(),
            "seconds": progress.elapsed(),
            "stats": result.stats,
            "files": files,
            "ambiguity": ambiguity_json,
        });
        return super::write_json(&summary);
    }
    Ok(())
}

/// `--dump-cnf DIR`: the size questions around the minimum as DIMACS files, each answered by
/// a fresh varisat solver on exactly the formula written (`verdicts.txt`).
fn dump_cnf(
    set: &ScenarioSet,
    sat: &exact::SatOptions,
    size: &fbsynth::ecc::Size,
    dir: &Path,
) -> Result<(), Failure> {
    use fbsynth::scenario::tree::ScenarioTree;
    let tree = ScenarioTree::build(set).map_err(pipeline::Error::from)?;
    let results = ResultSet::open(dir).map_err(Failure::input)?;
    let mut questions = vec![(format!("states-{}.cnf", size.c), size.c, None)];
    if size.c > 1 {
        questions.push((format!("states-{}.cnf", size.c - 1), size.c - 1, None));
    }
    questions.push((format!("transitions-{}.cnf", size.t), size.c, Some(size.t)));
    if size.t > 0 {
        questions.push((
            format!("transitions-{}.cnf", size.t - 1),
            size.c,
            Some(size.t - 1),
        ));
    }
    let mut verdicts = String::new();
    let mut staged = Vec::new();
    for (name, c, t) in questions {
        let formula = fbsynth::sat::basic::formula(&tree, sat, c, t);
        let mut text = Vec::new();
        varisat::dimacs::write_dimacs(&mut text, &formula).map_err(Failure::input)?;
        let path = results.staging().join(&name);
        fbsynth::files::write_atomic(&path, &text).map_err(Failure::input)?;
        staged.push(path);
        let mut solver = varisat::Solver::new();
        solver.add_formula(&formula);
        let sat = solver
            .solve()
            .map_err(|e| Failure::msg(exit::BUG, format!("varisat failed on {name}: {e}")))?;
        verdicts.push_str(&format!(
            "{name} {}\n",
            if sat { "SATISFIABLE" } else { "UNSATISFIABLE" }
        ));
    }
    let path = results.staging().join("verdicts.txt");
    fbsynth::files::write_atomic(&path, verdicts.as_bytes()).map_err(Failure::input)?;
    staged.push(path);
    let published: Vec<PathBuf> = staged.iter().map(|f| results.published(f)).collect();
    results
        .publish()
        .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
    print_written(&published);
    Ok(())
}

/// `synth infer --noisy`: candidates by ε, each in its folder, and the summary; with --ltl
/// the least verified machine over the candidates' corrected traces in `verified/`.
fn infer_noisy(args: &InferArgs) -> Result<(), Failure> {
    let progress = Progress::new(super::quiet());
    let set = args.traces.load()?;
    let formats = parse_formats(&args.format)?;
    check_exportable(&set, &args.name, &formats, &args.traces.recordings())?;
    let n = &args.noisy;
    // The recordings are not checked against the properties: their glitches may violate one.
    let check = optional_check(&args.ltl, &args.plant, &set, &args.nusmv)?;
    let out = out_dir(&args.out, &args.traces.recordings().stem());
    let results = infer_out(args)?;
    let opts = noisy::Options {
        algorithms: args.algorithms.into(),
        max_states: args.max_states,
        max_errors: n.max_errors,
        enumerate: n.enumerate.max(1),
        guard_budget: pipeline::seconds("--guard-budget", args.guard_budget, false)?,
        ..noisy::Options::default()
    };
    // --negative conflicts with --noisy.
    let loop_opts = loop_options(args, Vec::new())?;
    let (job_set, job_check, job_opts) = (set.clone(), check.clone(), opts.clone());
    let result = limited(
        args,
        &progress,
        move |events| {
            noisy::run(
                &job_set,
                job_check.as_ref().map(|c| (c, &loop_opts)),
                &job_opts,
                events,
            )
        },
        &mut |e| progress.event(e),
    )?;
    let table = output::write_noisy(
        results.staging(),
        &args.name,
        &formats,
        &result,
        progress.elapsed(),
    )?;
    out_raw!("{table}");
    let chosen = result.chosen();
    let mut staged = Vec::new();
    if let Some(k) = chosen {
        let c = &result.synthesis.candidates[k - 1];
        let single = result
            .verified(k)
            .expect("the chosen candidate is verified");
        let dir = results.staging().join("verified");
        let summary = serde_json::json!({
            "candidate": k,
            "errors": c.errors,
            "closed_loop": loop_summary(single, &progress),
        });
        staged = write_single(args, &dir, &formats, single, &summary)?;
        let mut csv = Vec::new();
        csvlog::write(&c.corrected, &mut csv).map_err(Failure::input)?;
        let corrected = dir.join("corrected.csv");
        fbsynth::files::write_atomic(&corrected, &csv).map_err(Failure::input)?;
        staged.push(corrected);
        let s = single.synthesis.size;
        out!(
            "result: the verified machine of candidate {k} (ε = {}): C = {}  K = {}  T = {}  N = {}; NuSMV: all {} properties hold; it reproduces the corrected traces",
            c.errors,
            s.c,
            s.k,
            s.t,
            s.n,
            single.certificate.as_ref().map_or(0, |c| c.report.properties.len())
        );
    }
    // Correct the traces first, then distribute the logic (with --ltl: the verified machine).
    if let Some(m) = args.modules {
        let k = chosen.unwrap_or(1);
        let c = &result.synthesis.candidates[k - 1];
        let dir = results.staging().join("modular");
        output::create_dir(&dir)?;
        out!(
            "modular synthesis (M = {m}) on the corrected traces of candidate {k} (ε = {}):",
            c.errors
        );
        staged.extend(match (&check, result.verified(k)) {
            (Some(check), Some(single)) => {
                distribute_verified(args, m, &c.corrected, single, check, &dir, &progress)?
            }
            (Some(_), None) => Vec::new(),
            (None, _) => distribute(args, m, &c.corrected, &dir, &progress)?,
        });
    }
    let written = publish(results, &staged)?;
    if !written.is_empty() {
        print_written(&written);
    }
    out!("results in {}", out.display());
    match (check.is_some(), chosen) {
        (true, None) => Err(Failure::msg(
            exit::NO_MACHINE,
            "no candidate's corrected traces have a verified machine (see summary.txt; raise --enumerate or --max-errors)",
        )),
        _ => Ok(()),
    }
}

/// `synth infer --distributed FILE` (the described controllers, synthesized together) or,
/// without a file, `--modules M --topology arbitrary` (a network wired by the solver).
fn infer_network(args: &InferArgs, file: Option<&PathBuf>) -> Result<(), Failure> {
    use fbsynth::pipeline::distributed;
    let progress = Progress::new(super::quiet());
    let set = args.traces.load()?;
    report_loaded(&progress, &set);
    // The controllers described in the file, or blocks the solver wires.
    enum Wiring {
        Given(distributed::Interfaces),
        Chosen(modular::Options, Vec<String>),
    }
    let wiring = match file {
        Some(file) => Wiring::Given(
            distributed::read_description(file)
                .and_then(|d| d.resolve(&set, file))
                .map_err(|e| Failure::input(pipeline::Error::from(e)))?,
        ),
        None => {
            let m = args.modules.unwrap_or(1);
            check_exportable_modular(&set, &args.name, m)?;
            let names = (0..m)
                .map(|k| export::modular::module_type_name(&args.name, k))
                .collect();
            Wiring::Chosen(modular_options(args, m, &set)?, names)
        }
    };
    let results = infer_out(args)?;
    let opts = distributed::Options {
        slots: args.slots.unwrap_or(modular::DEFAULT_SLOTS),
        max_states: args.max_states,
        algorithms: args.algorithms.into(),
    };
    let job_set = set.clone();
    let result = limited(
        args,
        &progress,
        move |events| match wiring {
            Wiring::Given(interfaces) => distributed::run(&job_set, &interfaces, &opts, events),
            Wiring::Chosen(o, names) => distributed::run_arbitrary(&job_set, names, &o, events),
        },
        &mut |e| progress.event(e),
    )?;
    let s = &result.synthesis.size;
    out!(
        "controllers = {}  largest = {} states  A = {} inputs read  N' = {} states in all  (K = {} slots per state)",
        result.network.names.len(),
        s.max_states,
        s.inputs_used,
        s.total_states,
        result.synthesis.stats.slots
    );
    for (module, name) in result
        .network
        .modular
        .modules
        .iter()
        .zip(&result.network.names)
    {
        let size = module.ecc.size();
        out!(
            "  {name}: {} states, {} transitions, {} guard literals; writes {}; reads {}",
            size.c,
            size.t,
            size.n,
            module.ecc.outputs.join(", "),
            if module.ecc.inputs.is_empty() {
                "-".to_string()
            } else {
                module.ecc.inputs.join(", ")
            }
        );
    }
    out!(
        "time {:.2} s (SAT {:.2} s); replayed {} scenarios on the network: all reproduced",
        progress.elapsed(),
        result.synthesis.stats.sat_seconds,
        set.scenarios.len()
    );
    let staged = export::network::write_network(&result.network, results.staging(), &args.name)
        .map_err(Failure::input)?;
    print_written(&publish(results, &staged)?);
    Ok(())
}

/// Modular synthesis of `set` into `out` (also the second stage of `--noisy --modules`, on
/// the corrected traces); the files written.
fn distribute(
    args: &InferArgs,
    modules: usize,
    set: &ScenarioSet,
    out: &Path,
    progress: &Progress,
) -> Result<Vec<PathBuf>, Failure> {
    let opts = modular_options(args, modules, set)?;
    check_exportable_modular(set, &args.name, modules)?;
    let job_set = set.clone();
    let result = limited(
        args,
        progress,
        move |events| modular::run(&job_set, &opts, events),
        &mut |e| progress.event(e),
    )?;
    describe_modular(modules, &result);
    out!(
        "time {:.2} s (SAT {:.2} s); replayed {} scenarios on the composite: all reproduced",
        progress.elapsed(),
        result.stats.sat_seconds,
        set.scenarios.len()
    );
    export::modular::write_modular(&result.modular, out, &args.name).map_err(Failure::input)
}

/// With --ltl/--plant: the check, after the recordings were checked against the properties
/// (recordings that violate one leave no machine to find).
fn loop_check(
    args: &InferArgs,
    set: &ScenarioSet,
    progress: &Progress,
) -> Result<Option<pipeline::Check>, Failure> {
    let check = optional_check(&args.ltl, &args.plant, set, &args.nusmv)?;
    if let (Some(check), Some(ltl)) = (&check, &args.ltl) {
        let props = &check.problem.props;
        let explained = fbsynth::pipeline::explain::refuse_violations(set, props, ltl)
            .map_err(pipeline::Error::from)?;
        progress.line(&super::main_job::recordings_line(&explained, props.len()));
        if let Some(line) = super::main_job::unrecorded_line(&explained) {
            progress.line(&line);
        }
    }
    Ok(check)
}

/// Who made a verified machine, for its `verification.txt`.
fn provenance(args: &InferArgs) -> Provenance<'_> {
    Provenance {
        name: &args.name,
        plant_file: args.plant.as_deref().unwrap_or(Path::new("")),
        spec_file: args.ltl.as_deref().unwrap_or(Path::new("")),
    }
}

/// The closed loop's options for `infer --ltl`.
fn loop_options(
    args: &InferArgs,
    negatives: Vec<NegativeScenario>,
) -> Result<exact::Options, Failure> {
    Ok(exact::Options {
        sat: exact::SatOptions {
            algorithms: args.algorithms.into(),
            max_states: args.max_states,
            start_state: args.start_state,
            ..exact::SatOptions::default()
        },
        max_iterations: args.max_iterations,
        negatives,
        ..exact::Options::default()
    })
}

/// The time `--time-limit` leaves after what this run has spent so far.
fn remaining(
    args: &InferArgs,
    progress: &Progress,
) -> Result<std::time::Duration, pipeline::Error> {
    let limit = pipeline::seconds("--time-limit", args.time_limit, true)?;
    Ok(limit.saturating_sub(std::time::Duration::from_secs_f64(progress.elapsed())))
}

/// A time-limit error names the limit given, not the part of it left to the stage.
fn full_limit(e: pipeline::Error, seconds: f64) -> pipeline::Error {
    match e {
        pipeline::Error::Interrupted { last, .. } => pipeline::Error::Interrupted { seconds, last },
        pipeline::Error::TimeLimit { so_far, .. } => pipeline::Error::TimeLimit { seconds, so_far },
        e => e,
    }
}

/// `job` within what `--time-limit` leaves ([`limit::within`]), its events to `events`.
fn limited<T: Send + 'static>(
    args: &InferArgs,
    progress: &Progress,
    job: impl FnOnce(pipeline::Events<'_>) -> Result<T, pipeline::Error> + Send + 'static,
    events: pipeline::Events<'_>,
) -> Result<T, pipeline::Error> {
    let r = limit::within(remaining(args, progress)?, events, job);
    if r.is_err() {
        // A NuSMV of the job's thread must not outlive us.
        fbsynth::nusmv::kill_all_children();
    }
    r.map_err(|e| full_limit(e, args.time_limit))
}

/// The `--negative` files, read over the recordings' interface.
pub(super) fn read_negatives(
    files: &[PathBuf],
    set: &ScenarioSet,
    progress: &Progress,
) -> Result<Vec<NegativeScenario>, Failure> {
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

/// With --ltl/--plant: the least machine for `set` that NuSMV verifies (the main job's loop).
fn verified_exact(
    args: &InferArgs,
    set: &ScenarioSet,
    check: &pipeline::Check,
    negatives: Vec<NegativeScenario>,
    progress: &Progress,
) -> Result<exact::Exact, Failure> {
    let r = limit::exact_within(
        set,
        check,
        &loop_options(args, negatives)?,
        remaining(args, progress)?,
        &mut |e| progress.event(e),
    );
    if r.is_err() {
        // On the time limit the loop's thread is still running: its NuSMV must not outlive us.
        fbsynth::nusmv::kill_all_children();
    }
    let r = r.map_err(|e| full_limit(e, args.time_limit))?;
    let report = &r
        .certificate
        .as_ref()
        .expect("a check gives a certificate")
        .report;
    out!(
        "{}",
        super::show::verified_line(report.properties.len(), set.scenarios.len())
    );
    let s = r.synthesis.size;
    out!(
        "C = {}  K = {}  T = {}  N = {}; {} candidates",
        s.c,
        s.k,
        s.t,
        s.n,
        r.iterations.len()
    );
    Ok(r)
}

/// Writes a verified machine of `infer --ltl` into `dir` ([`write_verified`]).
fn write_single(
    args: &InferArgs,
    dir: &Path,
    formats: &[export::Format],
    single: &exact::Exact,
    summary: &serde_json::Value,
) -> Result<Vec<PathBuf>, Failure> {
    let certificate = (single.certificate.as_ref()).expect("a check gives a certificate");
    Ok(write_verified(
        dir,
        formats,
        &single.synthesis.ecc,
        certificate,
        &provenance(args),
        summary,
    )?)
}

/// `summary.json` of a verified machine.
fn loop_summary(r: &exact::Exact, progress: &Progress) -> serde_json::Value {
    serde_json::json!({
        "size": r.synthesis.size,
        "transitions_proven_minimal": r.synthesis.transitions_exact,
        "guards_proven_minimal": r.synthesis.guards_exact,
        "iterations": r.iterations,
        "report": r.certificate.as_ref().map(|c| &c.report),
        "total_seconds": progress.elapsed(),
    })
}

/// The modular options of `synth infer --modules M`.
fn modular_options(
    args: &InferArgs,
    modules: usize,
    set: &ScenarioSet,
) -> Result<modular::Options, Failure> {
    Ok(modular::Options {
        modules,
        slots: args.slots.unwrap_or(modular::DEFAULT_SLOTS),
        widen_slots: args.slots.is_none(),
        max_states: args.max_states,
        algorithms: args.algorithms.into(),
        pins: modular::parse_pins(&args.pin, &set.outputs, modules)
            .map_err(|e| Failure::with_code(exit::USAGE, e))?,
        topology: args.topology.into(),
        reads: None,
        feedback: (args.topology == TopologyArg::Arbitrary).then_some(set.inputs.len()),
    })
}

/// Prints a modular controller's sizes and modules.
fn describe_modular(modules: usize, result: &modular::ModularSynthesis) {
    let s = &result.size;
    let chain = match result.modular.topology {
        modular::Topology::Consecutive => " in a chain",
        modular::Topology::Parallel => "",
    };
    out!(
        "modules = {}{chain}  largest module = {} states  A = {} inputs used  N' = {} states in all  (K = {} slots per state{})",
        modules,
        s.max_states,
        s.inputs_used,
        s.total_states,
        result.stats.slots,
        if result.stats.slots > modular::DEFAULT_SLOTS { ", widened" } else { "" }
    );
    for line in describe_modules(&result.modular) {
        out!("  {line}");
    }
}

/// With --ltl/--plant: `single`, the verified machine, split into `modules` function blocks
/// whose composite NuSMV verifies too ([`modular::run_verified`]). Writes the composite's
/// files, its `verification.txt`, `closed_loop.smv` and `rounds.json` (one entry per
/// composite checked); the files written.
fn distribute_verified(
    args: &InferArgs,
    modules: usize,
    set: &ScenarioSet,
    single: &exact::Exact,
    check: &pipeline::Check,
    out: &Path,
    progress: &Progress,
) -> Result<Vec<PathBuf>, Failure> {
    let opts = modular_options(args, modules, set)?;
    check_exportable_modular(set, &args.name, modules)?;
    out!("modular synthesis (M = {modules}) of the verified machine:");
    let (job_set, oracle, job_check) = (set.clone(), single.synthesis.ecc.clone(), check.clone());
    let max_rounds = args.max_iterations;
    let r = limited(
        args,
        progress,
        move |events| {
            modular::run_verified(&job_set, &oracle, &job_check, &opts, max_rounds, events)
        },
        &mut |e| progress.event(e),
    )?;
    describe_modular(modules, &r.synthesis);
    let added = r.scenarios.scenarios.len() - set.scenarios.len();
    out!(
        "verified: all {} properties hold for the composite (NuSMV); it reproduces the {} recorded scenarios and {} recorded from the verified machine along counterexamples ({} composites)",
        r.certificate.report.properties.len(),
        set.scenarios.len(),
        added,
        r.rounds.len()
    );
    let mut files = export::modular::write_modular(&r.synthesis.modular, out, &args.name)
        .map_err(Failure::input)?;
    files.extend(output::write_certificate(
        out,
        &format!("the composite {}", args.name),
        &r.certificate,
        &provenance(args),
    )?);
    let rounds = out.join("rounds.json");
    let json = serde_json::to_string_pretty(&r.rounds).expect("serializable");
    fbsynth::files::write_atomic(&rounds, json.as_bytes()).map_err(Failure::input)?;
    files.push(rounds);
    Ok(files)
}

/// `synth convert`.
pub fn convert(args: &ConvertArgs) -> Result<(), Failure> {
    let mut inputs: Vec<PathBuf> = args.traces.traces.clone();
    inputs.extend(args.traces.input_names.iter().cloned());
    inputs.extend(args.traces.output_names.iter().cloned());
    if let Some((i, o)) = args
        .traces
        .traces
        .first()
        .and_then(|t| fbsynth::scenario::names::default_names_files(t))
    {
        inputs.extend([i, o]);
    }
    let to_stdout = fbsynth::files::is_stdin(&args.output);
    if to_stdout {
        super::data_on_stdout();
    } else {
        super::args::refuse_overwrite(&[&args.output], &inputs)?;
    }
    let set = args.traces.load()?;
    let mut buf = Vec::new();
    match args.to {
        ConvertTo::Fbsat => fbsat::write(&set, &mut buf),
        ConvertTo::Csv => csvlog::write(&set, &mut buf),
    }
    .map_err(Failure::input)?;
    if to_stdout {
        return super::write_data(&buf);
    }
    fbsynth::files::write_atomic(&args.output, &buf).map_err(Failure::input)?;
    out!(
        "wrote {} scenarios ({} steps) to {}",
        set.scenarios.len(),
        set.step_count(),
        args.output.display()
    );
    super::note_written(std::slice::from_ref(&args.output));
    Ok(())
}

/// `synth replay`: replays scenarios on a machine read from JSON and reports the first
/// disagreement.
pub fn replay(args: &ReplayArgs) -> Result<(), Failure> {
    let (ecc, set) = machine_and_scenarios(&args.ecc, &args.traces.recordings())?;
    set.check(&ecc)
        .map_err(|m| Failure::msg(exit::FAILED, format!("not reproduced: {m}")))?;
    out!(
        "replayed {} scenarios ({} steps): all reproduced by {}",
        set.scenarios.len(),
        set.step_count(),
        args.ecc.display()
    );
    Ok(())
}
