//! `synth monitor`: a machine run beside the PLC, scan by scan, until the first step where
//! they part.
//!
//! In: a connected [`Sampler`], the machine, when to stop. Out: the first [`Divergence`] (step,
//! inputs, the PLC's outputs and the machine's) and the samples up to it as a CSV log, the
//! recording `synth conform --refine` learns from.
//!
//! The samples become steps by the same streaming conversion as every log ([`StepStream`]:
//! repeated samples collapse, a sample whose outputs lag its inputs by a scan is merged), and
//! each step is fed to the machine as it becomes final, as `synth replay` does with a file. The
//! last sample, still pending when the run ends, is not compared: the next scan could still
//! merge it. Both start together: the machine in its initial state with the first sample, so
//! the PLC is expected to start (or be reset) with the monitor.

use super::client::{Reading, Sampler};
use super::record::{Ended, LogWriter};
use super::{Counters, LiveError, Until};
use crate::ecc::{Controller, Ecc, Reactive};
use crate::files::{AtomicFile, WriteError};
use crate::ingest::{Mapping, StepStream};
use crate::scenario::csvlog::Sample;
use std::path::Path;
use std::time::Instant;

/// The first step where the machine and the PLC part.
#[derive(Debug, Clone, PartialEq)]
pub struct Divergence {
    /// 1-based step since the monitor started.
    pub step: u64,
    /// Seconds since the first sample, of the sample the step came from.
    pub time: f64,
    /// The step's inputs, in the machine's order.
    pub inputs: Vec<bool>,
    /// The outputs the PLC set at this step, or `None` if they did not change.
    pub plc: Option<Vec<bool>>,
    /// The outputs the machine set, or `None` if no transition fired.
    pub machine: Option<Vec<bool>>,
}

/// How the monitoring ended.
#[derive(Debug, Clone)]
pub(crate) struct Outcome {
    /// Rows, gaps, steps compared, seconds.
    pub counters: Counters,
    /// The first divergence, if any.
    pub divergence: Option<Divergence>,
    /// Whether a signal stopped the run.
    pub ended: Ended,
}

/// Where each of the machine's signals is in a sample over the mapping.
struct Interface {
    inputs: Vec<usize>,
    outputs: Vec<usize>,
}

impl Interface {
    /// The machine's inputs and outputs found by name in the mapping; both must name the
    /// same signals.
    fn new(ecc: &Ecc, mapping: &Mapping, ecc_file: &Path) -> Result<Interface, LiveError> {
        let find = |names: &[String], mapped: &[String], side: &str| {
            let mut same = names.len() == mapped.len();
            let positions: Vec<usize> = names
                .iter()
                .map(|n| {
                    mapped.iter().position(|m| m == n).unwrap_or_else(|| {
                        same = false;
                        0
                    })
                })
                .collect();
            match same {
                true => Ok(positions),
                false => Err(LiveError::Interface {
                    message: format!(
                        "{} has {side} [{}], the mapping [{}]: they must name the same signals",
                        ecc_file.display(),
                        names.join(" "),
                        mapped.join(" ")
                    ),
                }),
            }
        };
        Ok(Interface {
            inputs: find(&ecc.inputs, mapping.inputs(), "inputs")?,
            outputs: find(&ecc.outputs, mapping.outputs(), "outputs")?,
        })
    }

    /// A sample over the mapping as one over the machine's interface.
    fn reorder(&self, s: &Sample) -> Sample {
        Sample {
            inputs: self.inputs.iter().map(|&k| s.inputs[k]).collect(),
            outputs: self.outputs.iter().map(|&k| s.outputs[k]).collect(),
        }
    }
}

/// The machine beside the sampled PLC: samples in, the first divergence out.
pub(crate) struct Watch<R: Reactive> {
    run: R,
    stream: StepStream,
    steps: u64,
}

impl<R: Reactive> Watch<R> {
    /// A watch of `run` (a machine just started), whose initial outputs are `initial`.
    pub(crate) fn new(run: R, initial: Vec<bool>) -> Watch<R> {
        Watch {
            run,
            stream: StepStream::new(initial),
            steps: 0,
        }
    }

    /// Takes the sample at `time`; the divergence of the step it made final, if any.
    pub(crate) fn push(&mut self, time: f64, sample: Sample) -> Option<Divergence> {
        // The tag is the sample's time in milliseconds, to report where the step came from.
        let tag = (time * 1000.0).round() as usize;
        let (step, tag) = self.stream.push_tagged(sample, tag)?;
        self.steps += 1;
        let machine = self.run.react(&step.inputs).map(<[bool]>::to_vec);
        (machine != step.outputs).then(|| Divergence {
            step: self.steps,
            time: tag as f64 / 1000.0,
            inputs: step.inputs,
            plc: step.outputs,
            machine,
        })
    }

    /// Steps compared so far.
    pub(crate) fn steps(&self) -> u64 {
        self.steps
    }
}

/// Monitors the PLC behind `sampler` with `ecc` until `until`, a signal or the first
/// divergence; the samples go to `stretch` (a CSV log), which is committed only when the run
/// found a divergence. A lost connection is an error ([`LiveError::Lost`]).
pub(crate) fn monitor(
    sampler: &mut Sampler,
    mapping: &Mapping,
    (ecc, ecc_file): (&Ecc, &Path),
    stretch: &Path,
    until: Until,
    progress: &mut dyn FnMut(&Counters),
) -> Result<Outcome, LiveError> {
    let interface = Interface::new(ecc, mapping, ecc_file)?;
    let write_error = |source| WriteError {
        path: stretch.to_path_buf(),
        source,
    };
    let mut log = LogWriter::new(AtomicFile::create(stretch)?, mapping).map_err(write_error)?;
    let mut watch = Watch::new(ecc.start(), ecc.initial_outputs.clone());
    let counters = |log: &LogWriter<AtomicFile>, watch: &Watch<_>| Counters {
        steps: watch.steps(),
        ..log.counters()
    };
    let started = Instant::now();
    let (divergence, ended) = loop {
        if crate::signals::stop_asked() {
            break (None, Ended::Signal);
        }
        let c = log.counters();
        let reached = match until {
            Until::Seconds(s) => started.elapsed().as_secs_f64() >= s,
            Until::Samples(n) => c.rows >= n,
            Until::Signal => false,
        };
        if reached {
            break (None, Ended::Done);
        }
        match sampler.next()? {
            Reading::Sample { time, sample } => {
                log.row(time, &sample).map_err(write_error)?;
                let found = watch.push(time, interface.reorder(&sample));
                if found.is_some() {
                    break (found, Ended::Done);
                }
                progress(&counters(&log, &watch));
            }
            Reading::Gap => {
                return Err(LiveError::Lost {
                    url: sampler.url().to_string(),
                    steps: watch.steps(),
                })
            }
        }
    };
    let counters = counters(&log, &watch);
    if divergence.is_some() {
        log.into_inner().commit()?;
    }
    Ok(Outcome {
        counters,
        divergence,
        ended,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A machine that sets its output when `a` rises and keeps it: the PLC's log agrees until
    /// the PLC drops the output on its own.
    #[test]
    fn the_first_step_the_plc_and_the_machine_part_is_reported() {
        let ecc = crate::export::json::read_json(
            r#"{"format": 1, "inputs": ["a"], "outputs": ["z"], "initial_outputs": "0",
                "states": [{"name": "s0", "algorithm": "0"}, {"name": "s1", "algorithm": "1"}],
                "transitions": [{"from": 0, "to": 1, "guard": "a"}]}"#,
            Path::new("m.json"),
        )
        .unwrap();
        let s = |a: bool, z: bool| Sample {
            inputs: vec![a],
            outputs: vec![z],
        };
        let mut watch = Watch::new(ecc.start(), vec![false]);
        let log = [
            (0.0, s(false, false)),
            (0.1, s(true, false)),
            (0.2, s(true, true)),
            (0.3, s(false, true)),
            (0.4, s(false, false)),
            (0.5, s(true, false)),
        ];
        let found: Vec<Divergence> = log
            .into_iter()
            .filter_map(|(t, x)| watch.push(t, x))
            .collect();
        assert_eq!(
            found,
            [Divergence {
                step: 3,
                time: 0.4,
                inputs: vec![false],
                plc: Some(vec![false]),
                machine: None,
            }]
        );
    }
}
