//! Writing results: a machine in every requested format, and around a verified one NuSMV's
//! report, the closed-loop model it checked and `summary.json`; the noisy candidates each in
//! their folder with the corrected traces. Every file is written atomically (a temporary file
//! renamed over the target) with the mode of any file the user creates (0644 under umask 022).

use super::exact::Certificate;
use super::noisy::{InLoop, Noisy};
use super::recordings::Recordings;
use super::summary::{self, LoopSummary, NoisyVerifiedSummary};
use super::Error;
use crate::ecc::modular::{Modular, Module};
use crate::ecc::{Algorithm, AlgorithmKind, Ecc, InputId, OutputId, State};
use crate::export::{self, Format};
use crate::files::write_atomic;
use crate::scenario::{csvlog, fbsat, ScenarioSet};
use std::path::{Path, PathBuf};

/// Creates `dir` (and its parents) with a located error.
pub(crate) fn create_dir(dir: &Path) -> Result<(), Error> {
    std::fs::create_dir_all(dir)
        .map_err(|e| Error::Input(format!("cannot create {}: {e}", dir.display())))
}

fn write(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    Ok(write_atomic(path, bytes)?)
}

/// A machine with one initial state and no transition over the interface of `set`.
fn probe(set: &ScenarioSet, outputs: &[OutputId]) -> Ecc {
    Ecc {
        inputs: set.inputs.clone(),
        outputs: outputs.iter().map(|z| set.outputs[z.0].clone()).collect(),
        initial_outputs: outputs.iter().map(|z| set.initial_outputs[z.0]).collect(),
        states: vec![State {
            name: "s0".into(),
            algorithm: Algorithm::keep_all(AlgorithmKind::Tri, outputs.len()),
            transitions: Vec::new(),
        }],
    }
}

/// Checks up front, before any search, that the interface names and the block name can be
/// written in every requested format: an empty machine over the interface must export. An
/// interface name that cannot is reported where `recordings` wrote it (its names file and
/// line), since that is where the user renames it.
pub(crate) fn check_exportable(
    set: &ScenarioSet,
    name: &str,
    formats: &[Format],
    recordings: &Recordings,
) -> Result<(), Error> {
    let all: Vec<OutputId> = (0..set.outputs.len()).map(OutputId).collect();
    let dir = crate::files::WorkDir::new()?;
    match export::write_all(&probe(set, &all), dir.path(), name, formats) {
        Ok(_) => Ok(()),
        Err(e) => Err(locate_name_error(e, recordings)),
    }
}

/// An export error about an interface name, prefixed with the place the name was written.
fn locate_name_error(e: export::ExportError, recordings: &Recordings) -> Error {
    use crate::smv::SmvError;
    let (role, format, message) = match &e {
        export::ExportError::Name { format, source } => {
            (source.role.as_str(), *format, source.to_string())
        }
        export::ExportError::Smv(source @ SmvError::Identifier { role, .. }) => {
            (role.as_str(), Format::Smv, source.to_string())
        }
        _ => return e.into(),
    };
    let place = match role.split_once(' ') {
        Some(("input", n)) => n.parse::<usize>().ok().map(|n| (false, n)),
        Some(("output", n)) => n.parse::<usize>().ok().map(|n| (true, n)),
        _ => None,
    }
    .and_then(|(output, n)| recordings.name_place(output, n.checked_sub(1)?));
    match place {
        Some(place) => Error::Input(format!(
            "{place}: {message} (rename it there, or leave {} out of --format)",
            format.extension()
        )),
        None => e.into(),
    }
}

/// Checks before a modular search that the block name and the interface can be exported: a
/// probe composite with `modules` modules must pass the name checks of the `.fbt` and SMV
/// files.
pub(crate) fn check_exportable_modular(
    set: &ScenarioSet,
    name: &str,
    modules: usize,
) -> Result<(), Error> {
    let module = |owns: bool| {
        let outputs: Vec<OutputId> = if owns {
            (0..set.outputs.len()).map(OutputId).collect()
        } else {
            Vec::new()
        };
        Module {
            inputs: (0..set.inputs.len()).map(InputId).collect(),
            ecc: probe(set, &outputs),
            outputs,
        }
    };
    let composite = Modular {
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        modules: (0..modules.max(1)).map(|m| module(m == 0)).collect(),
        topology: crate::ecc::modular::Topology::Parallel,
    };
    export::modular::check_fbt_names(&composite, name)?;
    Ok(export::modular::check_smv_names(&composite, name)?)
}

/// Where a verified result came from, for the head of `verification.txt`.
pub(crate) struct Provenance<'a> {
    /// The function block type's name.
    pub(crate) name: &'a str,
    /// The plant model file the machine was closed in a loop with.
    pub(crate) plant_file: &'a Path,
    /// The LTL specification file with the properties checked.
    pub(crate) spec_file: &'a Path,
}

/// Writes a verified machine into `out`: every export format, NuSMV's report, the
/// closed-loop model it checked and `summary.json` (its keys sorted). Returns the files
/// written.
pub(crate) fn write_verified(
    out: &Path,
    formats: &[Format],
    ecc: &Ecc,
    certificate: &Certificate,
    provenance: &Provenance<'_>,
    summary: &impl serde::Serialize,
) -> Result<Vec<PathBuf>, Error> {
    let summary = serde_json::to_value(summary).expect("a summary is JSON");
    create_dir(out)?;
    let mut files = export::write_all(ecc, out, provenance.name, formats)?;
    files.extend(write_certificate(
        out,
        provenance.name,
        certificate,
        provenance,
    )?);
    let summary_file = out.join("summary.json");
    write(
        &summary_file,
        serde_json::to_string_pretty(&summary)
            .expect("serializable")
            .as_bytes(),
    )?;
    files.push(summary_file);
    Ok(files)
}

/// Writes the size questions around `size`, the least machine's for `set`, into `dir` as
/// DIMACS files with `verdicts.txt`, a fresh solver's answer to each
/// ([`crate::sat::dimacs`]). Returns the files written.
pub(crate) fn write_size_questions(
    dir: &Path,
    set: &ScenarioSet,
    sat: &crate::sat::Options,
    size: &crate::ecc::Size,
) -> Result<Vec<PathBuf>, Error> {
    let tree = crate::scenario::tree::ScenarioTree::build(set)?;
    let mut verdicts = String::new();
    let mut files = Vec::new();
    for q in crate::sat::dimacs::size_questions(&tree, sat, size) {
        let path = dir.join(&q.name);
        write(&path, &q.dimacs())?;
        files.push(path);
        verdicts.push_str(&q.verdict_line());
    }
    let path = dir.join("verdicts.txt");
    write(&path, verdicts.as_bytes())?;
    files.push(path);
    Ok(files)
}

/// Writes a composite NuSMV verified into `out`: its files
/// ([`export::modular::write_modular`]), its `verification.txt` and `closed_loop.smv`, and
/// `rounds.json` (one entry per composite checked). Returns the files written.
pub(crate) fn write_verified_modular(
    out: &Path,
    r: &super::modular::VerifiedModular,
    provenance: &Provenance<'_>,
) -> Result<Vec<PathBuf>, Error> {
    let name = provenance.name;
    let mut files = export::modular::write_modular(&r.synthesis.modular, out, name)?;
    let what = format!("the composite {name}");
    files.extend(write_certificate(out, &what, &r.certificate, provenance)?);
    let rounds = out.join("rounds.json");
    let json = serde_json::to_string_pretty(&r.rounds).expect("serializable");
    write(&rounds, json.as_bytes())?;
    files.push(rounds);
    Ok(files)
}

/// Writes the verified machine of noisy candidate `k` (1-based, [`Noisy::chosen`]) into
/// `dir`: as [`write_verified`], with its summary and the corrected traces as
/// `corrected.csv`. Returns the files written.
pub(crate) fn write_noisy_verified(
    dir: &Path,
    formats: &[Format],
    noisy: &Noisy,
    k: usize,
    provenance: &Provenance<'_>,
    total_seconds: f64,
) -> Result<Vec<PathBuf>, Error> {
    let c = &noisy.synthesis.candidates[k - 1];
    let Some((single, certificate)) = noisy
        .verified(k)
        .and_then(|v| Some((v, v.certificate.as_ref()?)))
    else {
        return Err(Error::Bug(format!(
            "noisy candidate {k} has no verified machine"
        )));
    };
    let summary = NoisyVerifiedSummary {
        format: summary::NOISY_VERIFIED,
        candidate: k,
        errors: c.errors,
        closed_loop: LoopSummary {
            size: single.synthesis.size,
            transitions_proven_minimal: single.synthesis.transitions_exact,
            guards_proven_minimal: single.synthesis.guards_exact,
            iterations: single.iterations.clone(),
            report: Some(certificate.report.clone()),
            total_seconds,
        },
    };
    let ecc = &single.synthesis.ecc;
    let mut files = write_verified(dir, formats, ecc, certificate, provenance, &summary)?;
    let mut csv = Vec::new();
    csvlog::write(&c.corrected, &mut csv)?;
    let corrected = dir.join("corrected.csv");
    write(&corrected, &csv)?;
    files.push(corrected);
    Ok(files)
}

/// Writes NuSMV's certificate for `what` into `out`: `verification.txt` (the report under a
/// header naming plant and properties) and `closed_loop.smv` (the model it checked). Returns
/// the files written.
pub(crate) fn write_certificate(
    out: &Path,
    what: &str,
    certificate: &Certificate,
    provenance: &Provenance<'_>,
) -> Result<Vec<PathBuf>, Error> {
    let report_txt = out.join("verification.txt");
    let mut text = format!(
        "Closed-loop verification by NuSMV of {what}\nplant: {}\nproperties: {}\n\n",
        provenance.plant_file.display(),
        provenance.spec_file.display()
    );
    text.push_str(&certificate.report.to_text());
    write(&report_txt, text.as_bytes())?;
    let model = out.join("closed_loop.smv");
    write(&model, certificate.model_text.as_bytes())?;
    Ok(vec![report_txt, model])
}

/// One row of the noisy summary.
#[derive(Debug, serde::Serialize, schemars::JsonSchema)]
pub struct NoisyRow {
    /// 1-based number of the candidate (as in `candidate_<k>`).
    pub(crate) candidate: usize,
    /// Number of recording errors ε the candidate corrects.
    pub(crate) errors: usize,
    /// The candidate's figures C, K, T and N.
    pub(crate) size: crate::ecc::Size,
    /// Whether every guard's literal count is proven minimal.
    pub(crate) guards_exact: bool,
    /// With a check: whether the closed loop found a verified machine for the corrected
    /// traces; `None`: not checked.
    pub(crate) verified: Option<bool>,
    /// That verified machine's size.
    pub(crate) verified_size: Option<crate::ecc::Size>,
    /// Why the closed loop found none.
    pub(crate) why_not: Option<String>,
    /// With a check: the properties the candidate as found violates (NuSMV).
    pub(crate) as_found_violates: Option<Vec<String>>,
    /// The candidate's folder name, `candidate_<k>`, relative to the output folder.
    pub(crate) folder: String,
}

/// Writes every noisy candidate into `out/candidate_<k>/` (the machine in every format, the
/// corrected traces as `corrected.txt` and `corrected.csv`, and `candidate.json`), then
/// `summary.txt` and `summary.json`. Returns the summary table.
pub(crate) fn write_noisy(
    out: &Path,
    name: &str,
    formats: &[Format],
    noisy: &Noisy,
    total_seconds: f64,
) -> Result<String, Error> {
    create_dir(out)?;
    let result = &noisy.synthesis;
    let mut rows = Vec::new();
    for (k, c) in result.candidates.iter().enumerate() {
        let row = noisy_row(noisy, k);
        let dir = out.join(&row.folder);
        create_dir(&dir)?;
        export::write_all(&c.ecc, &dir, name, formats)?;
        let mut text = Vec::new();
        fbsat::write(&c.corrected, &mut text)?;
        write(&dir.join("corrected.txt"), &text)?;
        let mut csv = Vec::new();
        csvlog::write(&c.corrected, &mut csv)?;
        write(&dir.join("corrected.csv"), &csv)?;
        let json = serde_json::to_string_pretty(&row).expect("serializable");
        write(&dir.join("candidate.json"), json.as_bytes())?;
        rows.push(row);
    }
    let table = noisy_table(noisy, &rows);
    write(&out.join("summary.txt"), table.as_bytes())?;
    let summary = summary::NoisySummary {
        format: summary::NOISY,
        c: result.n,
        k: result.k,
        t: result.r,
        exhausted: result.exhausted,
        chosen: noisy.chosen(),
        candidates: rows,
        stats: result.stats.clone(),
        total_seconds,
    };
    let json = format!("{:#}", summary::to_json(&summary));
    write(&out.join("summary.json"), json.as_bytes())?;
    Ok(table)
}

/// The summary row of noisy candidate `k` (from 0), kept in the folder `candidate_<k + 1>`.
fn noisy_row(noisy: &Noisy, k: usize) -> NoisyRow {
    let c = &noisy.synthesis.candidates[k];
    NoisyRow {
        candidate: k + 1,
        errors: c.errors,
        size: c.size,
        guards_exact: c.guards_exact,
        verified: (noisy.closed.get(k).and_then(Option::as_ref))
            .map(|c| matches!(c, InLoop::Verified(_))),
        verified_size: noisy.verified(k + 1).map(|e| e.synthesis.size),
        as_found_violates: noisy.as_found.get(k).cloned(),
        why_not: match noisy.closed.get(k) {
            Some(Some(InLoop::None(why))) => Some(why.clone()),
            _ => None,
        },
        folder: format!("candidate_{}", k + 1),
    }
}

/// The noisy synthesis's summary table (`summary.txt`): its bounds, then one line per
/// candidate of `rows`.
fn noisy_table(noisy: &Noisy, rows: &[NoisyRow]) -> String {
    let result = &noisy.synthesis;
    let mut table = format!(
        "noisy synthesis: C = {}  K = {}  T = {}; {} alternative edges; {} candidate(s){}\n\n\
         candidate  errors  C   K   T   N    verified (C K T N)  folder        as found (NuSMV)\n",
        result.n,
        result.k,
        result.r,
        result.stats.alternatives,
        rows.len(),
        if result.exhausted { ", all" } else { "" }
    );
    for r in rows {
        table.push_str(&format!(
            "{:<10} {:<7} {:<3} {:<3} {:<3} {:<4} {:<19} {:<13} {}\n",
            r.candidate,
            r.errors,
            r.size.c,
            r.size.k,
            r.size.t,
            r.size.n,
            match (r.verified, r.verified_size) {
                (Some(true), Some(s)) => format!("yes ({} {} {} {})", s.c, s.k, s.t, s.n),
                (Some(_), _) => "no".to_string(),
                (None, _) => "-".to_string(),
            },
            r.folder,
            match &r.as_found_violates {
                None => "-".to_string(),
                Some(v) if v.is_empty() => "holds".to_string(),
                Some(v) => format!("violates {}", v.join(", ")),
            }
        ));
    }
    if noisy.chosen().is_some() && rows.iter().any(|r| r.verified.is_none()) {
        table.push_str(
            "(verified -: closed loop not tried, an earlier candidate in the order gave the result)\n",
        );
    }
    table
}

/// Writes scenarios in the fbSAT text format with their names files beside them
/// (`<stem>.traces`, `<stem>.inputs`, `<stem>.outputs`). Returns the traces file.
pub(crate) fn write_scenarios(dir: &Path, stem: &str, set: &ScenarioSet) -> Result<PathBuf, Error> {
    create_dir(dir)?;
    let traces = dir.join(format!("{stem}.traces"));
    let mut text = Vec::new();
    fbsat::write(set, &mut text)?;
    write(&traces, &text)?;
    for (ext, names) in [("inputs", &set.inputs), ("outputs", &set.outputs)] {
        write(
            &dir.join(format!("{stem}.{ext}")),
            (names.join("\n") + "\n").as_bytes(),
        )?;
    }
    Ok(traces)
}
