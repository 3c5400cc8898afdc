//! The SAT reconstruction paper's conversion of samples into scenario steps (rules in [`super::csvlog`]), one
//! sample at a time: the one implementation behind both the CSV logs read whole
//! ([`samples_to_steps`]) and the raw logs streamed by [`crate::ingest`].
//!
//! In: samples pushed in log order. Out: [`Step`]s, each as soon as it can no longer change.
//! Only the pending element and the last emitted outputs are kept.
//!
//! Why one pending element suffices: the rules, applied to the whole trace, keep a stack in
//! which neighbours always differ in their inputs (rule 1 removes equal neighbours, rule 2
//! removes an element whose successor has the same inputs). A new sample can therefore pop at
//! most the top element (the one below has other inputs than the top, hence than the new
//! sample), so every element below the top is final and can be emitted. The tests check this
//! against the stack version.

use super::Step;

/// One sample: input and output values.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Sample {
    /// Input values at the sample, in interface order.
    pub(crate) inputs: Vec<bool>,
    /// Output values at the sample, in interface order.
    pub(crate) outputs: Vec<bool>,
}

/// The SAT reconstruction paper's preprocessing of one sampled trace into scenario steps.
pub(crate) fn samples_to_steps(samples: &[Sample], initial_outputs: &[bool]) -> Vec<Step> {
    let mut stream = StepStream::new(initial_outputs.to_vec());
    let mut steps: Vec<Step> = samples
        .iter()
        .filter_map(|s| stream.push(s.clone()))
        .collect();
    steps.extend(stream.finish());
    steps
}

/// Push-style streaming conversion of one trace.
#[derive(Debug, Clone)]
pub(crate) struct StepStream {
    pending: Option<Sample>,
    /// The tag (a line) given with the pending sample.
    pending_tag: usize,
    /// Outputs of the last emitted element (initially the initial outputs): a step is active
    /// when its outputs differ from these.
    prev: Vec<bool>,
}

impl StepStream {
    /// A conversion starting from `initial_outputs`.
    pub(crate) fn new(initial_outputs: Vec<bool>) -> StepStream {
        StepStream {
            pending: None,
            pending_tag: 0,
            prev: initial_outputs,
        }
    }

    /// Takes the next sample; returns a step that became final, if any.
    pub(crate) fn push(&mut self, sample: Sample) -> Option<Step> {
        self.push_tagged(sample, 0).map(|(step, _)| step)
    }

    /// [`StepStream::push`] of a sample with a tag (its line), returned with the step the
    /// sample became: the first of repeated samples, the last of skewed ones.
    pub(crate) fn push_tagged(&mut self, sample: Sample, tag: usize) -> Option<(Step, usize)> {
        match &self.pending {
            // Rule 1: a repeated sample adds nothing.
            Some(p) if *p == sample => None,
            // Rule 2: same inputs, other outputs: the output change belongs to the input
            // change that made the pending element, so the pending one is dropped.
            Some(p) if p.inputs == sample.inputs => {
                self.pending = Some(sample);
                self.pending_tag = tag;
                None
            }
            _ => {
                let before = std::mem::replace(&mut self.pending_tag, tag);
                (self.pending.replace(sample)).map(|e| (self.emit(e), before))
            }
        }
    }

    /// Ends the trace; returns the last step, if any.
    pub(crate) fn finish(&mut self) -> Option<Step> {
        self.finish_tagged().map(|(step, _)| step)
    }

    /// [`StepStream::finish`] with the tag of the last step.
    pub(crate) fn finish_tagged(&mut self) -> Option<(Step, usize)> {
        let tag = self.pending_tag;
        self.pending.take().map(|e| (self.emit(e), tag))
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
    use proptest::prelude::*;

    /// A step keeps the line of the first of repeated samples and of the last of skewed ones.
    #[test]
    fn tags_follow_the_sample_each_step_came_from() {
        let s = |i: bool, o: bool| Sample {
            inputs: vec![i],
            outputs: vec![o],
        };
        let mut stream = StepStream::new(vec![false]);
        let rows = [
            s(false, false),
            s(false, false),
            s(true, false),
            s(true, true),
        ];
        let mut tags: Vec<usize> = (rows.into_iter().zip(10..))
            .filter_map(|(r, line)| stream.push_tagged(r, line))
            .map(|(_, t)| t)
            .collect();
        tags.extend(stream.finish_tagged().map(|(_, t)| t));
        assert_eq!(tags, [10, 13]);
    }

    fn convert(samples: &[Sample], initial: &[bool]) -> Vec<Step> {
        samples_to_steps(samples, initial)
    }

    /// The rules applied to the whole trace with a stack, as the SAT reconstruction paper states them: the
    /// reference the streaming conversion is checked against.
    fn batch(samples: &[Sample], initial_outputs: &[bool]) -> Vec<Step> {
        let mut elems: Vec<&Sample> = Vec::with_capacity(samples.len());
        for s in samples {
            // Rule 1 (collapse identical rows) and rule 2 (drop the earlier of two elements
            // with equal inputs), until neither fires: dropping can make the new neighbours
            // equal or skewed again.
            loop {
                match elems.last() {
                    Some(last) if *last == s => break,
                    Some(last) if last.inputs == s.inputs && last.outputs != s.outputs => {
                        elems.pop();
                    }
                    _ => {
                        elems.push(s);
                        break;
                    }
                }
            }
        }
        let mut prev = initial_outputs;
        elems
            .into_iter()
            .map(|e| {
                let changed = e.outputs != prev;
                prev = &e.outputs;
                Step {
                    inputs: e.inputs.clone(),
                    outputs: changed.then(|| e.outputs.clone()),
                }
            })
            .collect()
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
            prop_assert_eq!(convert(&samples, &initial), batch(&samples, &initial));
        }
    }
}
