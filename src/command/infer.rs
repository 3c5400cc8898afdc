//! `synth infer` of one machine: the least machine that reproduces the recordings (with the
//! size questions around it, `--dump-cnf`, and the ambiguity check), or with `--ltl` the main
//! job's verified machine. The noisy, modular and distributed modes are [`super::noisy`] and
//! [`super::modular`]; they read the same [`Request`].

use super::ambiguity::{self, Report};
use super::{out_dir, publish, read_negatives, verified_line, Spec};
use crate::export::{self, Format};
use crate::files::output_rule::Claim;
use crate::files::ResultSet;
use crate::pipeline::event::NOISY_HINT;
use crate::pipeline::explain::Explanation;
use crate::pipeline::limit::Limit;
use crate::pipeline::main_job::{self, Summary, VerifiedMachine};
use crate::pipeline::output::{check_exportable, write_size_questions, write_verified};
use crate::pipeline::summary::{InferSummary, MainSummary, INFER};
use crate::pipeline::{exact, Check, Error, Event, Events, Note, Recordings};
use crate::sat::Synthesis;
use crate::scenario::negative::NegativeScenario;
use crate::scenario::ScenarioSet;
use std::fmt;
use std::path::PathBuf;

/// The number of states from which exact synthesis hints at `--noisy`: more than the
/// controllers of the shipped cases need (at most 9), and where each further C starts to take
/// long.
const GLITCH_HINT_STATES: usize = 10;

/// What `synth infer` is asked, in every mode.
#[derive(Debug, Clone)]
pub(crate) struct Request {
    /// The recordings.
    pub recordings: Recordings,
    /// Formats to write.
    pub formats: Vec<Format>,
    /// The function block type's name.
    pub name: String,
    /// Output folder (default `out/<stem of the first trace file>`).
    pub out: Option<PathBuf>,
    /// The machine on stdout instead of a folder (`--out -`).
    pub to_stdout: bool,
    /// The SAT synthesis: algorithms, bounds, guard budget.
    pub sat: exact::SatOptions,
    /// `--plateau W`: fewer guard literals with more states.
    pub plateau: Option<usize>,
    /// The time limit of every mode.
    pub limit: Limit,
    /// `--ltl`/`--plant`: the properties the machine must satisfy in closed loop.
    pub spec: Option<Spec>,
    /// With `spec`: candidates at most, in each loop.
    pub max_iterations: usize,
    /// Files of negative scenarios.
    pub negatives: Vec<PathBuf>,
    /// The ambiguity check (`None`: `--no-ambiguity`).
    pub ambiguity: Option<crate::pipeline::ambiguity::Options>,
    /// `--dump-cnf DIR`.
    pub dump_cnf: Option<PathBuf>,
}

impl Request {
    /// The output folder, taken for this run before the search, so that a second run into it
    /// stops at once.
    pub fn open(&self) -> Result<ResultSet, Error> {
        Ok(ResultSet::open(&self.folder(), self.claim("infer"))?)
    }

    /// What the run reads, for the output rule.
    fn claim(&self, command: &'static str) -> Claim {
        let reads = (self.recordings.paths().into_iter())
            .chain(self.spec.iter().flat_map(Spec::paths))
            .chain(self.negatives.iter().cloned());
        Claim::new(command, reads).writing(&self.name)
    }

    /// The output folder's path.
    pub fn folder(&self) -> PathBuf {
        out_dir(&self.out, &self.recordings.stem())
    }

    /// The recordings, read, with their event.
    pub fn load(&self, events: Events<'_>) -> Result<ScenarioSet, Error> {
        let set = self.recordings.load()?;
        events(Event::Note(Note::Loaded(&set)));
        Ok(set)
    }

    /// With `spec`: the check, after the recordings were checked against the properties
    /// (recordings that violate one leave no machine to find), with what they say about them.
    pub fn loop_check(
        &self,
        set: &ScenarioSet,
        events: Events<'_>,
    ) -> Result<Option<(Check, Explanation)>, Error> {
        let Some(spec) = &self.spec else {
            return Ok(None);
        };
        let check = spec.check(set)?;
        // The recordings' verdicts speak of the closed loop only where the plant can produce
        // them.
        crate::pipeline::plant_check::check_plant(set, &check)?;
        let props = &check.problem.props;
        let recorded = crate::pipeline::explain::refuse_violations(set, props, &spec.ltl);
        let found = crate::pipeline::plant_check::refuse_violations(recorded, set, &check)?;
        events(Event::Note(Note::Explained {
            explanation: &found,
            properties: props.len(),
        }));
        Ok(Some((check, found)))
    }

    /// The exact loop's options with a check (also the closed loop of `--noisy --ltl`).
    pub fn loop_options(&self, negatives: Vec<NegativeScenario>) -> exact::Options {
        exact::Options {
            sat: exact::SatOptions {
                algorithms: self.sat.algorithms,
                max_states: self.sat.max_states,
                start_state: self.sat.start_state,
                ..exact::SatOptions::default()
            },
            max_iterations: self.max_iterations,
            negatives,
            ..exact::Options::default()
        }
    }

    /// With a check: the main job's verified machine for `set`.
    pub fn verified(
        &self,
        set: &ScenarioSet,
        (check, found): (&Check, &Explanation),
        negatives: Vec<NegativeScenario>,
        events: Events<'_>,
    ) -> Result<VerifiedMachine, Error> {
        let opts = main_job::Options {
            method: main_job::Method::Sat,
            exact: self.loop_options(negatives),
            limit: self.limit,
        };
        main_job::run(set, check, found, &opts, events)
    }
}

/// What `synth infer` found for one machine.
pub(crate) enum Inferred {
    /// The least machine for the recordings.
    Least(Box<Least>),
    /// With `--ltl`: the verified machine.
    Verified(Box<Verified>),
}

/// The least machine for the recordings, written.
pub(crate) struct Least {
    /// The machine and its figures.
    pub result: Synthesis,
    /// Seconds since the start when it was found.
    pub seconds: f64,
    /// The recordings.
    pub set: ScenarioSet,
    /// The files of `--dump-cnf`, published.
    pub dumped: Vec<PathBuf>,
    /// The ambiguity check, when it ran.
    pub ambiguity: Option<Report>,
    /// The files published (none with `--out -`).
    pub files: Vec<PathBuf>,
    /// With `--out -`: the machine in the one format asked.
    pub text: Option<String>,
    /// Seconds since the start when it was written.
    pub total_seconds: f64,
}

/// The size and how long it took.
impl fmt::Display for Least {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.result;
        let n = if r.guards_exact {
            ""
        } else {
            " (N not proven minimal)"
        };
        write!(
            f,
            "{:#}{n}\ntime {:.2} s (SAT {:.2} s, guards {:.2} s); replayed {} scenarios: all reproduced",
            r.size,
            self.seconds,
            r.stats.sat_seconds,
            r.stats.guard_seconds,
            self.set.scenarios.len()
        )
    }
}

impl Least {
    /// The `--json` summary.
    pub fn summary(&self) -> InferSummary {
        let r = &self.result;
        InferSummary {
            format: INFER,
            size: r.size,
            guards_proven_minimal: r.guards_exact,
            transitions_proven_minimal: r.transitions_exact,
            scenarios: self.set.scenarios.len(),
            seconds: self.total_seconds,
            stats: r.stats.clone(),
            files: self.files.clone(),
            ambiguity: (self.ambiguity.as_ref()).map(|a| a.summary(&self.set, &r.ecc)),
        }
    }
}

/// With `--ltl`: the verified machine, written.
pub(crate) struct Verified {
    /// The machine, its certificate and summary.
    pub verified: VerifiedMachine,
    /// Scenarios reproduced.
    pub scenarios: usize,
    /// The files published.
    pub files: Vec<PathBuf>,
}

impl Verified {
    /// The `--json` summary.
    pub fn summary(&self) -> MainSummary {
        MainSummary::new(&self.verified.summary, Some(self.files.clone()))
    }
}

/// The verdict and the size (and for a machine not from the exact loop, how it was found).
impl fmt::Display for Verified {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let v = &self.verified;
        let properties = v.certificate.report.properties.len();
        writeln!(f, "{}", verified_line(properties, self.scenarios))?;
        match &v.summary {
            Summary::Exact(e) => write!(f, "{:#}; {} candidates", e.size, e.iterations.len()),
            s => write!(f, "{:#}\n{s}", s.size()),
        }
    }
}

/// `synth infer` of one machine (module documentation).
pub(crate) fn run(r: &Request, events: Events<'_>) -> Result<Inferred, Error> {
    let set = r.load(events)?;
    check_exportable(&set, &r.name, &r.formats, &r.recordings)?;
    let check = r.loop_check(&set, events)?;
    let negatives = read_negatives(&r.negatives, &set, events)?;
    // Rivals are searched without the negative scenarios, so they could be machines the user
    // ruled out: no verdict rather than a wrong one.
    if r.ambiguity.is_some() && !negatives.is_empty() {
        events(Event::Note(Note::AmbiguitySkipped));
    }
    let results = match r.to_stdout {
        true => None,
        false => Some(r.open()?),
    };
    match (check, results) {
        (Some((check, found)), Some(results)) => {
            let v = r.verified(&set, (&check, &found), negatives, events)?;
            let provenance = r.spec.as_ref().expect("a check").provenance(&r.name);
            let summary = MainSummary::new(&v.summary, None);
            let staged = write_verified(
                results.staging(),
                &r.formats,
                &v.ecc,
                &v.certificate,
                &provenance,
                &summary,
            )?;
            Ok(Inferred::Verified(Box::new(Verified {
                files: publish(results, &staged)?,
                scenarios: set.scenarios.len(),
                verified: v,
            })))
        }
        (Some(_), None) => Err(Error::Bug("--out - with --ltl is refused".into())),
        (None, results) => Ok(Inferred::Least(Box::new(least(
            r, set, negatives, results, events,
        )?))),
    }
}

/// The least machine, its size questions, ambiguity check and files.
fn least(
    r: &Request,
    set: ScenarioSet,
    negatives: Vec<NegativeScenario>,
    results: Option<ResultSet>,
    events: Events<'_>,
) -> Result<Least, Error> {
    let opts = exact::Options {
        sat: r.sat.clone(),
        negatives,
        ..exact::Options::default()
    };
    let result = synthesize(r, &set, &opts, events)?;
    let seconds = r.limit.elapsed();
    let ambiguity_check = |results: Option<&ResultSet>, events: Events<'_>| match (
        &r.ambiguity,
        opts.negatives.is_empty(),
    ) {
        (Some(a), true) => {
            let dir = results.map(ResultSet::staging);
            ambiguity::report(&set, &result.ecc, a, dir, events).map(Some)
        }
        _ => Ok(None),
    };
    let Some(results) = results else {
        let format = super::export::stdout_format(&r.formats);
        let text = export::text(&result.ecc, &r.name, format)?;
        let ambiguity = ambiguity_check(None, events)?;
        return Ok(Least {
            total_seconds: r.limit.elapsed(),
            result,
            seconds,
            set,
            dumped: Vec::new(),
            ambiguity,
            files: Vec::new(),
            text: Some(text),
        });
    };
    let dumped = match &r.dump_cnf {
        Some(dir) => dump_cnf(&set, &opts.sat, &result, dir, r.claim("infer --dump-cnf"))?,
        None => Vec::new(),
    };
    let mut staged = export::write_all(&result.ecc, results.staging(), &r.name, &r.formats)?;
    let ambiguity = ambiguity_check(Some(&results), events)?;
    staged.extend(ambiguity.iter().flat_map(|a| a.files.clone()));
    Ok(Least {
        files: publish(results, &staged)?,
        total_seconds: r.limit.elapsed(),
        result,
        seconds,
        set,
        dumped,
        ambiguity,
        text: None,
    })
}

/// The least machine for the recordings (and `--plateau`'s search on the guard size), within
/// the time limit, with the hint at `--noisy` where the recordings look glitchy.
fn synthesize(
    r: &Request,
    set: &ScenarioSet,
    opts: &exact::Options,
    events: Events<'_>,
) -> Result<Synthesis, Error> {
    let until = |deadline| {
        let mut o = opts.clone();
        o.sat.deadline = deadline;
        o
    };
    let first = r
        .limit
        .run(&mut glitch_hint(events), |d, events| {
            exact::run(set, None, &until(d), events)
        })
        .map_err(suggest_noisy)?
        .synthesis;
    match r.plateau {
        Some(width) => r.limit.run(events, |d, events| {
            exact::plateau(set, &until(d), first, width, events)
        }),
        None => Ok(first),
    }
}

/// A contradiction in recordings read as exact: most often a scan-cycle glitch of the logger,
/// which `--noisy` corrects, so the message says so.
fn suggest_noisy(e: Error) -> Error {
    use crate::scenario::ScenarioError;
    match e {
        Error::Scenario(ScenarioError::Contradiction(_)) => {
            Error::Input(format!("{e}\n{NOISY_HINT}"))
        }
        e => e,
    }
}

/// Passes every event on, and once the search climbs to [`GLITCH_HINT_STATES`] states the
/// hint at `--noisy`: glitches in a log read as exact each cost states, so a climb this high
/// is the sign.
fn glitch_hint<'e>(events: Events<'e>) -> impl FnMut(Event<'_>) + 'e {
    use crate::sat::{Bound, Step};
    let mut hinted = false;
    move |e| {
        let c = match &e {
            Event::Solver(Step::TryingStates { c, .. }) => Some(*c),
            Event::Solver(Step::Trying {
                bound: Bound::C,
                value,
            }) => Some(*value),
            _ => None,
        };
        events(e);
        if c.is_some_and(|c| c >= GLITCH_HINT_STATES) && !hinted {
            hinted = true;
            events(Event::Note(Note::GlitchHint));
        }
    }
}

/// `--dump-cnf DIR`: the size questions around the minimum as DIMACS files, each answered by
/// a fresh solver on exactly the formula written (`verdicts.txt`); the files published.
fn dump_cnf(
    set: &ScenarioSet,
    sat: &exact::SatOptions,
    result: &Synthesis,
    dir: &std::path::Path,
    claim: Claim,
) -> Result<Vec<PathBuf>, Error> {
    let results = ResultSet::open(dir, claim)?;
    let staged = write_size_questions(results.staging(), set, sat, &result.size)?;
    publish(results, &staged)
}
