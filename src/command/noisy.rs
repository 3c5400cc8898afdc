//! `synth infer --noisy`: candidates by corrected errors ε, each in its folder, and the
//! summary; with `--ltl` the least verified machine over their corrected traces in
//! `verified/`; with `--modules` the composite for the chosen candidate's corrected traces in
//! `modular/`.

use super::infer::Request;
use super::modular::{distribute, distribute_verified, Composite, Modules, VerifiedComposite};
use super::publish;
use crate::pipeline::output::{self, check_exportable};
use crate::pipeline::{noisy, Check, Error, Events};
use std::fmt;
use std::path::{Path, PathBuf};

/// The options only `--noisy` reads.
#[derive(Debug, Clone)]
pub(crate) struct Settings {
    /// At most this many corrected errors (default: no bound).
    pub max_errors: Option<usize>,
    /// Stop after this many distinct candidate machines.
    pub enumerate: usize,
}

/// What `synth infer --noisy` wrote.
pub(crate) struct Corrected {
    /// The summary table (`summary.txt`).
    pub table: String,
    /// The line of the verified machine, when a candidate has one.
    pub chosen: Option<String>,
    /// With `--modules`: the line saying on whose traces, and the composite.
    pub modular: Option<(String, Option<Stage>)>,
    /// The files published besides the candidates'.
    pub files: Vec<PathBuf>,
    /// The output folder.
    pub out: PathBuf,
    /// With a check and no candidate whose corrected traces have a verified machine: why
    /// this is a failure.
    pub failure: Option<Error>,
}

/// The composite of `--noisy --modules`.
pub(crate) enum Stage {
    /// For the corrected traces.
    Composite(Composite),
    /// With a check: following the verified machine.
    Verified(VerifiedComposite),
}

/// The table, the verified machine and the composite, a line each (and a final newline).
impl fmt::Display for Corrected {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.table)?;
        if let Some(line) = &self.chosen {
            writeln!(f, "{line}")?;
        }
        match &self.modular {
            Some((line, stage)) => {
                writeln!(f, "{line}")?;
                match stage {
                    Some(Stage::Composite(c)) => writeln!(f, "{c}"),
                    Some(Stage::Verified(c)) => writeln!(f, "{c}"),
                    None => Ok(()),
                }
            }
            None => Ok(()),
        }
    }
}

/// `synth infer --noisy` (module documentation).
pub(crate) fn run(
    r: &Request,
    settings: &Settings,
    modules: Option<&Modules>,
    events: Events<'_>,
) -> Result<Corrected, Error> {
    let set = r.recordings.load()?;
    check_exportable(&set, &r.name, &r.formats, &r.recordings)?;
    // The recordings are not checked against the properties: their glitches may violate one.
    let check = match &r.spec {
        Some(spec) => Some(spec.check(&set)?),
        None => None,
    };
    let results = r.open()?;
    let opts = noisy::Options {
        algorithms: r.sat.algorithms,
        max_states: r.sat.max_states,
        max_errors: settings.max_errors,
        enumerate: settings.enumerate.max(1),
        guard_budget: r.sat.guard_budget,
        ..noisy::Options::default()
    };
    // --negative conflicts with --noisy.
    let loop_opts = r.loop_options(Vec::new());
    let result = r.limit.run(events, |deadline, events| {
        let opts = noisy::Options { deadline, ..opts };
        noisy::run(&set, check.as_ref().map(|c| (c, &loop_opts)), &opts, events)
    })?;
    let staging = results.staging();
    let mut done = write(r, &result, staging)?;
    // Correct the traces first, then distribute the logic (with --ltl: the verified machine).
    if let Some(m) = modules {
        let k = result.chosen().unwrap_or(1);
        let (line, stage, files) =
            noisy_modules(r, m, &result, k, check.as_ref(), staging, events)?;
        done.files.extend(files);
        done.modular = Some((line, stage));
    }
    done.files = publish(results, &done.files)?;
    if check.is_some() && result.chosen().is_none() {
        done.failure = Some(Error::NoMachine(
            "no candidate's corrected traces have a verified machine (see summary.txt; raise --enumerate or --max-errors)".into(),
        ));
    }
    Ok(done)
}

/// Writes the candidates and the summary table into `staging`; with a check the chosen
/// candidate's verified machine in `verified/`.
fn write(r: &Request, result: &noisy::Noisy, staging: &Path) -> Result<Corrected, Error> {
    let total = r.limit.elapsed();
    let table = output::write_noisy(staging, &r.name, &r.formats, result, total)?;
    let mut done = Corrected {
        table,
        chosen: None,
        modular: None,
        files: Vec::new(),
        out: r.folder(),
        failure: None,
    };
    if let (Some(k), Some(spec)) = (result.chosen(), &r.spec) {
        let dir = staging.join("verified");
        let provenance = spec.provenance(&r.name);
        let total = r.limit.elapsed();
        done.files = output::write_noisy_verified(&dir, &r.formats, result, k, &provenance, total)?;
        done.chosen = chosen_line(result, k);
    }
    Ok(done)
}

/// The line that says which noisy candidate gave the verified machine.
fn chosen_line(result: &noisy::Noisy, k: usize) -> Option<String> {
    let c = &result.synthesis.candidates[k - 1];
    let single = result.verified(k)?;
    Some(format!(
        "result: the verified machine of candidate {k} (ε = {}): {:#}; NuSMV: all {} properties hold; it reproduces the corrected traces",
        c.errors,
        single.synthesis.size,
        (single.certificate.as_ref()).map_or(0, |c| c.report.properties.len())
    ))
}

/// `--noisy --modules M`: the composite for candidate `k`'s corrected traces in `modular/`
/// (with a check: for its verified machine, when it has one); the line saying so, the
/// composite and the files written.
fn noisy_modules(
    r: &Request,
    modules: &Modules,
    result: &noisy::Noisy,
    k: usize,
    check: Option<&Check>,
    staging: &Path,
    events: Events<'_>,
) -> Result<(String, Option<Stage>, Vec<PathBuf>), Error> {
    let c = &result.synthesis.candidates[k - 1];
    let dir = staging.join("modular");
    output::create_dir(&dir)?;
    let line = format!(
        "modular synthesis (M = {}) on the corrected traces of candidate {k} (ε = {}):",
        modules.count, c.errors
    );
    match (check, result.verified(k)) {
        (Some(check), Some(single)) => {
            let oracle = &single.synthesis.ecc;
            let (composite, files) =
                distribute_verified(r, modules, &c.corrected, oracle, check, &dir, events)?;
            Ok((line, Some(Stage::Verified(composite)), files))
        }
        (Some(_), None) => Ok((line, None, Vec::new())),
        (None, _) => {
            let (composite, files) = distribute(r, modules, &c.corrected, &dir, events)?;
            Ok((line, Some(Stage::Composite(composite)), files))
        }
    }
}
