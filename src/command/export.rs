//! `synth export`: any machine in the JSON contract (one `synth` wrote, or one edited by hand)
//! to every other format, into a result folder or, one format, on stdout.

use super::{out_dir, publish};
use crate::export::{self, Format};
use crate::files::output_rule::Claim;
use crate::files::ResultSet;
use crate::pipeline::recordings::read_ecc;
use crate::pipeline::Error;
use std::fmt;
use std::path::{Path, PathBuf};

/// What `synth export` wrote.
pub(crate) enum Exported {
    /// The machine in the one format asked, for stdout.
    Text(String),
    /// The files published, after the machine's size.
    Files {
        /// The machine's file.
        ecc: PathBuf,
        /// States.
        states: usize,
        /// Transitions.
        transitions: usize,
        /// The files published.
        files: Vec<PathBuf>,
    },
}

/// The machine's size (of files written).
impl fmt::Display for Exported {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Exported::Text(_) => Ok(()),
            Exported::Files {
                ecc,
                states,
                transitions,
                ..
            } => write!(
                f,
                "{}: {states} states, {transitions} transitions",
                ecc.display()
            ),
        }
    }
}

impl Exported {
    /// The files published (none on stdout).
    pub fn files(&self) -> &[PathBuf] {
        match self {
            Exported::Text(_) => &[],
            Exported::Files { files, .. } => files,
        }
    }
}

/// The one format written on stdout: the one `formats` names, JSON when it names several.
pub(crate) fn stdout_format(formats: &[Format]) -> Format {
    match formats {
        [one] => *one,
        _ => Format::Json,
    }
}

/// `synth export`: the machine in `ecc_file` in `formats`, on stdout (`to_stdout`) or into
/// `out` (default `out/<stem of the JSON file>`).
pub(crate) fn run(
    ecc_file: &Path,
    formats: &[Format],
    name: &str,
    out: &Option<PathBuf>,
    to_stdout: bool,
) -> Result<Exported, Error> {
    let ecc = read_ecc(ecc_file)?;
    if to_stdout {
        let text = export::text(&ecc, name, stdout_format(formats))?;
        return Ok(Exported::Text(text));
    }
    let stem =
        (ecc_file.file_stem()).map_or("machine".into(), |s| s.to_string_lossy().into_owned());
    let out = out_dir(out, &stem);
    let claim = Claim::new("export", [ecc_file]).writing(name);
    let results = ResultSet::open(&out, claim)?;
    let staged = export::write_all(&ecc, results.staging(), name, formats)?;
    Ok(Exported::Files {
        ecc: ecc_file.to_path_buf(),
        states: ecc.states.len(),
        transitions: ecc.size().t,
        files: publish(results, &staged)?,
    })
}
