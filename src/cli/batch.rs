//! `synth batch`: one reconstruction per PLC over a folder of logs, and one summary table.

use super::args::{out_dir, parse_formats, AlgorithmsArg, NusmvArgs};
use super::progress::Progress;
use super::show::print_written;
use super::Failure;
use crate::files::ResultSet;
use crate::ingest::Mapping;
use crate::pipeline::batch::{self, Outcome, Row, VerificationSetup};
use crate::pipeline::{self, exact};
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
pub fn batch(args: &BatchArgs) -> Result<(), Failure> {
    if super::json() {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    let mapping = match &args.map {
        Some(m) => Some(Mapping::read(m).map_err(Failure::input)?),
        None => None,
    };
    let plcs = batch::plcs(&args.logs)?;
    let formats = parse_formats(&args.format)?;
    let limit = pipeline::seconds("--time-limit", args.time_limit, true)?;
    let verification = match (&args.ltl, &args.plant) {
        (Some(ltl), Some(plant)) => Some(VerificationSetup {
            ltl: ltl.clone(),
            plant: plant.clone(),
            nusmv: args.nusmv.nusmv()?,
        }),
        _ => None,
    };
    let stem = crate::pipeline::recordings::stem(&args.logs);
    let out = out_dir(&args.out, &stem);
    let results = ResultSet::open(&out).map_err(Failure::input)?;
    let threads = args.threads.unwrap_or_else(rayon::current_num_threads);
    progress.line(&format!(
        "{} PLCs in {}, {} at a time{}",
        plcs.len(),
        args.logs.display(),
        threads.min(plcs.len()),
        if verification.is_some() {
            ", each verified by NuSMV"
        } else {
            ""
        }
    ));
    let opts = exact::Options {
        sat: exact::SatOptions {
            algorithms: args.algorithms.into(),
            max_states: args.max_states,
            ..exact::SatOptions::default()
        },
        ..exact::Options::default()
    };
    let outcomes = batch::run(
        &plcs,
        mapping.as_ref(),
        verification.as_ref(),
        &opts,
        limit,
        threads,
        &|o: &Outcome| progress.line(&outcome_line(o)),
    )?;
    let summary = batch::write_results(
        results.staging(),
        &args.logs,
        &outcomes,
        &args.name,
        &formats,
        verification.as_ref(),
    )?;
    let files: Vec<PathBuf> = summary.files.iter().map(|f| results.published(f)).collect();
    results
        .publish()
        .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
    print_table(&summary.rows);
    print_written(&files);
    if super::json() {
        super::write_json(&summary.to_json())?;
    }
    match summary.failure() {
        Some(e) => Err(e.into()),
        None => Ok(()),
    }
}

/// The progress line of one PLC done.
fn outcome_line(o: &Outcome) -> String {
    match &o.result {
        Ok(r) => format!(
            "{}: {}{} ({:.2} s)",
            o.plc.name,
            r.synthesis.size,
            if r.certificate.is_some() {
                ", verified"
            } else {
                ""
            },
            o.seconds
        ),
        Err(e) => format!("{}: failed: {e}", o.plc.name),
    }
}

/// The summary as a Markdown table on stdout.
fn print_table(rows: &[Row]) {
    out!("| PLC | status | scenarios | steps | C | K | T | N | seconds |");
    out!("|---|---|---|---|---|---|---|---|---|");
    for r in rows {
        let cell = |v: Option<usize>| v.map_or("-".to_string(), |v| v.to_string());
        out!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
            r.plc,
            r.status,
            r.scenarios,
            r.steps,
            cell(r.c),
            cell(r.k),
            cell(r.t),
            cell(r.n),
            r.seconds
        );
    }
}
