//! `synth verify`: a machine checked by NuSMV in closed loop with the plant; the verdicts, and
//! for every violated property its counterexample as a table and, with `--out`, a waveform.

use super::args::NusmvArgs;
use crate::command::{verify::run, Spec};
use crate::pipeline::Error;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `synth verify`.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// The machine to check, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    /// LTL properties.
    #[arg(long, value_name = "FILE")]
    pub ltl: PathBuf,
    /// Surrogate plant model.
    #[arg(long, value_name = "FILE")]
    pub plant: PathBuf,
    /// Folder to keep the closed-loop model NuSMV checked and, for every violated property,
    /// its counterexample as a waveform (`<property>.vcd` for GTKWave, `<property>.svg`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
}

/// `synth verify`.
pub fn verify(args: &VerifyArgs) -> Result<(), Error> {
    if super::json() {
        super::data_on_stdout();
    }
    let spec = Spec {
        ltl: args.ltl.clone(),
        plant: args.plant.clone(),
        nusmv: args.nusmv.tool(),
        couple: args.nusmv.couples(),
        learned: None,
    };
    let checked = run(&args.ecc, &spec, args.out.as_deref())?;
    if super::json() {
        super::write_json(&checked.summary())?;
    }
    out_raw!("{checked}");
    if args.out.is_some() {
        out!("");
        super::show::print_written(&checked.files);
    }
    out!("{}", checked.verdict()?);
    Ok(())
}
