//! `synth infer --noisy`: candidates by corrected errors ε; with `--ltl` the verified machine
//! over their corrected traces, with `--modules` the composite for the chosen one.

use super::modular::{distribute, distribute_verified};
use super::{infer_out, loop_options, provenance, publish, InferArgs};
use crate::cli::args::{optional_check, out_dir, parse_formats, time_limit};
use crate::cli::progress::Progress;
use crate::cli::show::{print_written, size_line};
use crate::cli::{exit, Failure};
use crate::pipeline::output::{self, check_exportable};
use crate::pipeline::{self, noisy, Check};
use std::path::{Path, PathBuf};

/// `synth infer --noisy`: candidates by ε, each in its folder, and the summary; with --ltl
/// the least verified machine over the candidates' corrected traces in `verified/`; with
/// --modules the composite for the chosen candidate's corrected traces in `modular/`.
pub(super) fn infer_noisy(args: &InferArgs) -> Result<(), Failure> {
    let progress = Progress::new(crate::cli::quiet());
    let set = args.traces.load()?;
    let formats = parse_formats(&args.format)?;
    check_exportable(&set, &args.name, &formats, &args.traces.recordings())?;
    // The recordings are not checked against the properties: their glitches may violate one.
    let check = optional_check(&args.ltl, &args.plant, &set, &args.nusmv)?;
    let out = out_dir(&args.out, &args.traces.recordings().stem());
    let results = infer_out(args)?;
    let opts = options(args)?;
    // --negative conflicts with --noisy.
    let loop_opts = loop_options(args, Vec::new());
    let result = time_limit(args.time_limit, &progress)?.run(
        &mut |e| progress.event(e),
        |deadline, events| {
            let opts = noisy::Options { deadline, ..opts };
            noisy::run(&set, check.as_ref().map(|c| (c, &loop_opts)), &opts, events)
        },
    )?;
    let check = check.as_ref();
    let staged = files(args, &result, check, &formats, results.staging(), &progress)?;
    let written = publish(results, &staged)?;
    if !written.is_empty() {
        print_written(&written);
    }
    out!("results in {}", out.display());
    match (check.is_some(), result.chosen()) {
        (true, None) => Err(Failure::msg(
            exit::NO_MACHINE,
            "no candidate's corrected traces have a verified machine (see summary.txt; raise --enumerate or --max-errors)",
        )),
        _ => Ok(()),
    }
}

/// The noisy synthesis the arguments ask for.
fn options(args: &InferArgs) -> Result<noisy::Options, Failure> {
    let n = &args.noisy;
    Ok(noisy::Options {
        algorithms: args.algorithms.into(),
        max_states: args.max_states,
        max_errors: n.max_errors,
        enumerate: n.enumerate.max(1),
        guard_budget: pipeline::seconds("--guard-budget", args.guard_budget, false)?,
        ..noisy::Options::default()
    })
}

/// Writes the candidates and the summary table (printed) into `staging`; with a check the
/// chosen candidate's verified machine in `verified/`; with `--modules` the composite in
/// `modular/`. The files written besides the candidates'.
fn files(
    args: &InferArgs,
    result: &noisy::Noisy,
    check: Option<&Check>,
    formats: &[crate::export::Format],
    staging: &Path,
    progress: &Progress,
) -> Result<Vec<PathBuf>, Failure> {
    let table = output::write_noisy(staging, &args.name, formats, result, progress.elapsed())?;
    out_raw!("{table}");
    let chosen = result.chosen();
    let mut staged = Vec::new();
    if let Some(k) = chosen {
        let dir = staging.join("verified");
        let provenance = provenance(args);
        let total = progress.elapsed();
        staged = output::write_noisy_verified(&dir, formats, result, k, &provenance, total)?;
        print_noisy_verified(result, k);
    }
    // Correct the traces first, then distribute the logic (with --ltl: the verified machine).
    if let Some(m) = args.modules {
        let k = chosen.unwrap_or(1);
        staged.extend(noisy_modules(args, m, result, k, check, staging, progress)?);
    }
    Ok(staged)
}

/// The line that says which noisy candidate gave the verified machine.
pub(super) fn print_noisy_verified(result: &noisy::Noisy, k: usize) {
    let c = &result.synthesis.candidates[k - 1];
    let Some(single) = result.verified(k) else {
        return;
    };
    let s = single.synthesis.size;
    out!(
        "result: the verified machine of candidate {k} (ε = {}): {}; NuSMV: all {} properties hold; it reproduces the corrected traces",
        c.errors,
        size_line(&s),
        single.certificate.as_ref().map_or(0, |c| c.report.properties.len())
    );
}

/// `--noisy --modules M`: the composite for candidate `k`'s corrected traces in `modular/`
/// (with a check: for its verified machine, when it has one).
pub(super) fn noisy_modules(
    args: &InferArgs,
    m: usize,
    result: &noisy::Noisy,
    k: usize,
    check: Option<&Check>,
    staging: &Path,
    progress: &Progress,
) -> Result<Vec<PathBuf>, Failure> {
    let c = &result.synthesis.candidates[k - 1];
    let dir = staging.join("modular");
    output::create_dir(&dir)?;
    out!(
        "modular synthesis (M = {m}) on the corrected traces of candidate {k} (ε = {}):",
        c.errors
    );
    match (check, result.verified(k)) {
        (Some(check), Some(single)) => {
            let oracle = &single.synthesis.ecc;
            distribute_verified(args, m, &c.corrected, oracle, check, &dir, progress)
        }
        (Some(_), None) => Ok(Vec::new()),
        (None, _) => distribute(args, m, &c.corrected, &dir, progress),
    }
}
