//! Monitoring and refinement, the loop Chivilikhin et al. ("Automatic state machine
//! reconstruction from legacy PLC using data collection and SAT solver") propose for a
//! machine in service: replay new recordings on it; where one diverges, add it to the training scenarios,
//! synthesize again (verified again with a [`Check`]) and show that the new machine reproduces
//! every new recording.

use super::exact::{self, Exact};
use super::{output, Check, Error, Events};
use crate::ecc::Ecc;
use crate::export::Format;
use crate::scenario::ScenarioSet;
use std::path::{Path, PathBuf};

/// What a refinement writes, and how it synthesizes.
pub struct Options<'a> {
    /// Folder for `refined.traces` (training + divergent) and the new machine.
    pub out: &'a Path,
    /// Formats of the new machine.
    pub formats: &'a [Format],
    /// The function block type's name.
    pub name: &'a str,
    /// Settings of the exact synthesis (algorithms default to the old machine's form).
    pub exact: exact::Options,
}

/// The result of a refinement.
pub struct Refined {
    /// Indices (in the new recordings) of the traces the old machine did not reproduce.
    pub divergent: Vec<usize>,
    /// Training scenarios before the divergent traces were added.
    pub(crate) training_scenarios: usize,
    /// The file holding training + divergent traces.
    pub traces_file: PathBuf,
    /// The new machine (with NuSMV's certificate when checked).
    pub(crate) exact: Exact,
    /// Files written for the new machine.
    pub(crate) files: Vec<PathBuf>,
}

impl Refined {
    /// The new machine.
    pub fn ecc(&self) -> &Ecc {
        &self.exact.synthesis.ecc
    }
}

/// Refines `ecc` with the traces of `new` it does not reproduce, on top of `training`.
/// `Ok(None)` when every new trace is already reproduced.
pub fn run(
    ecc: &Ecc,
    new: &ScenarioSet,
    mut training: ScenarioSet,
    check: Option<&Check>,
    opts: &Options<'_>,
    events: Events<'_>,
) -> Result<Option<Refined>, Error> {
    let divergent: Vec<usize> = new.divergences(ecc).iter().map(|d| d.scenario).collect();
    if divergent.is_empty() {
        return Ok(None);
    }
    let training_scenarios = training.scenarios.len();
    let mut learned = new.clone();
    learned.scenarios = divergent
        .iter()
        .map(|&k| new.scenarios[k].clone())
        .collect();
    training.merge(learned)?;
    let traces_file = output::write_scenarios(opts.out, "refined", &training)?;
    let mut exact_opts = opts.exact.clone();
    exact_opts.sat.algorithms = ecc.algorithm_kind();
    if check.is_some() && exact_opts.keep_failed_model.is_none() {
        exact_opts.keep_failed_model = Some(opts.out.join("closed_loop.last.smv"));
    }
    let result = exact::run(&training, check, &exact_opts, events)?;
    let files = match (&result.certificate, check) {
        (Some(cert), Some(check)) => {
            let summary = super::summary::RefinedSummary {
                format: super::summary::REFINED,
                size: result.synthesis.size,
                iterations: result.iterations.clone(),
                report: cert.report.clone(),
            };
            output::write_verified(
                opts.out,
                opts.formats,
                &result.synthesis.ecc,
                cert,
                &output::Provenance {
                    name: opts.name,
                    plant_file: &check.problem.plant.file,
                    spec_file: &check.problem.spec_file,
                },
                &summary,
            )?
        }
        _ => {
            output::create_dir(opts.out)?;
            crate::export::write_all(&result.synthesis.ecc, opts.out, opts.name, opts.formats)?
        }
    };
    let refined = Refined {
        divergent,
        training_scenarios,
        traces_file,
        exact: result,
        files,
    };
    // The new machine was synthesized from these very traces: a divergence is a bug.
    if let Some(d) = new.divergences(refined.ecc()).first() {
        return Err(Error::Bug(format!(
            "the refined machine still diverges on trace {}",
            new.scenarios[d.scenario].origin
        )));
    }
    Ok(Some(refined))
}
