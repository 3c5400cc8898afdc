//! Following a verified machine: a machine (or composite) learned from scenarios alone is
//! refined along NuSMV's counterexamples with the answers of a machine NuSMV already verified,
//! until NuSMV verifies it too.
//!
//! In: the recordings, the *oracle* (a verified single machine that reproduces them), a
//! [`Check`] and a way to make a controller from scenarios. Out: the last controller made, NuSMV's
//! certificate for it, the rounds, and the scenarios it reproduces.
//!
//! # Why it converges
//! Along a counterexample of the controller the oracle is run on the same inputs; its answers,
//! up to the first step where they differ from the controller's, become a new scenario. There is
//! such a step: the plant sees only the outputs, so a controller answering like the oracle along
//! the whole run would make that run one of the oracle's, which NuSMV verified. Each round thus
//! adds a scenario the controller got wrong, and the controllers converge on one that behaves
//! like the oracle wherever the closed loop goes. Used for modular synthesis
//! ([`super::modular::run_verified`]): the composite of M function blocks that splits a
//! verified machine.

use super::{Check, Error, Events};
use crate::ecc::sim::{Controller, Reactive, Run};
use crate::ecc::Ecc;
use crate::nusmv::CheckMode;
use crate::scenario::negative::NegativeScenario;
use crate::scenario::{Origin, Scenario, ScenarioSet};

/// What a round's controller is, for the round's figures and for NuSMV.
pub(crate) struct Made {
    /// States of the largest part (a single machine: all of them).
    pub(crate) largest: usize,
    /// States in all.
    pub(crate) states: usize,
    /// Wall-clock seconds spent making the controller (SAT).
    pub(crate) sat_seconds: f64,
    /// The controller as SMV text defining `MODULE ECC(REQ, inputs...)`.
    pub(crate) smv: String,
}

/// One controller checked by NuSMV.
#[derive(Debug, Clone, serde::Serialize, schemars::JsonSchema)]
pub struct Round {
    /// 1-based number of the round.
    pub(crate) number: usize,
    /// States of the controller's largest part.
    pub(crate) largest_states: usize,
    /// States of the controller in all.
    pub(crate) states: usize,
    /// Properties NuSMV found violated (empty: verified).
    pub(crate) failing: Vec<String>,
    /// Steps of the scenarios recorded from the oracle along the counterexamples.
    pub(crate) added_steps: usize,
    /// Wall-clock seconds spent making the controller (SAT).
    pub(crate) sat_seconds: f64,
    /// Seconds NuSMV took to check the controller.
    pub(crate) nusmv_seconds: f64,
}

/// The end of a successful [`run`].
pub struct Followed {
    /// NuSMV's report and the closed-loop model of the verified controller.
    pub certificate: super::exact::Certificate,
    /// Every round, the last one the verified controller.
    pub(crate) rounds: Vec<Round>,
    /// The recordings and the scenarios recorded from the oracle.
    pub(crate) scenarios: ScenarioSet,
}

/// A controller made from scenarios, with its figures and SMV text.
pub(crate) type Make<'m, C> = dyn FnMut(&ScenarioSet, Events<'_>) -> Result<(C, Made), Error> + 'm;

/// Makes controllers with `make` from `set` and the scenarios recorded from `oracle` along
/// their counterexamples until NuSMV verifies one (at most `max_rounds`).
pub(crate) fn run<C: Controller>(
    set: &ScenarioSet,
    oracle: &Ecc,
    check: &Check,
    max_rounds: usize,
    events: Events<'_>,
    make: &mut Make<'_, C>,
) -> Result<Followed, Error> {
    set.check(oracle)
        .map_err(|m| Error::Bug(format!("the verified machine does not replay {m}")))?;
    let mut verifier = check.verifier()?;
    let mut scenarios = set.clone();
    let mut rounds = Vec::new();
    for number in 1..=max_rounds {
        let (controller, made) = make(&scenarios, events)?;
        // Every counterexample at once: each costs NuSMV a backward re-check, but saves a
        // round (modular Pick-and-Place needs about a quarter of the rounds).
        let v = verifier.verify_controller(made.smv, &set.inputs, CheckMode::AllCounterexamples)?;
        let failing: Vec<String> = v.report.failing().iter().map(|s| s.to_string()).collect();
        let mut added_steps = 0;
        for cx in &v.counterexamples {
            let Some(neg) = cx.negative_scenario(&set.inputs, &set.outputs) else {
                continue;
            };
            let scenario = divergence(oracle, &controller, &neg, number).ok_or_else(|| {
                Error::Bug(format!(
                    "NuSMV says the controller violates {}, but the verified machine answers like it along the whole counterexample",
                    cx.property
                ))
            })?;
            added_steps += scenario.steps.len();
            scenarios.scenarios.push(scenario);
        }
        let round = Round {
            number,
            largest_states: made.largest,
            states: made.states,
            failing: failing.clone(),
            added_steps,
            sat_seconds: made.sat_seconds,
            nusmv_seconds: v.report.nusmv_seconds,
        };
        events(super::Event::Followed(&round));
        rounds.push(round);
        if failing.is_empty() {
            return Ok(Followed {
                certificate: super::exact::Certificate {
                    report: v.report,
                    model_text: v.model.text,
                },
                rounds,
                scenarios,
            });
        }
        if added_steps == 0 {
            return Err(Error::NoMachine(format!(
                "the controller violates {}, and NuSMV printed no counterexample with every controller input and output",
                failing.join(", ")
            )));
        }
    }
    Err(Error::NoMachine(format!(
        "no verified controller after {max_rounds} rounds (raise --max-iterations)"
    )))
}

/// The oracle's answers along the inputs of `neg` (a counterexample of `controller`; a lasso
/// is unrolled), up to and including the first step where its outputs differ from the
/// controller's; `None` if they never do.
fn divergence<C: Controller>(
    oracle: &Ecc,
    controller: &C,
    neg: &NegativeScenario,
    round: usize,
) -> Option<Scenario> {
    let mut inputs: Vec<&[bool]> = neg.steps.iter().map(|s| s.inputs.as_slice()).collect();
    if let Some(l) = neg.loop_start {
        // Along the loop the controller repeats itself (NuSMV's lasso includes its state);
        // the oracle's state at each pass over the loop start is a function of the one
        // before, so within C + 1 passes it repeats too, and a difference, if any, has shown.
        for _ in 0..oracle.states.len() + 1 {
            inputs.extend(neg.steps[l..].iter().map(|s| s.inputs.as_slice()));
        }
    }
    let mut a = Run::new(oracle);
    let mut b = controller.start();
    let mut outputs = oracle.initial_outputs.clone();
    for (k, x) in inputs.iter().enumerate() {
        a.step(x);
        if let Some(o) = b.react(x) {
            outputs.copy_from_slice(o);
        }
        if a.outputs != outputs {
            let steps: Vec<Vec<bool>> = inputs[..=k].iter().map(|x| x.to_vec()).collect();
            let origin = Origin {
                file: std::path::PathBuf::from(format!("counterexample of controller {round}")),
                line: 0,
                rows: None,
            };
            return Some(super::active::record(oracle, &steps, origin));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::{Algorithm, Guard, InputId, State, StateId, Transition, Tri};
    use crate::scenario::negative::NegativeStep;

    /// State 1 = lamp on; the button switches it on, and off again when `toggles`.
    fn button_lamp(toggles: bool) -> Ecc {
        let press = |target: usize| Transition {
            target: StateId(target),
            guard: Guard::Var(InputId(0)),
        };
        let state = |name: &str, on: bool, transitions: Vec<Transition>| State {
            name: name.into(),
            algorithm: Algorithm::Tri(vec![if on { Tri::One } else { Tri::Zero }]),
            transitions,
        };
        let back = if toggles { vec![press(0)] } else { Vec::new() };
        Ecc {
            inputs: vec!["button".into()],
            outputs: vec!["lamp".into()],
            initial_outputs: vec![false],
            states: vec![state("s0", false, vec![press(1)]), state("s1", true, back)],
        }
    }

    /// A lamp that a button switches on (state 1) and nothing switches off, against one that
    /// the button toggles: they differ at the second press.
    #[test]
    fn the_first_difference_ends_the_recorded_scenario() {
        let (on, toggle) = (button_lamp(false), button_lamp(true));
        let step = |b: bool| NegativeStep {
            inputs: vec![b],
            before: vec![false],
            after: vec![false],
        };
        let neg = NegativeScenario {
            steps: vec![step(true), step(false), step(true)],
            loop_start: Some(1),
            label: "test".into(),
        };
        let s = divergence(&toggle, &on, &neg, 1).unwrap();
        // press (on), release, press (toggle: off; the other stays on).
        assert_eq!(s.steps.len(), 3);
        assert_eq!(s.steps[2].outputs, Some(vec![false]));
        assert!(divergence(&on, &on, &neg, 1).is_none());
    }
}
