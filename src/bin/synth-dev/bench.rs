//! The benchmarks of synthesis on the shipped scenarios: a Markdown table each.
//!
//! - `bench`: exact synthesis on the project's Pick-and-Place scenarios and, when the fbSAT
//!   data folder is present (it is not part of the repository), on fbSAT's published scenario
//!   sets; then the main job (exact synthesis verified by NuSMV);
//! - `bench-modular`: modular synthesis for M = 1..4;
//! - `bench-search`: the search's scenario-fitness evaluations per second;
//! - `bench-ambiguity`: the ambiguity check after `synth infer`'s machine.

use crate::cli::args::TraceArgs;
use crate::stats::Stats;
use clap::Args;
use fbsynth::ecc::AlgorithmKind;
use fbsynth::out;
use fbsynth::pipeline::Error;
use fbsynth::pipeline::{self, exact, modular, Check, Recordings};
use fbsynth::search::{self, Evaluator, Machine, ScenarioData};
use rand::SeedableRng;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Runs per case; the table shows min / median / max.
    #[arg(long, default_value_t = 5, value_parser = crate::cli::args::repetitions())]
    pub runs: usize,
    /// Folder with fbSAT's public scenario sets (tests-N.gz and pnp/input-names,
    /// pnp/output-names; not shipped). Without it, or for files missing there, those cases are
    /// skipped.
    #[arg(long, value_name = "DIR")]
    pub fbsat_data: Option<PathBuf>,
    /// The project's Pick-and-Place scenarios.
    #[arg(long, default_value = "specs/pnp.traces", value_name = "FILE")]
    pub pnp: PathBuf,
    /// Runs of the main job (CEGIS with NuSMV on specs/pnp.ltl and smv/pnp_surrogate.smv);
    /// 0 skips it.
    #[arg(long, default_value_t = 3, value_parser = crate::cli::args::repetitions())]
    pub cegis_runs: usize,
    /// The NuSMV binary for the main-job benchmark (default: as the main job finds it).
    #[arg(long, value_name = "PATH")]
    pub nusmv: Option<PathBuf>,
}

struct Case {
    name: String,
    traces: Recordings,
    opts: exact::Options,
}

fn cases(args: &BenchArgs) -> Vec<Case> {
    let mut out = Vec::new();
    if args.pnp.is_file() {
        out.push(Case {
            name: format!("{} (tri)", args.pnp.display()),
            traces: Recordings::files(vec![args.pnp.clone()]),
            opts: exact::Options::default(),
        });
    }
    let Some(data) = &args.fbsat_data else {
        return out;
    };
    let names = |f: &str| data.join("pnp").join(f);
    for n in [1, 10, 39] {
        let file = data.join(format!("tests-{n}.gz"));
        if !file.is_file() || !names("input-names").is_file() {
            continue;
        }
        let traces = Recordings {
            traces: vec![file],
            input_names: Some(names("input-names")),
            output_names: Some(names("output-names")),
        };
        for (label, start_state) in [("binary, fbSAT start state", true), ("binary", false)] {
            out.push(Case {
                name: format!("fbSAT tests-{n} ({label})"),
                traces: traces.clone(),
                opts: exact::Options {
                    sat: exact::SatOptions {
                        algorithms: AlgorithmKind::Binary,
                        start_state,
                        ..exact::SatOptions::default()
                    },
                    ..exact::Options::default()
                },
            });
        }
    }
    out
}

/// The main job, `runs` times: iterations, time, SAT share, NuSMV time per check.
fn bench_cegis(args: &BenchArgs) -> Result<(), Error> {
    let (ltl, plant_file) = (
        Path::new("specs/pnp.ltl"),
        Path::new("smv/pnp_surrogate.smv"),
    );
    if !ltl.is_file() || !plant_file.is_file() || !args.pnp.is_file() {
        return Ok(());
    }
    let nusmv = pipeline::nusmv(args.nusmv.as_deref(), 60.0)?;
    let set = Recordings::files(vec![args.pnp.clone()]).load()?;
    let check = Check::new(
        pipeline::Problem::load(ltl, plant_file, &set.inputs, &set.outputs)?,
        nusmv,
    );
    let opts = exact::Options::default();
    out!();
    out!("| main job run | candidates | C | T | N | total s | SAT s | NuSMV s | NuSMV ms per NuSMV check (median) |");
    out!("|---|---|---|---|---|---|---|---|---|");
    for run in 1..=args.cegis_runs {
        let t = Instant::now();
        let v = exact::run(&set, Some(&check), &opts, &mut |_| {})?;
        let total = t.elapsed().as_secs_f64();
        let sat: f64 = v.iterations.iter().map(|i| i.sat_seconds).sum();
        // Candidates the in-process checker rejected never reach NuSMV: the median is over
        // those NuSMV checked.
        let nus: Vec<f64> = (v.iterations.iter())
            .filter(|i| i.checked_by == "NuSMV")
            .map(|i| i.nusmv_seconds)
            .collect();
        let med = Stats::of(&nus).map_or(0.0, |s| s.median);
        let s = v.synthesis.size;
        out!(
            "| {run} | {} | {} | {} | {} | {total:.2} | {sat:.2} ({:.0}%) | {:.2} | {:.0} |",
            v.iterations.len(),
            s.c,
            s.t,
            s.n,
            100.0 * sat / total,
            nus.iter().sum::<f64>(),
            med * 1000.0
        );
    }
    Ok(())
}

/// `synth-dev bench`: exact synthesis `--runs` times per case, as a Markdown table; then the
/// main job `--cegis-runs` times.
pub fn bench(args: &BenchArgs) -> Result<(), Error> {
    let runs = args.runs.max(1);
    let all = cases(args);
    if all.is_empty() {
        return Err(Error::Input(format!(
            "nothing to benchmark: {} does not exist and no fbSAT data was found{}",
            args.pnp.display(),
            args.fbsat_data
                .as_ref()
                .map(|d| format!(" in {}", d.display()))
                .unwrap_or_default()
        )));
    }
    // The last two columns measure the guards as fbSAT's extended guards: parse-tree nodes in
    // all (its N) and in the largest guard (its P).
    out!("| case | steps | C | K | T | N | min s | median s | max s | nodes | P |");
    out!("|---|---|---|---|---|---|---|---|---|---|---|");
    for case in all {
        let set = case.traces.load()?;
        let mut times = Vec::with_capacity(runs);
        let mut last = None;
        for _ in 0..runs {
            let t = Instant::now();
            let r = exact::run(&set, None, &case.opts, &mut |_| {})?.synthesis;
            times.push(t.elapsed().as_secs_f64());
            last = Some(r);
        }

        let r = last.expect("runs >= 1");
        let s = r.size;
        let guards = r.ecc.states.iter().flat_map(|q| &q.transitions);
        let nodes: usize = guards.clone().map(|t| t.guard.tree_size()).sum();
        let largest = guards.map(|t| t.guard.tree_size()).max().unwrap_or(0);
        let Stats {
            min: lo,
            median: med,
            max: hi,
            ..
        } = Stats::of(&times).expect("runs >= 1");
        out!(
            "| {} | {} | {} | {} | {} | {} | {lo:.3} | {med:.3} | {hi:.3} | {nodes} | {largest} |",
            case.name,
            set.step_count(),
            s.c,
            s.k,
            s.t,
            s.n
        );
    }
    if args.cegis_runs > 0 {
        bench_cegis(args)?;
    }
    Ok(())
}

#[derive(Debug, Args)]
pub struct BenchModularArgs {
    #[command(flatten)]
    pub traces: TraceArgs,
    /// Largest number of modules; the table has one row per M = 1..=this.
    #[arg(long, default_value_t = 4, value_name = "M")]
    pub max_modules: usize,
    /// Transition slots per state to start with (widened while too few; the table's K is the
    /// result's).
    #[arg(long, default_value_t = modular::DEFAULT_MAX_OUT_DEGREE, value_name = "K")]
    pub slots: usize,
    /// Runs per M; the table shows min / median / max.
    #[arg(long, default_value_t = 3, value_parser = crate::cli::args::repetitions())]
    pub runs: usize,
}

/// `synth-dev bench-modular`: modular synthesis for M = 1..=max, as a Markdown table.
pub fn bench_modular(args: &BenchModularArgs) -> Result<(), Error> {
    let recordings = args.traces.recordings();
    let set = recordings.load()?;
    out!(
        "{}: {} scenarios, {} steps, {} tree nodes, {} inputs, {} outputs; K from {} slots, {} runs",
        recordings.show(),
        set.scenarios.len(),
        set.step_count(),
        modular::tree_nodes(&set)?,
        set.inputs.len(),
        set.outputs.len(),
        args.slots,
        args.runs.max(1)
    );
    out!();
    out!("| M | largest | A | N' | transitions | K | variables | clauses | solver calls | time min / median / max (s) |");
    out!("|---|---|---|---|---|---|---|---|---|---|");
    for modules in 1..=args.max_modules {
        let opts = modular::Options {
            modules,
            max_out_degree: args.slots,
            ..modular::Options::default()
        };
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..args.runs.max(1) {
            let t0 = Instant::now();
            let r = modular::run(&set, &opts, &mut |_| {})?;
            times.push(t0.elapsed().as_secs_f64());
            last = Some(r);
        }
        let time = Stats::of(&times).expect("at least one run");
        let r = last.expect("at least one run");
        let t: usize = r.size.modules.iter().map(|s| s.t).sum();
        out!(
            "| {modules} | {} | {} | {} | {t} | {} | {} | {} | {} | {:.2} / {:.2} / {:.2} |",
            r.size.max_states,
            r.size.inputs_used,
            r.size.total_states,
            r.stats.max_out_degree,
            r.stats.variables,
            r.stats.clauses,
            r.stats.solver_calls,
            time.min,
            time.median,
            time.max
        );
        for line in r.modular.describe() {
            fbsynth::cli::err_line(format_args!("    M={modules} {line}"));
        }
    }
    Ok(())
}

#[derive(Debug, Args)]
pub struct BenchSearchArgs {
    /// Scenarios to evaluate on.
    #[arg(long, default_value = "specs/pnp.traces", value_name = "FILE")]
    pub traces: PathBuf,
    /// Seconds per measurement.
    #[arg(long, default_value_t = 3.0, value_parser = crate::cli::args::seconds)]
    pub seconds: f64,
    /// States of the evaluated machines.
    #[arg(long, default_value_t = 8)]
    pub states: usize,
    /// Threads of the parallel measurement (default: all cores).
    #[arg(long, value_parser = crate::cli::args::workers())]
    pub threads: Option<usize>,
}

/// Evaluations per second of one evaluator over a pool of machines.
fn evaluations_per_second(data: &ScenarioData, pool: &[Machine], seconds: f64) -> f64 {
    let mut ev = Evaluator::new(data);
    let start = Instant::now();
    let mut n = 0u64;
    let mut sink = 0.0;
    while start.elapsed().as_secs_f64() < seconds {
        for m in pool {
            sink += ev.evaluate(m).ed;
        }
        n += pool.len() as u64;
    }
    std::hint::black_box(sink);
    n as f64 / start.elapsed().as_secs_f64()
}

/// `synth-dev bench-search`.
pub fn bench_search(args: &BenchSearchArgs) -> Result<(), Error> {
    let set = Recordings::files(vec![args.traces.clone()]).load()?;
    let data = ScenarioData::new(&set).map_err(Error::from)?;
    // Machines as the search sees them: random starts moved by a few dozen mutations.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    let pool: Vec<Machine> = (0..256)
        .map(|_| {
            let mut m = Machine::random(&mut rng, data.inputs.len(), args.states, 4);
            for _ in 0..30 {
                search::operators::add_or_delete(&mut rng, &mut m, 0.2);
                search::operators::resize_significance(&mut rng, &mut m, 4);
            }
            m
        })
        .collect();
    let one = evaluations_per_second(&data, &pool, args.seconds);
    let n = pipeline::search::threads(args.threads);
    let per_thread: Vec<f64> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..n)
            .map(|_| s.spawn(|| evaluations_per_second(&data, &pool, args.seconds)))
            .collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("no panic"))
            .collect()
    });
    let total: f64 = per_thread.iter().sum();
    out!(
        "scenario fitness on {} ({} scenarios, {} steps), {} states:",
        args.traces.display(),
        data.scenario_count(),
        data.step_count(),
        args.states
    );
    out!("  1 thread:  {one:.0} evaluations/s");
    out!(
        "  {n} threads: {total:.0} evaluations/s in all, {:.0} per thread",
        total / n as f64
    );
    Ok(())
}

#[derive(Debug, Args)]
pub struct BenchAmbiguityArgs {
    /// Runs per case; the table shows min / median / max.
    #[arg(long, default_value_t = 3, value_parser = crate::cli::args::repetitions())]
    pub runs: usize,
}

/// The shipped cases' recordings the ambiguity benchmark reads.
const AMBIGUITY_CASES: [&str; 4] = [
    "specs/pnp.traces",
    "specs/distribution.csv",
    "specs/tank1.traces",
    "specs/tank2.traces",
];

/// `synth-dev bench-ambiguity`: the time of the ambiguity check (one rival, default depth) after
/// `synth infer`'s machine, on each shipped case.
pub fn bench_ambiguity(args: &BenchAmbiguityArgs) -> Result<(), Error> {
    use fbsynth::pipeline::ambiguity;
    use fbsynth::scenario::tree::ScenarioTree;
    out!("| recordings | C | verdict | min s | median s | max s |");
    out!("|---|---|---|---|---|---|");
    for file in AMBIGUITY_CASES {
        let set = Recordings::files(vec![PathBuf::from(file)]).load()?;
        let machine = exact::run(&set, None, &exact::Options::default(), &mut |_| {})?
            .synthesis
            .ecc;
        let tree = ScenarioTree::build(&set).map_err(pipeline::Error::from)?;
        let mut times = Vec::new();
        let mut verdict = None;
        for _ in 0..args.runs.max(1) {
            let t = Instant::now();
            let a = ambiguity::check(&set, &tree, &machine, &ambiguity::Options::default())?;
            times.push(t.elapsed().as_secs_f64());
            verdict = Some(a.verdict);
        }
        let t = Stats::of(&times).expect("runs >= 1");
        out!(
            "| {file} | {} | {:?} | {:.3} | {:.3} | {:.3} |",
            machine.states.len(),
            verdict.expect("runs >= 1"),
            t.min,
            t.median,
            t.max
        );
    }
    Ok(())
}
