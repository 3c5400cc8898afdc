//! `synth verify`: a machine checked by NuSMV in closed loop with the plant; the verdicts,
//! and for every violated property its counterexample as a table and, with an output folder,
//! the closed-loop model and a waveform (VCD and SVG).

use super::{publish, Spec};
use crate::export::waveform::{self, Waveform};
use crate::files::output_rule::Claim;
use crate::files::{write_atomic, ResultSet};
use crate::pipeline::recordings::read_ecc;
use crate::pipeline::summary::{VerifySummary, VERIFY};
use crate::pipeline::{self, Check, Error};
use crate::verify::Report;
use std::fmt;
use std::path::{Path, PathBuf};

/// A machine checked.
pub(crate) struct Checked {
    /// NuSMV's verdicts.
    pub report: Report,
    /// The counterexample of every violated property with a trace.
    pub waveforms: Vec<Waveform>,
    /// The files published.
    pub files: Vec<PathBuf>,
}

/// The verdicts, then each counterexample as a table.
impl fmt::Display for Checked {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.report.to_text())?;
        (self.waveforms.iter()).try_for_each(|w| write!(f, "\n{}", waveform::table(w)))
    }
}

impl Checked {
    /// The `--json` summary.
    pub fn summary(&self) -> VerifySummary {
        VerifySummary {
            format: VERIFY,
            verified: self.report.all_hold(),
            report: self.report.clone(),
        }
    }

    /// The closing line when every property holds, else the failure naming the violated ones.
    pub fn verdict(&self) -> Result<String, Error> {
        let r = &self.report;
        if r.all_hold() {
            return Ok(format!(
                "verified: all {} properties hold",
                r.properties.len()
            ));
        }
        let failing: Vec<String> = (r.failing().iter())
            .map(|name| crate::quote::cut(name).to_string())
            .collect();
        Err(Error::Negative(format!(
            "not verified: {} violated",
            failing.join(", ")
        )))
    }
}

/// `synth verify`: the machine in `ecc_file` against `spec`; with `out`, the closed-loop
/// model and the waveforms written there.
pub(crate) fn run(ecc_file: &Path, spec: &Spec, out: Option<&Path>) -> Result<Checked, Error> {
    let ecc = read_ecc(ecc_file)?;
    let problem = spec.problem(&ecc.inputs, &ecc.outputs)?;
    let check = Check::new(problem, spec.nusmv.locate()?);
    crate::pipeline::plant_check::refuse_unfair(&check)?;
    // Taken first: a second run into the same folder stops before NuSMV runs.
    let reads = [ecc_file.to_path_buf()].into_iter().chain(spec.paths());
    let claim = Claim::new("verify", reads);
    let results = out.map(|o| ResultSet::open(o, claim)).transpose()?;
    let verification = pipeline::verify(&ecc, &check)?;
    let waveforms: Vec<Waveform> = (verification.counterexamples.iter())
        .map(|cx| cx.waveform(&ecc.inputs, &ecc.outputs))
        .collect();
    let files = match results {
        Some(results) => {
            let staged = counterexamples(&results, &verification.model.text, &waveforms)?;
            publish(results, &staged)?
        }
        None => Vec::new(),
    };
    Ok(Checked {
        report: verification.report,
        waveforms,
        files,
    })
}

/// Stages the closed-loop model and each waveform as VCD and SVG (named after its property,
/// made a safe file name); the staged paths.
fn counterexamples(
    results: &ResultSet,
    model: &str,
    waveforms: &[Waveform],
) -> Result<Vec<PathBuf>, Error> {
    let dir = results.staging();
    let mut files = vec![dir.join("closed_loop.smv")];
    write_atomic(&files[0], model.as_bytes())?;
    for w in waveforms {
        let stem: String = (w.title.chars())
            .map(
                |c| match c.is_ascii_alphanumeric() || c == '_' || c == '-' {
                    true => c,
                    false => '_',
                },
            )
            .collect();
        for (ext, text) in [("vcd", waveform::vcd(w)), ("svg", waveform::svg(w))] {
            let path = dir.join(format!("{stem}.{ext}"));
            write_atomic(&path, text.as_bytes())?;
            files.push(path);
        }
    }
    Ok(files)
}
