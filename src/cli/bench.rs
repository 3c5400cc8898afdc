//! The benchmark commands: figures for the README, each reproducible with one command.
//!
//! - `synth bench`: exact synthesis on the project's Pick-and-Place scenarios and, when the
//!   fbSAT data folder is present (it is not part of the repository), on fbSAT's published
//!   scenario sets; then the main job (exact synthesis verified by NuSMV);
//! - `synth bench-noisy`: noisy synthesis on generated distribution-station logs;
//! - `synth bench-modular`: modular synthesis for M = 1..4;
//! - `synth bench-search`: the search's scenario-fitness evaluations per second;
//! - `synth bench-long`: exact synthesis on one long generated run (lazy synthesis).

use super::args::{problem, TraceArgs};
use super::progress::Progress;
use super::show::describe_modules;
use super::{exit, Failure};
use crate::cases::distribution;
use clap::Args;
use fbsynth::ecc::AlgorithmKind;
use fbsynth::pipeline::{self, exact, modular, noisy, Check, Recordings};
use fbsynth::search::{self, Evaluator, Machine, ScenarioData};
use rand::SeedableRng;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Runs per case; the table shows min / median / max.
    #[arg(long, default_value_t = 5)]
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
    #[arg(long, default_value_t = 3)]
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

fn stats(mut xs: Vec<f64>) -> (f64, f64, f64) {
    xs.sort_by(|a, b| a.total_cmp(b));
    (xs[0], xs[xs.len() / 2], xs[xs.len() - 1])
}

/// The main job, `runs` times: iterations, time, SAT share, NuSMV time per check.
fn bench_cegis(args: &BenchArgs) -> Result<(), Failure> {
    let (ltl, plant_file) = (
        Path::new("specs/pnp.ltl"),
        Path::new("smv/pnp_surrogate.smv"),
    );
    if !ltl.is_file() || !plant_file.is_file() || !args.pnp.is_file() {
        return Ok(());
    }
    let nusmv = pipeline::nusmv(args.nusmv.as_deref(), 60.0)?;
    let set = Recordings::files(vec![args.pnp.clone()]).load()?;
    let check = Check::new(problem(ltl, plant_file, &set.inputs, &set.outputs)?, nusmv);
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
        let med = match nus.is_empty() {
            true => 0.0,
            false => stats(nus.clone()).1,
        };
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

pub fn bench(args: &BenchArgs) -> Result<(), Failure> {
    let runs = args.runs.max(1);
    let all = cases(args);
    if all.is_empty() {
        return Err(Failure::msg(
            exit::INPUT,
            format!(
                "nothing to benchmark: {} does not exist and no fbSAT data was found{}",
                args.pnp.display(),
                args.fbsat_data
                    .as_ref()
                    .map(|d| format!(" in {}", d.display()))
                    .unwrap_or_default()
            ),
        ));
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
        let (lo, med, hi) = stats(times);
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
pub struct BenchNoisyArgs {
    /// Log lengths in samples, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "1000,10000,100000")]
    pub samples: Vec<usize>,
    /// Probability that an output change is recorded one sample early.
    #[arg(long, default_value_t = 0.02)]
    pub rate: f64,
    /// Seed of the use cases and of the injected errors.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Candidates to enumerate after minimization.
    #[arg(long, default_value_t = 1)]
    pub enumerate: usize,
    /// Bound on corrected errors, as a multiple of the number injected (0: no bound).
    #[arg(long, default_value_t = 1.0)]
    pub error_bound: f64,
    /// Also write each size's logs as `DIR/noisy-<samples>.csv` and `DIR/clean-<samples>.csv`
    /// (the format of `specs/distribution_noisy.csv`), to time `synth infer --noisy` on them.
    #[arg(long, value_name = "DIR")]
    pub save: Option<PathBuf>,
}

/// `synth bench-noisy`: times noisy synthesis on generated distribution-station logs
/// ([`distribution::random_logs`], skew injected per log).
pub fn bench_noisy(args: &BenchNoisyArgs) -> Result<(), Failure> {
    out!(
        "samples  steps    nodes   traces  injected  C  K  T   ε      rounds  encoded  vars      clauses    sizes_s  epsilon_s  total_s  clean  peak_rss"
    );
    for &len in &args.samples {
        let mut injected = 0;
        let clean = distribution::random_logs(len, args.seed);
        let noisy: Vec<_> = clean
            .iter()
            .enumerate()
            .map(|(k, log)| {
                let (n, i) = distribution::inject_skew(log, args.rate, args.seed + k as u64);
                injected += i;
                n
            })
            .collect();
        if let Some(dir) = &args.save {
            save_logs(dir, &format!("noisy-{len}.csv"), &noisy)?;
            save_logs(dir, &format!("clean-{len}.csv"), &clean)?;
        }
        let set = distribution::to_scenarios(&noisy, "<generated>");
        let opts = noisy::Options {
            enumerate: args.enumerate.max(1),
            max_errors: (args.error_bound > 0.0)
                .then(|| (injected as f64 * args.error_bound).ceil() as usize),
            ..noisy::Options::default()
        };
        let t = Instant::now();
        let progress = Progress::new(!super::verbose());
        let r = noisy::run(&set, None, &opts, &mut |e| progress.event(e))
            .map_err(|e| Failure::with_code(exit::BUG, e))?
            .synthesis;
        let total = t.elapsed().as_secs_f64();
        let first = r.candidates.first();
        // The candidate has been replayed on its corrected traces; the logs before the
        // injected errors are the ground truth it should reproduce as well.
        let replays_clean = first.is_some_and(|c| {
            distribution::to_scenarios(&clean, "<clean>")
                .check(&c.ecc)
                .is_ok()
        });
        out!(
            "{:<8} {:<8} {:<7} {:<7} {:<9} {:<2} {:<2} {:<3} {:<6} {:<7} {:<8} {:<9} {:<10} {:<8.2} {:<10.2} {:<8.2} {:<6} {}",
            len,
            set.step_count(),
            r.stats.graph_nodes,
            r.stats.distinct_traces,
            injected,
            r.n,
            r.k,
            r.r,
            first.map_or(0, |c| c.errors),
            r.stats.rounds,
            if r.stats.rounds == 0 { r.stats.graph_nodes } else { r.stats.encoded_nodes },
            r.stats.variables,
            r.stats.clauses,
            r.stats.minimize_seconds,
            r.stats.enumerate_seconds,
            total,
            if replays_clean { "yes" } else { "no" },
            super::ingest::peak_rss()
        );
    }
    Ok(())
}

fn save_logs(
    dir: &Path,
    name: &str,
    logs: &[Vec<fbsynth::scenario::csvlog::Sample>],
) -> Result<(), Failure> {
    std::fs::create_dir_all(dir).map_err(Failure::input)?;
    let mut text = Vec::new();
    distribution::write_csv(logs, &mut text).map_err(Failure::input)?;
    fbsynth::files::write_atomic(&dir.join(name), &text).map_err(Failure::input)
}

#[derive(Debug, Args)]
pub struct BenchLongArgs {
    /// Lengths of the run in steps, comma-separated; one row each, in this order.
    #[arg(long, value_delimiter = ',', default_value = "10000,100000,1000000")]
    pub steps: Vec<usize>,
    /// Seed of the operator's rounds.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Also write each run as a scenario file `DIR/long-<steps>.traces` (names in
    /// `DIR/long.inputs`, `DIR/long.outputs`), to time `synth infer` on it on its own.
    #[arg(long, value_name = "DIR")]
    pub save: Option<PathBuf>,
}

/// `synth bench-long`: exact synthesis (no properties) on one long run of the distribution
/// station ([`distribution::long_run`]); every machine is replayed on the whole run.
pub fn bench_long(args: &BenchLongArgs) -> Result<(), Failure> {
    out!("steps     C  K  T   N   rounds  encoded  generate_s  synth_s  peak_rss");
    for &steps in &args.steps {
        let t = Instant::now();
        let set = distribution::long_run(steps, args.seed);
        let generate = t.elapsed().as_secs_f64();
        if let Some(dir) = &args.save {
            save_run(&set, dir, steps)?;
        }
        let t = Instant::now();
        let progress = Progress::new(!super::verbose());
        let r = exact::run(&set, None, &exact::Options::default(), &mut |e| {
            progress.event(e)
        })
        .map_err(|e| Failure::with_code(exit::BUG, e))?
        .synthesis;
        // The pipeline has replayed the machine on every step of the run.
        let seconds = t.elapsed().as_secs_f64();
        out!(
            "{:<9} {:<2} {:<2} {:<3} {:<3} {:<7} {:<8} {:<11.2} {:<8.2} {}",
            steps,
            r.size.c,
            r.size.k,
            r.size.t,
            r.size.n,
            r.stats.rounds,
            r.stats.steps_encoded,
            generate,
            seconds,
            super::ingest::peak_rss()
        );
    }
    Ok(())
}

fn save_run(set: &fbsynth::scenario::ScenarioSet, dir: &Path, steps: usize) -> Result<(), Failure> {
    use fbsynth::files::write_atomic;
    std::fs::create_dir_all(dir).map_err(Failure::input)?;
    let mut text = Vec::new();
    fbsynth::scenario::fbsat::write(set, &mut text).map_err(Failure::input)?;
    write_atomic(&dir.join(format!("long-{steps}.traces")), &text).map_err(Failure::input)?;
    let names = |n: &[String]| format!("{}\n", n.join("\n"));
    write_atomic(&dir.join("long.inputs"), names(&set.inputs).as_bytes())
        .map_err(Failure::input)?;
    write_atomic(&dir.join("long.outputs"), names(&set.outputs).as_bytes())
        .map_err(Failure::input)?;
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
    #[arg(long, default_value_t = modular::DEFAULT_SLOTS, value_name = "K")]
    pub slots: usize,
    /// Runs per M; the table shows min / median / max.
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
}

/// `synth bench-modular`: modular synthesis for M = 1..=max, as a Markdown table.
pub fn bench_modular(args: &BenchModularArgs) -> Result<(), Failure> {
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
            slots: args.slots,
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
        times.sort_by(f64::total_cmp);
        let r = last.expect("at least one run");
        let t: usize = r.size.modules.iter().map(|s| s.t).sum();
        out!(
            "| {modules} | {} | {} | {} | {t} | {} | {} | {} | {} | {:.2} / {:.2} / {:.2} |",
            r.size.max_states,
            r.size.inputs_used,
            r.size.total_states,
            r.stats.slots,
            r.stats.variables,
            r.stats.clauses,
            r.stats.solver_calls,
            times[0],
            times[times.len() / 2],
            times[times.len() - 1]
        );
        for line in describe_modules(&r.modular) {
            eprintln!("    M={modules} {line}");
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
    let set = Recordings::files(vec![args.traces.clone()]).load()?;
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
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
}

/// The shipped cases' recordings the ambiguity benchmark reads.
const AMBIGUITY_CASES: [&str; 4] = [
    "specs/pnp.traces",
    "specs/distribution.csv",
    "specs/tank1.traces",
    "specs/tank2.traces",
];

/// `synth bench-ambiguity`: the time of the ambiguity check (one rival, default depth) after
/// `synth infer`'s machine, on each shipped case.
pub fn bench_ambiguity(args: &BenchAmbiguityArgs) -> Result<(), Failure> {
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
        let (lo, med, hi) = stats(times);
        out!(
            "| {file} | {} | {:?} | {lo:.3} | {med:.3} | {hi:.3} |",
            machine.states.len(),
            verdict.expect("runs >= 1")
        );
    }
    Ok(())
}
