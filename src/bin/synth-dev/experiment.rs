//! `synth-dev experiment table1`: Table I of the function-block reconstruction with NuSMV in
//! the loop (scenarios only; scenarios + LTL without the counterexample term; scenarios + LTL),
//! repeated with the search on the project's data ([`fbsynth::pipeline::table1`]).
//! `synth-dev experiment reconstruction`: the metaheuristic paper's experiment, seeded runs of
//! the search from random machines on every Pick-and-Place scenario, no properties
//! ([`fbsynth::pipeline::search::reconstruct`]).

use crate::cli::args::{Judge, NusmvArgs, Start};
use crate::cli::progress::Progress;
use crate::stats::Stats;
use clap::Args;
use fbsynth::out;
use fbsynth::pipeline::table1::{self, Configuration, Row, Run, Table1};
use fbsynth::pipeline::{search, Event, Recordings};
use fbsynth::pipeline::{Check, Error, Problem};
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct ExperimentArgs {
    /// The experiment: `table1` (the verification-in-the-loop paper, Table I: scenarios only; scenarios + LTL without
    /// F_ce; scenarios + LTL); `reconstruction` (the metaheuristic paper: from random machines,
    /// every scenario of --traces, no properties).
    #[arg(value_parser = ["table1", "reconstruction"])]
    pub name: String,
    /// Runs per configuration (seeds SEED, SEED+1, ...).
    #[arg(long, default_value_t = 10, value_parser = crate::cli::args::repetitions())]
    pub runs: usize,
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads per run (default: all cores).
    #[arg(long, value_parser = crate::cli::args::workers())]
    pub threads: Option<usize>,
    /// Seconds per run; a run without a solution by then counts with this time.
    #[arg(long, default_value_t = 120.0, value_name = "SECONDS")]
    pub time_limit: f64,
    #[arg(long, default_value = "specs/pnp.traces", value_name = "FILE")]
    pub traces: PathBuf,
    /// Use only the first N scenarios (default: 1 for table1, as the verification-in-the-loop
    /// paper, a single piece from track 1; every scenario for reconstruction).
    #[arg(long, value_name = "N")]
    pub scenarios: Option<usize>,
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
    /// States of every candidate (default: 6 for table1; 10 for reconstruction, where the
    /// least, 8, leaves some runs at 4 of the 10 Pick-and-Place scenarios for minutes).
    #[arg(long, value_name = "C", value_parser = crate::cli::args::states())]
    pub states: Option<usize>,
    /// Colonies sharing their best (reconstruction).
    #[arg(long, default_value_t = 4, value_name = "N")]
    pub colonies: usize,
    /// Where the colonies start.
    #[arg(long, value_enum, default_value_t = Start::Random)]
    pub start: Start,
    /// Configurations to run, comma-separated (1, 2, 3).
    #[arg(long, value_delimiter = ',', default_value = "1,2,3")]
    pub configs: Vec<usize>,
    /// Probability of verifying a candidate below the scenario threshold. Default: 0.01 with
    /// --judge in-process, 0.001 with --judge nusmv.
    #[arg(long, value_name = "P", value_parser = crate::cli::args::probability)]
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

/// `synth-dev experiment table1|reconstruction`.
pub fn experiment(args: &ExperimentArgs) -> Result<(), Error> {
    if args.name == "reconstruction" {
        return reconstruction(args);
    }
    let states = args.states.unwrap_or(6);
    let mut configurations = Vec::new();
    for &n in &args.configs {
        configurations.push(Configuration::numbered(n)?);
    }
    let progress = Progress::new(false);
    let mut set = Recordings::files(vec![args.traces.clone()]).load()?;
    set.scenarios.truncate(args.scenarios.unwrap_or(1).max(1));
    let problem = Problem::load(&args.ltl, &args.plant, &set.inputs, &set.outputs)?
        .select(&args.properties)?;
    let check = Check::new(problem, args.nusmv.nusmv()?);
    let threads = search::threads(args.threads);
    let opts = table1::Options {
        runs: args.runs.max(1),
        seed: args.seed,
        search: search::Options {
            threads: Some(threads),
            time_limit: args.time_limit,
            states: Some(states),
            start: args.start.into(),
            verify_probability: args.verify_probability,
            replay_counterexamples: !args.no_replay,
            judge: args.judge.into(),
            every_round: false,
            ..search::Options::default()
        },
    };
    let table = Table1::new(&set, &check, opts, &mut |e| progress.event(e))?;
    let names = table.properties();
    progress.line(&format!(
        "table1: {} scenario(s), {} steps; properties {}; {} states; {} runs per configuration on {} threads, limit {} s per run",
        set.scenarios.len(),
        set.step_count(),
        names.join(", "),
        states,
        args.runs,
        threads,
        args.time_limit
    ));
    let rows = table.run(
        &configurations,
        &mut |c, k, run| progress.line(&run_line(c, k, run)),
        &mut |e| {
            if crate::cli::verbose() && matches!(e, Event::SearchRound(_)) {
                progress.event(e);
            }
        },
    )?;
    print_table(&rows, &names);
    Ok(())
}

/// `synth-dev experiment reconstruction`: `--runs` seeded searches from random machines on the
/// scenarios alone; per run the time, the evaluations and the scenarios reproduced, then the
/// successes and the min / mean / median / max time (a failed run counts with its time).
fn reconstruction(args: &ExperimentArgs) -> Result<(), Error> {
    let progress = Progress::new(false);
    let mut set = Recordings::files(vec![args.traces.clone()]).load()?;
    if let Some(n) = args.scenarios {
        set.scenarios.truncate(n.max(1));
    }
    let threads = search::threads(args.threads);
    let states = args.states.unwrap_or(10);
    progress.line(&format!(
        "reconstruction: {} scenario(s), {} steps; {states} states, {} colonies; {} runs on {threads} threads, limit {} s per run",
        set.scenarios.len(),
        set.step_count(),
        args.colonies,
        args.runs,
        args.time_limit
    ));
    let (mut times, mut solved, mut evaluations) = (Vec::new(), 0, 0u64);
    for k in 0..args.runs.max(1) {
        let seed = args.seed + k as u64;
        let opts = search::Options {
            seed,
            threads: Some(threads),
            time_limit: args.time_limit,
            states: Some(states),
            colonies: args.colonies.max(1),
            ..search::Options::default()
        };
        let out = search::reconstruct(&set, &opts, &mut |e| {
            if crate::cli::verbose() && matches!(e, Event::SearchRound(_)) {
                progress.event(e);
            }
        })?;
        if out.perfect() {
            // The search's own score is not the claim: the scenarios are replayed on the ECC.
            set.check(&out.ecc).map_err(|e| {
                Error::Bug(format!("seed {seed}: the machine does not replay: {e}"))
            })?;
            solved += 1;
        }
        let (r, n) = out.reproduced();
        progress.line(&format!(
            "run {} (seed {seed}): {:.2} s, {}, {r}/{n} scenarios, {} evaluations ({:.0}/s)",
            k + 1,
            out.seconds(),
            if out.perfect() {
                "solved"
            } else {
                "NOT solved in time"
            },
            out.evaluations(),
            out.evaluations() as f64 / out.seconds().max(1e-9)
        ));
        times.push(out.seconds());
        evaluations += out.evaluations();
    }
    let t = Stats::of(&times).expect("at least one run");
    let total: f64 = times.iter().sum();
    out!(
        "reconstruction: {solved}/{} solved; time min / mean / median / max {:.1} / {:.1} / {:.1} / {:.1} s; {:.0} evaluations/s on {threads} threads",
        times.len(),
        t.min,
        t.mean,
        t.median,
        t.max,
        evaluations as f64 / total.max(1e-9)
    );
    Ok(())
}

/// The progress line of run `k` (0-based) of configuration `c`.
fn run_line(c: Configuration, k: usize, run: &Run) -> String {
    format!(
        "config {} run {} (seed {}): {:.2} s, {}, {} evaluations, {} in-process checks, {} NuSMV runs, {} cache hits, {} saved by counterexample replay; {} states reachable; final NuSMV check: {}",
        c.number(),
        k + 1,
        run.seed,
        run.seconds,
        if run.solved { "solved" } else { "NOT solved in time" },
        run.evaluations,
        run.in_process_checks,
        run.nusmv_runs,
        run.cache_hits,
        run.replayed,
        run.states_used,
        if run.all_hold {
            "all properties hold".to_string()
        } else {
            format!("fails {}", run.failing.join(", "))
        }
    )
}

/// The paper's table (seconds min / mean / median / max, solved, all LTL satisfied), then per
/// configuration how many runs satisfy each property.
fn print_table(rows: &[Row], names: &[String]) {
    out!();
    out!(
        "| # | Configuration | min, s | mean, s | median, s | max, s | solved | satisfied all LTL |"
    );
    out!("|---|---|---|---|---|---|---|---|");
    for row in rows {
        let times: Vec<f64> = row.runs.iter().map(|r| r.seconds).collect();
        let t = Stats::of(&times).expect("at least one run");
        let (n, all) = (row.runs.len(), row.all_hold());
        out!(
            "| {} | {} | {:.1} | {:.1} | {:.1} | {:.1} | {}/{n} | {:.0}% ({all}/{n}) |",
            row.configuration.number(),
            row.configuration.label(),
            t.min,
            t.mean,
            t.median,
            t.max,
            row.solved(),
            100.0 * all as f64 / n as f64
        );
    }
    out!();
    for row in rows {
        let n = row.runs.len();
        let per: Vec<String> = (names.iter())
            .map(|p| format!("{p} {}/{n}", row.holds(p)))
            .collect();
        out!("config {}: {}", row.configuration.number(), per.join(", "));
    }
}
