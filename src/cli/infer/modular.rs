//! `synth infer --modules M` and `--distributed FILE`: composites and networks of blocks,
//! for the recordings or, with `--ltl`, for the main job's verified machine.

use super::{infer_out, load, loop_check, provenance, publish, verified, InferArgs, TopologyArg};
use crate::cli::args::{parse_formats, time_limit};
use crate::cli::progress::Progress;
use crate::cli::show::{describe_modules, print_written};
use crate::cli::{exit, Failure};
use crate::ecc::Ecc;
use crate::export;
use crate::pipeline::output::{self, check_exportable_modular, write_verified};
use crate::pipeline::{self, distributed, modular, Check};
use crate::scenario::ScenarioSet;
use std::path::{Path, PathBuf};

/// `synth infer --modules M`: the composite for the recordings or, with `--ltl`, for the main
/// job's verified machine (written too, in `single/`).
pub(super) fn infer_modules(args: &InferArgs, m: usize) -> Result<(), Failure> {
    let progress = Progress::new(crate::cli::quiet());
    let set = load(args, &progress)?;
    let check = loop_check(args, &set, &progress)?;
    let results = infer_out(args)?;
    let staged = match &check {
        None => distribute(args, m, &set, results.staging(), &progress)?,
        Some((check, found)) => {
            // --negative conflicts with --modules.
            let single = verified(args, &set, check, found, Vec::new(), &progress)?;
            let staging = results.staging();
            let mut files =
                distribute_verified(args, m, &set, &single.ecc, check, staging, &progress)?;
            let formats = parse_formats(&args.format)?;
            files.extend(write_verified(
                &staging.join("single"),
                &formats,
                &single.ecc,
                &single.certificate,
                &provenance(args),
                &single.summary,
            )?);
            files
        }
    };
    print_written(&publish(results, &staged)?);
    Ok(())
}

/// `synth infer --distributed FILE` (the described controllers, synthesized together) or,
/// without a file, `--modules M --topology arbitrary` (a network wired by the solver).
pub(super) fn infer_network(args: &InferArgs, file: Option<&PathBuf>) -> Result<(), Failure> {
    let progress = Progress::new(crate::cli::quiet());
    let set = load(args, &progress)?;
    // The controllers described in the file, or blocks the solver wires.
    enum Wiring {
        Given(distributed::Interfaces),
        Chosen(modular::Options, Vec<String>),
    }
    let wiring = match file {
        Some(file) => Wiring::Given(
            distributed::read_description(file)
                .and_then(|d| d.resolve(&set, file))
                .map_err(|e| Failure::input(pipeline::Error::from(e)))?,
        ),
        None => {
            let m = args.modules.unwrap_or(1);
            check_exportable_modular(&set, &args.name, m)?;
            let names = (0..m)
                .map(|k| export::modular::module_type_name(&args.name, k))
                .collect();
            Wiring::Chosen(modular_options(args, m, &set)?, names)
        }
    };
    let results = infer_out(args)?;
    let opts = distributed::Options {
        max_out_degree: args.slots.unwrap_or(modular::DEFAULT_MAX_OUT_DEGREE),
        max_states: args.max_states,
        algorithms: args.algorithms.into(),
        deadline: crate::deadline::Deadline::NONE,
    };
    let result = time_limit(args.time_limit, &progress)?.run(
        &mut |e| progress.event(e),
        |deadline, events| match wiring {
            Wiring::Given(interfaces) => {
                let opts = distributed::Options { deadline, ..opts };
                distributed::run(&set, &interfaces, &opts, events)
            }
            Wiring::Chosen(o, names) => {
                let o = modular::Options { deadline, ..o };
                distributed::run_arbitrary(&set, names, &o, events)
            }
        },
    )?;
    print_network(&result, &set, &progress);
    let staged = export::network::write_network(&result.network, results.staging(), &args.name)
        .map_err(Failure::input)?;
    print_written(&publish(results, &staged)?);
    Ok(())
}

/// A network's sizes and controllers.
pub(super) fn print_network(
    result: &distributed::Distributed,
    set: &ScenarioSet,
    progress: &Progress,
) {
    let s = &result.synthesis.size;
    out!(
        "controllers = {}  largest = {} states  A = {} inputs read  N' = {} states in all  (K = {} slots per state)",
        result.network.names.len(),
        s.max_states,
        s.inputs_used,
        s.total_states,
        result.synthesis.stats.max_out_degree
    );
    let network = &result.network;
    for (module, name) in network.modular.modules.iter().zip(&network.names) {
        let size = module.ecc.size();
        out!(
            "  {name}: {} states, {} transitions, {} guard literals; writes {}; reads {}",
            size.c,
            size.t,
            size.n,
            module.ecc.outputs.join(", "),
            if module.ecc.inputs.is_empty() {
                "-".to_string()
            } else {
                module.ecc.inputs.join(", ")
            }
        );
    }
    out!(
        "time {:.2} s (SAT {:.2} s); replayed {} scenarios on the network: all reproduced",
        progress.elapsed(),
        result.synthesis.stats.sat_seconds,
        set.scenarios.len()
    );
}

/// Modular synthesis of `set` into `out` (also the second stage of `--noisy --modules`, on
/// the corrected traces); the files written.
pub(super) fn distribute(
    args: &InferArgs,
    modules: usize,
    set: &ScenarioSet,
    out: &Path,
    progress: &Progress,
) -> Result<Vec<PathBuf>, Failure> {
    let opts = modular_options(args, modules, set)?;
    check_exportable_modular(set, &args.name, modules)?;
    let result = time_limit(args.time_limit, progress)?
        .run(&mut |e| progress.event(e), |deadline, events| {
            modular::run(set, &modular::Options { deadline, ..opts }, events)
        })?;
    describe_modular(modules, &result);
    out!(
        "time {:.2} s (SAT {:.2} s); replayed {} scenarios on the composite: all reproduced",
        progress.elapsed(),
        result.stats.sat_seconds,
        set.scenarios.len()
    );
    export::modular::write_modular(&result.modular, out, &args.name).map_err(Failure::input)
}

/// The modular options of `synth infer --modules M`.
pub(super) fn modular_options(
    args: &InferArgs,
    modules: usize,
    set: &ScenarioSet,
) -> Result<modular::Options, Failure> {
    Ok(modular::Options {
        modules,
        max_out_degree: args.slots.unwrap_or(modular::DEFAULT_MAX_OUT_DEGREE),
        widen_max_out_degree: args.slots.is_none(),
        max_states: args.max_states,
        algorithms: args.algorithms.into(),
        pins: modular::parse_pins(&args.pin, &set.outputs, modules)
            .map_err(|e| Failure::with_code(exit::USAGE, e))?,
        topology: args.topology.into(),
        reads: None,
        feedback: (args.topology == TopologyArg::Arbitrary).then_some(set.inputs.len()),
        deadline: crate::deadline::Deadline::NONE,
    })
}

/// Prints a modular controller's sizes and modules.
pub(super) fn describe_modular(modules: usize, result: &modular::ModularSynthesis) {
    let s = &result.size;
    let chain = match result.modular.topology {
        modular::Topology::Consecutive => " in a chain",
        modular::Topology::Parallel => "",
    };
    out!(
        "modules = {}{chain}  largest module = {} states  A = {} inputs used  N' = {} states in all  (K = {} slots per state{})",
        modules,
        s.max_states,
        s.inputs_used,
        s.total_states,
        result.stats.max_out_degree,
        if result.stats.max_out_degree > modular::DEFAULT_MAX_OUT_DEGREE { ", widened" } else { "" }
    );
    for line in describe_modules(&result.modular) {
        out!("  {line}");
    }
}

/// With --ltl/--plant: `oracle`, the verified machine, split into `modules` function blocks
/// whose composite NuSMV verifies too ([`modular::run_verified`]), written into `out`
/// ([`output::write_verified_modular`]); the files written.
pub(super) fn distribute_verified(
    args: &InferArgs,
    modules: usize,
    set: &ScenarioSet,
    oracle: &Ecc,
    check: &Check,
    out: &Path,
    progress: &Progress,
) -> Result<Vec<PathBuf>, Failure> {
    let opts = modular_options(args, modules, set)?;
    check_exportable_modular(set, &args.name, modules)?;
    out!("modular synthesis (M = {modules}) of the verified machine:");
    let r = time_limit(args.time_limit, progress)?.run(
        &mut |e| progress.event(e),
        |deadline, events| {
            let opts = modular::Options { deadline, ..opts };
            modular::run_verified(set, oracle, check, &opts, args.max_iterations, events)
        },
    )?;
    describe_modular(modules, &r.synthesis);
    let added = r.scenarios.scenarios.len() - set.scenarios.len();
    out!(
        "verified: all {} properties hold for the composite (NuSMV); it reproduces the {} recorded scenarios and {} recorded from the verified machine along counterexamples ({} composites)",
        r.certificate.report.properties.len(),
        set.scenarios.len(),
        added,
        r.rounds.len()
    );
    Ok(output::write_verified_modular(out, &r, &provenance(args))?)
}
