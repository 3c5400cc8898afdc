//! One reconstruction per PLC over a folder of logs (`synth batch`), on all cores.
//!
//! In: a folder whose entries are the PLCs ([`plcs`]): a log file (CSV or Parquet recordings,
//! or with a mapping a raw data-flow log) or a subfolder of them (a partition of a data set,
//! `plc=3/part-00000.parquet`, each file one scenario), and the exact method's options; with a
//! [`VerificationSetup`], the properties and plant every machine must satisfy in closed loop.
//! Out: an [`Outcome`] per PLC, in the folder's order: the machine (and NuSMV's certificate),
//! or why there is none. A PLC that fails does not stop the others. [`write_results`] writes
//! every machine into its folder and the [`Summary`] (one [`Row`] per PLC) as `summary.csv`
//! and `summary.json`.
//!
//! Parallel over PLCs with rayon: each reconstruction is one SAT solver (and one NuSMV
//! dialogue), so `threads` PLCs run at once. Scaling beyond one machine is left to the engines
//! built for it: a Spark or DataFusion job writes one Parquet partition per
//! PLC, and an array job of `synth batch` runs over partitions.

use super::exact::{self, Certificate};
use super::recordings::{is_log, logs_in, Recordings};
use super::{limit, Check, Error};
use crate::ingest::Mapping;
use crate::nusmv::Nusmv;
use crate::sat::Synthesis;
use crate::scenario::ScenarioSet;
use crate::verify::Problem;
use rayon::prelude::*;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// One PLC: its name (the file's stem or the folder's name) and where its logs are.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Plc {
    /// The PLC's name: the log file's stem or the subfolder's name.
    pub(crate) name: String,
    /// The PLC's log file or its folder of logs.
    pub(crate) source: PathBuf,
}

/// The properties and plant every machine is checked against (each PLC's interface gives its
/// own closed loop), and the NuSMV that checks.
#[derive(Debug, Clone)]
pub(crate) struct VerificationSetup {
    /// The LTL specification file with the properties.
    pub(crate) ltl: PathBuf,
    /// The plant model file (SMV) every machine is closed in a loop with.
    pub(crate) plant: PathBuf,
    /// The NuSMV that checks every PLC's closed loop.
    pub(crate) nusmv: Nusmv,
}

/// A machine for one PLC.
#[derive(Debug, Clone)]
pub(crate) struct Reconstruction {
    /// The minimal machine found by exact synthesis, with its figures.
    pub(crate) synthesis: Synthesis,
    /// With a [`VerificationSetup`]: NuSMV's word that every property holds.
    pub(crate) certificate: Option<Certificate>,
}

/// What one PLC gave.
#[derive(Debug)]
pub(crate) struct Outcome {
    /// The PLC this is the outcome of.
    pub(crate) plc: Plc,
    /// Scenarios and steps read (zero when the logs could not be read).
    pub(crate) scenarios: usize,
    /// Steps read in all scenarios.
    pub(crate) steps: usize,
    /// The machine, or why there is none (read, synthesis, time limit or verification failed).
    pub(crate) result: Result<Reconstruction, Error>,
    /// Wall-clock seconds for this PLC: reading, synthesis and verification.
    pub(crate) seconds: f64,
}

/// The PLCs of `dir`: every log file (named by its stem) and every subfolder holding logs
/// (named by the folder), sorted by name. Two entries with one name are refused.
pub(crate) fn plcs(dir: &Path) -> Result<Vec<Plc>, Error> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| Error::Input(format!("{}: {e}", dir.display())))?;
    let mut found = Vec::new();
    for entry in entries {
        let path = entry
            .map_err(|e| Error::Input(format!("{}: {e}", dir.display())))?
            .path();
        let Some(file_name) = path.file_name().map(|n| n.to_string_lossy().into_owned()) else {
            continue;
        };
        if file_name.starts_with(['.', '_']) {
            continue;
        }
        let name = if path.is_dir() {
            file_name
        } else if is_log(&path) {
            super::recordings::stem(&path)
        } else {
            continue;
        };
        found.push(Plc { name, source: path });
    }
    found.sort_by(|a, b| a.name.cmp(&b.name));
    if let Some(w) = found.windows(2).find(|w| w[0].name == w[1].name) {
        return Err(Error::Input(format!(
            "{} and {} would both be PLC {}: rename one",
            w[0].source.display(),
            w[1].source.display(),
            crate::quote::quote(&w[0].name)
        )));
    }
    if found.is_empty() {
        return Err(Error::Input(format!(
            "{}: no logs (.csv, .csv.gz, .parquet) and no folders of them",
            dir.display()
        )));
    }
    Ok(found)
}

/// The scenarios of one PLC: its recordings, or with `mapping` its raw logs through the
/// ingestion (each file one scenario).
pub(crate) fn load(plc: &Plc, mapping: Option<&Mapping>) -> Result<ScenarioSet, Error> {
    let Some(mapping) = mapping else {
        return Recordings::files(vec![plc.source.clone()]).load();
    };
    let files = if plc.source.is_dir() {
        logs_in(&plc.source)?
    } else {
        vec![plc.source.clone()]
    };
    let mut set: Option<ScenarioSet> = None;
    for file in files {
        let (s, _) = crate::ingest::read_scenarios(&file, mapping, false)
            .map_err(|e| Error::Input(e.to_string()))?;
        match &mut set {
            None => set = Some(s),
            Some(all) => all.merge(s)?,
        }
    }
    set.ok_or_else(|| Error::Input(format!("{}: no logs in it", plc.source.display())))
}

/// Reconstructs every PLC, `threads` at a time, each within `limit`.
pub(crate) fn run(
    plcs: &[Plc],
    mapping: Option<&Mapping>,
    verification: Option<&VerificationSetup>,
    opts: &exact::Options,
    limit: Duration,
    threads: usize,
    done: &(dyn Fn(&Outcome) + Sync),
) -> Result<Vec<Outcome>, Error> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
        .map_err(|e| Error::Bug(format!("the thread pool: {e}")))?;
    let outcomes: Vec<Outcome> = pool.install(|| {
        plcs.par_iter()
            .map(|plc| {
                let outcome = one(plc, mapping, verification, opts, limit);
                done(&outcome);
                outcome
            })
            .collect()
    });
    if outcomes.iter().any(|o| {
        matches!(
            o.result,
            Err(Error::TimeLimit { .. } | Error::Interrupted { .. })
        )
    }) {
        // A PLC given up on at its time limit left its loop running: its NuSMV must not
        // outlive us. Every other PLC is done by now.
        crate::nusmv::kill_all_children();
    }
    Ok(outcomes)
}

fn one(
    plc: &Plc,
    mapping: Option<&Mapping>,
    verification: Option<&VerificationSetup>,
    opts: &exact::Options,
    limit: Duration,
) -> Outcome {
    let t0 = Instant::now();
    let mut outcome = Outcome {
        plc: plc.clone(),
        scenarios: 0,
        steps: 0,
        result: Err(Error::Bug("not run".into())),
        seconds: 0.0,
    };
    outcome.result = load(plc, mapping).and_then(|set| {
        outcome.scenarios = set.scenarios.len();
        outcome.steps = set.step_count();
        reconstruct(&set, verification, opts, limit)
    });
    outcome.seconds = t0.elapsed().as_secs_f64();
    outcome
}

fn reconstruct(
    set: &ScenarioSet,
    verification: Option<&VerificationSetup>,
    opts: &exact::Options,
    limit: Duration,
) -> Result<Reconstruction, Error> {
    let Some(v) = verification else {
        let exact = limit::within(limit, &mut |_| {}, |deadline, events| {
            let mut opts = opts.clone();
            opts.sat.deadline = deadline;
            exact::run(set, None, &opts, events)
        })?;
        return Ok(Reconstruction {
            synthesis: exact.synthesis,
            certificate: None,
        });
    };
    let problem = Problem::load(&v.ltl, &v.plant, &set.inputs, &set.outputs)?;
    let check = Check::new(problem, v.nusmv.clone());
    let exact = limit::exact_within(set, &check, opts, limit, &mut |_| {})?;
    Ok(Reconstruction {
        synthesis: exact.synthesis,
        certificate: exact.certificate,
    })
}

/// Writes one PLC's machine into `dir` (created): the exports in `formats` named `name`, and
/// with a verification NuSMV's `verification.txt`. Returns the files written.
pub(crate) fn write(
    dir: &Path,
    r: &Reconstruction,
    name: &str,
    formats: &[crate::export::Format],
    verification: Option<&VerificationSetup>,
) -> Result<Vec<PathBuf>, Error> {
    super::output::create_dir(dir)?;
    let mut files = crate::export::write_all(&r.synthesis.ecc, dir, name, formats)?;
    if let (Some(cert), Some(v)) = (&r.certificate, verification) {
        let provenance = super::output::Provenance {
            name,
            plant_file: &v.plant,
            spec_file: &v.ltl,
        };
        files.extend(super::output::write_certificate(
            dir,
            name,
            cert,
            &provenance,
        )?);
    }
    Ok(files)
}

/// One row of the summary: a PLC, its figures and whether it has a machine.
#[derive(Debug, Clone, serde::Serialize, schemars::JsonSchema)]
pub struct Row {
    /// The PLC's name.
    pub(crate) plc: String,
    /// Its log file or folder.
    pub(crate) source: String,
    /// `ok`, `verified` or `failed`.
    pub(crate) status: &'static str,
    /// Scenarios read.
    pub(crate) scenarios: usize,
    /// Steps read.
    pub(crate) steps: usize,
    /// States of the machine.
    #[serde(rename = "C")]
    pub(crate) c: Option<usize>,
    /// Largest out-degree of the machine.
    #[serde(rename = "K")]
    pub(crate) k: Option<usize>,
    /// Transitions of the machine.
    #[serde(rename = "T")]
    pub(crate) t: Option<usize>,
    /// Guard literals of the machine.
    #[serde(rename = "N")]
    pub(crate) n: Option<usize>,
    /// Wall-clock seconds for this PLC.
    pub(crate) seconds: f64,
    /// Why a PLC has no machine.
    pub(crate) message: String,
}

/// What a batch wrote: one row per PLC, and the files.
#[derive(Debug, Clone)]
pub(crate) struct Summary {
    /// The folder of logs.
    pub(crate) logs: PathBuf,
    /// One row per PLC, in the folder's order.
    pub(crate) rows: Vec<Row>,
    /// Every file written: the machines' and the summaries.
    pub(crate) files: Vec<PathBuf>,
    /// Whether every PLC without a machine failed for want of one within the limits.
    only_no_machine: bool,
}

impl Summary {
    /// `summary.json`: the folder of logs and the rows.
    pub(crate) fn summary(&self) -> super::summary::BatchSummary {
        super::summary::BatchSummary {
            format: super::summary::BATCH,
            logs: self.logs.clone(),
            plcs: self.rows.clone(),
        }
    }

    /// `summary.csv`: the rows (RFC 4180 quoting where a cell needs it).
    pub(crate) fn to_csv(&self) -> String {
        use crate::files::csv::quote_cell as quote;
        let cell = |v: Option<usize>| v.map_or(String::new(), |v| v.to_string());
        let mut text = String::from("plc,source,status,scenarios,steps,C,K,T,N,seconds,message\n");
        for r in &self.rows {
            text.push_str(&format!(
                "{},{},{},{},{},{},{},{},{},{:.3},{}\n",
                quote(&r.plc),
                quote(&r.source),
                r.status,
                r.scenarios,
                r.steps,
                cell(r.c),
                cell(r.k),
                cell(r.t),
                cell(r.n),
                r.seconds,
                quote(&r.message)
            ));
        }
        text
    }

    /// With a PLC left without a machine: the error that says which (no machine within the
    /// limits when that is why every one failed, else bad input).
    pub(crate) fn failure(&self) -> Option<Error> {
        let failed: Vec<&str> = (self.rows.iter())
            .filter(|r| r.status == "failed")
            .map(|r| r.plc.as_str())
            .collect();
        if failed.is_empty() {
            return None;
        }
        let message = format!(
            "{} of {} PLCs have no machine: {} (summary.csv says why)",
            failed.len(),
            self.rows.len(),
            failed.join(", ")
        );
        Some(match self.only_no_machine {
            true => Error::NoMachine(message),
            false => Error::Input(message),
        })
    }
}

/// Writes each PLC's machine into `dir/<plc>` ([`write()`]) and the [`Summary`] as
/// `dir/summary.csv` and `dir/summary.json`. A machine that cannot be written fails its row,
/// not the batch.
pub(crate) fn write_results(
    dir: &Path,
    logs: &Path,
    outcomes: &[Outcome],
    name: &str,
    formats: &[crate::export::Format],
    verification: Option<&VerificationSetup>,
) -> Result<Summary, Error> {
    let mut summary = Summary {
        logs: logs.to_path_buf(),
        rows: Vec::new(),
        files: Vec::new(),
        only_no_machine: true,
    };
    for o in outcomes {
        let mut row = Row {
            plc: o.plc.name.clone(),
            source: o.plc.source.display().to_string(),
            status: "failed",
            scenarios: o.scenarios,
            steps: o.steps,
            c: None,
            k: None,
            t: None,
            n: None,
            seconds: o.seconds,
            message: String::new(),
        };
        let written = match &o.result {
            Ok(r) => write(&dir.join(&o.plc.name), r, name, formats, verification).map(|f| (r, f)),
            Err(e) => {
                summary.only_no_machine &= e.class() == super::Class::NoMachine;
                row.message = e.to_string();
                summary.rows.push(row);
                continue;
            }
        };
        match written {
            Ok((r, files)) => {
                summary.files.extend(files);
                let s = r.synthesis.size;
                (row.c, row.k, row.t, row.n) = (Some(s.c), Some(s.k), Some(s.t), Some(s.n));
                row.status = match r.certificate {
                    Some(_) => "verified",
                    None => "ok",
                };
            }
            Err(e) => {
                summary.only_no_machine = false;
                row.message = e.to_string();
            }
        }
        summary.rows.push(row);
    }
    let csv_file = dir.join("summary.csv");
    let json_file = dir.join("summary.json");
    crate::files::write_atomic(&csv_file, summary.to_csv().as_bytes())?;
    crate::files::write_atomic(
        &json_file,
        format!("{:#}\n", super::summary::to_json(&summary.summary())).as_bytes(),
    )?;
    summary.files.extend([csv_file, json_file]);
    Ok(summary)
}
