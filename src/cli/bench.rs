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
    Ok(())
}
