//! Seed 000's conversion of samples into scenario steps, one sample at a time.
//!
//! In: samples pushed in log order. Out: [`Step`]s, each as soon as it can no longer change.
//! Same rules as [`samples_to_steps`](crate::scenario::csvlog::samples_to_steps); only the
//! pending element and the last emitted outputs are kept.
//!
//! Why one pending element suffices: the batch version keeps a stack in which neighbours
//! always differ in their inputs (rule 1 removes equal neighbours, rule 2 removes an element
//! whose successor has the same inputs). A new sample can therefore pop at most the top
//! element (the one below has other inputs than the top, hence than the new sample), so
//! every element below the top is final and can be emitted.

use crate::scenario::csvlog::Sample;
use crate::scenario::Step;

/// Push-style streaming conversion of one trace.
#[derive(Debug, Clone)]
pub struct StepStream {
    pending: Option<Sample>,
    /// Outputs of the last emitted element (initially the initial outputs): a step is active
    /// when its outputs differ from these.
    prev: Vec<bool>,
}

impl StepStream {
    /// A conversion starting from `initial_outputs`.
    pub fn new(initial_outputs: Vec<bool>) -> StepStream {
        StepStream {
            pending: None,
            prev: initial_outputs,
        }
    }

    /// Takes the next sample; returns a step that became final, if any.
    pub fn push(&mut self, sample: Sample) -> Option<Step> {
        match &self.pending {
            // Rule 1: a repeated sample adds nothing.
            Some(p) if *p == sample => None,
            // Rule 2: same inputs, other outputs: the output change belongs to the input
            // change that made the pending element, so the pending one is dropped.
            Some(p) if p.inputs == sample.inputs => {
                self.pending = Some(sample);
                None
            }
            _ => self.pending.replace(sample).map(|e| self.emit(e)),
        }
    }

    /// Ends the trace; returns the last step, if any.
    pub fn finish(&mut self) -> Option<Step> {
        self.pending.take().map(|e| self.emit(e))
    }

    fn emit(&mut self, e: Sample) -> Step {
        let changed = e.outputs != self.prev;
        if changed {
            self.prev.clone_from(&e.outputs);
        }
        Step {
            inputs: e.inputs,
            outputs: changed.then_some(e.outputs),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::csvlog::samples_to_steps;
    use proptest::prelude::*;

    fn convert(samples: &[Sample], initial: &[bool]) -> Vec<Step> {
        let mut s = StepStream::new(initial.to_vec());
        let mut steps: Vec<Step> = samples.iter().filter_map(|x| s.push(x.clone())).collect();
        steps.extend(s.finish());
        steps
    }

    fn sample(bits: u8) -> Sample {
        // Two inputs, two outputs: few distinct values make repeats and skews frequent.
        Sample {
            inputs: vec![bits & 1 != 0, bits & 2 != 0],
            outputs: vec![bits & 4 != 0, bits & 8 != 0],
        }
    }

    #[test]
    fn skewed_output_change_joins_the_input_change() {
        // inputs 00 -> 10 with outputs following one scan later, repeated rows in between.
        let samples = [0b0000, 0b0000, 0b0001, 0b0101, 0b0101, 0b0100].map(sample);
        let steps = convert(&samples, &[false, false]);
        assert_eq!(
            steps,
            vec![
                Step {
                    inputs: vec![false, false],
                    outputs: None
                },
                Step {
                    inputs: vec![true, false],
                    outputs: Some(vec![true, false])
                },
                Step {
                    inputs: vec![false, false],
                    outputs: None
                },
            ]
        );
    }

    proptest! {
        #[test]
        fn equals_the_batch_conversion(
            bits in proptest::collection::vec(0u8..16, 0..60),
            initial in proptest::collection::vec(any::<bool>(), 2),
        ) {
            let samples: Vec<Sample> = bits.into_iter().map(sample).collect();
            prop_assert_eq!(convert(&samples, &initial), samples_to_steps(&samples, &initial));
        }
    }
}
