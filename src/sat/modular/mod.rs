//! Exact synthesis of a modular controller (the SAT reconstruction paper, section V) with SAT.
//!
//! In: a [`ScenarioSet`], its [`ScenarioTree`] and [`ModularOptions`] (number of modules `M`,
//! transition slots `K` per state, outputs pinned to modules). Out: a [`ModularSynthesis`]:
//! the [`Modular`] controller, its sizes and figures.
//!
//! Minimization, lexicographic, on one incremental solver (every bound is an assumption):
//! 1. the largest module size (states of the largest module), `!uc[m,n]` for every `m`;
//! 2. the total number of inputs read by the modules `A` (a totalizer over `α`);
//! 3. the total number of states `N'` (a totalizer over `uc`).
//!
//! The encoding is built for a window of at most `N` states per module and rebuilt for a
//! doubled window when every size inside it is unsatisfiable.
//!
//! Minimal means minimal among controllers with at most `K` transitions per state: a state that
//! needs a disjunction of more than `K` cubes forces more states (or more inputs).
//!
//! Too few slots make the search climb through ever larger windows of states, each refuted
//! slowly (a 7-state truth with a 4-transition state ran for minutes with `K = 3`). A ceiling
//! stops that: the least single machine (tree-exact, a fraction of a second) has `C` states and
//! needs at most `D` cubes in one state (its DNF guards in priority order), and `M` copies of it,
//! each owning some outputs, form a modular controller with `C` states per module and `D` slots.
//! So while `K < D`, a largest module above `C` is never needed: when every size up to `C` is
//! refuted, the slots are too few and `K` grows by one (the ascent starts over, since more slots
//! may allow fewer states). With `widen_max_out_degree` off, `K` stays as given.
//!
//! The decoded controller is pruned of transitions the scenarios never fire (they cannot change
//! what the scenarios see) and of guard literals the scenarios do not need (greedily, so `N`
//! is not minimal), and replayed on every scenario before it is returned; a mismatch is
//! reported as [`ModularError::Bug`].

pub(crate) mod constraints;
pub(crate) mod decode;
pub(crate) mod vars;

use super::card::Totalizer;
use super::solver::{Model, Solver};
use crate::ecc::modular::{Modular, ModularSize, Topology};
use crate::ecc::{AlgorithmKind, InputId, OutputId};
use crate::sat::step::{Bound, Progress, Step};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use std::time::Instant;
use varisat::Lit;
use vars::ModVars;

/// Settings of a modular synthesis run.
#[derive(Debug, Clone)]
pub struct ModularOptions {
    /// Number of modules `M` (at least 1).
    pub modules: usize,
    /// The largest out-degree `K`: transition slots per state (guards are conjunctions, so a
    /// disjunction needs several).
    pub max_out_degree: usize,
    /// Give up above this many states in one module.
    pub max_states: usize,
    /// The algorithm form of every module's states (`Tri` or fbSAT's `Binary`).
    pub algorithms: AlgorithmKind,
    /// `pins[m]`: outputs that must belong to module `m` (0-based; may be shorter than `M`).
    pub pins: Vec<Vec<OutputId>>,
    /// Widen `max_out_degree` one at a time when it is too small ([`synthesize_modular`]).
    pub widen_max_out_degree: bool,
    /// How the modules are wired.
    pub topology: Topology,
    /// `reads[m]`: the only inputs module `m` may read (a distributed controller's interface);
    /// `None`: any input.
    pub reads: Option<Vec<Vec<InputId>>>,
    /// `Some(X)`: the inputs from `X` on are the outputs before the step (a network's extended
    /// inputs, [`crate::ecc::network`]), and no module reads its own.
    pub feedback: Option<usize>,
    /// Where every solver call stops ([`Solver::until`]).
    pub deadline: crate::deadline::Deadline,
}

/// The transition slots per state a run starts with when none are given.
pub const DEFAULT_MAX_OUT_DEGREE: usize = 3;

impl Default for ModularOptions {
    fn default() -> Self {
        ModularOptions {
            modules: 2,
            max_out_degree: DEFAULT_MAX_OUT_DEGREE,
            max_states: 16,
            algorithms: AlgorithmKind::Tri,
            pins: Vec::new(),
            widen_max_out_degree: true,
            topology: Topology::Parallel,
            reads: None,
            feedback: None,
            deadline: crate::deadline::Deadline::NONE,
        }
    }
}

/// The result of a modular synthesis run.
#[derive(Debug, Clone)]
pub struct ModularSynthesis {
    /// The controller, replayed through the simulator on every scenario.
    pub modular: Modular,
    /// Largest module, inputs read `A`, states in all `N'`, and each module's size.
    pub size: ModularSize,
    /// Figures of the run (encoding size, solver calls, time, slots).
    pub stats: ModularStats,
}

/// Figures of a run.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct ModularStats {
    /// Nodes of the scenario tree, root included.
    pub(crate) tree_nodes: usize,
    /// Variables of the encoding as built, summed over every window of states tried.
    pub variables: usize,
    /// Clauses of the encoding as built, summed like `variables`.
    pub clauses: usize,
    /// SAT calls made.
    pub solver_calls: usize,
    /// Wall-clock seconds of the minimization (before decoding and pruning).
    pub(crate) sat_seconds: f64,
    /// The largest out-degree `K` of the result: slots per state (more than asked when widened).
    #[serde(rename = "slots")]
    pub max_out_degree: usize,
}

/// Why modular synthesis produced no controller.
#[derive(Debug, thiserror::Error)]
pub enum ModularError {
    /// Every module size up to `max_states` is UNSAT with this many modules and slots (and
    /// widening the slots, when on, did not help).
    #[error("no modular controller with {modules} modules of at most {max_states} states and {max_out_degree} transitions per state reproduces the scenarios (raise --max-states or --slots)")]
    NoController {
        /// The number of modules `M` asked for.
        modules: usize,
        /// The `--max-states` limit per module that was exhausted.
        max_states: usize,
        /// The largest out-degree `K` at the end (after any widening).
        max_out_degree: usize,
    },
    /// The deadline of the run passed ([`crate::deadline`]): the search stopped unfinished.
    #[error("stopped at the time limit")]
    Stopped,
    /// `--pin` with a consecutive composite, whose modules all write every output.
    #[error("--pin applies to parallel composites only: in a consecutive one every module writes every output")]
    PinsInChain,
    /// `--modules 0`: a controller needs at least one module.
    #[error("--modules must be at least 1")]
    NoModules,
    /// A broken internal invariant (a decoded controller that does not replay its scenarios,
    /// pins for more modules than exist); the message says which.
    #[error("internal error (a bug in synth, please report it): {0}")]
    Bug(String),
}

/// A bad `--pin` argument.
#[derive(Debug, thiserror::Error)]
pub enum PinError {
    /// Not of the form `MODULE=OUTPUT[,OUTPUT...]`: no `=`, or an empty output name.
    #[error("--pin `{text}`: expected MODULE=OUTPUT[,OUTPUT...], e.g. 1=start_led,reset_led")]
    Syntax {
        /// The whole `--pin` argument.
        text: String,
    },
    /// The module number is not an integer in `1..=modules`.
    #[error("--pin `{text}`: module {module} does not exist; modules are numbered 1 to {modules}")]
    Module {
        /// The whole `--pin` argument.
        text: String,
        /// The module part as written (before `=`).
        module: String,
        /// The number of modules `M`.
        modules: usize,
    },
    /// A name after `=` is not an output of the scenarios.
    #[error("--pin `{text}`: `{name}` is not an output; the outputs are {}", outputs.join(", "))]
    Output {
        /// The whole `--pin` argument.
        text: String,
        /// The name that is not an output.
        name: String,
        /// Every output name, for the message.
        outputs: Vec<String>,
    },
    /// An output is pinned to two different modules.
    #[error("--pin `{text}`: output `{name}` is already pinned to module {other}")]
    Twice {
        /// The whole `--pin` argument.
        text: String,
        /// The output pinned twice.
        name: String,
        /// The module (numbered from 1) it was pinned to first.
        other: usize,
    },
}

/// Parses `--pin` arguments `MODULE=OUTPUT,OUTPUT` (modules numbered from 1) against the output
/// names; returns the pinned outputs per module (0-based, `modules` entries).
pub(crate) fn parse_pins(
    args: &[String],
    outputs: &[String],
    modules: usize,
) -> Result<Vec<Vec<OutputId>>, PinError> {
    let mut pins: Vec<Vec<OutputId>> = vec![Vec::new(); modules];
    for text in args {
        let syntax = || PinError::Syntax { text: text.clone() };
        let (module, names) = text.split_once('=').ok_or_else(syntax)?;
        let m = module
            .trim()
            .parse::<usize>()
            .ok()
            .filter(|&m| (1..=modules).contains(&m))
            .ok_or_else(|| PinError::Module {
                text: text.clone(),
                module: module.trim().to_string(),
                modules,
            })?;
        let names: Vec<&str> = names.split(',').map(str::trim).collect();
        if names.iter().any(|n| n.is_empty()) {
            return Err(syntax());
        }
        for name in names {
            let z = outputs
                .iter()
                .position(|o| o == name)
                .ok_or_else(|| PinError::Output {
                    text: text.clone(),
                    name: name.to_string(),
                    outputs: outputs.to_vec(),
                })?;
            if let Some(other) = pins.iter().position(|p| p.contains(&OutputId(z))) {
                if other != m - 1 {
                    return Err(PinError::Twice {
                        text: text.clone(),
                        name: name.to_string(),
                        other: other + 1,
                    });
                }
                continue;
            }
            pins[m - 1].push(OutputId(z));
        }
    }
    Ok(pins)
}

/// The two sums minimized after the largest module.
#[derive(Debug, Clone, Copy)]
enum Counter {
    /// `A`: the `α` set.
    Inputs,
    /// `N'`: the `uc` set.
    States,
}

/// The solver with the modular encoding for a window of `c_max` states per module.
struct Encoding {
    solver: Solver,
    vars: ModVars,
    total_alpha: Totalizer,
    total_used: Totalizer,
}

impl Encoding {
    fn new(tree: &ScenarioTree, c_max: usize, opts: &ModularOptions) -> Encoding {
        let mut solver = Solver::until(opts.deadline);
        let sink = &mut solver;
        let chain = opts.topology == Topology::Consecutive;
        let vars = ModVars::new(
            sink,
            tree,
            opts.modules,
            c_max,
            opts.max_out_degree.max(1),
            chain,
        );
        constraints::all(
            sink,
            &vars,
            tree,
            opts.algorithms,
            &opts.pins,
            opts.topology,
        );
        if let Some(reads) = &opts.reads {
            constraints::allowed_reads(sink, &vars, reads);
        }
        if let Some(external) = opts.feedback {
            constraints::no_self_reads(sink, &vars, external);
        }
        let total_alpha = Totalizer::new(sink, vars.all_alpha(), vars.all_alpha().len());
        let total_used = Totalizer::new(sink, vars.all_used(), vars.all_used().len());
        Encoding {
            solver,
            vars,
            total_alpha,
            total_used,
        }
    }
}

fn check_options(opts: &ModularOptions) -> Result<(), ModularError> {
    if opts.modules == 0 {
        return Err(ModularError::NoModules);
    }
    if opts.reads.as_ref().is_some_and(|r| r.len() != opts.modules) {
        return Err(ModularError::Bug(
            "reads for a different number of modules".into(),
        ));
    }
    if opts.pins.len() > opts.modules {
        return Err(ModularError::Bug("pins for more modules than exist".into()));
    }
    if opts.topology == Topology::Consecutive && opts.pins.iter().any(|p| !p.is_empty()) {
        return Err(ModularError::PinsInChain);
    }
    Ok(())
}

/// Synthesizes a modular controller with `opts.modules` modules reproducing every scenario of
/// `set`: least largest module, then least `A`, then least `N'`.
/// `progress` receives one line per step of the search.
pub fn synthesize_modular(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    opts: &ModularOptions,
    progress: Progress<'_>,
) -> Result<ModularSynthesis, ModularError> {
    check_options(opts)?;
    let t0 = Instant::now();
    let mut stats = ModularStats {
        tree_nodes: tree.nodes.len(),
        ..ModularStats::default()
    };
    // The ceiling's copies of the single machine read every input: not when reads are fixed or
    // a module may not read its own outputs.
    let ceiling = if opts.widen_max_out_degree && opts.reads.is_none() && opts.feedback.is_none() {
        single_machine_ceiling(set, tree, opts)
    } else {
        None
    };
    let mut opts = opts.clone();
    opts.max_out_degree = opts.max_out_degree.max(1);
    let (mut enc, n, model) = largest_module(tree, &mut opts, ceiling, &mut stats, progress)?;
    progress(Step::LargestModule { states: n });
    let model = enc.least_sums(enc.vars.size_at_most(n), model, progress);
    stats.solver_calls += enc.solver.stats().calls;
    stats.sat_seconds = t0.elapsed().as_secs_f64();
    stats.max_out_degree = opts.max_out_degree;
    let modular = decoded(&model, &enc.vars, set, &opts)?;
    Ok(ModularSynthesis {
        size: modular.size(),
        modular,
        stats,
    })
}

/// Step 1: the least largest module, with the encoding that found it and its model. The
/// window of states per module grows (doubled) when every size in it is refuted; with a
/// `ceiling` `(C, D)` ([`single_machine_ceiling`]) and fewer than `D` slots, no module needs
/// more than `C` states, so refuting every size up to `C` widens the slots by one instead
/// (and the ascent starts over, since more slots may allow fewer states).
fn largest_module(
    tree: &ScenarioTree,
    opts: &mut ModularOptions,
    ceiling: Option<(usize, usize)>,
    stats: &mut ModularStats,
    progress: Progress<'_>,
) -> Result<(Encoding, usize, Model), ModularError> {
    let max_states = opts.max_states;
    let limit = |max_out_degree: usize| match ceiling {
        Some((c, cubes)) if max_out_degree < cubes => c.min(max_states),
        _ => max_states,
    };
    let mut lo = 1;
    let mut c_max = max_states.clamp(1, 4).min(limit(opts.max_out_degree));
    loop {
        if opts.deadline.passed() {
            return Err(ModularError::Stopped);
        }
        let mut enc = Encoding::new(tree, c_max, opts);
        stats.variables += enc.solver.stats().variables;
        stats.clauses += enc.solver.stats().clauses;
        let vars = &enc.vars;
        let found = enc.solver.ascend(
            lo..=c_max,
            |n| vars.size_at_most(n),
            |n| {
                progress(Step::TryingModules {
                    states: n,
                    modules: opts.modules,
                    tree_nodes: tree.nodes.len(),
                })
            },
        );
        match found {
            Some((n, m)) => return Ok((enc, n, m)),
            None if c_max >= limit(opts.max_out_degree)
                && limit(opts.max_out_degree) < max_states =>
            {
                stats.solver_calls += enc.solver.stats().calls;
                progress(Step::WideningOutDegree {
                    max_out_degree: opts.max_out_degree + 1,
                    states: c_max,
                });
                opts.max_out_degree += 1;
                lo = 1;
                c_max = max_states.clamp(1, 4).min(limit(opts.max_out_degree));
            }
            None if c_max >= max_states => {
                return Err(ModularError::NoController {
                    modules: opts.modules,
                    max_states,
                    max_out_degree: opts.max_out_degree,
                })
            }
            None => {
                // Every size inside the window is unsatisfiable.
                lo = c_max + 1;
                stats.solver_calls += enc.solver.stats().calls;
                c_max = (c_max * 2).min(limit(opts.max_out_degree));
                progress(Step::Reencoding {
                    states: c_max,
                    per_module: true,
                });
            }
        }
    }
}

impl Encoding {
    /// Steps 2 and 3: the least `A`, then the least `N'`, under `base` (the largest module's
    /// bound), each descending from the current model's value and then kept as a bound.
    /// Returns the last model.
    fn least_sums(
        &mut self,
        mut base: Vec<Lit>,
        mut model: Model,
        progress: Progress<'_>,
    ) -> Model {
        for (label, counter) in [
            (Bound::InputsUsed, Counter::Inputs),
            (Bound::TotalStates, Counter::States),
        ] {
            let Encoding {
                solver,
                vars,
                total_alpha,
                total_used,
            } = self;
            let (total, lits) = match counter {
                Counter::Inputs => (&*total_alpha, vars.all_alpha()),
                Counter::States => (&*total_used, vars.all_used()),
            };
            let value = solver.descend(
                &base,
                model.count(lits),
                0,
                |b| total.at_most(b),
                |b| {
                    progress(Step::Trying {
                        bound: label,
                        value: b,
                    })
                },
                |m| {
                    let value = m.count(lits);
                    model = m;
                    value
                },
            );
            base.extend(total.at_most(value));
            progress(Step::Minimal {
                bound: label,
                value,
            });
        }
        model
    }
}

/// The controller of `model`, pruned of transitions the scenarios never fire and of guard
/// literals they do not need (greedily), completed as a chain when consecutive, and checked:
/// valid, replaying every scenario, every pinned output in its module.
fn decoded(
    model: &Model,
    vars: &ModVars,
    set: &ScenarioSet,
    opts: &ModularOptions,
) -> Result<Modular, ModularError> {
    let mut modular = decode::decode(model, vars, set, opts.algorithms, opts.topology);
    decode::prune_unfired(&mut modular, set);
    if set.check(&modular).is_ok() {
        decode::prune_literals(&mut modular, set);
    }
    if opts.topology == Topology::Consecutive {
        decode::complete_chain(&mut modular);
    }
    modular.validate().map_err(ModularError::Bug)?;
    set.check(&modular)
        .map_err(|m| ModularError::Bug(format!("the modular controller does not replay {m}")))?;
    for (m, zs) in opts.pins.iter().enumerate() {
        if let Some(z) = zs.iter().find(|z| modular.owner(**z) != Some(m)) {
            return Err(ModularError::Bug(format!(
                "output {} was pinned to module {} but is not there",
                set.outputs[z.0],
                m + 1
            )));
        }
    }
    Ok(modular)
}

/// `(C, D)`: the least single machine's states, and the most guard cubes one of its states
/// needs (`None` when it cannot be had). See the module documentation.
fn single_machine_ceiling(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    opts: &ModularOptions,
) -> Option<(usize, usize)> {
    let single = crate::sat::Options {
        algorithms: opts.algorithms,
        max_states: opts.max_states,
        // Any guards that replay the scenarios will do; fewer cubes only widen less often.
        guard_budget: std::time::Duration::from_secs(1),
        deadline: opts.deadline,
        ..crate::sat::Options::default()
    };
    let s = crate::sat::synthesize(set, tree, &single, &mut |_| {}).ok()?;
    let mut cubes = 0;
    for state in &s.ecc.states {
        let mut here = 0;
        for t in &state.transitions {
            here += t.guard.as_dnf()?.len();
        }
        cubes = cubes.max(here);
    }
    Some((s.size.c, cubes))
}

/// Whether a modular controller whose modules have at most `n` states each reproduces the tree
/// (the building block of the first minimization, exposed for tests of known minima).
pub(crate) fn satisfiable_modular(tree: &ScenarioTree, opts: &ModularOptions, n: usize) -> bool {
    if n == 0 || check_options(opts).is_err() {
        return false;
    }
    let mut enc = Encoding::new(tree, n, opts);
    enc.solver.solve(&[]).is_some()
}

#[cfg(test)]
mod tests;
