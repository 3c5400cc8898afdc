//! Event logs for process-mining tools, by the conversion of PLC data-flow logs that the
//! process-mining paper ("Process Mining of Programmable Logic Controllers: Input/Output Event
//! Logs") proposes.
//!
//! In: the samples of a raw I/O log ([`LogReader`] with its
//! [`Mapping`]), each with its timestamp, and a reset activity. Out: [`Event`]s grouped into
//! traces, handed to [`EventSink`]s as they arise; [`xes`] writes IEEE 1849 XES and [`csv`] a
//! flat CSV. Streaming: only the samples of the current timestamp and the values before it are
//! kept, so memory does not grow with the log.
//!
//! # Conversion rules (the paper's section V-B)
//! 1. An activity is one address changing to a value, written `ADDRESS VALUE` with the value
//!    `true` or `false` (e.g. `%IX0.1 false`). Its class is `input` or `output`, the side the
//!    mapping gives the address.
//! 2. A value that does not change gives no event, whatever the log repeats.
//! 3. The changes of one class at one timestamp merge into one event whose activity is the
//!    concatenation of theirs in mapping order, joined by [`JOIN`] (`%IX0.1 true + %IX0.2 true`).
//!    Changes of different classes are never merged: at one timestamp the input event comes
//!    first, then the output event (the PLC reads, then writes).
//! 4. The stream is sliced into traces at the reset activity: an event that contains every
//!    change of the reset activity starts a new trace (the reset is that trace's first event).
//!
//! Choices where the process-mining paper is silent:
//! - The first sample is compared with all signals `false`, the state the log formats assume
//!   before the first row (the long format starts every signal at 0). A signal that is `true`
//!   in the first sample therefore gives an event at the first timestamp.
//! - A change that is undone within the same timestamp (two rows, or two wide rows, with one
//!   timestamp) gives no event: the net change per timestamp counts.
//! - The events before the first reset form the first trace; the events after the last reset
//!   form the last trace, even when the process had not reset again when the log ended.
//! - Timestamps are seconds; XES and CSV write them as UTC date-times counted from
//!   1970-01-01T00:00:00Z (so `12.5` becomes `1970-01-01T00:00:12.500+00:00`).
//!
//! Each rule has a unit test on a small hand-made log (`src/events/tests.rs`). The reset given
//! to `synth events --reset` may name the address or the mapping name (`"ll false"`), and may
//! be several changes of one class joined by `+`.
//!
//! # Outputs
//! XES (IEEE 1849-2016: the Concept, Time and Lifecycle extensions declared, globals, the
//! classifiers `Activity` and `Activity_and_class`; every event has `concept:name`,
//! `time:timestamp`, `lifecycle:transition=complete` and `class`), and CSV
//! `case_id,activity,timestamp,class` (`--csv`, by default beside the XES). Both are streamed
//! and published atomically: a bad row stops the run with `file:line: ...` and leaves no output
//! (`--lenient` skips and counts bad rows). An output path that is the input log (e.g. `--log
//! run.csv --out run.xes`, whose default CSV is `run.csv`) is refused.
//!
//! # In pm4py
//! `.ci/install-pm4py.sh` prints the Python of a venv (`~/.cache/fbsynth/pm4py-venv`, pm4py
//! 2.7.11.11 from wheels). `tests/pm4py_check.py LOG.xes` loads the log with `pm4py.read_xes`,
//! discovers a Petri net with the inductive miner (`pm4py.discover_petri_net_inductive`),
//! replays the log on it and prints `traces, events, activities, places, transitions,
//! inductive_fitness`; `--pnml NET` also imports a PNML net (`pm4py.read_pnml`) and replays the
//! log on it; `--replay OTHER.xes` replays another log on both nets. Any error exits 1. The
//! integration tests `tank::pm4py_loads_the_tank_event_logs_and_replays_them_on_the_program_net`
//! and `tank::only_the_machine_net_notices_a_wrong_cycle_count` run it on the tank logs with
//! `$PM4PY_PYTHON`; without it they are skipped with a note, except under `CI=true`, where a
//! missing pm4py fails them, as a missing NuSMV does.
//!
//! # Petri nets of synthesized machines
//! With `--ecc M.json --pnml NET`, `synth events` also writes the machine as a PNML net
//! ([`crate::export::pnml`]) whose labels are the mapping's addresses, so they match the
//! activities of the XES. `--pnml-dialect iso` (the default) writes the ISO/IEC 15909-2 P/T
//! net in the PNML namespace; `--pnml-dialect prom` writes the dialect ProM and pm4py read
//! (the pm4py tests use it). The net assumes one `REQ` per scan and replays a log only if every
//! output event follows the input event that, in the machine's state, causes it; merged input
//! events and two output events in a row are not represented. The tank case
//! (`src/cases/tank.rs`) shows what this buys: only the machine's net notices a controller
//! that counts its cycles wrongly.
//!
//! # Throughput
//! Memory stays flat in the log length; writing the XES, about ten times the log's size, is
//! the bottleneck. The benchmark log (10^7 rows, 16 signals, each row toggling one, the
//! timestamp advancing on about half of the rows) and the run whose figures `BENCHMARKS.md`
//! shows:
//!
//! ```text
//! python3 - <<'EOF'
//! import random
//! random.seed(1)
//! a = [f"%IX0.{k}" for k in range(8)] + [f"%QX0.{k}" for k in range(8)]
//! with open("big.map", "w") as m:
//!     for i, x in enumerate(a):
//!         m.write(f"{x} {'in' if x[1] == 'I' else 'out'} s{i}\n")
//! v, t = [0] * 16, 0
//! with open("big.log.csv", "w") as f:
//!     f.write("timestamp,address,value\n")
//!     for _ in range(10**7):
//!         t += random.random() < 0.5
//!         k = random.randrange(16)
//!         v[k] ^= 1
//!         f.write(f"{t // 100}.{t % 100:02d},{a[k]},{v[k]}\n")
//! EOF
//! /usr/bin/time -v synth events --log big.log.csv --map big.map --reset "%IX0.0 false" \
//!     --out big.xes --csv big.events.csv
//! ```

pub(crate) mod csv;
pub(crate) mod xes;

use crate::files::AtomicFile;
use crate::ingest::{IngestError, LogReader, Mapping, Sample, Slot};
use std::fmt;
use std::io::BufRead;
use std::path::Path;

/// Joins the activities of merged changes into one activity name.
pub(crate) const JOIN: &str = " + ";

/// The two classes of the process-mining paper: data read by the PLC, or written by it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum EventClass {
    /// A change of a signal the PLC reads.
    Input,
    /// A change of a signal the PLC writes.
    Output,
}

impl EventClass {
    /// The attribute value written to event logs.
    pub(crate) fn label(self) -> &'static str {
        match self {
            EventClass::Input => "input",
            EventClass::Output => "output",
        }
    }
}

/// One address taking a value.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Change {
    /// The signal's address as the log names it.
    pub(crate) address: String,
    /// The value it takes.
    pub(crate) value: bool,
}

impl fmt::Display for Change {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}", self.address, self.value)
    }
}

/// One event: the changes of one class at one timestamp.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Event {
    /// Seconds, as in the log.
    pub(crate) time: f64,
    /// Whether the changes are of inputs or of outputs.
    pub(crate) class: EventClass,
    /// In mapping order; never empty.
    pub(crate) changes: Vec<Change>,
}

impl Event {
    /// The activity name: the changes joined by [`JOIN`].
    pub(crate) fn activity(&self) -> String {
        self.changes
            .iter()
            .map(Change::to_string)
            .collect::<Vec<_>>()
            .join(JOIN)
    }
}

/// A problem with the conversion's input.
#[derive(Debug, thiserror::Error)]
pub enum EventsError {
    /// The log cannot be read (file, line and cell named).
    #[error(transparent)]
    Log(#[from] IngestError),
    /// The `--reset` activity cannot be read; `text` is the whole argument.
    #[error("reset activity {}: {message}", crate::quote::quote(text))]
    Reset {
        /// The argument as given.
        text: String,
        /// What is wrong with it.
        message: String,
    },
    /// An output file cannot be written.
    #[error(transparent)]
    Write(#[from] crate::files::WriteError),
    /// A sink failed while writing; the paths name the files being written.
    #[error("cannot write {paths}: {source}")]
    Sink {
        /// The files being written, comma-separated.
        paths: String,
        /// The error of the write.
        #[source]
        source: std::io::Error,
    },
}

/// The activity that starts a new trace: one or more changes of one class.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ResetActivity {
    /// The class of the event it matches.
    pub(crate) class: EventClass,
    /// The changes the event must consist of, in mapping order.
    pub(crate) changes: Vec<Change>,
}

impl ResetActivity {
    /// Reads `ADDRESS VALUE` parts joined by `+` (e.g. `%IX0.1 false`); an address may also be
    /// given by its mapping name (`ll false`) and is stored as the address. Values are
    /// `true/false/1/0`. Every part must be of the same class.
    pub fn parse(text: &str, mapping: &Mapping) -> Result<ResetActivity, EventsError> {
        let err = |message: String| EventsError::Reset {
            text: text.to_string(),
            message,
        };
        let mut class = None;
        let mut changes = Vec::new();
        for part in text.split('+') {
            let words: Vec<&str> = part.split_whitespace().collect();
            let [key, value] = words[..] else {
                return Err(err(format!(
                    "{} is not 'ADDRESS VALUE' (e.g. '%IX0.1 false')",
                    crate::quote::quote(part.trim())
                )));
            };
            let slot = mapping.slot(key.as_bytes()).ok_or_else(|| {
                err(format!(
                    "{} is not an address or name of the mapping",
                    crate::quote::quote(key)
                ))
            })?;
            let Some(value) = crate::files::csv::parse_bool_cell(value.as_bytes()) else {
                return Err(err(format!(
                    "{} is not true, false, 1 or 0",
                    crate::quote::quote(value)
                )));
            };
            let (c, address) = match slot {
                Slot::Input(_) => (EventClass::Input, address_of(mapping, slot)),
                Slot::Output(_) => (EventClass::Output, address_of(mapping, slot)),
            };
            if *class.get_or_insert(c) != c {
                return Err(err(
                    "mixes inputs and outputs, which never merge into one event".into(),
                ));
            }
            changes.push(Change { address, value });
        }
        Ok(ResetActivity {
            class: class.unwrap_or(EventClass::Input),
            changes,
        })
    }

    /// Whether `event` resets the process: it has the reset's class and every reset change.
    pub(crate) fn matches(&self, event: &Event) -> bool {
        event.class == self.class && self.changes.iter().all(|c| event.changes.contains(c))
    }
}

impl fmt::Display for ResetActivity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self.changes.iter().map(Change::to_string).collect();
        f.write_str(&parts.join(JOIN))
    }
}

fn address_of(mapping: &Mapping, slot: Slot) -> String {
    mapping
        .addresses()
        .iter()
        .find(|(_, s)| *s == slot)
        .map(|(a, _)| a.clone())
        .expect("every slot of a mapping has an address")
}

/// Push-style conversion of timestamped samples into events (rules 1-3).
#[derive(Debug, Clone)]
pub(crate) struct EventStream {
    input_addresses: Vec<String>,
    output_addresses: Vec<String>,
    /// Values at the end of the last finished timestamp.
    before: Sample,
    /// The timestamp being collected and the values at its latest sample.
    current: Option<(f64, Sample)>,
}

impl EventStream {
    /// A conversion for the signals of `mapping`, all `false` before the first sample.
    pub(crate) fn new(mapping: &Mapping) -> EventStream {
        let mut input_addresses = vec![String::new(); mapping.inputs().len()];
        let mut output_addresses = vec![String::new(); mapping.outputs().len()];
        for (address, slot) in mapping.addresses() {
            match slot {
                Slot::Input(x) => input_addresses[x.0] = address.clone(),
                Slot::Output(z) => output_addresses[z.0] = address.clone(),
            }
        }
        EventStream {
            before: Sample {
                inputs: vec![false; input_addresses.len()],
                outputs: vec![false; output_addresses.len()],
            },
            input_addresses,
            output_addresses,
            current: None,
        }
    }

    /// Takes the sample at `time` (not before the previous one); returns the events of the
    /// previous timestamp once `time` moves past it.
    pub(crate) fn push(&mut self, time: f64, sample: Sample) -> Vec<Event> {
        match &mut self.current {
            Some((t, values)) if *t == time => {
                *values = sample;
                Vec::new()
            }
            _ => {
                let done = self.flush();
                self.current = Some((time, sample));
                done
            }
        }
    }

    /// Ends the stream; returns the events of the last timestamp.
    pub(crate) fn finish(&mut self) -> Vec<Event> {
        self.flush()
    }

    fn flush(&mut self) -> Vec<Event> {
        let Some((time, now)) = self.current.take() else {
            return Vec::new();
        };
        let diff = |before: &[bool], now: &[bool], addresses: &[String]| -> Vec<Change> {
            (0..now.len())
                .filter(|&k| before[k] != now[k])
                .map(|k| Change {
                    address: addresses[k].clone(),
                    value: now[k],
                })
                .collect()
        };
        let mut events = Vec::new();
        for (class, changes) in [
            (
                EventClass::Input,
                diff(&self.before.inputs, &now.inputs, &self.input_addresses),
            ),
            (
                EventClass::Output,
                diff(&self.before.outputs, &now.outputs, &self.output_addresses),
            ),
        ] {
            if !changes.is_empty() {
                events.push(Event {
                    time,
                    class,
                    changes,
                });
            }
        }
        self.before = now;
        events
    }
}

/// Receives the event log as it is produced: traces in order, each with its events.
pub(crate) trait EventSink {
    /// A new trace starts; `case` is its 1-based number.
    fn begin_trace(&mut self, case: usize) -> std::io::Result<()>;
    /// One event of the current trace.
    fn event(&mut self, event: &Event) -> std::io::Result<()>;
    /// The current trace is complete.
    fn end_trace(&mut self) -> std::io::Result<()>;
}

/// Slices events into traces at the reset activity (rule 4) and feeds the sinks.
pub(crate) struct TraceSlicer<'a> {
    reset: &'a ResetActivity,
    /// Number of the open trace, if one is open.
    open: Option<usize>,
    traces: usize,
    events: u64,
    resets: u64,
}

impl<'a> TraceSlicer<'a> {
    /// A slicer with no trace open yet.
    pub(crate) fn new(reset: &'a ResetActivity) -> TraceSlicer<'a> {
        TraceSlicer {
            reset,
            open: None,
            traces: 0,
            events: 0,
            resets: 0,
        }
    }

    /// Hands one event to every sink, opening a new trace first when it is a reset (or when
    /// no trace is open yet).
    pub(crate) fn push(
        &mut self,
        event: &Event,
        sinks: &mut [&mut dyn EventSink],
    ) -> std::io::Result<()> {
        let reset = self.reset.matches(event);
        if reset {
            self.resets += 1;
        }
        if reset || self.open.is_none() {
            if self.open.is_some() {
                for s in sinks.iter_mut() {
                    s.end_trace()?;
                }
            }
            self.traces += 1;
            self.open = Some(self.traces);
            for s in sinks.iter_mut() {
                s.begin_trace(self.traces)?;
            }
        }
        self.events += 1;
        for s in sinks.iter_mut() {
            s.event(event)?;
        }
        Ok(())
    }

    /// Closes the open trace; returns the counts.
    pub(crate) fn finish(self, sinks: &mut [&mut dyn EventSink]) -> std::io::Result<Summary> {
        if self.open.is_some() {
            for s in sinks.iter_mut() {
                s.end_trace()?;
            }
        }
        Ok(Summary {
            traces: self.traces,
            events: self.events,
            resets: self.resets,
            samples: 0,
            rows: 0,
            skipped: 0,
        })
    }
}

/// What a conversion produced.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct Summary {
    /// Traces written.
    pub(crate) traces: usize,
    /// Events written, over all traces.
    pub(crate) events: u64,
    /// Events that matched the reset activity.
    pub(crate) resets: u64,
    /// Samples and data rows read, rows skipped (lenient mode).
    pub(crate) samples: u64,
    /// Data rows read.
    pub(crate) rows: u64,
    /// Rows skipped (lenient mode only).
    pub(crate) skipped: u64,
}

/// Streams a whole log through rules 1-4 into `sinks`.
pub(crate) fn convert<R: BufRead>(
    mut reader: LogReader<R>,
    mapping: &Mapping,
    reset: &ResetActivity,
    sinks: &mut [&mut dyn EventSink],
) -> Result<Summary, ConvertError> {
    let mut stream = EventStream::new(mapping);
    let mut slicer = TraceSlicer::new(reset);
    while let Some(sample) = reader.next() {
        let sample = sample?;
        let time = reader
            .sample_time()
            .expect("the reader sets the time of every sample it returns");
        for e in stream.push(time, sample) {
            slicer.push(&e, sinks).map_err(ConvertError::Sink)?;
        }
    }
    for e in stream.finish() {
        slicer.push(&e, sinks).map_err(ConvertError::Sink)?;
    }
    let mut summary = slicer.finish(sinks).map_err(ConvertError::Sink)?;
    let stats = reader.stats();
    summary.samples = stats.samples;
    summary.rows = stats.rows;
    summary.skipped = stats.skipped_total();
    Ok(summary)
}

/// Why [`convert`] stopped: a bad log, or a sink that could not write (the caller knows
/// which files its sinks write).
#[derive(Debug, thiserror::Error)]
pub(crate) enum ConvertError {
    /// The log cannot be read.
    #[error(transparent)]
    Log(#[from] IngestError),
    /// A sink failed.
    #[error("{0}")]
    Sink(std::io::Error),
}

/// `synth events`: converts the log file `log` into an XES file and a CSV file, both written
/// atomically (neither is touched when the log has a bad row).
pub(crate) fn write_event_logs(
    log: &Path,
    mapping: &Mapping,
    reset: &ResetActivity,
    lenient: bool,
    xes_path: &Path,
    csv_path: &Path,
) -> Result<Summary, EventsError> {
    let reader = LogReader::open(log, mapping, lenient)?;
    let name = log
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let sink_err = |source| EventsError::Sink {
        paths: format!("{}, {}", xes_path.display(), csv_path.display()),
        source,
    };
    let xes_file = AtomicFile::create(xes_path)?;
    let csv_file = AtomicFile::create(csv_path)?;
    let mut xes = xes::XesWriter::new(xes_file, &name).map_err(sink_err)?;
    let mut csv = csv::CsvWriter::new(csv_file).map_err(sink_err)?;
    let summary = match convert(reader, mapping, reset, &mut [&mut xes, &mut csv]) {
        Ok(s) => s,
        Err(ConvertError::Log(e)) => return Err(e.into()),
        Err(ConvertError::Sink(e)) => return Err(sink_err(e)),
    };
    xes.finish().map_err(sink_err)?.commit()?;
    csv.finish().commit()?;
    Ok(summary)
}

/// Formats seconds since 1970-01-01T00:00:00Z as an ISO 8601 UTC date-time with milliseconds,
/// as XES's `xs:dateTime` wants it.
pub(crate) fn iso_time(seconds: f64) -> String {
    let millis = (seconds * 1000.0).round() as i64;
    let days = millis.div_euclid(86_400_000);
    let ms_of_day = millis.rem_euclid(86_400_000);
    let (y, m, d) = civil_from_days(days);
    let (h, rest) = (ms_of_day / 3_600_000, ms_of_day % 3_600_000);
    let (min, rest) = (rest / 60_000, rest % 60_000);
    let (s, ms) = (rest / 1000, rest % 1000);
    format!("{y:04}-{m:02}-{d:02}T{h:02}:{min:02}:{s:02}.{ms:03}+00:00")
}

/// The proleptic Gregorian date of a day count from 1970-01-01 (H. Hinnant's algorithm).
fn civil_from_days(z: i64) -> (i64, u32, u32) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

#[cfg(test)]
mod tests;
