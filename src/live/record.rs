//! `synth record`: the samples of a [`Sampler`] as a CSV log, row by row.
//!
//! In: a connected sampler, the mapping's names, when to stop. Out: the log
//! (`time,scenario,in:NAME,...,out:NAME,...`, the format of [`crate::scenario::csvlog`]),
//! written through an [`AtomicFile`] so that it appears whole, also when SIGINT stopped the
//! run, and never half-written. Memory is constant: each row is written as it comes.

use super::client::{Reading, Sampler};
use super::{Counters, LiveError, Until};
use crate::files::{AtomicFile, WriteError};
use crate::ingest::Mapping;
use crate::scenario::csvlog::Sample;
use std::io::Write;
use std::path::Path;
use std::time::Instant;

/// Writes samples as CSV log rows; a gap makes the next row start a new scenario.
pub(crate) struct LogWriter<W: Write> {
    out: W,
    scenario: u64,
    after_gap: bool,
    counters: Counters,
}

impl<W: Write> LogWriter<W> {
    /// A log over `mapping`'s interface; writes the header.
    pub(crate) fn new(mut out: W, mapping: &Mapping) -> std::io::Result<LogWriter<W>> {
        let mut header = vec!["time".to_string(), "scenario".to_string()];
        header.extend(mapping.inputs().iter().map(|n| format!("in:{n}")));
        header.extend(mapping.outputs().iter().map(|n| format!("out:{n}")));
        writeln!(out, "{}", header.join(","))?;
        Ok(LogWriter {
            out,
            scenario: 1,
            after_gap: false,
            counters: Counters::default(),
        })
    }

    /// Writes one row.
    pub(crate) fn row(&mut self, time: f64, sample: &Sample) -> std::io::Result<()> {
        if std::mem::take(&mut self.after_gap) && self.counters.rows > 0 {
            self.scenario += 1;
        }
        let bit = |b: &bool| if *b { ",1" } else { ",0" };
        let cells: String = sample
            .inputs
            .iter()
            .chain(&sample.outputs)
            .map(bit)
            .collect();
        writeln!(self.out, "{time:.3},{}{cells}", self.scenario)?;
        self.counters.rows += 1;
        self.counters.scenarios = self.scenario;
        self.counters.seconds = time;
        Ok(())
    }

    /// Notes a gap (once per run of failed reads).
    pub(crate) fn gap(&mut self) {
        if !self.after_gap {
            self.after_gap = true;
            self.counters.gaps += 1;
        }
    }

    /// What was written so far.
    pub(crate) fn counters(&self) -> Counters {
        self.counters
    }

    /// The writer.
    pub(crate) fn into_inner(self) -> W {
        self.out
    }
}

/// Why a recording ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ended {
    /// The duration or the sample count was reached.
    Done,
    /// A signal asked to stop.
    Signal,
}

/// Records from `sampler` into `file` until `until` or a signal; `progress` sees the counters
/// after every row and gap. The file is committed in both cases.
pub(crate) fn record(
    sampler: &mut Sampler,
    mapping: &Mapping,
    path: &Path,
    until: Until,
    progress: &mut dyn FnMut(&Counters),
) -> Result<(Counters, Ended), LiveError> {
    let write_error = |source| WriteError {
        path: path.to_path_buf(),
        source,
    };
    let file = AtomicFile::create(path)?;
    let mut log = LogWriter::new(file, mapping).map_err(write_error)?;
    let started = Instant::now();
    let ended = loop {
        if crate::signals::stop_asked() {
            break Ended::Signal;
        }
        let c = log.counters();
        let reached = match until {
            Until::Seconds(s) => started.elapsed().as_secs_f64() >= s,
            Until::Samples(n) => c.rows >= n,
            Until::Signal => false,
        };
        if reached {
            break Ended::Done;
        }
        match sampler.next()? {
            Reading::Sample { time, sample } => log.row(time, &sample).map_err(write_error)?,
            Reading::Gap => log.gap(),
        }
        progress(&log.counters());
    };
    let counters = log.counters();
    let file = log.into_inner();
    file.commit()?;
    Ok((counters, ended))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_after_a_gap_start_a_new_scenario_and_read_back() {
        let mapping =
            Mapping::parse(Path::new("m.map"), "ns=2;s=a in a\nns=2;s=z out z\n").unwrap();
        let mut log = LogWriter::new(Vec::new(), &mapping).unwrap();
        let s = |a: bool, z: bool| Sample {
            inputs: vec![a],
            outputs: vec![z],
        };
        log.row(0.0, &s(false, false)).unwrap();
        log.row(0.05, &s(true, false)).unwrap();
        log.gap();
        log.gap();
        log.row(0.5, &s(true, true)).unwrap();
        log.row(0.55, &s(false, true)).unwrap();
        assert_eq!(log.counters().gaps, 1);
        let text = String::from_utf8(log.into_inner()).unwrap();
        assert_eq!(
            text,
            "time,scenario,in:a,out:z\n0.000,1,0,0\n0.050,1,1,0\n0.500,2,1,1\n0.550,2,0,1\n"
        );
        let set = crate::scenario::csvlog::parse(Path::new("log.csv"), &text, None, None).unwrap();
        assert_eq!(set.scenarios.len(), 2);
        assert_eq!(set.inputs, ["a"]);
    }
}
