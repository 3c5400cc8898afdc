//! Negative scenarios: behaviours the controller must *not* show, as lassos.
//!
//! A counterexample of the model checker is an infinite closed-loop run: a prefix and a loop
//! repeated forever. Seen from the controller it is a sequence of steps `(inputs, outputs
//! before, outputs after)`. A controller that reproduces those outputs on those inputs forever
//! lets the plant follow the same run, so the property fails again. A correct controller must
//! therefore leave the lasso somewhere: produce different outputs at some step.

use crate::ecc::{Ecc, Run, StateId};
use std::collections::HashSet;

/// One step of a negative scenario.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct NegativeStep {
    pub inputs: Vec<bool>,
    /// Controller outputs when the step starts.
    pub before: Vec<bool>,
    /// Controller outputs after the step.
    pub after: Vec<bool>,
}

/// A lasso of steps: `steps[..loop_start]` once, then `steps[loop_start..]` forever; the
/// outputs after the last step are the outputs before `steps[loop_start]`. Without a loop
/// (`loop_start: None`) it is a finite prefix: reproducing all its steps is already bad (a
/// safety violation is reached at its end).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct NegativeScenario {
    pub steps: Vec<NegativeStep>,
    pub loop_start: Option<usize>,
    /// What it came from, for messages (e.g. the property name).
    pub label: String,
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
