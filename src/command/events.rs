//! `synth events`: a raw PLC I/O log into an event log (XES and CSV) for process-mining tools,
//! and a synthesized machine as a Petri net labelled with the log's activities.

use super::{lenient_hint, refuse_overwrite};
use crate::events::{self, EventsError, ResetActivity};
use crate::export::pnml::{write_pnml_labelled, Dialect, Labels, NetSize};
use crate::files::same_file;
use crate::ingest::{IngestError, Mapping};
use crate::pipeline::recordings::read_ecc;
use crate::pipeline::Error;
use std::fmt;
use std::path::{Path, PathBuf};

/// What `synth events` is asked.
pub(crate) struct Request {
    /// The raw log.
    pub log: PathBuf,
    /// The address mapping.
    pub map: PathBuf,
    /// The activity that starts a new trace.
    pub reset: String,
    /// The XES file.
    pub out: PathBuf,
    /// The CSV file (default: the XES path with the extension `.csv`).
    pub csv: Option<PathBuf>,
    /// Skip bad rows and count them.
    pub lenient: bool,
    /// A machine to write as a Petri net, and where, in which dialect of PNML.
    pub net: Option<(PathBuf, PathBuf, Dialect)>,
}

/// What `synth events` wrote.
pub(crate) struct Done {
    /// The log's figures.
    pub summary: events::Summary,
    /// The reset activity.
    pub reset: ResetActivity,
    /// The XES and CSV files.
    pub logs: [PathBuf; 2],
    /// The Petri net written: its file, the machine's and the net's size.
    pub net: Option<(PathBuf, PathBuf, NetSize)>,
}

impl fmt::Display for Done {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = &self.summary;
        write!(
            f,
            "rows {}, samples {}, skipped {}; {} events in {} traces ({} of them the reset '{}')\nwrote {}, {}",
            s.rows,
            s.samples,
            s.skipped,
            s.events,
            s.traces,
            s.resets,
            self.reset,
            crate::quote::path(&self.logs[0]),
            crate::quote::path(&self.logs[1])
        )?;
        match &self.net {
            Some((pnml, ecc, size)) => write!(
                f,
                "\nwrote {} (Petri net of {}: {} places, {} transitions)",
                crate::quote::path(pnml),
                crate::quote::path(ecc),
                size.places,
                size.transitions
            ),
            None => Ok(()),
        }
    }
}

impl Done {
    /// A note for stderr when the reset activity never occurs.
    pub fn note(&self) -> Option<String> {
        let s = &self.summary;
        (s.resets == 0 && s.events > 0).then(|| {
            format!(
                "note: the reset activity '{}' never occurs: the log is one trace",
                self.reset
            )
        })
    }

    /// Every file written.
    pub fn files(&self) -> Vec<PathBuf> {
        let mut files = self.logs.to_vec();
        files.extend(self.net.iter().map(|n| n.0.clone()));
        files
    }
}

/// `synth events`: the XES and CSV files, then the optional Petri net.
pub(crate) fn run(r: &Request) -> Result<Done, Error> {
    let mapping = Mapping::read(&r.map)?;
    let reset = ResetActivity::parse(&r.reset, &mapping)?;
    let csv = (r.csv.clone()).unwrap_or_else(|| r.out.with_extension("csv"));
    refuse_clashes(r, &csv)?;
    // The net first: when it cannot be made, nothing is written.
    let net = match &r.net {
        Some((ecc, pnml, dialect)) => Some((net_of(ecc, &mapping, *dialect)?, ecc, pnml)),
        None => None,
    };
    let summary = events::write_event_logs(&r.log, &mapping, &reset, r.lenient, &r.out, &csv)
        .map_err(|e| {
            let row = matches!(e, EventsError::Log(IngestError::Row { .. }));
            lenient_hint(e.into(), row)
        })?;
    let net = match net {
        Some(((bytes, size), ecc, pnml)) => {
            crate::files::write_atomic(pnml, &bytes)?;
            Some((pnml.clone(), ecc.clone(), size))
        }
        None => None,
    };
    Ok(Done {
        summary,
        reset,
        logs: [r.out.clone(), csv],
        net,
    })
}

/// Refuses outputs that are one file, or that would overwrite an input.
fn refuse_clashes(r: &Request, csv: &Path) -> Result<(), Error> {
    if same_file(csv, &r.out) {
        return Err(Error::Input(format!(
            "the CSV and XES outputs are both {}; give --csv another path",
            csv.display()
        )));
    }
    // The default CSV path of `--out log.xes` is `log.csv`, which may well be the input log.
    if let Some(out) = [&r.out, csv].into_iter().find(|o| same_file(o, &r.log)) {
        return Err(Error::Input(format!(
            "the output {} would overwrite the input log; give --out/--csv other paths",
            out.display()
        )));
    }
    let mut outputs = vec![&r.out, csv];
    let mut inputs = vec![&r.map];
    if let Some((ecc, pnml, _)) = &r.net {
        outputs.push(pnml);
        inputs.push(ecc);
    }
    refuse_overwrite(&outputs, &inputs)
}

/// The PNML text of the Petri net of the machine in `ecc_file`, labelled with the mapping's
/// addresses, and the net's size.
fn net_of(
    ecc_file: &Path,
    mapping: &Mapping,
    dialect: Dialect,
) -> Result<(Vec<u8>, NetSize), Error> {
    let ecc = read_ecc(ecc_file)?;
    let address = |name: &String| -> Result<String, Error> {
        let slot = mapping.slot(name.as_bytes());
        let found = slot.and_then(|slot| {
            (mapping.addresses().iter())
                .find(|(_, s)| *s == slot)
                .map(|(a, _)| a.clone())
        });
        found.ok_or_else(|| {
            Error::Input(format!(
                "{}: signal {} is not in the mapping",
                ecc_file.display(),
                crate::quote::quote(name)
            ))
        })
    };
    let labels = Labels {
        inputs: ecc.inputs.iter().map(address).collect::<Result<_, _>>()?,
        outputs: ecc.outputs.iter().map(address).collect::<Result<_, _>>()?,
    };
    let name = (ecc_file.file_stem())
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let mut buf = Vec::new();
    let size = write_pnml_labelled(&ecc, &labels, &name, dialect, &mut buf)?;
    Ok((buf, size))
}
