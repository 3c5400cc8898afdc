//! The search path on the command line: `synth --method search` (the main job by metaheuristic
//! search), `synth experiment table1` (seed 001's Table I on the project's data) and
//! `synth bench-search` (scenario-fitness evaluations per second).
//!
//! This is where the SAT and search paths meet: `--start sat` seeds the colonies with the
//! minimal machine SAT finds for the scenarios alone.

use super::infer::{load_scenarios, TraceArgs};
use super::verified::{
    load_setup, nusmv, print_files, write_verified, MainArgs, MainInputs, NusmvArgs,
};
use super::{exit, Failure, Progress};
use crate::ecc::Ecc;
use crate::ltl::{property_name, Property};
use crate::sat::{self, Options};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use crate::search::oracle::{Checker, Context, Oracle, Shared};
use crate::search::{self, Config, Evaluator, Machine, Outcome, ScenarioData, Weights};
use crate::smv::closed_loop::Coupling;
use crate::smv::plant::Plant;
use crate::verify::{verify, Setup};
use clap::{Args, ValueEnum};
use rand::SeedableRng;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Where the colonies start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Start {
    /// Random machines (the seeds' method).
    Random,
    /// The minimal machine SAT finds for the scenarios alone (verification left to the search).
    Sat,
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
    #[arg(long)]
    pub threads: Option<usize>,
    /// Give up after this many seconds.
    #[arg(long, default_value_t = 600.0, value_name = "SECONDS")]
    pub time_limit: f64,
    /// States of every candidate (default: 8, or the SAT machine's with --start sat).
    #[arg(long, value_name = "C")]
    pub states: Option<usize>,
    /// Colonies ((1+λ) strategies sharing their best).
    #[arg(long, default_value_t = 4)]
    pub colonies: usize,
    /// Where the colonies start. From random machines the search does not reproduce all ten
    /// Pick-and-Place scenarios within minutes (as in seed 004, which took hours), so the main
    /// job starts from SAT's machine for the scenarios and leaves the properties to the search.
    #[arg(long, value_enum, default_value_t = Start::Sat)]
    pub start: Start,
    /// Probability of verifying a candidate whose scenario fitness is below 99% of the maximum
    /// (seed 001's p; above it every candidate is verified).
    #[arg(long, default_value_t = 0.001, value_name = "P")]
    pub verify_probability: f64,
}

impl Default for SearchArgs {
    /// The defaults of the command line.
    fn default() -> Self {
        SearchArgs {
            seed: 1,
            threads: None,
            time_limit: 600.0,
            states: None,
            colonies: 4,
            start: Start::Sat,
            verify_probability: 0.001,
        }
    }
}

fn threads(arg: Option<usize>) -> usize {
    arg.unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    })
}

/// The minimal machine SAT finds for the scenarios alone (guards: conjunctions, at most
/// `out_degree` transitions per state, as in the SAT main job), as a search machine.
fn sat_start(
    set: &ScenarioSet,
    out_degree: usize,
    progress: &Progress,
) -> Result<Machine, Failure> {
    let t = Instant::now();
    let tree = ScenarioTree::build(set).map_err(Failure::input)?;
    let opts = Options {
        cube_slots: Some(out_degree.max(1)),
        ..Options::default()
    };
    let s = sat::synthesize(set, &tree, &opts, &mut |_| {}).map_err(Failure::input)?;
    progress.line(&format!(
        "SAT start: {} for the scenarios alone in {:.2} s",
        s.size,
        t.elapsed().as_secs_f64()
    ));
    Machine::from_ecc(&s.ecc).ok_or_else(|| {
        Failure::msg(
            exit::BUG,
            "the SAT machine has a guard that is not a sum of products",
        )
    })
}

/// One NuSMV-backed checker per colony, sharing one cache.
fn checkers(
    colonies: usize,
    ctx: &Arc<Context>,
    shared: &Arc<Shared>,
) -> Result<Vec<Box<dyn Checker>>, Failure> {
    (0..colonies)
        .map(|_| {
            Oracle::new(ctx.clone(), shared.clone())
                .map(|o| Box::new(o) as Box<dyn Checker>)
                .map_err(Failure::input)
        })
        .collect()
}

/// One line of search progress.
fn describe(p: &search::Progress) -> String {
    let props = p
        .properties
        .map(|(s, t)| format!(", properties {s}/{t}"))
        .unwrap_or_default();
    format!(
        "round {}: best fitness {:.5} ({}/{} scenarios{props}), {} evaluations, {:.0}/s",
        p.round,
        p.best_fitness,
        p.best_score.reproduced,
        p.best_score.scenarios,
        p.evaluations,
        p.evaluations as f64 / p.seconds.max(1e-9)
    )
}

/// Verifies a machine in a fresh NuSMV session; the report the "verified" claim rests on.
fn final_check(ecc: &Ecc, ctx: &Context) -> Result<crate::verify::Verification, Failure> {
    let mut session = ctx.nusmv.session();
    let work = tempfile::tempdir().map_err(Failure::input)?;
    let setup = Setup {
        plant: &ctx.plant,
        coupling: &ctx.coupling,
        spec_file: &ctx.spec_file,
        props: &ctx.props,
    };
    verify(ecc, &setup, &mut session, work.path()).map_err(Failure::input)
}

/// `synth --method search`.
pub fn main_job(args: &MainArgs, inputs: &MainInputs, progress: &Progress) -> Result<(), Failure> {
    let s = &args.search;
    let data = ScenarioData::new(&inputs.set).map_err(Failure::input)?;
    let initial = match s.start {
        Start::Random => vec![],
        Start::Sat => vec![sat_start(&inputs.set, args.max_out_degree, progress)?],
    };
    let states = s
        .states
        .or(initial.first().map(|m| m.states.len()))
        .unwrap_or(8);
    let ctx = Arc::new(Context {
        plant: inputs.plant.clone(),
        coupling: inputs.coupling.clone(),
        spec_file: inputs.ltl.clone(),
        props: inputs.props.clone(),
        nusmv: nusmv(&args.nusmv)?,
    });
    let shared = Arc::new(Shared::default());
    let config = Config {
        states,
        colonies: s.colonies.max(1),
        seed: s.seed,
        threads: threads(s.threads),
        time_limit: Some(Duration::from_secs_f64(s.time_limit.max(0.0))),
        verify_probability: s.verify_probability.clamp(0.0, 1.0),
        initial,
        ..Config::default()
    };
    progress.line(&format!(
        "search: seed {}, {} states, {} colonies on {} threads, limit {} s",
        config.seed, config.states, config.colonies, config.threads, s.time_limit
    ));
    let mut last = Instant::now();
    let outcome = search::run(
        &data,
        &config,
        checkers(config.colonies, &ctx, &shared)?,
        &mut |p| {
            if last.elapsed() >= Duration::from_secs(1) {
                last = Instant::now();
                progress.line(&describe(p));
            }
        },
    )
    .map_err(Failure::input)?;
    let runs = shared.runs.load(std::sync::atomic::Ordering::Relaxed);
    let hits = shared.hits.load(std::sync::atomic::Ordering::Relaxed);
    progress.line(&format!(
        "search ended after {:.2} s: {} evaluations, NuSMV {} runs + {} cache hits",
        outcome.stats.seconds, outcome.stats.evaluations, runs, hits
    ));
    if !outcome.perfect {
        return Err(Failure::msg(
            exit::NO_MACHINE,
            format!(
                "no verified controller within --time-limit {} s (seed {}): the best reproduces {}/{} scenarios{}; raise --time-limit or try --start sat",
                s.time_limit,
                s.seed,
                outcome.score.reproduced,
                outcome.score.scenarios,
                outcome
                    .verdicts
                    .as_ref()
                    .map(|v| format!(" and satisfies {}/{} properties", v.satisfied, v.total))
                    .unwrap_or_default()
            ),
        ));
    }
    let ecc = outcome.ecc.clone();
    if let Err(e) = inputs.set.check(&ecc) {
        return Err(Failure::msg(
            exit::BUG,
            format!("the search's machine does not replay the scenarios: {e}"),
        ));
    }
    let v = final_check(&ecc, &ctx)?;
    if !v.report.all_hold() {
        return Err(Failure::msg(
            exit::BUG,
            format!(
                "the search's machine fails {} in the final NuSMV check",
                v.report.failing().join(", ")
            ),
        ));
    }
    let size = ecc.size();
    let summary = serde_json::json!({
        "method": "search",
        "seed": s.seed,
        "start": format!("{:?}", s.start).to_lowercase(),
        "size": size,
        "fitness": outcome.fitness,
        "search": outcome.stats,
        "nusmv_runs": runs,
        "nusmv_cache_hits": hits,
        "report": v.report,
        "total_seconds": progress.elapsed(),
    });
    let files = write_verified(args, inputs, &ecc, &v.report, &v.model.text, &summary)?;
    println!(
        "{}",
        super::verified::verified_line(v.report.properties.len(), inputs.set.scenarios.len())
    );
    println!(
        "C = {}  K = {}  T = {}  N = {}",
        size.c, size.k, size.t, size.n
    );
    println!(
        "search, seed {}: {:.2} s total, {} evaluations, {} NuSMV runs",
        s.seed,
        progress.elapsed(),
        outcome.stats.evaluations,
        runs
    );
    print_files(&inputs.out, &files);
    Ok(())
}

#[derive(Debug, Args)]
pub struct ExperimentArgs {
    /// The experiment: `table1` (seed 001, Table I: scenarios only; scenarios + LTL without
    /// F_ce; scenarios + LTL).
    #[arg(value_parser = ["table1"])]
    pub name: String,
    /// Runs per configuration (seeds SEED, SEED+1, ...).
    #[arg(long, default_value_t = 10)]
    pub runs: usize,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads per run (default: all cores).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Seconds per run; a run without a solution by then counts with this time.
    #[arg(long, default_value_t = 120.0, value_name = "SECONDS")]
    pub time_limit: f64,
    #[arg(long, default_value = "specs/pnp.traces", value_name = "FILE")]
    pub traces: PathBuf,
    /// Use only the first N scenarios (seed 001 used one: a single piece from track 1).
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub scenarios: usize,
    #[arg(long, default_value = "specs/pnp.ltl", value_name = "FILE")]
    pub ltl: PathBuf,
    /// Properties of the spec to use, by name (seed 001's three by default); `all` for every
    /// property of the file.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "c1_exclusive,c2_exclusive,track1_served"
    )]
    pub properties: Vec<String>,
    #[arg(long, default_value = "smv/pnp_surrogate.smv", value_name = "FILE")]
    pub plant: PathBuf,
    /// States of every candidate.
    #[arg(long, default_value_t = 6, value_name = "C")]
    pub states: usize,
    /// Where the colonies start.
    #[arg(long, value_enum, default_value_t = Start::Random)]
    pub start: Start,
    /// Configurations to run, comma-separated (1, 2, 3).
    #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
    pub configs: Vec<usize>,
    #[arg(long, default_value_t = 0.001, value_name = "P")]
    pub verify_probability: f64,
    /// Progress of every run (one line per second) on stderr.
    #[arg(long, short)]
    pub verbose: bool,
    /// Ask NuSMV even for a child that still follows a counterexample of its parent (seed
    /// 001 as written; by default such a child keeps its parent's verdicts).
    #[arg(long)]
    pub no_replay: bool,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
}

/// One run of the experiment.
struct RunResult {
    seconds: f64,
    solved: bool,
    all_hold: bool,
    failing: Vec<String>,
    states_used: usize,
}

fn pick_properties(
    all: Vec<Property>,
    names: &[String],
    file: &Path,
) -> Result<Vec<Property>, Failure> {
    if names.iter().any(|n| n == "all") {
        return Ok(all);
    }
    let named: Vec<(String, Property)> = all
        .into_iter()
        .enumerate()
        .map(|(k, p)| (property_name(k, &p), p))
        .collect();
    names
        .iter()
        .map(|n| {
            named
                .iter()
                .find(|(m, _)| m == n)
                .map(|(_, p)| p.clone())
                .ok_or_else(|| {
                    Failure::msg(
                        exit::INPUT,
                        format!("{}: no property named `{n}`", file.display()),
                    )
                })
        })
        .collect()
}

fn stats(times: &mut [f64]) -> (f64, f64, f64, f64) {
    times.sort_by(f64::total_cmp);
    let n = times.len();
    let mean = times.iter().sum::<f64>() / n as f64;
    let median = if n % 2 == 1 {
        times[n / 2]
    } else {
        (times[n / 2 - 1] + times[n / 2]) / 2.0
    };
    (times[0], mean, median, times[n - 1])
}

/// `synth experiment table1`.
pub fn experiment(args: &ExperimentArgs) -> Result<(), Failure> {
    let progress = Progress::new(false);
    let mut set = load_scenarios(&TraceArgs {
        traces: vec![args.traces.clone()],
        input_names: None,
        output_names: None,
    })?;
    set.scenarios.truncate(args.scenarios.max(1));
    let (props, plant, coupling): (Vec<Property>, Plant, Coupling) =
        load_setup(&args.ltl, &args.plant, &set.inputs, &set.outputs)?;
    let props = pick_properties(props, &args.properties, &args.ltl)?;
    let names: Vec<String> = props
        .iter()
        .enumerate()
        .map(|(k, p)| p.label.clone().unwrap_or_else(|| format!("p{}", k + 1)))
        .collect();
    let data = ScenarioData::new(&set).map_err(Failure::input)?;
    let ctx = Arc::new(Context {
        plant,
        coupling,
        spec_file: args.ltl.clone(),
        props,
        nusmv: nusmv(&args.nusmv)?,
    });
    let initial = match args.start {
        Start::Random => vec![],
        Start::Sat => vec![sat_start(&set, 6, &progress)?],
    };
    let threads = threads(args.threads);
    progress.line(&format!(
        "table1: {} scenario(s), {} steps; properties {}; {} states; {} runs per configuration on {} threads, limit {} s per run",
        data.scenario_count(),
        data.step_count(),
        names.join(", "),
        args.states,
        args.runs,
        threads,
        args.time_limit
    ));
    let labels = [
        "",
        "Scenarios",
        "Scenarios + LTL (no F_ce)",
        "Scenarios + LTL",
    ];
    let mut rows = Vec::new();
    for &cfg in &args.configs {
        if !(1..=3).contains(&cfg) {
            return Err(Failure::msg(
                exit::USAGE,
                format!("no configuration {cfg} (1, 2 or 3)"),
            ));
        }
        let weights = match cfg {
            1 => Weights {
                sat: 0.0,
                ce: 0.0,
                ..Weights::default()
            },
            2 => Weights {
                ce: 0.0,
                ..Weights::default()
            },
            _ => Weights::default(),
        };
        let mut results = Vec::new();
        for r in 0..args.runs.max(1) {
            let seed = args.seed + r as u64;
            let shared = Arc::new(Shared::default());
            let config = Config {
                states: args
                    .states
                    .max(initial.first().map_or(1, |m| m.states.len())),
                seed,
                threads,
                weights,
                time_limit: Some(Duration::from_secs_f64(args.time_limit)),
                verify_probability: args.verify_probability,
                replay_counterexamples: !args.no_replay,
                initial: initial.clone(),
                ..Config::default()
            };
            let checkers = if cfg == 1 {
                vec![]
            } else {
                checkers(config.colonies, &ctx, &shared)?
            };
            let t = Instant::now();
            let mut last = Instant::now();
            let out: Outcome = search::run(&data, &config, checkers, &mut |p| {
                if args.verbose && last.elapsed() >= Duration::from_secs(1) {
                    last = Instant::now();
                    progress.line(&describe(p));
                }
            })
            .map_err(Failure::input)?;
            let seconds = t.elapsed().as_secs_f64();
            // Every configuration's machine is checked by NuSMV at the end, on every property.
            let v = final_check(&out.ecc, &ctx)?;
            let res = RunResult {
                seconds,
                solved: out.perfect,
                all_hold: v.report.all_hold(),
                failing: v.report.failing().iter().map(|s| s.to_string()).collect(),
                states_used: reachable_states(&out.ecc),
            };
            progress.line(&format!(
                "config {cfg} run {} (seed {seed}): {:.2} s, {}, {} evaluations, {} NuSMV runs, {} cache hits, {} saved by counterexample replay; {} states reachable; final NuSMV check: {}",
                r + 1,
                seconds,
                if res.solved { "solved" } else { "NOT solved in time" },
                out.stats.evaluations,
                shared.runs.load(std::sync::atomic::Ordering::Relaxed),
                shared.hits.load(std::sync::atomic::Ordering::Relaxed),
                out.stats.replayed,
                res.states_used,
                if res.all_hold {
                    "all properties hold".to_string()
                } else {
                    format!("fails {}", res.failing.join(", "))
                }
            ));
            results.push(res);
        }
        rows.push((cfg, results));
    }
    println!();
    println!(
        "| # | Configuration | min, s | mean, s | median, s | max, s | solved | satisfied all LTL |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (cfg, results) in &rows {
        let mut times: Vec<f64> = results.iter().map(|r| r.seconds).collect();
        let (min, mean, median, max) = stats(&mut times);
        let n = results.len();
        let solved = results.iter().filter(|r| r.solved).count();
        let all = results.iter().filter(|r| r.all_hold).count();
        println!(
            "| {cfg} | {} | {min:.1} | {mean:.1} | {median:.1} | {max:.1} | {solved}/{n} | {:.0}% ({all}/{n}) |",
            labels[*cfg],
            100.0 * all as f64 / n as f64
        );
    }
    println!();
    for (cfg, results) in &rows {
        let n = results.len();
        let per: Vec<String> = names
            .iter()
            .map(|p| {
                let ok = results.iter().filter(|r| !r.failing.contains(p)).count();
                format!("{p} {ok}/{n}")
            })
            .collect();
        println!("config {cfg}: {}", per.join(", "));
    }
    Ok(())
}

/// States reachable from the initial state along transitions.
fn reachable_states(ecc: &Ecc) -> usize {
    let mut seen = vec![false; ecc.states.len()];
    let mut stack = vec![0usize];
    seen[0] = true;
    while let Some(s) = stack.pop() {
        for t in &ecc.states[s].transitions {
            if !seen[t.target.0] {
                seen[t.target.0] = true;
                stack.push(t.target.0);
            }
        }
    }
    seen.iter().filter(|&&b| b).count()
}

#[derive(Debug, Args)]
pub struct BenchSearchArgs {
    /// Scenarios to evaluate on.
    #[arg(long, default_value = "specs/pnp.traces", value_name = "FILE")]
    pub traces: PathBuf,
    /// Seconds per measurement.
    #[arg(long, default_value_t = 3.0)]
    pub seconds: f64,
    /// States of the evaluated machines.
    #[arg(long, default_value_t = 8)]
    pub states: usize,
    /// Threads of the parallel measurement (default: all cores).
    #[arg(long)]
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

/// `synth bench-search`.
pub fn bench_search(args: &BenchSearchArgs) -> Result<(), Failure> {
    let set = load_scenarios(&TraceArgs {
        traces: vec![args.traces.clone()],
        input_names: None,
        output_names: None,
    })?;
    let data = ScenarioData::new(&set).map_err(Failure::input)?;
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
    let n = threads(args.threads);
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
    println!(
        "scenario fitness on {} ({} scenarios, {} steps), {} states:",
        args.traces.display(),
        data.scenario_count(),
        data.step_count(),
        args.states
    );
    println!("  1 thread:  {one:.0} evaluations/s");
    println!(
        "  {n} threads: {total:.0} evaluations/s in all, {:.0} per thread",
        total / n as f64
    );
    Ok(())
}
