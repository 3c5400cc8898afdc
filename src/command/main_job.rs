//! The main job (`synth --ltl SPEC --plant PLANT`) from files to its result folder: the
//! recordings, the problem and what the recordings say about it, the negative scenarios, the
//! verified machine ([`crate::pipeline::main_job::run`]) in every format with NuSMV's report
//! and `summary.json`, and the ambiguity report when asked.

use super::ambiguity::{report_verified, Report};
use super::{out_dir, publish, read_negatives, verified_line, Spec};
use crate::export::Format;
use crate::files::output_rule::Claim;
use crate::files::ResultSet;
use crate::pipeline::explain;
use crate::pipeline::limit::Limit;
use crate::pipeline::main_job::{self, VerifiedMachine};
use crate::pipeline::output::{check_exportable, write_verified};
use crate::pipeline::recordings::stem;
use crate::pipeline::summary::MainSummary;
use crate::pipeline::{
    ambiguity, exact, plant_check, Check, Error, Event, Events, Note, Recordings,
};
use crate::scenario::ScenarioSet;
use std::fmt;
use std::path::PathBuf;

/// What the main job is asked.
pub(crate) struct Request {
    /// The properties, the plant and NuSMV.
    pub spec: Spec,
    /// The recordings; without trace files, `<stem>.traces` beside the `--ltl` file.
    pub recordings: Recordings,
    /// Files of negative scenarios.
    pub negatives: Vec<PathBuf>,
    /// Output folder (default `out/<stem of the --ltl file>`).
    pub out: Option<PathBuf>,
    /// Formats to write.
    pub formats: Vec<Format>,
    /// The function block type's name.
    pub name: String,
    /// How to synthesize.
    pub method: main_job::Method,
    /// The exact loop (its negative scenarios and kept model are the job's).
    pub exact: exact::Options,
    /// The time limit.
    pub limit: Limit,
    /// The ambiguity check after synthesis, when asked.
    pub ambiguity: Option<ambiguity::Options>,
}

/// The main job's result, published.
pub(crate) struct Done {
    /// The machine, its certificate and summary.
    pub verified: VerifiedMachine,
    /// Scenarios reproduced.
    pub scenarios: usize,
    /// The output folder.
    pub out: PathBuf,
    /// The files published.
    pub files: Vec<PathBuf>,
    /// The ambiguity report, when asked.
    pub ambiguity: Option<Report>,
}

impl Done {
    /// The `--json` summary.
    pub fn summary(&self) -> MainSummary {
        MainSummary::new(&self.verified.summary, Some(self.files.clone()))
    }
}

/// The ambiguity report, then the verdict, the warnings, the size and how it was found.
impl fmt::Display for Done {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(a) = &self.ambiguity {
            write!(f, "{a}")?;
        }
        let v = &self.verified;
        let report = &v.certificate.report;
        writeln!(
            f,
            "{}",
            verified_line(report.properties.len(), self.scenarios)
        )?;
        report
            .warning_lines()
            .try_for_each(|w| writeln!(f, "{w}"))?;
        write!(f, "{:#}\n{}", v.summary.size(), v.summary)
    }
}

/// The recordings of the main job: those given, or `<stem>.traces` beside the `--ltl` file.
fn recordings(r: &Request) -> Result<Recordings, Error> {
    if !r.recordings.traces.is_empty() {
        return Ok(r.recordings.clone());
    }
    let ltl = &r.spec.ltl;
    let default = ltl.with_file_name(format!("{}.traces", stem(ltl)));
    if !default.is_file() {
        return Err(Error::Input(format!(
            "no --traces given and no default scenario file {} beside {}",
            default.display(),
            ltl.display()
        )));
    }
    Ok(Recordings {
        traces: vec![default],
        ..r.recordings.clone()
    })
}

/// The main job: the verified machine, written and published.
pub(crate) fn run(r: &Request, events: Events<'_>) -> Result<Done, Error> {
    let recordings = recordings(r)?;
    let (set, problem) = read_problem(r, &recordings, events)?;
    let negatives = read_negatives(&r.negatives, &set, events)?;
    if !negatives.is_empty() && !matches!(r.method, main_job::Method::Sat) {
        return Err(Error::Usage(
            "--negative takes --method sat (the search does not read negative scenarios)".into(),
        ));
    }
    check_exportable(&set, &r.name, &r.formats, &recordings)?;
    let out = out_dir(&r.out, &stem(&r.spec.ltl));
    // Taken before the search: a second run into the same folder stops now, not at the end.
    let reads = (recordings.paths().into_iter())
        .chain(r.spec.paths())
        .chain(r.negatives.iter().cloned());
    let results = ResultSet::open(&out, Claim::new("main", reads).writing(&r.name))?;
    // Recordings that violate a property are refused even where NuSMV cannot be run; only the
    // claim about controllers waits for NuSMV's replay of the recordings on the plant.
    let recorded = explain::refuse_violations(&set, &problem.props, &r.spec.ltl);
    let (nusmv, recorded) = match (r.spec.nusmv.locate(), recorded) {
        (Ok(nusmv), recorded) => (nusmv, recorded),
        (Err(e), Err(mut violate)) => {
            violate.unreplayed = Some(format!("a step NuSMV could not check: {e}"));
            return Err(violate.into());
        }
        (Err(e), Ok(_)) => return Err(e),
    };
    let check = Check::new(problem, nusmv);
    // The recordings' verdicts speak of the closed loop only where the plant can produce them.
    plant_check::check_plant(&set, &check)?;
    let found = plant_check::refuse_violations(recorded, &set, &check)?;
    events(Event::Note(Note::Explained {
        explanation: &found,
        properties: check.problem.props.len(),
    }));
    let opts = main_job::Options {
        method: r.method.clone(),
        exact: exact::Options {
            negatives,
            keep_failed_model: Some(out.join("closed_loop.last.smv")),
            ..r.exact.clone()
        },
        limit: r.limit,
    };
    let verified = main_job::run(&set, &check, &found, &opts, events)?;
    let summary = MainSummary::new(&verified.summary, None);
    let provenance = r.spec.provenance(&r.name);
    let (ecc, certificate) = (&verified.ecc, &verified.certificate);
    let mut staged = write_verified(
        results.staging(),
        &r.formats,
        ecc,
        certificate,
        &provenance,
        &summary,
    )?;
    let ambiguity = match &r.ambiguity {
        Some(a) => Some(report_verified(
            &set,
            ecc,
            a,
            &check,
            results.staging(),
            events,
        )?),
        None => None,
    };
    staged.extend(ambiguity.iter().flat_map(|a| a.files.clone()));
    Ok(Done {
        files: publish(results, &staged)?,
        scenarios: set.scenarios.len(),
        verified,
        out,
        ambiguity,
    })
}

/// The recordings and the problem, each with its event. (Recordings that violate a property
/// leave no machine to find: [`run`] refuses them before any synthesis, once the plant is
/// known to produce them.)
fn read_problem(
    r: &Request,
    recordings: &Recordings,
    events: Events<'_>,
) -> Result<(ScenarioSet, crate::verify::Problem), Error> {
    let set = recordings.load()?;
    events(Event::Note(Note::Recordings {
        scenarios: set.scenarios.len(),
        steps: set.step_count(),
        from: &recordings.show(),
    }));
    let problem = r.spec.problem(&set.inputs, &set.outputs)?;
    events(Event::Note(Note::Problem {
        properties: problem.props.len(),
        spec: &r.spec.ltl,
        plant: &r.spec.plant,
    }));
    let unaffected = problem.unaffected();
    if !unaffected.is_empty() {
        events(Event::Note(Note::Unaffected(&unaffected)));
    }
    Ok((set, problem))
}
