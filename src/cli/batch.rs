//! `synth batch`: one reconstruction per PLC over a folder of logs, and one summary table.

use super::args::{parse_formats, AlgorithmsArg, NusmvArgs};
use super::progress::Progress;
use super::show::print_written;
use crate::command::batch::{run, Request};
use crate::pipeline::{self, exact, Error};
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct BatchArgs {
    /// Folder of logs: each log file (CSV or Parquet recordings, or raw logs with --map) and
    /// each subfolder of them (a partition such as `plc=3/`) is one PLC.
    #[arg(long, value_name = "DIR")]
    pub logs: PathBuf,
    /// Address mapping (`ADDRESS in|out NAME` per line): the logs are raw data-flow logs, as
    /// `synth ingest` reads them (long or wide CSV, plain or gzip), each file one scenario.
    #[arg(long, value_name = "FILE")]
    pub map: Option<PathBuf>,
    /// LTL properties every machine must satisfy in closed loop with --plant (NuSMV checks
    /// each; the interface of each PLC's logs gives its closed loop).
    #[arg(long, value_name = "FILE", requires = "plant")]
    pub ltl: Option<PathBuf>,
    /// Surrogate plant for --ltl (SMV).
    #[arg(long, value_name = "FILE", requires = "ltl")]
    pub plant: Option<PathBuf>,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
    /// Output folder: one folder per PLC, `summary.csv` and `summary.json`. Default:
    /// `out/<name of the --logs folder>`.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Formats to write for every machine, comma-separated: json, fbt, smv, dot, st, pnml, plcopen
    /// (PLCopen TC6 XML, written as .xml).
    #[arg(long, value_delimiter = ',', default_value = "json,fbt,smv,dot,st")]
    pub format: Vec<String>,
    /// Name of the function block type in the exports.
    #[arg(long, default_value = "SynthesizedFB", value_parser = super::args::block_name)]
    pub name: String,
    /// Form of the state output algorithms.
    #[arg(long, value_enum, default_value_t = AlgorithmsArg::Tri)]
    pub algorithms: AlgorithmsArg,
    /// Give up on a PLC when more states than this would be needed.
    #[arg(long, default_value_t = 32, value_name = "C", value_parser = super::args::states())]
    pub max_states: usize,
    /// PLCs reconstructed at once (default: all cores).
    #[arg(long, value_parser = clap::builder::RangedU64ValueParser::<usize>::new().range(1..=1024))]
    pub threads: Option<usize>,
    /// Seconds each PLC may take (its row then says so; the others go on).
    #[arg(long, default_value_t = 600.0, value_name = "SECONDS")]
    pub time_limit: f64,
}

/// `synth batch --logs DIR [--map M] [--ltl F --plant P]`.
pub fn batch(args: &BatchArgs) -> Result<(), Error> {
    if super::json() {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    let mut exact = exact::Options::default();
    exact.sat.algorithms = args.algorithms.into();
    exact.sat.max_states = args.max_states;
    let request = Request {
        logs: args.logs.clone(),
        map: args.map.clone(),
        formats: parse_formats(&args.format)?,
        limit: pipeline::seconds("--time-limit", args.time_limit, true)?,
        spec: args.nusmv.spec(&args.ltl, &args.plant),
        out: args.out.clone(),
        name: args.name.clone(),
        exact,
        threads: args.threads,
    };
    let done = run(&request, &mut |e| progress.event(e), &|o| {
        progress.line(&o.to_string())
    })?;
    out!("{done}");
    print_written(&done.files);
    if super::json() {
        super::write_json(&done.summary())?;
    }
    done.failure().map_or(Ok(()), Err)
}
