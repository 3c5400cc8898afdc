//! Properties inside the encoding: the closed loop of machine and plant, unrolled along a
//! fixed environment, with every property required on the unrolled run.
//!
//! In: the cube-model variables of the basic encoding ([`Vars`], [`CubeVars`]), a [`Spec`]
//! (the plant's [`Model`], how machine and plant are wired, the properties) and an
//! [`Environment`] (what the plant's free variables did along one run, usually a
//! counterexample). Out: clauses saying "on this environment, the closed loop of *the
//! solver's machine* with the plant satisfies every property" (up to the bound explained in
//! [`property`]).
//!
//! # Why this converges where negative scenarios do not
//! A negative scenario forbids one sequence of controller outputs on one sequence of inputs;
//! machines of the same size that fail the same way on slightly different inputs are still
//! allowed, and there are exponentially many. Here the counterexample only contributes the
//! *environment* (the operator's buttons, the pieces put on tracks): the plant's reaction to
//! whatever the machine does is part of the formula, so every machine that fails on that
//! environment is ruled out at once, however it fails. This is bounded synthesis in the
//! counterexample-guided form (each environment is one universally quantified play, added
//! lazily), over the explicit plant model instead of NuSMV's.
//!
//! # Families (one function each)
//! - [`machine::step`]: the machine reacting to the sensors of a step;
//! - [`plant::next_state`]: the plant's next state under the machine's outputs;
//! - [`property::Bounded::require`]: each property on the run.
//!
//! Timing is the closed loop's (see [`crate::smv::composition`]): at step `t` the machine reads
//! the plant's values of step `t`, its new outputs appear at `t + 1`, and the plant's step from
//! `t` to `t + 1` reads the outputs of step `t`.

pub(crate) mod gates;
pub(crate) mod machine;
pub(crate) mod plant;
pub(crate) mod property;

use self::gates::{Fd, Gates, B};
use self::machine::MachineState;
use crate::ltl::Ltl;
use crate::plant::{Model, Name, Value, VarKind};
use crate::sat::vars::{CubeVars, Vars};
use std::collections::HashMap;
use std::sync::Arc;
use varisat::ExtendFormula;

/// How machine, plant and properties fit together, checked by the caller.
#[derive(Debug, Clone)]
pub(crate) struct Spec {
    /// The plant as a finite-state model (the SMV subset the plants use).
    pub(crate) plant: Arc<Model>,
    /// Per machine input (scenario order): the plant variable or define it reads.
    pub(crate) inputs: Vec<Name>,
    /// Per plant parameter: the machine output (index) it reads.
    pub(crate) params: Vec<usize>,
    /// Machine output names, as properties use them.
    pub(crate) outputs: Vec<String>,
    /// The properties encoded: future-only, every name resolved.
    pub(crate) properties: Vec<Ltl>,
    /// Steps unrolled after the environment's end: within them eventualities must be
    /// fulfilled, and safety properties are required on them too.
    pub(crate) response_bound: usize,
    /// The machine's output values before its first step (scenario order).
    pub(crate) initial_outputs: Vec<bool>,
}

/// What the plant's free variables did along one run: the full plant state of each step (only
/// the free parts and the nondeterministic choices are read), as a lasso.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Environment {
    /// Per step, the value of every plant variable ([`crate::plant::VarId`] order).
    pub(crate) states: Vec<Vec<Value>>,
    /// The run continues `states[loop_start..]` forever.
    pub(crate) loop_start: usize,
}

impl Environment {
    /// The plant state of step `t` of the infinite run.
    pub(crate) fn at(&self, t: usize) -> &[Value] {
        let (n, l) = (self.states.len(), self.loop_start);
        let p = if t < n { t } else { l + (t - l) % (n - l) };
        &self.states[p]
    }
}

/// The names a property may read, for checking before anything is encoded: every machine
/// output and every plant variable and define.
pub(crate) fn resolves(spec: &Spec, name: &str) -> bool {
    spec.outputs.iter().any(|o| o == name)
        || matches!(
            spec.plant.lookup(name),
            Some(Name::Var(_)) | Some(Name::Define(_))
        )
        || spec.plant.symbol(name).is_some()
}

/// The plant's free variables: `IVAR`s and `VAR`s without `init` and `next`, whose values are
/// the environment's alone.
pub(crate) fn environment_names(model: &Model) -> Vec<String> {
    model
        .vars
        .iter()
        .filter(|v| is_free(v))
        .map(|v| v.name.clone())
        .collect()
}

fn is_free(v: &crate::plant::Var) -> bool {
    v.kind == VarKind::Input || (v.next.is_none() && v.init.is_none())
}

/// Whether `name`, read by a property, is the environment's alone: a free variable of the
/// plant ([`environment_names`]) or a symbolic constant that names nothing else of the closed
/// loop. A subformula over such names only is a constant on a given environment.
pub fn is_environment(spec: &Spec, name: &str) -> bool {
    let model = &*spec.plant;
    match model.lookup(name) {
        Some(Name::Var(v)) => is_free(model.var(v)),
        Some(_) => false,
        None => !spec.outputs.iter().any(|o| o == name) && model.symbol(name).is_some(),
    }
}

/// Adds the closed loop along `env` with every property of `spec` required on it.
pub(crate) fn encode(
    f: &mut impl ExtendFormula,
    vars: &Vars,
    cv: &CubeVars,
    spec: &Spec,
    env: &Environment,
) {
    let model = &*spec.plant;
    let mut g = Gates { f };
    let deadline = env.states.len().saturating_sub(1);
    let last = deadline + spec.response_bound;
    let names = property_names(spec);
    let env_vars = environment_vars(model);
    let mut state: Vec<Fd> = env.at(0).iter().map(|&v| Fd::constant(v)).collect();
    let mut machine = MachineState::initial(vars.c_max, &spec.initial_outputs);
    let mut atoms: Vec<HashMap<String, Fd>> = Vec::with_capacity(last + 1);
    let mut envs: Vec<HashMap<String, Value>> = Vec::with_capacity(last + 1);
    for t in 0..=last {
        let params: Vec<B> = spec.params.iter().map(|&z| machine.outputs[z]).collect();
        let mut frame = plant::Frame::new(model, &state, &params);
        let inputs = sensors(&mut g, spec, &mut frame);
        atoms.push(atoms_at(&mut g, spec, &names, &machine, &mut frame));
        envs.push(
            (env_vars.iter())
                .map(|(name, i)| (name.clone(), env.at(t)[*i]))
                .collect(),
        );
        if t < last {
            let next_plant = plant::next_state(&mut g, model, &mut frame, env.at(t + 1));
            machine = machine::step(&mut g, vars, cv, &machine, &inputs);
            state = next_plant;
        }
    }
    let symbol = |name: &str| model.symbol(name);
    let run = property::Run {
        atoms: &atoms,
        env: &envs,
        env_len: env.states.len(),
        env_loop: env.loop_start,
        symbol: &symbol,
        deadline,
    };
    let mut bounded = property::Bounded::new(&run);
    for p in &spec.properties {
        bounded.require(&mut g, p);
    }
}

/// The names the properties read. Both operands of a comparison: `on_for != k` reads the
/// define `k` as well.
fn property_names(spec: &Spec) -> std::collections::BTreeSet<String> {
    (spec.properties.iter())
        .flat_map(property::operand_names)
        .collect()
}

/// The plant's free variables ([`environment_names`]) with their indices.
fn environment_vars(model: &Model) -> Vec<(String, usize)> {
    environment_names(model)
        .into_iter()
        .filter_map(|n| match model.lookup(&n) {
            Some(Name::Var(v)) => Some((n, v.0)),
            _ => None,
        })
        .collect()
}

/// The machine's inputs in one step: what the plant shows in `frame`.
fn sensors<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    spec: &Spec,
    frame: &mut plant::Frame<'_>,
) -> Vec<B> {
    (spec.inputs.iter())
        .map(|&name| {
            let e = match name {
                Name::Var(v) => crate::plant::Expr::Var(v),
                Name::Define(d) => crate::plant::Expr::Define(d),
                Name::Param(p) => crate::plant::Expr::Param(p),
            };
            plant::boolean(g, &spec.plant, &e, frame)
        })
        .collect()
}

/// The value of every name a property reads in one step: a machine output, or a plant
/// variable or define in `frame`.
fn atoms_at<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    spec: &Spec,
    names: &std::collections::BTreeSet<String>,
    machine: &MachineState,
    frame: &mut plant::Frame<'_>,
) -> HashMap<String, Fd> {
    let model = &*spec.plant;
    let mut here = HashMap::new();
    for name in names {
        if let Some(z) = spec.outputs.iter().position(|o| o == name) {
            here.insert(name.clone(), Fd::of_bool(machine.outputs[z]));
            continue;
        }
        let value = match model.lookup(name) {
            Some(Name::Var(v)) => frame.state[v.0].clone(),
            Some(Name::Define(d)) => {
                plant::eval(g, model, &crate::plant::Expr::Define(d), frame, None)
            }
            Some(Name::Param(_)) | None => continue,
        };
        here.insert(name.clone(), value);
    }
    here
}

#[cfg(test)]
mod tests;
