//! `synth verify`: a machine checked by NuSMV in closed loop with the plant; the verdicts, and
//! for every violated property its counterexample as a table and, with `--out`, a waveform.

use super::args::{check, problem, NusmvArgs};
use super::{exit, Failure};
use crate::files::ResultSet;
use crate::pipeline;
use crate::pipeline::recordings::read_ecc;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `synth verify`.
#[derive(Debug, Args)]
pub struct VerifyArgs {
    /// The machine to check, in the JSON format `synth infer` writes.
    #[arg(long, value_name = "FILE")]
    pub ecc: PathBuf,
    /// LTL properties.
    #[arg(long, value_name = "FILE")]
    pub ltl: PathBuf,
    /// Surrogate plant model.
    #[arg(long, value_name = "FILE")]
    pub plant: PathBuf,
    /// Folder to keep the closed-loop model NuSMV checked and, for every violated property,
    /// its counterexample as a waveform (`<property>.vcd` for GTKWave, `<property>.svg`).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    #[command(flatten)]
    pub nusmv: NusmvArgs,
}

/// Stages the closed-loop model and each waveform as VCD and SVG (named after its property,
/// made a safe file name); the staged paths.
fn write_counterexamples(
    results: &ResultSet,
    model: &str,
    waveforms: &[crate::export::waveform::Waveform],
) -> Result<Vec<PathBuf>, Failure> {
    use crate::export::waveform;
    let dir = results.staging();
    let mut files = vec![dir.join("closed_loop.smv")];
    crate::files::write_atomic(&files[0], model.as_bytes()).map_err(Failure::input)?;
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
            crate::files::write_atomic(&path, text.as_bytes()).map_err(Failure::input)?;
            files.push(path);
        }
    }
    Ok(files)
}

/// `synth verify`.
pub fn verify(args: &VerifyArgs) -> Result<(), Failure> {
    if super::json() {
        super::data_on_stdout();
    }
    let ecc = read_ecc(&args.ecc)?;
    let problem = problem(&args.ltl, &args.plant, &ecc.inputs, &ecc.outputs)?;
    let check = check(problem, &args.nusmv)?;
    // Taken first: a second run into the same folder stops before NuSMV runs.
    let results = match &args.out {
        Some(out) => Some(ResultSet::open(out).map_err(Failure::input)?),
        None => None,
    };
    let verification = pipeline::verify(&ecc, &check)?;
    let report = &verification.report;
    if super::json() {
        let summary = serde_json::json!({ "verified": report.all_hold(), "report": report });
        super::write_json(&summary)?;
    }
    out_raw!("{}", report.to_text());
    let waveforms: Vec<_> = (verification.counterexamples.iter())
        .map(|cx| cx.waveform(&ecc.inputs, &ecc.outputs))
        .collect();
    for w in &waveforms {
        out!("");
        out_raw!("{}", crate::export::waveform::table(w));
    }
    if let Some(results) = results {
        let files = write_counterexamples(&results, &verification.model.text, &waveforms)?;
        let published: Vec<PathBuf> = files.iter().map(|f| results.published(f)).collect();
        results
            .publish()
            .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
        out!("");
        super::show::print_written(&published);
    }
    if report.all_hold() {
        out!("verified: all {} properties hold", report.properties.len());
        Ok(())
    } else {
        Err(Failure::msg(
            exit::FAILED,
            format!(
                "not verified: {} violated",
                report
                    .failing()
                    .iter()
                    .map(|name| crate::quote::cut(name).to_string())
                    .collect::<Vec<_>>()
                    .join(", ")
            ),
        ))
    }
}
