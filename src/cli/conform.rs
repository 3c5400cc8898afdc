//! `synth conform`: replay new recordings on a machine in service, report every trace's first
//! divergence, and with `--refine` learn the divergent traces and synthesize again (verified
//! again with `--ltl`/`--plant`).

use super::args::{NusmvArgs, TraceArgs};
use super::progress::Progress;
use crate::command::conform::{conformance, refine, Request};
use crate::pipeline::recordings::machine_and_scenarios;
use crate::pipeline::{Error, Recordings};
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

/// `synth conform`.
pub fn conform(args: &ConformArgs) -> Result<(), Error> {
    let (ecc, set) = machine_and_scenarios(&args.ecc, &args.traces.recordings())?;
    let found = conformance(&ecc, &set);
    out!("{found}");
    if found.divergent == 0 {
        return Ok(());
    }
    if !args.refine {
        return Err(found.failure());
    }
    let request = Request {
        training: Recordings {
            traces: args.train.clone(),
            ..args.traces.recordings()
        },
        spec: args.nusmv.spec(&args.ltl, &args.plant),
        out: args.out.clone(),
        reads: [args.ecc.clone()]
            .into_iter()
            .chain(args.traces.recordings().paths())
            .collect(),
    };
    let progress = Progress::new(false);
    let done = refine(&request, &ecc, &set, &mut |e| progress.event(e))?;
    out!("{done}");
    super::show::print_written(&done.files);
    out!("after refinement, on the new recordings:");
    out!("{}", conformance(done.refined.ecc(), &set));
    Ok(())
}
