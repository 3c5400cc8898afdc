//! `synth conform`: replay new recordings on a machine in service, report every trace's first
//! divergence, and with `--refine` learn the divergent traces and synthesize again (verified
//! again with `--ltl`/`--plant`).

use super::args::{optional_check, parse_formats, NusmvArgs, TraceArgs};
use super::progress::Progress;
use super::{exit, Failure};
use crate::ecc::Ecc;
use crate::pipeline::recordings::machine_and_scenarios;
use crate::pipeline::{exact, refine, Recordings};
use crate::scenario::ScenarioSet;
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

/// Prints the conformance report; returns the number of divergent scenarios.
fn report(ecc: &Ecc, set: &ScenarioSet) -> usize {
    let divergences = set.divergences(ecc);
    let mut agreeing_steps = 0;
    for (k, sc) in set.scenarios.iter().enumerate() {
        match divergences.iter().find(|d| d.scenario == k) {
            None => {
                agreeing_steps += sc.steps.len();
                out!("{}: agrees on all {} steps", sc.origin, sc.steps.len());
            }
            Some(d) => {
                agreeing_steps += d.step;
                out!("{}: DIVERGES: {}", sc.origin, d.describe_step());
            }
        }
    }
    let steps = set.step_count().max(1);
    out!(
        "agreement: {} of {} traces reproduced; {} of {} steps before the first divergence ({:.1}%)",
        set.scenarios.len() - divergences.len(),
        set.scenarios.len(),
        agreeing_steps,
        set.step_count(),
        100.0 * agreeing_steps as f64 / steps as f64
    );
    divergences.len()
}

/// `synth conform`.
pub fn conform(args: &ConformArgs) -> Result<(), Failure> {
    let (ecc, set) = machine_and_scenarios(&args.ecc, &args.traces.recordings())?;
    let divergent = report(&ecc, &set);
    if divergent == 0 {
        return Ok(());
    }
    if !args.refine {
        return Err(Failure::msg(
            exit::FAILED,
            format!(
                "{} of {} traces diverge (use --refine --train FILE... to learn them)",
                divergent,
                set.scenarios.len()
            ),
        ));
    }
    let training = Recordings {
        traces: args.train.clone(),
        input_names: args.traces.input_names.clone(),
        output_names: args.traces.output_names.clone(),
    }
    .load()?;
    let check = optional_check(&args.ltl, &args.plant, &set, &args.nusmv)?;
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("out/refined"));
    let formats = parse_formats(&["json", "fbt", "smv", "dot", "st"].map(String::from))?;
    let progress = Progress::new(false);
    // One result in the folder, published whole at the end, as `infer` does.
    let results = crate::files::ResultSet::open(&out).map_err(Failure::input)?;
    let opts = refine::Options {
        out: results.staging(),
        formats: &formats,
        name: "SynthesizedFB",
        exact: exact::Options {
            // The model NuSMV failed on is kept for the user, beside the results.
            keep_failed_model: check.is_some().then(|| out.join("closed_loop.last.smv")),
            ..exact::Options::default()
        },
    };
    let refined = refine::run(&ecc, &set, training, check.as_ref(), &opts, &mut |e| {
        progress.event(e)
    })?
    .expect("a divergent trace was found above");
    out!(
        "refining: {} training scenarios + {} divergent traces -> {}",
        refined.training_scenarios,
        refined.divergent.len(),
        results.published(&refined.traces_file).display()
    );
    let s = refined.exact.synthesis.size;
    if let Some(cert) = &refined.exact.certificate {
        out!(
            "verified: all {} properties hold (NuSMV)",
            cert.report.properties.len()
        );
        for w in cert.report.warning_lines() {
            out!("{w}");
        }
    }
    out!("{s:#}");
    let files: Vec<PathBuf> = refined.files.iter().map(|f| results.published(f)).collect();
    results
        .publish()
        .map_err(|e| Failure::input(crate::pipeline::Error::from(e)))?;
    super::show::print_written(&files);
    out!("after refinement, on the new recordings:");
    report(refined.ecc(), &set);
    Ok(())
}
