//! `synth conform`: seed 000's proposed loop. Replay new recordings on a synthesized machine,
//! report every trace's first divergence, and with `--refine` add the divergent traces to the
//! training scenarios and synthesize again (verified again with `--ltl`/`--plant`).

use super::infer::{self, load_scenarios, AlgorithmsArg, InferArgs, TraceArgs};
use super::verified::{self, MainArgs, NusmvArgs};
use super::{exit, Failure};
use crate::ecc::Ecc;
use crate::scenario::{fbsat, ScenarioSet};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct ConformArgs {
    /// The machine in service, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    /// New recordings (`--log` and `--traces` are the same option).
    #[command(flatten)]
    pub traces: TraceArgs,
    /// Add the divergent traces to the training scenarios (`--train`) and synthesize again.
    #[arg(long, requires = "train")]
    pub refine: bool,
    /// The scenarios the machine was synthesized from (for --refine).
    #[arg(long, value_name = "FILE", num_args = 1..)]
    pub train: Vec<PathBuf>,
    /// With --refine: LTL properties to verify the refined machine against (needs --plant).
    #[arg(long, value_name = "FILE", requires = "plant")]
    pub ltl: Option<PathBuf>,
    /// With --refine: the surrogate plant model (needs --ltl).
    #[arg(long, value_name = "FILE", requires = "ltl")]
    pub plant: Option<PathBuf>,
    /// With --refine: output folder. Default: `out/refined`.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
}

/// Prints the conformance report; returns the indices of the divergent scenarios.
fn report(ecc: &Ecc, set: &ScenarioSet) -> Vec<usize> {
    let divergences = set.divergences(ecc);
    let mut agreeing_steps = 0;
    for (k, sc) in set.scenarios.iter().enumerate() {
        match divergences.iter().find(|d| d.scenario == k) {
            None => {
                agreeing_steps += sc.steps.len();
                println!("{}: agrees on all {} steps", sc.origin, sc.steps.len());
            }
            Some(d) => {
                agreeing_steps += d.step;
                println!("{}: DIVERGES: {}", sc.origin, d.describe_step());
            }
        }
    }
    let steps = set.step_count().max(1);
    println!(
        "agreement: {} of {} traces reproduced; {} of {} steps before the first divergence ({:.1}%)",
        set.scenarios.len() - divergences.len(),
        set.scenarios.len(),
        agreeing_steps,
        set.step_count(),
        100.0 * agreeing_steps as f64 / steps as f64
    );
    divergences.iter().map(|d| d.scenario).collect()
}

pub fn conform(args: &ConformArgs) -> Result<(), Failure> {
    let (ecc, set) = infer::machine_and_scenarios(&args.ecc, &args.traces)?;
    let divergent = report(&ecc, &set);
    if divergent.is_empty() {
        return Ok(());
    }
    if !args.refine {
        return Err(Failure::msg(
            exit::INPUT,
            format!(
                "{} of {} traces diverge (use --refine --train FILE... to learn them)",
                divergent.len(),
                set.scenarios.len()
            ),
        ));
    }

    // Training scenarios + the divergent new ones, written where the user can see them.
    let mut training = load_scenarios(&TraceArgs {
        traces: args.train.clone(),
        input_names: args.traces.input_names.clone(),
        output_names: args.traces.output_names.clone(),
    })?;
    let mut new = set.clone();
    new.scenarios = divergent
        .iter()
        .map(|&k| set.scenarios[k].clone())
        .collect();
    training.merge(new).map_err(Failure::input)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/refined"));
    let traces = out.join("refined.traces");
    let mut text = Vec::new();
    fbsat::write(&training, &mut text).map_err(Failure::input)?;
    crate::files::write_atomic(&traces, &text).map_err(Failure::input)?;
    for (file, names) in [
        ("refined.inputs", &training.inputs),
        ("refined.outputs", &training.outputs),
    ] {
        crate::files::write_atomic(&out.join(file), (names.join("\n") + "\n").as_bytes())
            .map_err(Failure::input)?;
    }
    println!(
        "refining: {} training scenarios + {} divergent traces -> {}",
        training.scenarios.len() - divergent.len(),
        divergent.len(),
        traces.display()
    );
    let algorithms = match ecc.algorithm_kind() {
        crate::ecc::AlgorithmKind::Tri => AlgorithmsArg::Tri,
        crate::ecc::AlgorithmKind::Binary => AlgorithmsArg::Binary,
    };
    let trace_args = TraceArgs {
        traces: vec![traces],
        input_names: None,
        output_names: None,
    };
    let formats: Vec<String> = ["json", "fbt", "smv", "dot", "st"]
        .iter()
        .map(|f| f.to_string())
        .collect();
    match (&args.ltl, &args.plant) {
        (Some(ltl), Some(plant)) => verified::main_job(&MainArgs {
            ltl: Some(ltl.clone()),
            plant: Some(plant.clone()),
            traces: trace_args.traces,
            input_names: None,
            output_names: None,
            out: Some(out.clone()),
            algorithms,
            max_states: 32,
            max_out_degree: 6,
            max_iterations: 500,
            format: formats,
            name: "SynthesizedFB".into(),
            nusmv: args.nusmv.clone(),
            quiet: false,
            verbose: false,
            method: verified::Method::Sat,
            search: Default::default(),
        })?,
        _ => infer::infer(&InferArgs {
            traces: trace_args,
            algorithms,
            minimize_k: false,
            start_state: false,
            max_states: 32,
            guard_budget: 10.0,
            out: Some(out.clone()),
            format: formats,
            name: "SynthesizedFB".into(),
            quiet: false,
            modules: None,
            pin: Vec::new(),
            slots: 3,
            noisy: super::noisy::NoisyArgs::off(),
        })?,
    }
    let refined = infer::read_ecc(&out.join("SynthesizedFB.json"))?;
    println!("after refinement, on the new recordings:");
    let left = report(&refined, &set);
    if left.is_empty() {
        Ok(())
    } else {
        // The refined machine was synthesized from these very traces: a divergence is a bug.
        Err(Failure::msg(
            exit::BUG,
            format!(
                "the refined machine still diverges on trace {}",
                set.scenarios[left[0]].origin
            ),
        ))
    }
}
