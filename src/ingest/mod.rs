//! Streaming ingestion of raw PLC I/O data-flow logs, as a tapping device writes them.
//!
//! In: a mapping file ([`Mapping`]) and a log file, plain or gzip. Out: a stream of
//! [`Sample`]s ([`LogReader`]) and, through the SAT reconstruction paper's conversion done on the fly
//! ([`StepStream`]), scenario [`Step`](crate::scenario::Step)s. Memory stays constant in the
//! log length: the log is read line by line and only the pending sample is kept.
//!
//! # Mapping file
//! ```text
//! # address  side  name
//! %IX0.1     in    start
//! %IX0.2     in    stop
//! %QX0.0     out   motor
//! ```
//! One signal per line: `ADDRESS in|out NAME`, separated by whitespace. An address is any
//! text without whitespace or `,`: a PLC address (`%IX0.1`) or an OPC UA node id
//! (`ns=2;s=start`, `ns=3;i=1001`), which [`crate::live`] reads from a running PLC. `#` starts a comment;
//! blank lines are ignored. Names follow [`is_identifier`](crate::ecc::ident::is_identifier).
//! An address or a name used twice is an error naming both lines. The interface order is the
//! file order of the `in` lines, then of the `out` lines.
//!
//! # Log files
//! Both formats are CSV with `,` (quoted cells as RFC 4180 says: [`crate::files::csv`]; a
//! leading byte order mark ignored: [`crate::files::open_input`]), told apart by their header; the file may be
//! gzip-compressed (recognized by its magic bytes, multi-member streams accepted). Values are `0`, `1`,
//! `true`, `false` (any case). Timestamps are numbers and must not go backwards. Blank lines
//! are ignored; line numbers count every line of the (decompressed) file. A line (or a record
//! whose quoted cells span lines) longer than [`MAX_LINE_BYTES`](crate::files::MAX_LINE_BYTES)
//! is an [`IngestError::Read`], in lenient mode too: nothing after it can be trusted to be a
//! row.
//! - **long**, header `timestamp,address,value`: one row per changed signal. Every signal
//!   starts at 0 and keeps its value until a row changes it. Rows with the same timestamp form
//!   one sample, emitted once a later timestamp (or the end of the file) is seen.
//! - **wide**, header `timestamp,COL,...`: one row per scan; each `COL` is an address or a
//!   name of the mapping, and every mapped signal needs exactly one column.
//!
//! In the long format, the address column may also hold a name of the mapping.
//!
//! # Bad rows
//! An unparsable value or timestamp, a timestamp beyond [`MAX_TIMESTAMP`] seconds either side
//! of 0, an unknown address, a timestamp smaller than the one before, or a wrong number of
//! cells stops the reader with an [`IngestError::Row`] naming
//! file and line. In lenient mode the row is skipped instead and counted per [`RowKind`].

mod mapping;
mod reader;

pub(crate) use crate::scenario::steps::StepStream;
pub use mapping::Mapping;
pub(crate) use mapping::Slot;
pub use reader::{LogReader, ReadStats, Throughput};

use crate::quote::quote;
pub use crate::scenario::csvlog::Sample;
use std::fmt;
use std::path::PathBuf;

/// The largest timestamp accepted either side of 0, in seconds: about 285,000 years, below
/// 2^53 milliseconds, so every accepted timestamp keeps its milliseconds exactly (in a double,
/// and in the integer count `synth events` writes dates from) and two scans a millisecond
/// apart stay apart. Unix times in seconds and in milliseconds fit; `1e20` does not, and would
/// otherwise be merged with its neighbours or turned into a date clamped to the year 292 million.
pub(crate) const MAX_TIMESTAMP: f64 = 9e12;

/// What is wrong with a data row.
#[derive(Debug, Clone, PartialEq)]
pub enum BadRow {
    /// A cell that is not a value (`0/1/true/false`) or, in the timestamp column, a number.
    Value {
        /// Header name of the column holding the cell.
        column: String,
        /// The cell's text as read.
        cell: String,
    },
    /// A timestamp beyond [`MAX_TIMESTAMP`] either side of 0.
    TimeRange {
        /// Header name of the timestamp column.
        column: String,
        /// The timestamp cell's text as read.
        cell: String,
    },
    /// An address (long format) that the mapping does not know.
    UnknownAddress(String),
    /// A timestamp smaller than the one before.
    TimeBackwards {
        /// This row's timestamp, in seconds.
        time: f64,
        /// The timestamp of the row before, in seconds.
        previous: f64,
    },
    /// A row with more or fewer cells than the header.
    CellCount {
        /// Number of cells in the row.
        found: usize,
        /// Number of columns in the header.
        expected: usize,
    },
}

/// The kinds of [`BadRow`], for counting skipped rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum RowKind {
    /// [`BadRow::Value`]: an unparsable value or timestamp.
    Value,
    /// [`BadRow::TimeRange`]: a timestamp beyond [`MAX_TIMESTAMP`].
    TimeRange,
    /// [`BadRow::UnknownAddress`]: an address not in the mapping.
    UnknownAddress,
    /// [`BadRow::TimeBackwards`]: a timestamp smaller than the one before.
    TimeBackwards,
    /// [`BadRow::CellCount`]: a row whose cell count differs from the header's.
    CellCount,
}

impl RowKind {
    /// Every kind, in the order reports list them.
    pub(crate) const ALL: [RowKind; 5] = [
        RowKind::Value,
        RowKind::TimeRange,
        RowKind::UnknownAddress,
        RowKind::TimeBackwards,
        RowKind::CellCount,
    ];

    /// A short label for reports.
    pub(crate) fn label(self) -> &'static str {
        match self {
            RowKind::Value => "unparsable value",
            RowKind::TimeRange => "timestamp out of range",
            RowKind::UnknownAddress => "unknown address",
            RowKind::TimeBackwards => "time going backwards",
            RowKind::CellCount => "wrong cell count",
        }
    }
}

impl BadRow {
    /// The kind of the problem.
    pub(crate) fn kind(&self) -> RowKind {
        match self {
            BadRow::Value { .. } => RowKind::Value,
            BadRow::TimeRange { .. } => RowKind::TimeRange,
            BadRow::UnknownAddress(_) => RowKind::UnknownAddress,
            BadRow::TimeBackwards { .. } => RowKind::TimeBackwards,
            BadRow::CellCount { .. } => RowKind::CellCount,
        }
    }
}

impl fmt::Display for BadRow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BadRow::Value { column, cell } => {
                write!(f, "column {}: cannot read {}", quote(column), quote(cell))
            }
            BadRow::UnknownAddress(a) => {
                write!(f, "unknown address {} (not in the mapping)", quote(a))
            }
            BadRow::TimeRange { column, cell } => write!(
                f,
                "column {}: {} is out of range: timestamps are seconds within ±9e12 (about 285,000 years) of 0",
                quote(column),
                quote(cell)
            ),
            BadRow::TimeBackwards { time, previous } => {
                write!(f, "time goes backwards: {time} after {previous}")
            }
            BadRow::CellCount { found, expected } => {
                write!(f, "{found} cells, the header has {expected}")
            }
        }
    }
}

/// An error while ingesting a log, always with its place.
#[derive(Debug, thiserror::Error)]
pub enum IngestError {
    /// A Parquet log that cannot be decoded (naming the file and row).
    #[error(transparent)]
    Parquet(Box<crate::scenario::ScenarioError>),
    /// A file (log, mapping or output) could not be opened or read.
    #[error("{file}: {source}")]
    Io {
        /// The file concerned.
        file: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A malformed mapping file line (bad syntax, duplicate address or name).
    #[error("{file}:{line}: {message}")]
    Mapping {
        /// The mapping file.
        file: PathBuf,
        /// 1-based line number in the mapping file.
        line: usize,
        /// What is wrong with the line.
        message: String,
    },
    /// A log header that is neither format's, or whose columns do not match the mapping.
    #[error("{file}:{line}: {message}")]
    Header {
        /// The log file.
        file: PathBuf,
        /// 1-based line number of the header.
        line: usize,
        /// What is wrong with the header.
        message: String,
    },
    /// A bad data row, in strict mode (lenient mode skips it).
    #[error("{file}:{line}: {problem}")]
    Row {
        /// The log file.
        file: PathBuf,
        /// 1-based line number of the row in the (decompressed) file.
        line: usize,
        /// What is wrong with the row.
        problem: BadRow,
    },
    /// A line longer than the limit, in the log or the mapping.
    #[error(transparent)]
    Read(#[from] crate::files::FileReadError),
    /// The scenario file could not be written.
    #[error(transparent)]
    Write(#[from] crate::files::WriteError),
    /// A log whose header is followed by no sample: a scenario needs at least one step.
    /// `skipped` counts the bad rows that lenient mode skipped.
    #[error("{}: the log has no data rows{}", file.display(), match skipped {
        0 => String::new(),
        n => format!(" that could be read ({n} bad rows skipped)"),
    })]
    NoData {
        /// The log file.
        file: PathBuf,
        /// Bad rows skipped in lenient mode.
        skipped: u64,
    },
}

/// Streams a whole log through the SAT reconstruction paper's conversion, handing each step to `sink` as soon as
/// it is final; the first error of the log or of `sink` stops it. Returns what the reader
/// counted.
pub fn convert_log<R: std::io::BufRead, E: From<IngestError>>(
    mut reader: LogReader<R>,
    initial_outputs: Vec<bool>,
    mut sink: impl FnMut(crate::scenario::Step) -> Result<(), E>,
) -> Result<ReadStats, E> {
    let mut steps = StepStream::new(initial_outputs);
    for sample in reader.by_ref() {
        if let Some(step) = steps.push(sample?) {
            sink(step)?;
        }
    }
    if let Some(step) = steps.finish() {
        sink(step)?;
    }
    Ok(reader.stats().clone())
}

/// What [`write_scenario`] read and wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Written {
    /// What the log reader counted (rows, samples, skipped bad rows).
    pub(crate) stats: ReadStats,
    /// Steps written, and those of them with a `CNF`.
    pub(crate) steps: u64,
    /// Steps written that carry a `CNF` output event (some output changed).
    pub(crate) active: u64,
}

/// `synth ingest`: converts the log file `log` into an fbSAT scenario file `out` with one
/// scenario (initial outputs all 0, as the log formats assume), written step by step as the
/// log is read, so memory does not grow with the log; `out` is published atomically (`.gz`
/// compresses) and not touched when the log has a bad row.
pub(crate) fn write_scenario(
    log: &std::path::Path,
    mapping: &Mapping,
    lenient: bool,
    out: &std::path::Path,
) -> Result<Written, IngestError> {
    let reader = LogReader::open(log, mapping, lenient)?;
    let file = crate::files::AtomicFile::create(out)?;
    let write_err = |source| {
        IngestError::Write(crate::files::WriteError {
            path: out.to_path_buf(),
            source,
        })
    };
    let mut w = crate::scenario::fbsat::ScenarioWriter::new(file, 1).map_err(write_err)?;
    let (mut steps, mut active) = (0, 0);
    let stats = convert_log(reader, vec![false; mapping.outputs().len()], |step| {
        steps += 1;
        active += u64::from(step.outputs.is_some());
        w.step(&step).map_err(write_err)
    })?;
    // Dropping the writer drops the unfinished file: nothing is left at `out`.
    if steps == 0 {
        return Err(IngestError::NoData {
            file: log.to_path_buf(),
            skipped: stats.skipped_total(),
        });
    }
    w.end_scenario().map_err(write_err)?;
    w.into_inner().commit()?;
    Ok(Written {
        stats,
        steps,
        active,
    })
}

/// Reads a log file into a scenario set with one scenario for the whole log (initial outputs
/// all 0, as the log formats assume). A log without a sample is an [`IngestError::NoData`]:
/// a scenario of no step is no scenario file `synth infer` reads.
pub fn read_scenarios(
    log: &std::path::Path,
    mapping: &Mapping,
    lenient: bool,
) -> Result<(crate::scenario::ScenarioSet, ReadStats), IngestError> {
    use crate::scenario::{Origin, Scenario, ScenarioSet};
    let reader = LogReader::open(log, mapping, lenient)?;
    let initial = vec![false; mapping.outputs().len()];
    let mut steps = Vec::new();
    let stats = convert_log(reader, initial.clone(), |s| {
        steps.push(s);
        Ok::<(), IngestError>(())
    })?;
    if steps.is_empty() {
        return Err(IngestError::NoData {
            file: log.to_path_buf(),
            skipped: stats.skipped_total(),
        });
    }
    let set = ScenarioSet {
        inputs: mapping.inputs().to_vec(),
        outputs: mapping.outputs().to_vec(),
        initial_outputs: initial,
        scenarios: vec![Scenario {
            origin: Origin {
                file: log.to_path_buf(),
                line: 1,
                rows: None,
            },
            steps,
        }],
    };
    Ok((set, stats))
}

/// Writes a random long-format log for benchmarks: `inputs` + `outputs` signals at
/// `%IX0.k` / `%QX0.k`, each row toggling one random signal, the timestamp advancing by 0.01
/// on about half of the rows. Returns the matching mapping file text. Streams: memory does not
/// grow with `rows`.
pub fn write_random_log(
    w: &mut impl std::io::Write,
    inputs: usize,
    outputs: usize,
    rows: u64,
    seed: u64,
) -> std::io::Result<String> {
    use rand::{Rng, SeedableRng};
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut map = String::new();
    let mut addresses = Vec::new();
    for k in 0..inputs {
        addresses.push(format!("%IX{}.{}", k / 8, k % 8));
        map.push_str(&format!("{} in x{k}\n", addresses[k]));
    }
    for k in 0..outputs {
        addresses.push(format!("%QX{}.{}", k / 8, k % 8));
        map.push_str(&format!("{} out z{k}\n", addresses[inputs + k]));
    }
    let mut values = vec![false; addresses.len()];
    let mut tick: u64 = 0;
    writeln!(w, "timestamp,address,value")?;
    for _ in 0..rows {
        if rng.gen::<bool>() {
            tick += 1;
        }
        let k = rng.gen_range(0..addresses.len());
        values[k] = !values[k];
        writeln!(
            w,
            "{}.{:02},{},{}",
            tick / 100,
            tick % 100,
            addresses[k],
            u8::from(values[k])
        )?;
    }
    Ok(map)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    #[test]
    fn a_hand_made_log_becomes_one_fbsat_scenario() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("log.csv");
        // The motor follows start one scan late (the SAT reconstruction paper's rule 2 joins the two), a repeated
        // scan collapses, stop turns the motor off in the same scan.
        std::fs::write(
            &log,
            "time,start,stop,motor\n0,0,0,0\n1,1,0,0\n2,1,0,1\n3,1,0,1\n4,1,1,0\n",
        )
        .unwrap();
        let map = "%IX0.0 in start\n%IX0.1 in stop\n%QX0.0 out motor\n";
        let mapping = Mapping::parse(Path::new("m.map"), map).unwrap();
        let (set, stats) = read_scenarios(&log, &mapping, false).unwrap();
        assert_eq!((stats.rows, stats.samples), (5, 5));
        let mut text = Vec::new();
        crate::scenario::fbsat::write(&set, &mut text).unwrap();
        assert_eq!(
            String::from_utf8(text).unwrap(),
            "1\nin=REQ[00]; in=REQ[10]; out=CNF[1]; in=REQ[11]; out=CNF[0];\n"
        );
    }

    #[test]
    fn a_log_without_data_rows_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("log.csv");
        let mapping = Mapping::parse(Path::new("m.map"), "%IX0.0 in a\n%QX0.0 out z\n").unwrap();
        for (text, lenient, why) in [
            ("timestamp,address,value\n", false, "no data rows"),
            ("time,a,z\n\n  \n", false, "no data rows"),
            (
                "timestamp,address,value\n0,%IX0.0,maybe\n",
                true,
                "no data rows that could be read (1 bad rows skipped)",
            ),
        ] {
            std::fs::write(&log, text).unwrap();
            let e = read_scenarios(&log, &mapping, lenient).unwrap_err();
            assert_eq!(
                e.to_string(),
                format!("{}: the log has {why}", log.display())
            );
        }
    }

    #[test]
    fn a_generated_log_reads_back_into_steps() {
        let dir = tempfile::tempdir().unwrap();
        let log = dir.path().join("log.csv");
        let mut buf = Vec::new();
        let map = write_random_log(&mut buf, 3, 2, 500, 7).unwrap();
        std::fs::write(&log, buf).unwrap();
        let mapping = Mapping::parse(Path::new("m.map"), &map).unwrap();
        let (set, stats) = read_scenarios(&log, &mapping, false).unwrap();
        assert_eq!(stats.rows, 500);
        assert_eq!(stats.skipped_total(), 0);
        assert_eq!(set.inputs, ["x0", "x1", "x2"]);
        assert_eq!(set.outputs, ["z0", "z1"]);
        let steps = &set.scenarios[0].steps;
        assert!(!steps.is_empty() && steps.len() as u64 <= stats.samples);
        // The SAT reconstruction paper's rule 2 leaves no two neighbouring steps with equal inputs.
        assert!(steps.windows(2).all(|w| w[0].inputs != w[1].inputs));
    }
}
