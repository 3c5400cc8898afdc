//! `synth infer --modules M` (modular synthesis) and `synth bench-modular`.
//!
//! In: scenarios, `M`, pins. Out: the decomposition and sizes on stdout, and the composite's
//! files ([`crate::export::modular::write_modular`]) in the output folder.

use super::infer::{load_scenarios, out_dir, print_written, report_loaded, InferArgs, TraceArgs};
use super::{exit, Failure, Progress};
use crate::ecc::modular::{Modular, Module};
use crate::ecc::{Algorithm, AlgorithmKind, Ecc, InputId, OutputId, State};
use crate::export::modular::{check_fbt_names, check_smv_names, write_modular};
use crate::sat::modular::{parse_pins, synthesize_modular, ModularError, ModularOptions};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use clap::Args;
use std::path::Path;
use std::time::Instant;

/// Checks before any search that the block name and the interface can be exported: a probe
/// composite with `modules` modules must pass the name checks of the `.fbt` and SMV files.
fn check_exportable(set: &ScenarioSet, name: &str, modules: usize) -> Result<(), Failure> {
    let probe_module = |owns: bool| {
        let outputs: Vec<OutputId> = if owns {
            (0..set.outputs.len()).map(OutputId).collect()
        } else {
            Vec::new()
        };
        Module {
            inputs: (0..set.inputs.len()).map(InputId).collect(),
            ecc: Ecc {
                inputs: set.inputs.clone(),
                outputs: outputs.iter().map(|z| set.outputs[z.0].clone()).collect(),
                initial_outputs: outputs.iter().map(|z| set.initial_outputs[z.0]).collect(),
                states: vec![State {
                    name: "s0".into(),
                    algorithm: Algorithm::keep_all(AlgorithmKind::Tri, outputs.len()),
                    transitions: Vec::new(),
                }],
            },
            outputs,
        }
    };
    let probe = Modular {
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        modules: (0..modules.max(1)).map(|m| probe_module(m == 0)).collect(),
    };
    check_fbt_names(&probe, name).map_err(Failure::input)?;
    check_smv_names(&probe, name).map_err(Failure::input)
}

fn options(args: &InferArgs, set: &ScenarioSet, modules: usize) -> Result<ModularOptions, Failure> {
    Ok(ModularOptions {
        modules,
        slots: args.slots,
        max_states: args.max_states,
        algorithms: match args.algorithms {
            super::infer::AlgorithmsArg::Tri => AlgorithmKind::Tri,
            super::infer::AlgorithmsArg::Binary => AlgorithmKind::Binary,
        },
        pins: parse_pins(&args.pin, &set.outputs, modules)
            .map_err(|e| Failure::with_code(exit::USAGE, e))?,
    })
}

fn failure(e: ModularError) -> Failure {
    match e {
        ModularError::NoController { .. } => Failure::with_code(exit::NO_MACHINE, e),
        ModularError::NoModules => Failure::with_code(exit::USAGE, e),
        ModularError::Bug(_) => Failure::with_code(exit::BUG, e),
    }
}

/// One line per module: its outputs, inputs and size.
pub fn describe(modular: &Modular) -> Vec<String> {
    modular
        .modules
        .iter()
        .enumerate()
        .map(|(m, module)| {
            let s = module.ecc.size();
            let list = |v: &[String]| {
                if v.is_empty() {
                    "-".to_string()
                } else {
                    v.join(", ")
                }
            };
            format!(
                "module {}: {} states, {} transitions, {} guard literals; outputs: {}; inputs: {}",
                m + 1,
                s.c,
                s.t,
                s.n,
                list(&module.ecc.outputs),
                list(&module.ecc.inputs)
            )
        })
        .collect()
}

/// `synth infer --modules M`: modular synthesis, summary and files.
pub fn infer_modular(args: &InferArgs, modules: usize) -> Result<(), Failure> {
    let progress = Progress::new(args.quiet);
    let set = load_scenarios(&args.traces)?;
    report_loaded(&progress, &set);
    let out = out_dir(args)?;
    distribute(args, modules, &set, &out, &progress)
}

/// Modular synthesis of `set` into `out` (also the second stage of `--noisy --modules`,
/// on the corrected traces).
pub fn distribute(
    args: &InferArgs,
    modules: usize,
    set: &ScenarioSet,
    out: &Path,
    progress: &Progress,
) -> Result<(), Failure> {
    let opts = options(args, set, modules)?;
    check_exportable(set, &args.name, modules)?;
    let tree = ScenarioTree::build(set).map_err(Failure::input)?;
    let result =
        synthesize_modular(set, &tree, &opts, &mut |m| progress.line(m)).map_err(failure)?;
    let s = &result.size;
    println!(
        "modules = {}  largest module = {} states  A = {} inputs used  N' = {} states in all",
        modules, s.max_states, s.inputs_used, s.total_states
    );
    for line in describe(&result.modular) {
        println!("  {line}");
    }
    println!(
        "time {:.2} s (SAT {:.2} s); replayed {} scenarios on the composite: all reproduced",
        progress.elapsed(),
        result.stats.sat_seconds,
        set.scenarios.len()
    );
    let files = write_modular(&result.modular, out, &args.name).map_err(Failure::input)?;
    print_written(&files);
    Ok(())
}

#[derive(Debug, Args)]
pub struct BenchModularArgs {
    #[command(flatten)]
    pub traces: TraceArgs,
    /// Largest number of modules; the table has one row per M = 1..=this.
    #[arg(long, default_value_t = 4, value_name = "M")]
    pub max_modules: usize,
    /// Transition slots per state.
    #[arg(long, default_value_t = 3, value_name = "K")]
    pub slots: usize,
    /// Runs per M; the table shows min / median / max.
    #[arg(long, default_value_t = 3)]
    pub runs: usize,
}

/// `synth bench-modular`: modular synthesis for M = 1..=max, as a Markdown table.
pub fn bench_modular(args: &BenchModularArgs) -> Result<(), Failure> {
    let set = load_scenarios(&args.traces)?;
    let tree = ScenarioTree::build(&set).map_err(Failure::input)?;
    println!(
        "{}: {} scenarios, {} steps, {} tree nodes, {} inputs, {} outputs; K = {} slots, {} runs",
        super::show(&args.traces.traces),
        set.scenarios.len(),
        set.step_count(),
        tree.nodes.len(),
        set.inputs.len(),
        set.outputs.len(),
        args.slots,
        args.runs.max(1)
    );
    println!();
    println!("| M | largest | A | N' | transitions | variables | clauses | solver calls | time min / median / max (s) |");
    println!("|---|---|---|---|---|---|---|---|---|");
    for modules in 1..=args.max_modules {
        let opts = ModularOptions {
            modules,
            slots: args.slots,
            ..ModularOptions::default()
        };
        let mut times = Vec::new();
        let mut last = None;
        for _ in 0..args.runs.max(1) {
            let t0 = Instant::now();
            let r = synthesize_modular(&set, &tree, &opts, &mut |_| {}).map_err(failure)?;
            times.push(t0.elapsed().as_secs_f64());
            last = Some(r);
        }
        times.sort_by(f64::total_cmp);
        let r = last.expect("at least one run");
        let t: usize = r.size.modules.iter().map(|s| s.t).sum();
        println!(
            "| {modules} | {} | {} | {} | {t} | {} | {} | {} | {:.2} / {:.2} / {:.2} |",
            r.size.max_states,
            r.size.inputs_used,
            r.size.total_states,
            r.stats.variables,
            r.stats.clauses,
            r.stats.solver_calls,
            times[0],
            times[times.len() / 2],
            times[times.len() - 1]
        );
        for line in describe(&r.modular) {
            eprintln!("    M={modules} {line}");
        }
    }
    Ok(())
}
