//! The ambiguity report of `synth infer` (unique or ambiguous, with rivals) and `synth
//! next-recording` (what to record next so that the rivals found are told apart).

use super::args::{AlgorithmsArg, AmbiguityArgs, TraceArgs};
use super::progress::Progress;
use super::show::print_written;
use super::{exit, Failure};
use crate::ecc::Ecc;
use crate::export;
use crate::files::ResultSet;
use crate::pipeline::ambiguity::{self, Ambiguity, Uniqueness};
use crate::pipeline::{self, exact};
use crate::scenario::ScenarioSet;
use clap::Args;
use std::path::{Path, PathBuf};

/// Runs the check on `machine` (minimal for `set`), prints the verdict and every rival, and
/// writes `rival<k>.json` and `ambiguity.txt` into `dir` when given; the files written.
pub fn report(
    set: &ScenarioSet,
    machine: &Ecc,
    args: &AmbiguityArgs,
    algorithms: AlgorithmsArg,
    progress: &Progress,
    dir: Option<&Path>,
) -> Result<(Ambiguity, Vec<PathBuf>), Failure> {
    progress.line(&format!(
        "ambiguity: looking for up to {} other machines with {} states that fit the recordings",
        args.rivals,
        machine.states.len()
    ));
    let found = ambiguity::check_long(set, machine, &args.options(algorithms.into())?)?;
    let text = found.to_text(set, machine);
    out_raw!("{text}");
    let mut files = Vec::new();
    let Some(dir) = dir else {
        return Ok((found, files));
    };
    for (k, r) in found.rivals.iter().enumerate() {
        let path = dir.join(format!("rival{}.json", k + 1));
        crate::files::write_atomic(&path, export::json::to_string(&r.ecc).as_bytes())
            .map_err(Failure::input)?;
        files.push(path);
    }
    let path = dir.join("ambiguity.txt");
    crate::files::write_atomic(&path, text.as_bytes()).map_err(Failure::input)?;
    files.push(path);
    Ok((found, files))
}

/// As [`report`], for a machine NuSMV verified: every rival is checked by NuSMV too, and
/// the lines say which of them the properties rule out.
pub fn report_verified(
    set: &ScenarioSet,
    machine: &Ecc,
    args: &AmbiguityArgs,
    algorithms: AlgorithmsArg,
    check: &pipeline::Check,
    progress: &Progress,
    dir: &Path,
) -> Result<Vec<PathBuf>, Failure> {
    let (found, files) = report(set, machine, args, algorithms, progress, Some(dir))?;
    let mut fitting = 0;
    for (k, failing) in found.verify_rivals(check)?.iter().enumerate() {
        if failing.is_empty() {
            fitting += 1;
            out!(
                "rival {}: NuSMV: every property holds in closed loop too",
                k + 1
            );
        } else {
            out!(
                "rival {}: NuSMV: violates {} (the properties rule it out)",
                k + 1,
                failing.join(", ")
            );
        }
    }
    match (found.verdict, fitting) {
        (Uniqueness::Ambiguous, 0) => out!(
            "every rival found violates a property: the properties, not the recordings, tell them apart (more rivals may exist: --rivals N)"
        ),
        (Uniqueness::Ambiguous, n) => out!(
            "ambiguous with the properties: {n} rival{} reproduce{} the recordings and satisfy every property",
            if n == 1 { "" } else { "s" },
            if n == 1 { "s" } else { "" }
        ),
        _ => {}
    }
    Ok(files)
}

#[derive(Debug, Args)]
pub struct NextRecordingArgs {
    #[command(flatten)]
    pub traces: TraceArgs,
    /// The machine inferred from the recordings (JSON, as `synth infer` wrote it); default:
    /// infer it now.
    #[arg(long, value_name = "FILE")]
    pub ecc: Option<PathBuf>,
    /// Form of the state output algorithms.
    #[arg(long, value_enum, default_value_t = AlgorithmsArg::Tri)]
    pub algorithms: AlgorithmsArg,
    #[command(flatten)]
    pub ambiguity: AmbiguityArgs,
    /// Output folder for `plan.csv`, `plan.txt`, the rivals and the machine they rival
    /// (`machine.json`). Default: `out/<stem of the first trace file>-next`.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

/// `synth next-recording`: the sequences that tell the rivals apart, as a plan.
pub fn next_recording(args: &NextRecordingArgs) -> Result<(), Failure> {
    if super::json() {
        super::data_on_stdout();
    }
    let progress = Progress::new(super::quiet());
    let recordings = args.traces.recordings();
    let set = args.traces.load()?;
    let out = super::args::out_dir(&args.out, &format!("{}-next", recordings.stem()));
    let results = ResultSet::open(&out).map_err(Failure::input)?;
    let machine = match &args.ecc {
        Some(file) => {
            let (ecc, set2) = pipeline::recordings::machine_and_scenarios(file, &recordings)?;
            set2.check(&ecc).map_err(|m| {
                Failure::msg(
                    exit::INPUT,
                    format!("{}: does not reproduce the recordings: {m}", file.display()),
                )
            })?;
            ecc
        }
        None => {
            let opts = exact::Options {
                sat: exact::SatOptions {
                    algorithms: args.algorithms.into(),
                    ..exact::SatOptions::default()
                },
                ..exact::Options::default()
            };
            exact::run(&set, None, &opts, &mut |e| progress.event(e))?
                .synthesis
                .ecc
        }
    };
    let (found, mut files) = report(
        &set,
        &machine,
        &args.ambiguity,
        args.algorithms,
        &progress,
        Some(results.staging()),
    )?;
    let (csv, txt) = (
        found.plan_csv(&set, &machine),
        found.plan_text(&set, &machine),
    );
    let json = export::json::to_string(&machine);
    for (name, text) in [("plan.csv", csv), ("plan.txt", txt), ("machine.json", json)] {
        let path = results.staging().join(name);
        crate::files::write_atomic(&path, text.as_bytes()).map_err(Failure::input)?;
        files.push(path);
    }
    let published: Vec<PathBuf> = files.iter().map(|f| results.published(f)).collect();
    results
        .publish()
        .map_err(|e| Failure::input(pipeline::Error::from(e)))?;
    match found.verdict {
        Uniqueness::Unique => {
            out!("nothing to record: the recordings determine the machine within the bounds above")
        }
        Uniqueness::Unknown => out!("no plan: the check found no answer within the budget"),
        Uniqueness::Ambiguous => out!(
            "plan: {} sequences, {} steps to record in all",
            found.rivals.len(),
            found
                .rivals
                .iter()
                .map(|r| r.inputs(&set).len())
                .sum::<usize>()
        ),
    }
    print_written(&published);
    if super::json() {
        let mut summary = found.to_json(&set, &machine);
        summary["files"] = serde_json::json!(published);
        return super::write_json(&summary);
    }
    Ok(())
}
