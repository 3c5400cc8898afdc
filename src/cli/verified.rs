//! The main job (`synth --ltl SPEC --plant PLANT`) and `synth verify`.

use super::infer::{check_exportable, load_scenarios, parse_formats, AlgorithmsArg, TraceArgs};
use super::{exit, Failure, Progress};
use crate::cegis::{self, CegisError, Config};
use crate::ecc::{AlgorithmKind, Ecc};
use crate::export;
use crate::ltl::{parse_spec_file, Property};
use crate::nusmv::{locate, Nusmv, NusmvError, Session};
use crate::sat::{Options, SatError};
use crate::scenario::tree::ScenarioTree;
use crate::smv::closed_loop::{check_coupling, Coupling};
use crate::smv::plant::{read_plant, Plant};
use crate::verify::{Report, Setup, VerifyError};
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Duration;

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

/// Arguments of the main job (no subcommand).
#[derive(Debug, Args, Clone)]
pub struct MainArgs {
    /// LTL properties, one per line (NuSMV syntax over bare names; `--` comments; `name:`).
    #[arg(long, value_name = "FILE")]
    pub ltl: Option<PathBuf>,
    /// Surrogate plant model: an SMV file defining `MODULE plant(<controller outputs>)`.
    #[arg(long, value_name = "FILE")]
    pub plant: Option<PathBuf>,
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
    /// Form of the state output algorithms.
    #[arg(long, value_enum, default_value_t = AlgorithmsArg::Tri)]
    pub algorithms: AlgorithmsArg,
    /// Give up when more states than this would be needed.
    #[arg(long, default_value_t = 32, value_name = "C")]
    pub max_states: usize,
    /// Transitions per state at most (each guarded by a conjunction of input literals).
    #[arg(long, default_value_t = 6, value_name = "K")]
    pub max_out_degree: usize,
    /// Give up after this many candidate controllers.
    #[arg(long, default_value_t = 500, value_name = "N")]
    pub max_iterations: usize,
    /// Formats to write, comma-separated: json, fbt, smv, dot, st.
    #[arg(long, value_delimiter = ',', default_value = "json,fbt,smv,dot,st")]
    pub format: Vec<String>,
    /// Name of the function block type in the exports.
    #[arg(long, default_value = "SynthesizedFB")]
    pub name: String,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
    /// No progress lines on stderr.
    #[arg(long, short)]
    pub quiet: bool,
    /// Progress of every minimization step, not only one line per candidate.
    #[arg(long, short)]
    pub verbose: bool,
    /// How to synthesize: exact SAT with counterexample-guided refinement (default), or the
    /// metaheuristic search of seeds 004 and 001 (options under "Search").
    #[arg(long, value_enum, default_value_t = Method::Sat)]
    pub method: Method,
    #[command(flatten)]
    pub search: super::search::SearchArgs,
}

/// Synthesis method of the main job.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Method {
    /// Exact SAT synthesis, minimal, with CEGIS against NuSMV.
    Sat,
    /// Metaheuristic search with verification-aware fitness (seeds 004, 001).
    Search,
}

#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// The machine to check, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    /// LTL properties.
    #[arg(long, value_name = "FILE")]
    pub ltl: PathBuf,
    /// Surrogate plant model.
    #[arg(long, value_name = "FILE")]
    pub plant: PathBuf,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
}

fn stem(path: &Path) -> String {
    path.file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .and_then(|f| f.split('.').next().map(str::to_string))
        .unwrap_or_else(|| "result".into())
}

/// Locates NuSMV; fails early with the install hint.
pub(super) fn nusmv(args: &NusmvArgs) -> Result<Nusmv, Failure> {
    let path = locate(args.nusmv.as_deref()).map_err(Failure::input)?;
    let mut n = Nusmv::new(path);
    n.timeout = Duration::from_secs_f64(args.timeout.max(0.1));
    Ok(n)
}

/// Locates NuSMV and opens a session.
pub(super) fn session(args: &NusmvArgs) -> Result<Session, Failure> {
    Ok(nusmv(args)?.session())
}

/// Reads and checks the spec, the plant and the coupling with the controller interface.
pub(super) fn load_setup(
    ltl: &Path,
    plant: &Path,
    inputs: &[String],
    outputs: &[String],
) -> Result<(Vec<Property>, Plant, Coupling), Failure> {
    let props = parse_spec_file(ltl).map_err(Failure::input)?;
    let plant = read_plant(plant).map_err(Failure::input)?;
    let coupling = check_coupling(inputs, outputs, &plant, ltl, &props).map_err(Failure::input)?;
    Ok((props, plant, coupling))
}

fn verify_failure(e: VerifyError) -> Failure {
    Failure::input(e)
}

/// What the main job reads and checks before synthesizing, whichever the method.
pub(super) struct MainInputs {
    pub set: crate::scenario::ScenarioSet,
    pub props: Vec<Property>,
    pub plant: Plant,
    pub coupling: Coupling,
    pub formats: Vec<export::Format>,
    pub ltl: PathBuf,
    pub plant_file: PathBuf,
    pub out: PathBuf,
}

/// Reads scenarios, spec and plant of the main job and checks them against each other.
pub(super) fn main_inputs(args: &MainArgs, progress: &Progress) -> Result<MainInputs, Failure> {
    let (Some(ltl), Some(plant_file)) = (&args.ltl, &args.plant) else {
        return Err(Failure::msg(
            exit::USAGE,
            "the main job needs --ltl FILE and --plant FILE (or use a subcommand: synth --help)",
        ));
    };
    let traces = if args.traces.is_empty() {
        let default = ltl.with_file_name(format!("{}.traces", stem(ltl)));
        if !default.is_file() {
            return Err(Failure::msg(
                exit::INPUT,
                format!(
                    "no --traces given and no default scenario file {} beside {}",
                    default.display(),
                    ltl.display()
                ),
            ));
        }
        vec![default]
    } else {
        args.traces.clone()
    };
    let trace_args = TraceArgs {
        traces,
        input_names: args.input_names.clone(),
        output_names: args.output_names.clone(),
    };
    let set = load_scenarios(&trace_args)?;
    progress.line(&format!(
        "read {} scenarios ({} steps) from {}",
        set.scenarios.len(),
        set.step_count(),
        super::show(&trace_args.traces)
    ));
    let (props, plant, coupling) = load_setup(ltl, plant_file, &set.inputs, &set.outputs)?;
    progress.line(&format!(
        "read {} properties from {} and plant {}",
        props.len(),
        ltl.display(),
        plant_file.display()
    ));
    let formats = parse_formats(&args.format)?;
    check_exportable(&set, &args.name, &formats)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out").join(stem(ltl)));
    Ok(MainInputs {
        set,
        props,
        plant,
        coupling,
        formats,
        ltl: ltl.clone(),
        plant_file: plant_file.clone(),
        out,
    })
}

pub fn main_job(args: &MainArgs) -> Result<(), Failure> {
    let progress = Progress::new(args.quiet);
    let inputs = main_inputs(args, &progress)?;
    if args.method == Method::Search {
        return super::search::main_job(args, &inputs, &progress);
    }
    let MainInputs {
        set,
        props,
        plant,
        coupling,
        ltl,
        out,
        ..
    } = &inputs;
    let ltl = ltl.as_path();
    let mut session = session(&args.nusmv)?;
    let tree = ScenarioTree::build(set).map_err(Failure::input)?;
    let work = tempfile::tempdir().map_err(Failure::input)?;
    let config = Config {
        sat: Options {
            algorithms: match args.algorithms {
                AlgorithmsArg::Tri => AlgorithmKind::Tri,
                AlgorithmsArg::Binary => AlgorithmKind::Binary,
            },
            max_states: args.max_states,
            cube_slots: Some(args.max_out_degree.max(1)),
            ..Options::default()
        },
        max_iterations: args.max_iterations,
        verbose: args.verbose,
    };
    let setup = Setup {
        plant,
        coupling,
        spec_file: ltl,
        props,
    };
    let result = cegis::run(
        set,
        &tree,
        &setup,
        &mut session,
        &config,
        work.path(),
        &mut |m| progress.line(m),
    );
    let verified = match result {
        Ok(v) => v,
        Err(e) => {
            // Keep the model NuSMV choked on where the user can read it.
            let kept = work.path().join("closed_loop.smv");
            if kept.is_file() {
                let _ = std::fs::create_dir_all(out);
                let _ = std::fs::copy(&kept, out.join("closed_loop.last.smv"));
            }
            return Err(match e {
                CegisError::Sat(SatError::TooManyStates { .. }) | CegisError::Iterations { .. } => {
                    Failure::with_code(exit::NO_MACHINE, e)
                }
                CegisError::Sat(SatError::Bug(_)) => Failure::with_code(exit::BUG, e),
                e => Failure::input(e),
            });
        }
    };
    let s = verified.synthesis.size;
    let sat_total: f64 = verified.iterations.iter().map(|i| i.sat_seconds).sum();
    let nusmv_total: f64 = verified.iterations.iter().map(|i| i.nusmv_seconds).sum();
    let summary = serde_json::json!({
        "size": s,
        "iterations": verified.iterations,
        "report": verified.report,
        "sat_seconds": sat_total,
        "nusmv_seconds": nusmv_total,
        "total_seconds": progress.elapsed(),
    });
    let files = write_verified(
        args,
        &inputs,
        &verified.synthesis.ecc,
        &verified.report,
        &verified.model_text,
        &summary,
    )?;
    println!(
        "{}",
        verified_line(verified.report.properties.len(), set.scenarios.len())
    );
    println!("C = {}  K = {}  T = {}  N = {}", s.c, s.k, s.t, s.n);
    let n = verified.iterations.len();
    println!(
        "{n} candidate{}, {:.2} s total (SAT {:.2} s, NuSMV {:.2} s)",
        if n == 1 { "" } else { "s" },
        progress.elapsed(),
        sat_total,
        nusmv_total
    );
    print_files(out, &files);
    Ok(())
}

/// Writes a verified machine: every export format, NuSMV's report, the closed-loop model it
/// checked and `summary.json`. Returns the files written.
pub(super) fn write_verified(
    args: &MainArgs,
    inputs: &MainInputs,
    ecc: &Ecc,
    report: &Report,
    model_text: &str,
    summary: &serde_json::Value,
) -> Result<Vec<PathBuf>, Failure> {
    let out = &inputs.out;
    std::fs::create_dir_all(out)
        .map_err(|e| Failure::msg(exit::INPUT, format!("cannot create {}: {e}", out.display())))?;
    let mut files =
        export::write_all(ecc, out, &args.name, &inputs.formats).map_err(Failure::input)?;
    let report_txt = out.join("verification.txt");
    let mut text = format!(
        "Closed-loop verification by NuSMV of {}\nplant: {}\nproperties: {}\n\n",
        args.name,
        inputs.plant_file.display(),
        inputs.ltl.display()
    );
    text.push_str(&report.to_text());
    crate::files::write_atomic(&report_txt, text.as_bytes()).map_err(Failure::input)?;
    files.push(report_txt);
    let model = out.join("closed_loop.smv");
    crate::files::write_atomic(&model, model_text.as_bytes()).map_err(Failure::input)?;
    files.push(model);
    let summary_file = out.join("summary.json");
    crate::files::write_atomic(
        &summary_file,
        serde_json::to_string_pretty(summary)
            .expect("serializable")
            .as_bytes(),
    )
    .map_err(Failure::input)?;
    files.push(summary_file);
    Ok(files)
}

/// The closing lines of the main job: where the results are.
pub(super) fn print_files(out: &Path, files: &[PathBuf]) {
    println!("results in {}:", out.display());
    for f in files {
        println!("  {}", f.display());
    }
}

pub fn verify(args: &VerifyArgs) -> Result<(), Failure> {
    let ecc: Ecc = super::infer::read_ecc(&args.ecc)?;
    let (props, plant, coupling) = load_setup(&args.ltl, &args.plant, &ecc.inputs, &ecc.outputs)?;
    let mut session = session(&args.nusmv)?;
    let work = tempfile::tempdir().map_err(Failure::input)?;
    let setup = Setup {
        plant: &plant,
        coupling: &coupling,
        spec_file: &args.ltl,
        props: &props,
    };
    let report: Report =
        cegis::check_existing(&ecc, &setup, &mut session, work.path()).map_err(verify_failure)?;
    print!("{}", report.to_text());
    if report.all_hold() {
        println!("verified: all {} properties hold", report.properties.len());
        Ok(())
    } else {
        Err(Failure::msg(
            exit::INPUT,
            format!("not verified: {} violated", report.failing().join(", ")),
        ))
    }
}

impl From<NusmvError> for Failure {
    fn from(e: NusmvError) -> Failure {
        Failure::input(e)
    }
}

/// The line that says a controller is verified (only ever printed after NuSMV said so).
pub(super) fn verified_line(properties: usize, scenarios: usize) -> String {
    let holds = if properties == 1 {
        "the property holds".to_string()
    } else {
        format!("all {properties} properties hold")
    };
    let s = if scenarios == 1 { "" } else { "s" };
    format!("verified: {holds} (NuSMV), {scenarios} scenario{s} reproduced")
}
