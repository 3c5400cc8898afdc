//! `synth learn-plant` (a surrogate plant learned from the recordings) and `synth
//! compare-plants` (two plants compared on random closed-loop runs of a machine).

use super::args::TraceArgs;
use crate::command::learn_plant::{compare, run, Options};
use crate::pipeline::Error;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `synth learn-plant`.
#[derive(Debug, Args)]
pub struct LearnPlantArgs {
    #[command(flatten)]
    pub traces: TraceArgs,
    #[command(flatten)]
    pub learning: LearningArgs,
    /// The plant file to write (`MODULE plant(<controller outputs>)`).
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
}

/// How a plant is learned: the options `synth learn-plant` and the main job's
/// `--learn-plant` share.
#[derive(Debug, Args, Clone)]
pub struct LearningArgs {
    /// SMV declarations (VAR, DEFINE, ASSIGN) added to the learned module: the names the
    /// properties use that no recording shows (an overflow, a "piece placed" event), over the
    /// sensors and controller outputs.
    #[arg(long, value_name = "FILE")]
    pub observe: Option<PathBuf>,
    /// Scans a sensor change a command drives may come later than recorded (the model's scan
    /// need not be the recording PLC's); from 1 on, a change the environment makes when a
    /// sensor has a value may also come in the scan that sensor takes it, and comes by the
    /// next scan where its sensors held a scan apart (the cup gripped as it left).
    #[arg(long, default_value_t = 0, value_name = "N")]
    pub slack: usize,
    /// What is known of the plant beyond the recordings, as named LTL properties over the
    /// sensors (the format of --ltl): the recordings are checked against them (one that breaks
    /// an assumption is named with its step) and the plant's header lists them; the learned
    /// model does not enforce them.
    #[arg(long, value_name = "FILE")]
    pub assume: Option<PathBuf>,
}

impl LearningArgs {
    /// The learner's options.
    pub fn options(&self) -> Options {
        Options {
            observe: self.observe.clone(),
            slack: self.slack,
            assume: self.assume.clone(),
        }
    }
}

/// Arguments of `synth compare-plants`.
#[derive(Debug, Args)]
pub struct ComparePlantsArgs {
    /// The machine both closed loops run, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    /// The two plants.
    #[arg(long, value_name = "FILE", num_args = 2, required = true)]
    pub plants: Vec<PathBuf>,
    /// Random runs per direction.
    #[arg(long, default_value_t = 1000)]
    pub runs: usize,
    /// Scans per run.
    #[arg(long, default_value_t = 50)]
    pub scans: usize,
    /// Seed of the random choices.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// `synth learn-plant`.
pub fn learn_plant(args: &LearnPlantArgs) -> Result<(), Error> {
    let written = run(
        &args.traces.recordings(),
        &args.learning.options(),
        &args.out,
    )?;
    for line in written.lines() {
        out!("{line}");
    }
    Ok(())
}

/// `synth compare-plants`.
pub fn compare_plants(args: &ComparePlantsArgs) -> Result<(), Error> {
    let plants = [args.plants[0].as_path(), args.plants[1].as_path()];
    let compared = compare(&args.ecc, plants, args.runs, args.scans, args.seed)?;
    for line in compared.lines() {
        out!("{line}");
    }
    Ok(())
}
