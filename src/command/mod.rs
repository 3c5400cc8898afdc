//! What each command of `synth` does between its arguments and what it prints: the files it
//! reads, the pipeline it calls, the result folder it writes.
//!
//! In: a request per command, in the library's terms (paths, formats, the options of the
//! pipelines), as the command line ([`crate::cli`]) builds it from its arguments. Out: the
//! files written and an outcome whose [`std::fmt::Display`] is the lines the command prints
//! on stdout, with the typed summary of `--json` ([`crate::pipeline::summary`]). Progress
//! comes as [`Event`]s, as from the pipelines. Failures are [`Error`]s with a
//! [`crate::pipeline::Class`]: the command line only maps that to an exit code.
//!
//! One module per command; what several share is here and in [`ambiguity`].

pub(crate) mod ambiguity;
pub(crate) mod batch;
pub(crate) mod conform;
pub(crate) mod convert;
pub(crate) mod diff;
pub(crate) mod events;
pub(crate) mod export;
pub(crate) mod infer;
pub(crate) mod ingest;
pub(crate) mod learn;
pub(crate) mod learn_plant;
pub(crate) mod live;
pub(crate) mod main_job;
pub(crate) mod modular;
pub(crate) mod noisy;
pub(crate) mod verify;

use crate::files::ResultSet;
use crate::pipeline::{self, Check, Error, Event, Events, Note, Nusmv, Problem};
use crate::scenario::negative::{self, NegativeScenario};
use crate::scenario::ScenarioSet;
use std::path::{Path, PathBuf};

/// NuSMV as the command line names it, located only when a command needs it (a run that
/// fails on its input before says so, with or without NuSMV).
#[derive(Debug, Clone)]
pub(crate) struct Tool {
    /// The binary; default: `$NUSMV`, then `PATH`, then the install script's cache.
    pub path: Option<PathBuf>,
    /// Seconds NuSMV may spend on one closed-loop model.
    pub timeout: f64,
}

impl Tool {
    /// Locates NuSMV; fails with the install hint.
    pub fn locate(&self) -> Result<Nusmv, Error> {
        pipeline::nusmv(self.path.as_deref(), self.timeout)
    }
}

/// The properties a machine must satisfy in closed loop with a plant, and NuSMV to check it.
#[derive(Debug, Clone)]
pub(crate) struct Spec {
    /// The LTL properties.
    pub ltl: PathBuf,
    /// The surrogate plant (SMV).
    pub plant: PathBuf,
    /// NuSMV.
    pub nusmv: Tool,
    /// Plant signals coupled with controller signals of other names (`--couple`).
    pub couple: Vec<crate::smv::composition::Couple>,
    /// The text of a plant learned on the way (the main job's `--learn-plant`): `plant` is
    /// then the file it will be published as, named in messages and never read.
    pub learned: Option<String>,
}

impl Spec {
    /// The problem over the interface `inputs`, `outputs`.
    pub fn problem(&self, inputs: &[String], outputs: &[String]) -> Result<Problem, Error> {
        let (ltl, plant, couple) = (&self.ltl, &self.plant, &self.couple);
        Ok(match &self.learned {
            Some(text) => Problem::load_text(ltl, plant, text, inputs, outputs, couple)?,
            None => Problem::load_by(ltl, plant, inputs, outputs, couple)?,
        })
    }

    /// The problem over the interface of `set`, and the NuSMV that checks it.
    pub fn check(&self, set: &ScenarioSet) -> Result<Check, Error> {
        let problem = self.problem(&set.inputs, &set.outputs)?;
        Ok(Check::new(problem, self.nusmv.locate()?))
    }

    /// The files the properties are read from (a learned plant is not read).
    pub fn paths(&self) -> Vec<PathBuf> {
        let plant = self.learned.is_none().then(|| self.plant.clone());
        [self.ltl.clone()].into_iter().chain(plant).collect()
    }

    /// Who made a verified machine, for its `verification.txt`.
    pub fn provenance<'a>(&'a self, name: &'a str) -> pipeline::output::Provenance<'a> {
        pipeline::output::Provenance {
            name,
            plant_file: &self.plant,
            spec_file: &self.ltl,
        }
    }
}

/// `out`, or `out/<stem>`.
pub(crate) fn out_dir(out: &Option<PathBuf>, stem: &str) -> PathBuf {
    out.clone()
        .unwrap_or_else(|| PathBuf::from("out").join(stem))
}

/// Publishes the staged results; the published paths of `staged`.
pub(crate) fn publish(results: ResultSet, staged: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let files = staged.iter().map(|f| results.published(f)).collect();
    results.publish()?;
    Ok(files)
}

/// Refuses to run when an output path names a folder (found only when the first files of
/// the result were already written), or one of the input files (the output rule,
/// [`crate::files::output_rule`]).
pub(crate) fn refuse_overwrite<P: AsRef<Path>, Q: AsRef<Path>>(
    outputs: &[P],
    inputs: &[Q],
) -> Result<(), Error> {
    for out in outputs.iter().map(AsRef::as_ref) {
        if out.is_dir() {
            return Err(Error::Input(format!(
                "the output {} is a folder; give a file name (or move the folder away)",
                out.display()
            )));
        }
    }
    crate::files::output_rule::refuse_inputs(outputs, inputs).map_err(|e| Error::Folder(e.into()))
}

/// The negative scenarios in `files`, read over the interface of `set` (an event each).
pub(crate) fn read_negatives(
    files: &[PathBuf],
    set: &ScenarioSet,
    events: Events<'_>,
) -> Result<Vec<NegativeScenario>, Error> {
    let mut all = Vec::new();
    for file in files {
        let negs = negative::read(file, &set.inputs, &set.outputs, &set.initial_outputs)?;
        events(Event::Note(Note::Negatives {
            count: negs.len(),
            file,
        }));
        all.extend(negs);
    }
    Ok(all)
}

/// The line that says a controller is verified (only ever printed after NuSMV said so).
pub(crate) fn verified_line(properties: usize, scenarios: usize) -> String {
    let holds = if properties == 1 {
        "the property holds".to_string()
    } else {
        format!("all {properties} properties hold")
    };
    let s = if scenarios == 1 { "" } else { "s" };
    format!("verified: {holds} (NuSMV), {scenarios} scenario{s} reproduced")
}

/// A bad row of a raw log: the message says how to go on.
pub(crate) fn lenient_hint(e: Error, row: bool) -> Error {
    match row {
        true => Error::Noted {
            error: Box::new(e),
            notes: vec!["--lenient skips bad rows and counts them instead".into()],
        },
        false => e,
    }
}
