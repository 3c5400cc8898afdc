//! From a satisfying assignment of the modular encoding to a [`Modular`] controller, and the
//! clean-up that keeps its behaviour on the scenarios.
//!
//! In: the solver's [`Model`], the [`ModVars`] registry and the scenarios. Out: one [`Module`]
//! per module with its inputs (`α`), outputs (`θ`) and ECC over them: the used states, the
//! enabled slots in priority order with their cubes, and the algorithms of the owned outputs.

use super::vars::ModVars;
use crate::ecc::modular::{Modular, ModularRun, Module, Topology};
use crate::ecc::{AlgorithmKind, Ecc, Guard, InputId, OutputId, State, StateId, Transition};
use crate::sat::decode::{algorithm, cube_transition};
use crate::sat::solver::Model;
use crate::scenario::ScenarioSet;
use std::collections::HashSet;

/// Reads the controller out of `model`.
pub(crate) fn decode(
    model: &Model,
    v: &ModVars,
    set: &ScenarioSet,
    kind: AlgorithmKind,
    topology: Topology,
) -> Modular {
    let d = v.d;
    let modules = (0..d.modules)
        .map(|m| {
            let inputs: Vec<InputId> = (0..d.bits)
                .filter(|&x| model.value(v.alpha(m, x)))
                .map(InputId)
                .collect();
            let outputs: Vec<OutputId> = (0..d.outputs)
                .filter(|&z| model.value(v.theta(m, z)))
                .map(OutputId)
                .collect();
            let local = |x: usize| {
                InputId(
                    inputs
                        .iter()
                        .position(|i| i.0 == x)
                        .expect("guard literals imply α"),
                )
            };
            let n = (0..d.c_max).filter(|&q| model.value(v.used(m, q))).count();
            let states = (0..n)
                .map(|q| {
                    let transitions = (0..d.max_out_degree)
                        .take_while(|&k| model.value(v.cubes.en(m, q, k)))
                        .map(|k| cube_transition(model, &v.cubes, m, q, k, local))
                        .collect();
                    let a0: Vec<bool> = outputs
                        .iter()
                        .map(|z| model.value(v.a0(m, q, z.0)))
                        .collect();
                    let a1: Vec<bool> = outputs
                        .iter()
                        .map(|z| model.value(v.a1(m, q, z.0)))
                        .collect();
                    State {
                        name: format!("s{q}"),
                        algorithm: algorithm(kind, a0, a1),
                        transitions,
                    }
                })
                .collect();
            let ecc = Ecc {
                inputs: inputs.iter().map(|i| set.inputs[i.0].clone()).collect(),
                outputs: outputs.iter().map(|z| set.outputs[z.0].clone()).collect(),
                initial_outputs: outputs.iter().map(|z| set.initial_outputs[z.0]).collect(),
                states,
            };
            Module {
                inputs,
                outputs,
                ecc,
            }
        })
        .collect();
    Modular {
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        modules,
        topology,
    }
}

/// Removes every transition no scenario fires. What the scenarios see is unchanged: a slot
/// that never fires first on a step where its module gets `REQ` decides nothing there.
pub(crate) fn prune_unfired(modular: &mut Modular, set: &ScenarioSet) {
    let mut fired: Vec<HashSet<(StateId, usize)>> = vec![HashSet::new(); modular.modules.len()];
    for sc in &set.scenarios {
        let mut run = ModularRun::new(modular);
        for step in &sc.steps {
            run.step(&step.inputs);
            for (seen, f) in fired.iter_mut().zip(&run.fired) {
                seen.extend(f.map(|f| (f.source, f.index)));
            }
        }
    }
    for (module, fired) in modular.modules.iter_mut().zip(&fired) {
        for (q, state) in module.ecc.states.iter_mut().enumerate() {
            let mut k = 0;
            state.transitions.retain(|_| {
                k += 1;
                fired.contains(&(StateId(q), k - 1))
            });
        }
    }
}

/// Drops guard literals one at a time, greedily, while the composite still replays every
/// scenario: the solver only bounds the inputs a module reads, not the literals it writes, so
/// a guard may test more than the scenarios need.
pub(crate) fn prune_literals(modular: &mut Modular, set: &ScenarioSet) {
    for m in 0..modular.modules.len() {
        for q in 0..modular.modules[m].ecc.states.len() {
            for k in 0..modular.modules[m].ecc.states[q].transitions.len() {
                let mut lits = modular.modules[m].ecc.states[q].transitions[k]
                    .guard
                    .as_cube()
                    .expect("decoded guards are cubes");
                let mut i = 0;
                while i < lits.len() {
                    let mut fewer = lits.clone();
                    fewer.remove(i);
                    let old = std::mem::replace(
                        &mut modular.modules[m].ecc.states[q].transitions[k].guard,
                        Guard::cube(&fewer),
                    );
                    if set.check(modular).is_ok() {
                        lits = fewer;
                    } else {
                        modular.modules[m].ecc.states[q].transitions[k].guard = old;
                        i += 1;
                    }
                }
            }
        }
    }
}

/// Makes every module after the first of a chain complete, as a consecutive composite's are
/// (see [`crate::ecc::modular`]): the last transition of each state becomes unconditional, and
/// a state without transitions gets an unconditional loop. What the scenarios see is
/// unchanged: such a module gets `REQ` only on active steps, where it fires anyway, and a state
/// without transitions never gets one.
pub(crate) fn complete_chain(modular: &mut Modular) {
    for module in modular.modules.iter_mut().skip(1) {
        for (q, state) in module.ecc.states.iter_mut().enumerate() {
            match state.transitions.last_mut() {
                Some(t) => t.guard = Guard::True,
                None => state.transitions.push(Transition {
                    target: StateId(q),
                    guard: Guard::True,
                }),
            }
        }
    }
}
