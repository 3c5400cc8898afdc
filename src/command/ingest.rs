//! `synth ingest`: a raw PLC I/O log into a scenario file, with its names files beside it.

use super::{lenient_hint, refuse_overwrite};
use crate::ingest::{self, IngestError, Mapping, Throughput};
use crate::pipeline::Error;
use std::fmt;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `synth ingest` wrote.
pub(crate) struct Done {
    /// The reader's figures and the steps written.
    pub written: ingest::Written,
    /// Seconds the conversion took.
    pub seconds: f64,
    /// The scenario file and its names files.
    pub files: [PathBuf; 3],
}

impl fmt::Display for Done {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let w = &self.written;
        let [scenarios, inputs, outputs] = &self.files;
        writeln!(
            f,
            "{}",
            Throughput {
                stats: &w.stats,
                seconds: self.seconds
            }
        )?;
        writeln!(f, "steps:   {} ({} with CNF)", w.steps, w.active)?;
        write!(
            f,
            "wrote {}, {}, {}",
            crate::quote::path(scenarios),
            crate::quote::path(inputs),
            crate::quote::path(outputs)
        )
    }
}

/// `synth ingest`: `log` read with the mapping in `map` into the scenario file `output`
/// (`<stem>.inputs` and `<stem>.outputs` beside it).
pub(crate) fn run(log: &Path, map: &Path, lenient: bool, output: &Path) -> Result<Done, Error> {
    let start = Instant::now();
    let (inputs_file, outputs_file) = names_files(output);
    refuse_overwrite(&[output, &inputs_file, &outputs_file], &[log, map])?;
    let mapping = Mapping::read(map)?;
    let written = ingest::write_scenario(log, &mapping, lenient, output).map_err(|e| {
        let row = matches!(e, IngestError::Row { .. });
        lenient_hint(e.into(), row)
    })?;
    let seconds = start.elapsed().as_secs_f64();
    for (file, names) in [
        (&inputs_file, mapping.inputs()),
        (&outputs_file, mapping.outputs()),
    ] {
        let text: String = names.iter().map(|n| format!("{n}\n")).collect();
        crate::files::write_atomic(file, text.as_bytes())?;
    }
    Ok(Done {
        written,
        seconds,
        files: [output.to_path_buf(), inputs_file, outputs_file],
    })
}

/// `<stem>.inputs` / `<stem>.outputs` beside `out`, where the other commands look for them.
fn names_files(out: &Path) -> (PathBuf, PathBuf) {
    let dir = out.parent().unwrap_or(Path::new(""));
    let file = (out.file_name())
        .and_then(|f| f.to_str())
        .unwrap_or("scenarios");
    let stem = file.split('.').next().unwrap_or(file);
    (
        dir.join(format!("{stem}.inputs")),
        dir.join(format!("{stem}.outputs")),
    )
}
