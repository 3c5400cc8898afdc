//! `synth convert` (scenarios from one format into another) and `synth replay` (scenarios
//! replayed on a machine).

use super::refuse_overwrite;
use crate::pipeline::recordings::machine_and_scenarios;
use crate::pipeline::{Error, Recordings};
use crate::scenario::{csvlog, fbsat, ScenarioSet};
use std::path::{Path, PathBuf};

/// The formats scenarios are converted to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum To {
    /// fbSAT scenario text format.
    Fbsat,
    /// CSV log with `in:`/`out:` headers and a `scenario` column.
    Csv,
}

/// Scenarios converted.
pub(crate) struct Converted {
    /// The scenarios.
    pub set: ScenarioSet,
    /// Their text in the format asked.
    pub bytes: Vec<u8>,
}

impl Converted {
    /// The line that says what was written to `output`.
    pub fn line(&self, output: &Path) -> String {
        format!(
            "wrote {} scenarios ({} steps) to {}",
            self.set.scenarios.len(),
            self.set.step_count(),
            crate::quote::path(output)
        )
    }
}

/// `synth convert`: the recordings in format `to`, written to `output` unless `None`
/// (stdout: the caller writes [`Converted::bytes`]).
pub(crate) fn convert(
    recordings: &Recordings,
    to: To,
    output: Option<&Path>,
) -> Result<Converted, Error> {
    if let Some(output) = output {
        let mut inputs: Vec<PathBuf> = recordings.traces.clone();
        inputs.extend(recordings.input_names.iter().cloned());
        inputs.extend(recordings.output_names.iter().cloned());
        let defaults = (recordings.traces.first())
            .and_then(|t| crate::scenario::names::default_names_files(t));
        inputs.extend(defaults.into_iter().flat_map(|(i, o)| [i, o]));
        refuse_overwrite(&[output], &inputs)?;
    }
    let set = recordings.load()?;
    let mut bytes = Vec::new();
    match to {
        To::Fbsat => fbsat::write(&set, &mut bytes),
        To::Csv => csvlog::write(&set, &mut bytes),
    }?;
    if let Some(output) = output {
        crate::files::write_atomic(output, &bytes)?;
    }
    Ok(Converted { set, bytes })
}

/// `synth replay`: the recordings replayed on the machine in `ecc_file`; the line saying
/// all are reproduced, or the first step that is not.
pub(crate) fn replay(ecc_file: &Path, recordings: &Recordings) -> Result<String, Error> {
    let (ecc, set) = machine_and_scenarios(ecc_file, recordings)?;
    set.check(&ecc)
        .map_err(|m| Error::Negative(format!("not reproduced: {m}")))?;
    Ok(format!(
        "replayed {} scenarios ({} steps): all reproduced by {}",
        set.scenarios.len(),
        set.step_count(),
        ecc_file.display()
    ))
}
