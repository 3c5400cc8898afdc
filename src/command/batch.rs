//! `synth batch`: one reconstruction per PLC over a folder of logs, each machine in its
//! folder, and one summary table (`summary.csv`, `summary.json`).

use super::{out_dir, Spec};
use crate::export::Format;
use crate::files::output_rule::Claim;
use crate::files::ResultSet;
use crate::ingest::Mapping;
use crate::pipeline::batch::{self, Outcome, VerificationSetup};
use crate::pipeline::summary::BatchSummary;
use crate::pipeline::{exact, recordings, Error, Event, Events, Note};
use std::fmt;
use std::path::PathBuf;
use std::time::Duration;

/// What `synth batch` is asked.
pub(crate) struct Request {
    /// The folder of logs: each log file and each subfolder of them is one PLC.
    pub logs: PathBuf,
    /// The address mapping of raw logs.
    pub map: Option<PathBuf>,
    /// The properties every machine must satisfy.
    pub spec: Option<Spec>,
    /// Output folder (default `out/<name of the logs folder>`).
    pub out: Option<PathBuf>,
    /// Formats to write for every machine.
    pub formats: Vec<Format>,
    /// The function block type's name.
    pub name: String,
    /// The exact synthesis of each PLC.
    pub exact: exact::Options,
    /// The time each PLC may take.
    pub limit: Duration,
    /// PLCs reconstructed at once (default: all cores).
    pub threads: Option<usize>,
}

/// What a batch wrote.
pub(crate) struct Done {
    /// The rows and the files.
    pub summary: batch::Summary,
    /// The files published.
    pub files: Vec<PathBuf>,
}

/// The summary as a Markdown table.
impl fmt::Display for Done {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "| PLC | status | scenarios | steps | C | K | T | N | seconds |"
        )?;
        write!(f, "|---|---|---|---|---|---|---|---|---|")?;
        let cell = |v: Option<usize>| v.map_or("-".to_string(), |v| v.to_string());
        for r in &self.summary.rows {
            write!(
                f,
                "\n| {} | {} | {} | {} | {} | {} | {} | {} | {:.2} |",
                r.plc,
                r.status,
                r.scenarios,
                r.steps,
                cell(r.c),
                cell(r.k),
                cell(r.t),
                cell(r.n),
                r.seconds
            )?;
        }
        Ok(())
    }
}

impl Done {
    /// The `--json` summary (the same as `summary.json`).
    pub fn summary(&self) -> BatchSummary {
        self.summary.summary()
    }

    /// With a PLC left without a machine: the failure that says which.
    pub fn failure(&self) -> Option<Error> {
        self.summary.failure()
    }
}

/// `synth batch`: every PLC, then the summary; `done` hears of each PLC as it ends (from the
/// threads that reconstruct them).
pub(crate) fn run(
    r: &Request,
    events: Events<'_>,
    done: &(dyn Fn(&Outcome) + Sync),
) -> Result<Done, Error> {
    let mapping = match &r.map {
        Some(m) => Some(Mapping::read(m)?),
        None => None,
    };
    let plcs = batch::plcs(&r.logs)?;
    let verification = match &r.spec {
        Some(spec) => Some(VerificationSetup {
            ltl: spec.ltl.clone(),
            plant: spec.plant.clone(),
            nusmv: spec.nusmv.locate()?,
        }),
        None => None,
    };
    let out = out_dir(&r.out, &recordings::stem(&r.logs));
    let reads = [r.logs.clone()]
        .into_iter()
        .chain(r.map.clone())
        .chain(r.spec.iter().flat_map(super::Spec::paths))
        .chain(plcs.iter().map(|p| p.source.clone()));
    let results = ResultSet::open(&out, Claim::new("batch", reads).writing(&r.name))?;
    let threads = r.threads.unwrap_or_else(rayon::current_num_threads);
    events(Event::Note(Note::BatchStarted {
        plcs: plcs.len(),
        logs: &r.logs,
        threads,
        verified: verification.is_some(),
    }));
    let verification = verification.as_ref();
    let outcomes = batch::run(
        &plcs,
        mapping.as_ref(),
        verification,
        &r.exact,
        r.limit,
        threads,
        done,
    )?;
    let summary = batch::write_results(
        results.staging(),
        &r.logs,
        &outcomes,
        &r.name,
        &r.formats,
        verification,
    )?;
    let files = super::publish(results, &summary.files)?;
    Ok(Done { summary, files })
}
