//! The scenarios as the search reads them: precomputed once into flat bit-mask arrays.
//!
//! In: a [`ScenarioSet`]. Out: [`ScenarioData`]: per step the inputs, the recorded `CNF`
//! outputs (or `PASSIVE`, no `CNF`) and the outputs before the step, as bit masks (bit `i` is input or
//! output `i`), in one array; and per scenario its range and, for scenarios of at most 128 steps,
//! the match masks of the bit-parallel edit distance. State labeling ([`super::labeling`]) and
//! the fitness ([`super::fitness`]) both run on it.

use super::machine::{input_bits, MAX_INPUTS};
use crate::scenario::ScenarioSet;
use std::ops::Range;

/// The symbol of a passive step (no `CNF`); output vectors use the low 31 bits.
pub(crate) const PASSIVE: u32 = u32::MAX;

/// The search supports at most this many outputs.
pub(crate) const MAX_OUTPUTS: usize = 31;

/// One step, precomputed.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StepData {
    /// Inputs as a bit mask.
    pub(crate) x: u32,
    /// Recorded `CNF` outputs as a bit mask, or [`PASSIVE`].
    pub(crate) expected: u32,
    /// Recorded outputs before the step.
    pub(crate) before: u32,
}

/// The scenarios as flat bit-mask arrays.
#[derive(Debug, Clone)]
pub struct ScenarioData {
    /// Input variable names; input `i` is bit `i` of a step's input mask.
    pub inputs: Vec<String>,
    /// Output variable names; output `i` is bit `i` of an output mask.
    pub(crate) outputs: Vec<String>,
    /// Output values before the first step of every scenario.
    pub(crate) initial_outputs: Vec<bool>,
    pub(crate) initial: u32,
    pub(crate) steps: Vec<StepData>,
    /// Range of `steps` of every scenario.
    pub(crate) bounds: Vec<Range<usize>>,
    /// Per scenario of at most 128 steps, Myers' match masks: for every recorded symbol, the
    /// steps that record it. Empty for longer scenarios (they use the quadratic algorithm).
    pub(crate) peq: Vec<Vec<(u32, u128)>>,
}

/// Why scenarios cannot be searched.
#[derive(Debug, thiserror::Error)]
pub enum DataError {
    /// More inputs than fit the bit masks of the search.
    #[error("the search handles at most {max} inputs, the scenarios have {got}")]
    TooManyInputs {
        /// The most inputs the search handles.
        max: usize,
        /// The number of inputs of the scenarios.
        got: usize,
    },
    /// More outputs than [`MAX_OUTPUTS`].
    #[error("the search handles at most {max} outputs, the scenarios have {got}")]
    TooManyOutputs {
        /// The most outputs the search handles ([`MAX_OUTPUTS`]).
        max: usize,
        /// The number of outputs of the scenarios.
        got: usize,
    },
    /// Every scenario is empty: there is nothing to fit.
    #[error("no scenario has a step")]
    Empty,
}

impl ScenarioData {
    /// Precomputes `set` (skipping empty scenarios), or says why the search cannot take it.
    pub fn new(set: &ScenarioSet) -> Result<ScenarioData, DataError> {
        if set.inputs.len() > MAX_INPUTS {
            return Err(DataError::TooManyInputs {
                max: MAX_INPUTS,
                got: set.inputs.len(),
            });
        }
        if set.outputs.len() > MAX_OUTPUTS {
            return Err(DataError::TooManyOutputs {
                max: MAX_OUTPUTS,
                got: set.outputs.len(),
            });
        }
        let initial = input_bits(&set.initial_outputs);
        let mut steps = Vec::with_capacity(set.step_count());
        let mut bounds = Vec::with_capacity(set.scenarios.len());
        for sc in &set.scenarios {
            if sc.steps.is_empty() {
                continue;
            }
            let start = steps.len();
            let mut before = initial;
            for st in &sc.steps {
                let expected = st.outputs.as_deref().map_or(PASSIVE, input_bits);
                steps.push(StepData {
                    x: input_bits(&st.inputs),
                    expected,
                    before,
                });
                if expected != PASSIVE {
                    before = expected;
                }
            }
            bounds.push(start..steps.len());
        }
        if steps.is_empty() {
            return Err(DataError::Empty);
        }
        let peq = bounds
            .iter()
            .map(|r| {
                let mut masks: Vec<(u32, u128)> = Vec::new();
                if r.len() <= 128 {
                    for (j, st) in steps[r.clone()].iter().enumerate() {
                        match masks.iter_mut().find(|(c, _)| *c == st.expected) {
                            Some((_, m)) => *m |= 1 << j,
                            None => masks.push((st.expected, 1 << j)),
                        }
                    }
                }
                masks
            })
            .collect();
        Ok(ScenarioData {
            inputs: set.inputs.clone(),
            outputs: set.outputs.clone(),
            initial_outputs: set.initial_outputs.clone(),
            initial,
            steps,
            bounds,
            peq,
        })
    }

    /// Number of steps over all scenarios.
    pub fn step_count(&self) -> usize {
        self.steps.len()
    }

    /// Number of (non-empty) scenarios.
    pub fn scenario_count(&self) -> usize {
        self.bounds.len()
    }
}
