//! `synth events`: a raw PLC I/O log into an event log (XES and CSV) for process-mining tools.

use super::Failure;
use crate::events::{self, ResetActivity};
use crate::export::pnml::{write_pnml_labelled, Dialect, Labels};
use crate::files::same_file;
use crate::ingest::Mapping;
use clap::Args;
use std::path::{Path, PathBuf};

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
pub fn events(args: &EventsArgs) -> Result<(), Failure> {
    let mapping = Mapping::read(&args.map).map_err(Failure::input)?;
    let reset = ResetActivity::parse(&args.reset, &mapping).map_err(Failure::input)?;
    let csv = args
        .csv
        .clone()
        .unwrap_or_else(|| args.out.with_extension("csv"));
    if same_file(&csv, &args.out) {
        return Err(Failure::msg(
            super::exit::INPUT,
            format!(
                "the CSV and XES outputs are both {}; give --csv another path",
                csv.display()
            ),
        ));
    }
    // The default CSV path of `--out log.xes` is `log.csv`, which may well be the input log.
    for out in [&args.out, &csv] {
        if same_file(out, &args.log) {
            return Err(Failure::msg(
                super::exit::INPUT,
                format!(
                    "the output {} would overwrite the input log; give --out/--csv other paths",
                    out.display()
                ),
            ));
        }
    }
    let mut outputs = vec![&args.out, &csv];
    outputs.extend(&args.pnml);
    let mut inputs = vec![&args.map];
    inputs.extend(&args.ecc);
    super::args::refuse_overwrite(&outputs, &inputs)?;
    // The net first: when it cannot be made, nothing is written.
    let net = match (&args.ecc, &args.pnml) {
        (Some(ecc), Some(pnml)) => Some((net_of(ecc, &mapping, args.pnml_dialect)?, ecc, pnml)),
        _ => None,
    };
    let s = events::write_event_logs(&args.log, &mapping, &reset, args.lenient, &args.out, &csv)
        .map_err(|e| {
            let row = matches!(
                e,
                events::EventsError::Log(crate::ingest::IngestError::Row { .. })
            );
            let mut f = Failure::input(e);
            if row {
                f.message
                    .push_str("\n(--lenient skips bad rows and counts them instead)");
            }
            f
        })?;
    out!(
        "rows {}, samples {}, skipped {}; {} events in {} traces ({} of them the reset '{}')",
        s.rows,
        s.samples,
        s.skipped,
        s.events,
        s.traces,
        s.resets,
        reset
    );
    if s.resets == 0 && s.events > 0 {
        eprintln!("note: the reset activity '{reset}' never occurs: the log is one trace");
    }
    out!("wrote {}, {}", args.out.display(), csv.display());
    super::note_written(&[args.out.clone(), csv.clone()]);
    if let Some(((bytes, places), ecc_file, pnml)) = net {
        crate::files::write_atomic(pnml, &bytes).map_err(Failure::input)?;
        out!(
            "wrote {} (Petri net of {}: {places} places)",
            pnml.display(),
            ecc_file.display(),
        );
        super::note_written(std::slice::from_ref(pnml));
    }
    Ok(())
}

/// The PNML text of the Petri net of the machine in `ecc_file`, labelled with the mapping's
/// addresses, and its number of places.
fn net_of(
    ecc_file: &Path,
    mapping: &Mapping,
    dialect: Dialect,
) -> Result<(Vec<u8>, usize), Failure> {
    // Machines may be written as one line of JSON: only the file's size is limited.
    let text = crate::files::read_text(ecc_file, None).map_err(Failure::input)?;
    let ecc = crate::export::json::read_json(&text, ecc_file).map_err(Failure::input)?;
    let address = |name: &String| -> Result<String, Failure> {
        mapping
            .slot(name.as_bytes())
            .and_then(|slot| {
                mapping
                    .addresses()
                    .iter()
                    .find(|(_, s)| *s == slot)
                    .map(|(a, _)| a.clone())
            })
            .ok_or_else(|| {
                Failure::msg(
                    super::exit::INPUT,
                    format!(
                        "{}: signal {} is not in the mapping",
                        ecc_file.display(),
                        crate::quote::quote(name)
                    ),
                )
            })
    };
    let labels = Labels {
        inputs: ecc.inputs.iter().map(address).collect::<Result<_, _>>()?,
        outputs: ecc.outputs.iter().map(address).collect::<Result<_, _>>()?,
    };
    let name = ecc_file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut buf = Vec::new();
    write_pnml_labelled(&ecc, &labels, &name, dialect, &mut buf).map_err(Failure::input)?;
    Ok((buf, ecc.states.len()))
}
