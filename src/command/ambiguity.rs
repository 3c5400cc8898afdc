//! The ambiguity report of `synth infer` and the main job (unique or ambiguous, with rivals;
//! for a verified machine, NuSMV's verdict on each rival) and `synth next-recording` (what
//! to record next so that the rivals found are told apart).

use super::{out_dir, publish};
use crate::ecc::Ecc;
use crate::export;
use crate::files::output_rule::Claim;
use crate::files::{write_atomic, ResultSet};
use crate::pipeline::ambiguity::{self, Ambiguity, Uniqueness};
use crate::pipeline::summary::AmbiguitySummary;
use crate::pipeline::{exact, recordings, Check, Error, Event, Events, Note, Recordings};
use crate::scenario::ScenarioSet;
use std::fmt;
use std::path::{Path, PathBuf};

/// The ambiguity check of a machine, as printed and written.
pub(crate) struct Report {
    /// What the check found.
    pub found: Ambiguity,
    /// The verdict and every rival with its sequence (`ambiguity.txt`).
    pub text: String,
    /// For a verified machine: what NuSMV says of each rival, one line each, and what that
    /// means for the machine.
    pub verified: Vec<String>,
    /// `rival<k>.json` and `ambiguity.txt`, when written.
    pub files: Vec<PathBuf>,
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.text)?;
        self.verified.iter().try_for_each(|l| writeln!(f, "{l}"))
    }
}

impl Report {
    /// The `--json` form of the check.
    pub fn summary(&self, set: &ScenarioSet, machine: &Ecc) -> AmbiguitySummary {
        AmbiguitySummary::new(&self.found, set, machine)
    }
}

/// Runs the check on `machine` (minimal for `set`) and writes `rival<k>.json` and
/// `ambiguity.txt` into `dir` when given.
pub(crate) fn report(
    set: &ScenarioSet,
    machine: &Ecc,
    opts: &ambiguity::Options,
    dir: Option<&Path>,
    events: Events<'_>,
) -> Result<Report, Error> {
    events(Event::Note(Note::AmbiguityStarted {
        rivals: opts.rivals,
        states: machine.states.len(),
    }));
    let found = ambiguity::check_long(set, machine, opts)?;
    let text = found.to_text(set, machine);
    let mut files = Vec::new();
    if let Some(dir) = dir {
        for (k, r) in found.rivals.iter().enumerate() {
            let path = dir.join(format!("rival{}.json", k + 1));
            write_atomic(&path, export::json::to_string(&r.ecc).as_bytes())?;
            files.push(path);
        }
        let path = dir.join("ambiguity.txt");
        write_atomic(&path, text.as_bytes())?;
        files.push(path);
    }
    Ok(Report {
        found,
        text,
        verified: Vec::new(),
        files,
    })
}

/// As [`report`], for a machine NuSMV verified: every rival is checked by NuSMV too, and
/// the lines say which of them the properties rule out.
pub(crate) fn report_verified(
    set: &ScenarioSet,
    machine: &Ecc,
    opts: &ambiguity::Options,
    check: &Check,
    dir: &Path,
    events: Events<'_>,
) -> Result<Report, Error> {
    let mut report = report(set, machine, opts, Some(dir), events)?;
    let mut fitting = 0;
    for (k, failing) in report.found.verify_rivals(check)?.iter().enumerate() {
        report.verified.push(match failing.is_empty() {
            true => {
                fitting += 1;
                format!(
                    "rival {}: NuSMV: every property holds in closed loop too",
                    k + 1
                )
            }
            false => format!(
                "rival {}: NuSMV: violates {} (the properties rule it out)",
                k + 1,
                failing.join(", ")
            ),
        });
    }
    match (report.found.verdict, fitting) {
        (Uniqueness::Ambiguous, 0) => report.verified.push(
            "every rival found violates a property: the properties, not the recordings, tell them apart (more rivals may exist: --rivals N)".into(),
        ),
        (Uniqueness::Ambiguous, n) => report.verified.push(format!(
            "ambiguous with the properties: {n} rival{} reproduce{} the recordings and satisfy every property",
            if n == 1 { "" } else { "s" },
            if n == 1 { "s" } else { "" }
        )),
        _ => {}
    }
    Ok(report)
}

/// What `synth next-recording` asks for.
pub(crate) struct Request {
    /// The recordings.
    pub recordings: Recordings,
    /// The machine inferred from them (JSON); `None`: infer it now.
    pub ecc: Option<PathBuf>,
    /// The algorithm form of the machine inferred.
    pub algorithms: crate::ecc::AlgorithmKind,
    /// The check's bounds.
    pub ambiguity: ambiguity::Options,
    /// Output folder (default `out/<stem>-next`).
    pub out: Option<PathBuf>,
}

/// What `synth next-recording` found and wrote.
pub(crate) struct Plan {
    /// The check.
    pub report: Report,
    /// The recordings.
    pub set: ScenarioSet,
    /// The machine the rivals rival.
    pub machine: Ecc,
    /// The files published.
    pub files: Vec<PathBuf>,
}

impl fmt::Display for Plan {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.report)?;
        let found = &self.report.found;
        match found.verdict {
            Uniqueness::Unique => write!(
                f,
                "nothing to record: the recordings determine the machine within the bounds above"
            ),
            Uniqueness::Unknown => {
                write!(f, "no plan: the check found no answer within the budget")
            }
            Uniqueness::Ambiguous => write!(
                f,
                "plan: {} sequences, {} steps to record in all",
                found.rivals.len(),
                (found.rivals.iter())
                    .map(|r| r.inputs(&self.set).len())
                    .sum::<usize>()
            ),
        }
    }
}

/// `synth next-recording`: the sequences that tell the rivals apart, as a plan (`plan.csv`,
/// `plan.txt`), with the rivals and the machine they rival (`machine.json`).
pub(crate) fn next_recording(r: &Request, events: Events<'_>) -> Result<Plan, Error> {
    let set = r.recordings.load()?;
    let out = out_dir(&r.out, &format!("{}-next", r.recordings.stem()));
    let reads = r.recordings.paths().into_iter().chain(r.ecc.clone());
    let results = ResultSet::open(&out, Claim::new("next-recording", reads))?;
    let machine = match &r.ecc {
        Some(file) => {
            let (ecc, set2) = recordings::machine_and_scenarios(file, &r.recordings)?;
            set2.check(&ecc).map_err(|m| {
                Error::Input(format!(
                    "{}: does not reproduce the recordings: {m}",
                    file.display()
                ))
            })?;
            ecc
        }
        None => {
            let mut opts = exact::Options::default();
            opts.sat.algorithms = r.algorithms;
            exact::run(&set, None, &opts, events)?.synthesis.ecc
        }
    };
    let mut report = report(
        &set,
        &machine,
        &r.ambiguity,
        Some(results.staging()),
        events,
    )?;
    let found = &report.found;
    let json = export::json::to_string(&machine);
    let plans = [
        ("plan.csv", found.plan_csv(&set, &machine)),
        ("plan.txt", found.plan_text(&set, &machine)),
        ("machine.json", json),
    ];
    for (name, text) in plans {
        let path = results.staging().join(name);
        write_atomic(&path, text.as_bytes())?;
        report.files.push(path);
    }
    let files = publish(results, &report.files)?;
    Ok(Plan {
        report,
        set,
        machine,
        files,
    })
}
