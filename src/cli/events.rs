//! `synth events`: a raw PLC I/O log into an event log (XES and CSV) for process-mining tools.

use super::Failure;
use crate::events::{self, ResetActivity};
use crate::ingest::Mapping;
use clap::Args;
use std::path::PathBuf;

#[derive(Debug, Args)]
pub struct EventsArgs {
    /// Data-flow log: long (`timestamp,address,value`) or wide (`timestamp,<signal>,...`)
    /// CSV, plain or gzip. Timestamps are seconds.
    #[arg(long, value_name = "FILE")]
    pub log: PathBuf,
    /// Mapping file: one `ADDRESS in|out NAME` per line.
    #[arg(long, value_name = "FILE")]
    pub map: PathBuf,
    /// The activity that starts a new trace, e.g. "%IX0.1 false" (an address or mapping
    /// name, then true/false; several changes of one class joined by '+').
    #[arg(long, value_name = "ACTIVITY")]
    pub reset: String,
    /// XES file to write.
    #[arg(long, value_name = "FILE")]
    pub out: PathBuf,
    /// CSV file to write (default: the XES path with the extension .csv).
    #[arg(long, value_name = "FILE")]
    pub csv: Option<PathBuf>,
    /// Skip bad rows and count them, instead of stopping at the first.
    #[arg(long)]
    pub lenient: bool,
}

pub fn events(args: &EventsArgs) -> Result<(), Failure> {
    let mapping = Mapping::read(&args.map).map_err(Failure::input)?;
    let reset = ResetActivity::parse(&args.reset, &mapping).map_err(Failure::input)?;
    let csv = args
        .csv
        .clone()
        .unwrap_or_else(|| args.out.with_extension("csv"));
    if csv == args.out {
        return Err(Failure::msg(
            super::exit::INPUT,
            format!(
                "the CSV and XES outputs are both {}; give --csv another path",
                csv.display()
            ),
        ));
    }
    let s = events::write_event_logs(&args.log, &mapping, &reset, args.lenient, &args.out, &csv)
        .map_err(Failure::input)?;
    println!(
        "rows {}, samples {}, skipped {}; {} events in {} traces ({} resets at '{}')",
        s.rows, s.samples, s.skipped, s.events, s.traces, s.resets, reset
    );
    if s.resets == 0 && s.events > 0 {
        eprintln!("note: the reset activity '{reset}' never occurs: the log is one trace");
    }
    println!("wrote {}, {}", args.out.display(), csv.display());
    Ok(())
}

/// `synth generate tank`: the tank case's scenario files and raw logs.
pub fn generate_tank(out: &std::path::Path) -> Result<(), Failure> {
    let files = crate::cases::tank::write_files(out).map_err(Failure::input)?;
    println!("recorded seed 002's tank scenarios and held-out runs from the reference programs:");
    for f in files {
        println!("  {}", f.display());
    }
    Ok(())
}
