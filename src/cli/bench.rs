//! `synth bench`: measured figures for the README, reproducible with one command.
//!
//! Runs exact synthesis on the project's Pick-and-Place scenarios and, when the fbSAT data
//! folder is present (it is not part of the repository), on fbSAT's published scenario sets,
//! several times each, and prints a Markdown table of wall-clock times and sizes.

use super::infer::{load_scenarios, TraceArgs};
use super::{exit, Failure};
use crate::ecc::AlgorithmKind;
use crate::sat::{self, Options};
use crate::scenario::tree::ScenarioTree;
use clap::Args;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Debug, Args)]
pub struct BenchArgs {
    /// Runs per case; the table shows min / median / max.
    #[arg(long, default_value_t = 5)]
    pub runs: usize,
    /// Folder with fbSAT's scenario sets (tests-N.gz and pnp/input-names, pnp/output-names).
    /// Cases whose files are missing are skipped.
    #[arg(
        long,
        default_value = "../shared/anchors/fbsat/data",
        value_name = "DIR"
    )]
    pub fbsat_data: PathBuf,
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
    traces: TraceArgs,
    opts: Options,
}

fn cases(args: &BenchArgs) -> Vec<Case> {
    let mut out = Vec::new();
    if args.pnp.is_file() {
        out.push(Case {
            name: format!("{} (tri)", args.pnp.display()),
            traces: TraceArgs {
                traces: vec![args.pnp.clone()],
                input_names: None,
                output_names: None,
            },
            opts: Options::default(),
        });
    }
    let names = |f: &str| args.fbsat_data.join("pnp").join(f);
    for n in [1, 10, 39] {
        let file = args.fbsat_data.join(format!("tests-{n}.gz"));
        if !file.is_file() || !names("input-names").is_file() {
            continue;
        }
        let traces = TraceArgs {
            traces: vec![file],
            input_names: Some(names("input-names")),
            output_names: Some(names("output-names")),
        };
        for (label, start_state) in [("binary, fbSAT start state", true), ("binary", false)] {
            out.push(Case {
                name: format!("fbSAT tests-{n} ({label})"),
                traces: traces.clone(),
                opts: Options {
                    algorithms: AlgorithmKind::Binary,
                    start_state,
                    ..Options::default()
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

/// The main job, `runs` times: iterations, time, SAT share, NuSMV time per candidate.
fn bench_cegis(args: &BenchArgs) -> Result<(), Failure> {
    use crate::cegis::{self, Config};
    use crate::nusmv::{locate, Nusmv};
    use crate::verify::Setup;
    let (ltl, plant_file) = (
        Path::new("specs/pnp.ltl"),
        Path::new("smv/pnp_surrogate.smv"),
    );
    if !ltl.is_file() || !plant_file.is_file() || !args.pnp.is_file() {
        return Ok(());
    }
    let nusmv = locate(args.nusmv.as_deref()).map_err(Failure::input)?;
    let set = load_scenarios(&TraceArgs {
        traces: vec![args.pnp.clone()],
        input_names: None,
        output_names: None,
    })?;
    let (props, plant, coupling) =
        super::verified::load_setup(ltl, plant_file, &set.inputs, &set.outputs)?;
    let setup = Setup {
        plant: &plant,
        coupling: &coupling,
        spec_file: ltl,
        props: &props,
    };
    let config = Config {
        sat: Options {
            cube_slots: Some(6),
            ..Options::default()
        },
        max_iterations: 500,
        verbose: false,
    };
    println!();
    println!("| main job run | candidates | C | T | N | total s | SAT s | NuSMV s | NuSMV ms per candidate (median) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for run in 1..=args.cegis_runs {
        let mut session = Nusmv::new(nusmv.clone()).session();
        let work = tempfile::tempdir().map_err(Failure::input)?;
        let tree = ScenarioTree::build(&set).map_err(Failure::input)?;
        let t = Instant::now();
        let v = cegis::run(
            &set,
            &tree,
            &setup,
            &mut session,
            &config,
            work.path(),
            &mut |_| {},
        )
        .map_err(Failure::input)?;
        let total = t.elapsed().as_secs_f64();
        let sat: f64 = v.iterations.iter().map(|i| i.sat_seconds).sum();
        let nus: Vec<f64> = v.iterations.iter().map(|i| i.nusmv_seconds).collect();
        let (_, med, _) = stats(nus.clone());
        let s = v.synthesis.size;
        println!(
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
                "nothing to benchmark: neither {} nor {} exists",
                args.pnp.display(),
                Path::new(&args.fbsat_data).display()
            ),
        ));
    }
    println!("| case | steps | C | K | T | N | min s | median s | max s |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for case in all {
        let set = load_scenarios(&case.traces)?;
        let mut times = Vec::with_capacity(runs);
        let mut size = None;
        for _ in 0..runs {
            let t = Instant::now();
            let tree = ScenarioTree::build(&set).map_err(Failure::input)?;
            let r = sat::synthesize(&set, &tree, &case.opts, &mut |_| {})
                .map_err(|e| Failure::with_code(exit::NO_MACHINE, e))?;
            times.push(t.elapsed().as_secs_f64());
            size = Some(r.size);
        }

        let s = size.expect("runs >= 1");
        let (lo, med, hi) = stats(times);
        println!(
            "| {} | {} | {} | {} | {} | {} | {lo:.3} | {med:.3} | {hi:.3} |",
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
