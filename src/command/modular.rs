//! `synth infer --modules M` and `--distributed FILE`: composites and networks of blocks,
//! for the recordings or, with `--ltl`, for the main job's verified machine; also the second
//! stage of `--noisy --modules`, on a candidate's corrected traces.

use super::infer::{Request, Verified};
use super::publish;
use crate::ecc::Ecc;
use crate::export;
use crate::pipeline::output::{self, check_exportable_modular, write_verified};
use crate::pipeline::summary::MainSummary;
use crate::pipeline::{distributed, modular, Check, Error, Events};
use crate::sat::modular::ModularSynthesis;
use crate::scenario::ScenarioSet;
use std::fmt;
use std::path::{Path, PathBuf};

/// How many modules, and how they are wired.
#[derive(Debug, Clone)]
pub(crate) struct Modules {
    /// M.
    pub count: usize,
    /// Transition slots per state, fixed; `None`: the default, widened while too few.
    pub slots: Option<usize>,
    /// `--pin MODULE=OUTPUTS`.
    pub pins: Vec<String>,
    /// Parallel or consecutive.
    pub topology: modular::Topology,
    /// A network the solver wires (`--topology arbitrary`), written as for `--distributed`.
    pub arbitrary: bool,
}

impl Modules {
    /// The modular options over the interface of `set`.
    pub fn options(&self, r: &Request, set: &ScenarioSet) -> Result<modular::Options, Error> {
        Ok(modular::Options {
            modules: self.count,
            max_out_degree: self.slots.unwrap_or(modular::DEFAULT_MAX_OUT_DEGREE),
            widen_max_out_degree: self.slots.is_none(),
            max_states: r.sat.max_states,
            algorithms: r.sat.algorithms,
            pins: modular::parse_pins(&self.pins, &set.outputs, self.count)?,
            topology: self.topology,
            reads: None,
            feedback: self.arbitrary.then_some(set.inputs.len()),
            deadline: crate::deadline::Deadline::NONE,
        })
    }
}

/// A composite: its sizes and modules, and the run.
pub(crate) struct Composite {
    /// The composite and its figures.
    pub result: ModularSynthesis,
    /// Seconds since the start.
    pub seconds: f64,
    /// Scenarios it reproduces.
    pub scenarios: usize,
}

/// The lines of a composite's sizes and modules.
fn describe(f: &mut fmt::Formatter<'_>, result: &ModularSynthesis) -> fmt::Result {
    let s = &result.size;
    let chain = match result.modular.topology {
        modular::Topology::Consecutive => " in a chain",
        modular::Topology::Parallel => "",
    };
    let widened = match result.stats.max_out_degree > modular::DEFAULT_MAX_OUT_DEGREE {
        true => ", widened",
        false => "",
    };
    writeln!(
        f,
        "modules = {}{chain}  largest module = {} states  A = {} inputs used  N' = {} states in all  (K = {} slots per state{widened})",
        result.modular.modules.len(),
        s.max_states,
        s.inputs_used,
        s.total_states,
        result.stats.max_out_degree,
    )?;
    (result.modular.describe().iter()).try_for_each(|line| writeln!(f, "  {line}"))
}

impl fmt::Display for Composite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        describe(f, &self.result)?;
        write!(
            f,
            "time {:.2} s (SAT {:.2} s); replayed {} scenarios on the composite: all reproduced",
            self.seconds, self.result.stats.sat_seconds, self.scenarios
        )
    }
}

/// A composite NuSMV verified, following a verified machine.
pub(crate) struct VerifiedComposite {
    /// The composite, its certificate and rounds.
    pub result: modular::VerifiedModular,
    /// Scenarios recorded.
    pub scenarios: usize,
}

impl fmt::Display for VerifiedComposite {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = &self.result;
        let m = r.synthesis.modular.modules.len();
        writeln!(f, "modular synthesis (M = {m}) of the verified machine:")?;
        describe(f, &r.synthesis)?;
        write!(
            f,
            "verified: all {} properties hold for the composite (NuSMV); it reproduces the {} recorded scenarios and {} recorded from the verified machine along counterexamples ({} composites)",
            r.certificate.report.properties.len(),
            self.scenarios,
            r.scenarios.scenarios.len() - self.scenarios,
            r.rounds.len()
        )
    }
}

/// Modular synthesis of `set` into `out` (also the second stage of `--noisy --modules`, on
/// the corrected traces); the composite and the files written.
pub(crate) fn distribute(
    r: &Request,
    modules: &Modules,
    set: &ScenarioSet,
    out: &Path,
    events: Events<'_>,
) -> Result<(Composite, Vec<PathBuf>), Error> {
    let opts = modules.options(r, set)?;
    check_exportable_modular(set, &r.name, modules.count)?;
    let result = r.limit.run(events, |deadline, events| {
        modular::run(set, &modular::Options { deadline, ..opts }, events)
    })?;
    let files = export::modular::write_modular(&result.modular, out, &r.name)?;
    let composite = Composite {
        result,
        seconds: r.limit.elapsed(),
        scenarios: set.scenarios.len(),
    };
    Ok((composite, files))
}

/// With a check: `oracle`, the verified machine, split into modules whose composite NuSMV
/// verifies too ([`modular::run_verified`]), written into `out`
/// ([`output::write_verified_modular`]); the composite and the files written.
pub(crate) fn distribute_verified(
    r: &Request,
    modules: &Modules,
    set: &ScenarioSet,
    oracle: &Ecc,
    check: &Check,
    out: &Path,
    events: Events<'_>,
) -> Result<(VerifiedComposite, Vec<PathBuf>), Error> {
    let opts = modules.options(r, set)?;
    check_exportable_modular(set, &r.name, modules.count)?;
    let result = r.limit.run(events, |deadline, events| {
        let opts = modular::Options { deadline, ..opts };
        modular::run_verified(set, oracle, check, &opts, r.max_iterations, events)
    })?;
    let spec = r.spec.as_ref().expect("a check comes with its spec");
    let files = output::write_verified_modular(out, &result, &spec.provenance(&r.name))?;
    let composite = VerifiedComposite {
        result,
        scenarios: set.scenarios.len(),
    };
    Ok((composite, files))
}

/// What `synth infer --modules M` made, published.
pub(crate) struct Split {
    /// The composite, and with `--ltl` the machine it follows.
    pub made: Made,
    /// The files published.
    pub files: Vec<PathBuf>,
}

/// The composite of `synth infer --modules M`.
pub(crate) enum Made {
    /// For the recordings.
    Composite(Composite),
    /// With `--ltl`: the verified machine (written in `single/`) and its verified composite.
    Verified(Box<Verified>, VerifiedComposite),
}

impl fmt::Display for Split {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.made {
            Made::Composite(c) => write!(f, "{c}"),
            Made::Verified(single, composite) => write!(f, "{single}\n{composite}"),
        }
    }
}

/// `synth infer --modules M`: the composite for the recordings or, with `--ltl`, for the main
/// job's verified machine (written too, in `single/`).
pub(crate) fn modules(r: &Request, modules: &Modules, events: Events<'_>) -> Result<Split, Error> {
    let set = r.load(events)?;
    let check = r.loop_check(&set, events)?;
    let results = r.open()?;
    let staging = results.staging();
    let Some((check, found)) = &check else {
        let (composite, staged) = distribute(r, modules, &set, staging, events)?;
        return Ok(Split {
            made: Made::Composite(composite),
            files: publish(results, &staged)?,
        });
    };
    // --negative conflicts with --modules.
    let single = r.verified(&set, (check, found), Vec::new(), events)?;
    let (composite, mut staged) =
        distribute_verified(r, modules, &set, &single.ecc, check, staging, events)?;
    let spec = r.spec.as_ref().expect("a check comes with its spec");
    staged.extend(write_verified(
        &staging.join("single"),
        &r.formats,
        &single.ecc,
        &single.certificate,
        &spec.provenance(&r.name),
        &MainSummary::new(&single.summary, None),
    )?);
    let single = Verified {
        verified: single,
        scenarios: set.scenarios.len(),
        files: Vec::new(),
    };
    Ok(Split {
        made: Made::Verified(Box::new(single), composite),
        files: publish(results, &staged)?,
    })
}

/// A network of controllers, and the run.
pub(crate) struct Network {
    /// The network and its figures.
    pub result: distributed::Distributed,
    /// Seconds since the start.
    pub seconds: f64,
    /// Scenarios it reproduces.
    pub scenarios: usize,
    /// The files published.
    pub files: Vec<PathBuf>,
}

/// A network's sizes and controllers.
impl fmt::Display for Network {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (network, synthesis) = (&self.result.network, &self.result.synthesis);
        let s = &synthesis.size;
        writeln!(
            f,
            "controllers = {}  largest = {} states  A = {} inputs read  N' = {} states in all  (K = {} slots per state)",
            network.names.len(),
            s.max_states,
            s.inputs_used,
            s.total_states,
            synthesis.stats.max_out_degree
        )?;
        for (module, name) in network.modular.modules.iter().zip(&network.names) {
            let size = module.ecc.size();
            let reads = match module.ecc.inputs.is_empty() {
                true => "-".to_string(),
                false => module.ecc.inputs.join(", "),
            };
            writeln!(
                f,
                "  {name}: {} states, {} transitions, {} guard literals; writes {}; reads {reads}",
                size.c,
                size.t,
                size.n,
                module.ecc.outputs.join(", "),
            )?;
        }
        write!(
            f,
            "time {:.2} s (SAT {:.2} s); replayed {} scenarios on the network: all reproduced",
            self.seconds, synthesis.stats.sat_seconds, self.scenarios
        )
    }
}

/// The controllers described in a file, or blocks the solver wires.
enum Wiring {
    Given(distributed::Interfaces),
    Chosen(modular::Options, Vec<String>),
}

/// `synth infer --distributed FILE` (the described controllers, synthesized together) or,
/// without a file, `--modules M --topology arbitrary` (a network wired by the solver).
pub(crate) fn network(
    r: &Request,
    modules: &Modules,
    file: Option<&Path>,
    events: Events<'_>,
) -> Result<Network, Error> {
    let set = r.load(events)?;
    let wiring = match file {
        Some(file) => Wiring::Given(distributed::read_description(file)?.resolve(&set, file)?),
        None => {
            check_exportable_modular(&set, &r.name, modules.count)?;
            let names = (0..modules.count)
                .map(|k| export::modular::module_type_name(&r.name, k))
                .collect();
            Wiring::Chosen(modules.options(r, &set)?, names)
        }
    };
    let results = r.open()?;
    let opts = distributed::Options {
        max_out_degree: modules.slots.unwrap_or(modular::DEFAULT_MAX_OUT_DEGREE),
        max_states: r.sat.max_states,
        algorithms: r.sat.algorithms,
        deadline: crate::deadline::Deadline::NONE,
    };
    let result = r.limit.run(events, |deadline, events| match wiring {
        Wiring::Given(interfaces) => {
            let opts = distributed::Options { deadline, ..opts };
            distributed::run(&set, &interfaces, &opts, events)
        }
        Wiring::Chosen(o, names) => {
            let o = modular::Options { deadline, ..o };
            distributed::run_arbitrary(&set, names, &o, events)
        }
    })?;
    let seconds = r.limit.elapsed();
    let staged = export::network::write_network(&result.network, results.staging(), &r.name)?;
    Ok(Network {
        files: publish(results, &staged)?,
        result,
        seconds,
        scenarios: set.scenarios.len(),
    })
}
