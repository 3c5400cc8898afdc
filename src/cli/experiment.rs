//! `synth experiment table1`: Table I of the function-block reconstruction with NuSMV in the
//! loop (scenarios only; scenarios + LTL without the counterexample term; scenarios + LTL),
//! repeated with the search on the project's data.

use super::args::{check, problem, Judge, NusmvArgs, Start};
use super::progress::{describe, Progress};
use super::{exit, Failure};
use clap::Args;
use fbsynth::pipeline::search::{self, Options};
use fbsynth::pipeline::{Event, Recordings};
use fbsynth::search::Weights;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct ExperimentArgs {
    /// The experiment: `table1` (the verification-in-the-loop paper, Table I: scenarios only; scenarios + LTL without
    /// F_ce; scenarios + LTL).
    #[arg(value_parser = ["table1"])]
    pub name: String,
    /// Runs per configuration (seeds SEED, SEED+1, ...).
    #[arg(long, default_value_t = 10)]
    pub runs: usize,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads per run (default: all cores).
    #[arg(long, value_parser = super::args::workers())]
    pub threads: Option<usize>,
    /// Seconds per run; a run without a solution by then counts with this time.
    #[arg(long, default_value_t = 120.0, value_name = "SECONDS")]
    pub time_limit: f64,
    #[arg(long, default_value = "specs/pnp.traces", value_name = "FILE")]
    pub traces: PathBuf,
    /// Use only the first N scenarios (the verification-in-the-loop paper used one: a single piece from track 1).
    #[arg(long, default_value_t = 1, value_name = "N")]
    pub scenarios: usize,
    #[arg(long, default_value = "specs/pnp.ltl", value_name = "FILE")]
    pub ltl: PathBuf,
    /// Properties of the spec to use, by name (the verification-in-the-loop paper's three by default); `all` for every
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
    #[arg(long, default_value_t = 6, value_name = "C", value_parser = super::args::states())]
    pub states: usize,
    /// Where the colonies start.
    #[arg(long, value_enum, default_value_t = Start::Random)]
    pub start: Start,
    /// Configurations to run, comma-separated (1, 2, 3).
    #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
    pub configs: Vec<usize>,
    /// Probability of verifying a candidate below the scenario threshold. Default: 0.01 with
    /// --judge in-process, 0.001 with --judge nusmv.
    #[arg(long, value_name = "P")]
    pub verify_probability: Option<f64>,
    /// Who judges the candidates during the search; NuSMV checks the machine each run ends with.
    #[arg(long, value_enum, default_value_t = Judge::InProcess)]
    pub judge: Judge,
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
    let mut set = Recordings::files(vec![args.traces.clone()]).load()?;
    set.scenarios.truncate(args.scenarios.max(1));
    let problem = problem(&args.ltl, &args.plant, &set.inputs, &set.outputs)?
        .select(&args.properties)
        .map_err(|e| Failure::from(fbsynth::pipeline::Error::from(e)))?;
    let names: Vec<String> = problem
        .props
        .iter()
        .enumerate()
        .map(|(k, p)| p.label.clone().unwrap_or_else(|| format!("p{}", k + 1)))
        .collect();
    let check = check(problem, &args.nusmv)?;
    let initial = match args.start {
        Start::Random => vec![],
        Start::Sat => vec![search::sat_start(&set, 6, &mut |e| progress.event(e))?],
    };
    let threads = search::threads(args.threads);
    let steps: usize = set.scenarios.iter().map(|s| s.steps.len()).sum();
    progress.line(&format!(
        "table1: {} scenario(s), {} steps; properties {}; {} states; {} runs per configuration on {} threads, limit {} s per run",
        set.scenarios.len(),
        steps,
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
            let opts = Options {
                seed,
                threads: Some(threads),
                time_limit: args.time_limit,
                states: Some(args.states),
                verify_probability: args.verify_probability,
                weights,
                replay_counterexamples: !args.no_replay,
                judge: args.judge.into(),
                every_round: false,
                ..Options::default()
            };
            let t = std::time::Instant::now();
            let run = search::run(&set, &check, &opts, Some(initial.clone()), &mut |e| {
                if super::verbose() && matches!(e, Event::SearchRound(_)) {
                    progress.line(&describe(&e));
                }
            })?;
            let seconds = t.elapsed().as_secs_f64();
            // Every configuration's machine is checked by NuSMV at the end, on every property.
            let report = &run.verification.report;
            let res = RunResult {
                seconds,
                solved: run.outcome.perfect,
                all_hold: report.all_hold(),
                failing: report.failing().iter().map(|s| s.to_string()).collect(),
                states_used: run.reachable_states,
            };
            progress.line(&format!(
                "config {cfg} run {} (seed {seed}): {:.2} s, {}, {} evaluations, {} in-process checks, {} NuSMV runs, {} cache hits, {} saved by counterexample replay; {} states reachable; final NuSMV check: {}",
                r + 1,
                seconds,
                if res.solved { "solved" } else { "NOT solved in time" },
                run.outcome.stats.evaluations,
                run.in_process_checks,
                run.nusmv_runs,
                run.cache_hits,
                run.outcome.stats.replayed,
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
    out!();
    out!(
        "| # | Configuration | min, s | mean, s | median, s | max, s | solved | satisfied all LTL |"
    );
    out!("|---|---|---|---|---|---|---|---|");
    for (cfg, results) in &rows {
        let mut times: Vec<f64> = results.iter().map(|r| r.seconds).collect();
        let (min, mean, median, max) = stats(&mut times);
        let n = results.len();
        let solved = results.iter().filter(|r| r.solved).count();
        let all = results.iter().filter(|r| r.all_hold).count();
        out!(
            "| {cfg} | {} | {min:.1} | {mean:.1} | {median:.1} | {max:.1} | {solved}/{n} | {:.0}% ({all}/{n}) |",
            labels[*cfg],
            100.0 * all as f64 / n as f64
        );
    }
    out!();
    for (cfg, results) in &rows {
        let n = results.len();
        let per: Vec<String> = names
            .iter()
            .map(|p| {
                let ok = results.iter().filter(|r| !r.failing.contains(p)).count();
                format!("{p} {ok}/{n}")
            })
            .collect();
        out!("config {cfg}: {}", per.join(", "));
    }
    Ok(())
}
