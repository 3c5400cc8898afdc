//! The main job (`synth --ltl SPEC --plant PLANT`) from files to its result folder: the
//! recordings, the problem and what the recordings say about it, the negative scenarios, the
//! verified machine ([`crate::pipeline::main_job::run`]) in every format with NuSMV's report
//! and `summary.json`, and the ambiguity report when asked.
//!
//! With `--learn-plant` the plant is not read but learned from the same recordings
//! ([`crate::plant::learn`], as `synth learn-plant` does) before the problem is read; it is
//! published with the result as [`LEARNED_PLANT`], its figures in `summary.json`. Recordings
//! it cannot be learned from stop the job before the output folder is taken.

use super::ambiguity::{report_verified, Report};
use super::learn_plant::{self, learn_set, read_observers};
use super::{out_dir, publish, read_negatives, verified_line, Spec};
use crate::export::Format;
use crate::files::output_rule::Claim;
use crate::files::ResultSet;
use crate::pipeline::explain;
use crate::pipeline::limit::Limit;
use crate::pipeline::main_job::{self, VerifiedMachine};
use crate::pipeline::output::{check_exportable, write_verified};
use crate::pipeline::recordings::stem;
use crate::pipeline::summary::{LearnedPlantSummary, MainSummary};
use crate::pipeline::{
    ambiguity, exact, plant_check, Check, Error, Event, Events, Note, Recordings,
};
use crate::scenario::ScenarioSet;
use std::fmt;
use std::path::{Path, PathBuf};

/// The name of a learned plant in the output folder (`--learn-plant`).
pub(crate) const LEARNED_PLANT: &str = "plant.smv";

/// What the main job is asked.
pub(crate) struct Request {
    /// The properties, the plant and NuSMV.
    pub spec: Spec,
    /// Learn the plant from the recordings with these options instead of reading the
    /// spec's (`--learn-plant`).
    pub learn_plant: Option<learn_plant::Options>,
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
    /// The plant learned on the way, when asked.
    pub learned_plant: Option<LearnedPlantSummary>,
}

impl Done {
    /// The `--json` summary.
    pub fn summary(&self) -> MainSummary {
        MainSummary::new(&self.verified.summary, Some(self.files.clone()))
            .with_learned_plant(self.learned_plant.clone())
    }
}

/// The learned plant, the ambiguity report, then the verdict, the warnings, the size and how
/// it was found.
impl fmt::Display for Done {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(p) = &self.learned_plant {
            writeln!(f, "{}", learned_note(p))?;
        }
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
    let out = out_dir(&r.out, &stem(&r.spec.ltl));
    let read = read_problem(r, &recordings, &out, events)?;
    let (set, problem, spec) = (read.set, read.problem, read.spec);
    let negatives = read_negatives(&r.negatives, &set, events)?;
    if !negatives.is_empty() && !matches!(r.method, main_job::Method::Sat) {
        return Err(Error::Usage(
            "--negative takes --method sat (the search does not read negative scenarios)".into(),
        ));
    }
    check_exportable(&set, &r.name, &r.formats, &recordings)?;
    // Taken before the search: a second run into the same folder stops now, not at the end.
    let results = ResultSet::open(&out, claim(r, &recordings, &spec))?;
    let (check, found) = checked(r, &set, problem, &spec, events)?;
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
    let summary =
        MainSummary::new(&verified.summary, None).with_learned_plant(read.learned_plant.clone());
    let mut staged = write_verified(
        results.staging(),
        &r.formats,
        &verified.ecc,
        &verified.certificate,
        &spec.provenance(&r.name),
        &summary,
    )?;
    let ambiguity = match &r.ambiguity {
        Some(a) => Some(report_verified(
            &set,
            &verified.ecc,
            a,
            &check,
            results.staging(),
            events,
        )?),
        None => None,
    };
    staged.extend(ambiguity.iter().flat_map(|a| a.files.clone()));
    staged.extend(staged_plant(&results, &spec)?);
    Ok(Done {
        files: publish(results, &staged)?,
        scenarios: set.scenarios.len(),
        verified,
        out,
        ambiguity,
        learned_plant: read.learned_plant,
    })
}

/// The check of the problem with NuSMV, and what the recordings say of the properties.
/// Recordings that violate a property are refused even where NuSMV cannot be run; only the
/// claim about controllers waits for NuSMV's replay of the recordings on the plant, and the
/// recordings' verdicts speak of the closed loop only where the plant can produce them.
fn checked(
    r: &Request,
    set: &ScenarioSet,
    problem: crate::verify::Problem,
    spec: &Spec,
    events: Events<'_>,
) -> Result<(Check, explain::Explanation), Error> {
    let recorded = explain::refuse_violations(set, &problem.props, &r.spec.ltl);
    let (nusmv, recorded) = match (spec.nusmv.locate(), recorded) {
        (Ok(nusmv), recorded) => (nusmv, recorded),
        (Err(e), Err(mut violate)) => {
            violate.unreplayed = Some(format!("a step NuSMV could not check: {e}"));
            return Err(violate.into());
        }
        (Err(e), Ok(_)) => return Err(e),
    };
    let check = Check::new(problem, nusmv);
    plant_check::check_plant(set, &check)?;
    let found = plant_check::refuse_violations(recorded, set, &check)?;
    events(Event::Note(Note::Explained {
        explanation: &found,
        properties: check.problem.props.len(),
    }));
    Ok((check, found))
}

/// The learned plant, when one was learned, written into the result set's staging folder.
fn staged_plant(results: &ResultSet, spec: &Spec) -> Result<Option<PathBuf>, Error> {
    let Some(text) = &spec.learned else {
        return Ok(None);
    };
    let file = results.staging().join(LEARNED_PLANT);
    crate::files::write_atomic(&file, text.as_bytes())?;
    Ok(Some(file))
}

/// What the main job claims of its output folder: it reads the recordings, the properties,
/// the plant it does not learn, the observers and assumptions and the negative scenarios, and writes the
/// machine's files (and the learned plant).
fn claim(r: &Request, recordings: &Recordings, spec: &Spec) -> Claim {
    let learner = (r.learn_plant.iter()).flat_map(|l| [l.observe.clone(), l.assume.clone()]);
    let reads = (recordings.paths().into_iter())
        .chain(spec.paths())
        .chain(learner.flatten())
        .chain(r.negatives.iter().cloned());
    let claim = Claim::new("main", reads).writing(&r.name);
    match spec.learned {
        Some(_) => claim.naming(LEARNED_PLANT),
        None => claim,
    }
}

/// What [`read_problem`] read.
struct Read {
    /// The recordings.
    set: ScenarioSet,
    /// The problem.
    problem: crate::verify::Problem,
    /// The spec, with the learned plant when one was learned.
    spec: Spec,
    /// The learned plant's figures, when one was learned.
    learned_plant: Option<LearnedPlantSummary>,
}

/// The recordings, the plant learned from them when asked (to go into `out`), and the
/// problem, each with its event. (Recordings that violate a property leave no machine to
/// find: [`run`] refuses them before any synthesis, once the plant is known to produce them.)
fn read_problem(
    r: &Request,
    recordings: &Recordings,
    out: &Path,
    events: Events<'_>,
) -> Result<Read, Error> {
    let set = recordings.load()?;
    events(Event::Note(Note::Recordings {
        scenarios: set.scenarios.len(),
        steps: set.step_count(),
        from: &recordings.show(),
    }));
    let (spec, learned_plant) = match &r.learn_plant {
        Some(options) => {
            let (spec, summary) = learn_plant(r, &set, recordings, options, out)?;
            events(Event::Note(learned_note(&summary)));
            (spec, Some(summary))
        }
        None => (r.spec.clone(), None),
    };
    let problem = spec.problem(&set.inputs, &set.outputs)?;
    events(Event::Note(Note::Problem {
        properties: problem.props.len(),
        spec: &spec.ltl,
        plant: &spec.plant,
    }));
    let unaffected = problem.unaffected();
    if !unaffected.is_empty() {
        events(Event::Note(Note::Unaffected(&unaffected)));
    }
    Ok(Read {
        set,
        problem,
        spec,
        learned_plant,
    })
}

/// The plant of `set` (read from `recordings`) learned with `options`: the spec with it, as
/// the file it is published as in `out`, and its figures.
fn learn_plant(
    r: &Request,
    set: &ScenarioSet,
    recordings: &Recordings,
    options: &learn_plant::Options,
    out: &Path,
) -> Result<(Spec, LearnedPlantSummary), Error> {
    let observers = options.observe.as_deref().map(read_observers).transpose()?;
    let learned = learn_set(set, recordings, observers.as_ref(), options)?;
    let file = out.join(LEARNED_PLANT);
    let summary = LearnedPlantSummary {
        file: file.clone(),
        recordings: recordings.traces.clone(),
        observers: options.observe.clone(),
        slack: options.slack,
        scans: learned.steps,
        runs: learned.runs,
        sensors: learned.parts.len(),
        delayed: learned.parts.iter().filter(|p| p.wait_cap > 0).count(),
    };
    let spec = Spec {
        plant: file,
        learned: Some(learned.text),
        ..r.spec.clone()
    };
    Ok((spec, summary))
}

/// The progress line of a learned plant (also the first line the job prints).
fn learned_note(p: &LearnedPlantSummary) -> Note<'static> {
    Note::LearnedPlant {
        scans: p.scans,
        runs: p.runs,
        sensors: p.sensors,
        delayed: p.delayed,
    }
}
