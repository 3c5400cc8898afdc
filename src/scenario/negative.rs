//! Negative scenarios: behaviours the controller must *not* show, as lassos.
//!
//! A counterexample of the model checker is an infinite closed-loop run: a prefix and a loop
//! repeated forever. Seen from the controller it is a sequence of steps `(inputs, outputs
//! before, outputs after)`. A controller that reproduces those outputs on those inputs forever
//! lets the plant follow the same run, so the property fails again. A correct controller must
//! therefore leave the lasso somewhere: produce different outputs at some step.
//!
//! The user may also forbid behaviours directly ([`read`], `--negative FILE`, fbSAT's complete
//! synthesis): finite scenarios in the positive scenarios' syntax.

use super::tree::{InputVec, NodeId, ScenarioTree};
use super::{Scenario, ScenarioError, ScenarioSet};
use crate::ecc::{Ecc, Run, StateId};
use std::collections::HashSet;
use std::path::Path;

/// One step of a negative scenario.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) struct NegativeStep {
    /// Input values of the step's `REQ`.
    pub(crate) inputs: Vec<bool>,
    /// Controller outputs when the step starts.
    pub(crate) before: Vec<bool>,
    /// Controller outputs after the step.
    pub(crate) after: Vec<bool>,
}

/// A lasso of steps: `steps[..loop_start]` once, then `steps[loop_start..]` forever; the
/// outputs after the last step are the outputs before `steps[loop_start]`. Without a loop
/// (`loop_start: None`) it is a finite prefix: reproducing all its steps is already bad (a
/// safety violation is reached at its end).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct NegativeScenario {
    /// The steps, prefix then loop.
    pub(crate) steps: Vec<NegativeStep>,
    /// 0-based index of the first step of the loop, or `None` for a finite prefix.
    pub(crate) loop_start: Option<usize>,
    /// What it came from, for messages (e.g. the property name).
    pub(crate) label: String,
}

impl NegativeScenario {
    /// Whether `ecc`, started in its initial state, reproduces the lasso forever (or, for a
    /// finite prefix, every step of it).
    pub fn followed_by(&self, ecc: &Ecc) -> bool {
        let Some(first) = self.steps.first() else {
            return false;
        };
        if first.before != ecc.initial_outputs {
            return false;
        }
        let mut run = Run::new(ecc);
        let Some(loop_start) = self.loop_start else {
            return self.steps.iter().all(|step| {
                run.step(&step.inputs);
                run.outputs == step.after
            });
        };
        let mut seen: HashSet<(usize, StateId)> = HashSet::new();
        let mut i = 0;
        loop {
            if i >= loop_start && !seen.insert((i, run.state)) {
                // The same position in the same state: the run repeats forever.
                return true;
            }
            let step = &self.steps[i];
            run.step(&step.inputs);
            if run.outputs != step.after {
                return false;
            }
            i = if i + 1 < self.steps.len() {
                i + 1
            } else {
                loop_start
            };
        }
    }
}

/// Reads negative scenarios written by the user in the fbSAT scenario syntax (the format of
/// positive scenarios, [`super::fbsat`]): each line is a finite behaviour the machine must not
/// show in full from its initial state. A step with `out=CNF[bits]` forbids those outputs
/// after the step; a step without `out=` forbids the outputs staying as they were. Only the
/// output values count (as in closed loop, where the plant sees values, not events), so a
/// machine shows the scenario when its outputs after every step equal the scenario's.
pub fn read(
    file: &Path,
    inputs: &[String],
    outputs: &[String],
    initial_outputs: &[bool],
) -> Result<Vec<NegativeScenario>, ScenarioError> {
    let set = super::fbsat::read(file, Some(inputs.to_vec()), Some(outputs.to_vec()))?;
    Ok(set
        .scenarios
        .iter()
        .map(|s| from_scenario(s, initial_outputs))
        .collect())
}

/// The scenario's behaviour as a finite negative scenario labelled with its origin.
fn from_scenario(s: &Scenario, initial_outputs: &[bool]) -> NegativeScenario {
    let mut before = initial_outputs.to_vec();
    let steps = s
        .steps
        .iter()
        .map(|step| {
            let after = step.outputs.clone().unwrap_or_else(|| before.clone());
            NegativeStep {
                inputs: step.inputs.clone(),
                before: std::mem::replace(&mut before, after.clone()),
                after,
            }
        })
        .collect();
    NegativeScenario {
        steps,
        loop_start: None,
        label: s.origin.to_string(),
    }
}

/// A negative scenario that the recordings force: every machine that reproduces them shows
/// it, so none can exist.
#[derive(Debug, thiserror::Error)]
#[error("{negative}: every machine that reproduces the recordings shows this negative scenario (its {steps} steps follow the recorded behaviour, last through {place}), so none can avoid it: remove it or the recording")]
pub struct Recorded {
    /// The negative scenario's label.
    pub(crate) negative: String,
    /// The recorded step the scenario's last active step coincides with (or the start).
    pub(crate) place: String,
    /// Number of steps of the negative scenario.
    pub(crate) steps: usize,
}

/// Checks that no finite negative scenario is forced by the recordings: following it through
/// the scenario tree, every step recorded (actively, or passively: nothing fires, which the
/// tree merges into its node) with the outputs the negative scenario names.
pub(crate) fn check_not_recorded(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    negatives: &[NegativeScenario],
) -> Result<(), Recorded> {
    for neg in negatives.iter().filter(|n| n.loop_start.is_none()) {
        if neg.steps.first().map(|s| &s.before) != Some(&set.initial_outputs) {
            continue;
        }
        let Some(node) = forced(tree, neg) else {
            continue;
        };
        let (si, step) = tree.witness[node.0];
        let place = match set.scenarios.get(si) {
            Some(s) if step > 0 => s.origin.step(step),
            _ => "the initial state".to_string(),
        };
        return Err(Recorded {
            negative: neg.label.clone(),
            place,
            steps: neg.steps.len(),
        });
    }
    Ok(())
}

/// The tree node where `neg` ends when the recordings force every one of its steps.
fn forced(tree: &ScenarioTree, neg: &NegativeScenario) -> Option<NodeId> {
    let mut node = tree.root();
    for step in &neg.steps {
        let u = InputVec(tree.input_vectors.iter().position(|x| *x == step.inputs)?);
        let n = &tree.nodes[node.0];
        if let Some(&(_, child)) = n.children.iter().find(|(v, _)| *v == u) {
            node = child;
        } else if !n.passive.contains(&u) {
            return None;
        }
        if tree.nodes[node.0].outputs != step.after {
            return None;
        }
    }
    Some(node)
}
