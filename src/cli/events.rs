//! `synth events`: a raw PLC I/O log into an event log (XES and CSV) for process-mining tools.

use crate::command::events::{run, Request};
use crate::export::pnml::Dialect;
use crate::pipeline::Error;
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
    /// A synthesized machine (JSON) to export as a Petri net whose labels are the log's
    /// activities (needs --pnml; its signal names must be the mapping's).
    #[arg(long, value_name = "FILE", requires = "pnml")]
    pub ecc: Option<PathBuf>,
    /// PNML file to write the --ecc machine's Petri net to.
    #[arg(long, value_name = "FILE", requires = "ecc")]
    pub pnml: Option<PathBuf>,
    /// PNML of the net: iso (ISO/IEC 15909-2 P/T net in the PNML namespace, for strict tools)
    /// or prom (what ProM and pm4py read for token replay: silent transitions and the final
    /// marking in their own extensions, which the standard rejects).
    #[arg(long, value_name = "DIALECT", default_value = "iso", requires = "pnml")]
    pub pnml_dialect: Dialect,
}

/// Runs `synth events`: the XES and CSV files, then the optional Petri net.
pub fn events(args: &EventsArgs) -> Result<(), Error> {
    let done = run(&Request {
        log: args.log.clone(),
        map: args.map.clone(),
        reset: args.reset.clone(),
        out: args.out.clone(),
        csv: args.csv.clone(),
        lenient: args.lenient,
        net: (args.ecc.clone())
            .zip(args.pnml.clone())
            .map(|(ecc, pnml)| (ecc, pnml, args.pnml_dialect)),
    })?;
    if let Some(note) = done.note() {
        super::err_line(format_args!("{note}"));
    }
    out!("{done}");
    super::note_written(&done.files());
    Ok(())
}
