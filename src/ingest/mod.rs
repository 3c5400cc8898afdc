//! Streaming ingestion of raw PLC I/O data-flow logs, as a tapping device writes them.
//!
//! In: a mapping file ([`Mapping`]) and a log file, plain or gzip. Out: a stream of
//! [`Sample`]s ([`LogReader`]) and, through seed 000's conversion done on the fly
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
//! One signal per line: `ADDRESS in|out NAME`, separated by whitespace. `#` starts a comment;
//! blank lines are ignored. Names follow [`is_identifier`](crate::scenario::names::is_identifier).
//! An address or a name used twice is an error naming both lines. The interface order is the
//! file order of the `in` lines, then of the `out` lines.
//!
//! # Log files
//! Both formats are CSV with `,`, told apart by their header; the file may be gzip-compressed
//! (recognized by its magic bytes, multi-member streams accepted). Values are `0`, `1`,
//! `true`, `false` (any case). Timestamps are numbers and must not go backwards. Blank lines
//! are ignored; line numbers count every line of the (decompressed) file.
//! - **long**, header `timestamp,address,value`: one row per changed signal. Every signal
//!   starts at 0 and keeps its value until a row changes it. Rows with the same timestamp form
//!   one sample, emitted once a later timestamp (or the end of the file) is seen.
//! - **wide**, header `timestamp,COL,...`: one row per scan; each `COL` is an address or a
//!   name of the mapping, and every mapped signal needs exactly one column.
//! In both, the address column may hold a name of the mapping instead of an address.
//!
//! # Bad rows
//! An unparsable value or timestamp, an unknown address, a timestamp smaller than the one
//! before, or a wrong number of cells stops the reader with an [`IngestError::Row`] naming
//! file and line. In lenient mode the row is skipped instead and counted per [`RowKind`].

mod convert;
mod mapping;
mod reader;

pub use convert::StepStream;
pub use mapping::{Mapping, Slot};
pub use reader::{LogFormat, LogReader, ReadStats};

pub use crate::scenario::csvlog::Sample;
use std::fmt;
use std::path::PathBuf;

/// What is wrong with a data row.
#[derive(Debug, Clone, PartialEq)]
pub enum BadRow {
    /// A cell that is not a value (`0/1/true/false`) or, in the timestamp column, a number.
    Value { column: String, cell: String },
    /// An address (long format) that the mapping does not know.
    UnknownAddress(String),
    /// A timestamp smaller than the one before.
    TimeBackwards { time: f64, previous: f64 },
    /// A row with more or fewer cells than the header.
    CellCount { found: usize, expected: usize },
}

/// The kinds of [`BadRow`], for counting skipped rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RowKind {
    Value,
    UnknownAddress,
    TimeBackwards,
    CellCount,
}

impl RowKind {
    /// Every kind, in the order reports list them.
    pub const ALL: [RowKind; 4] = [
        RowKind::Value,
        RowKind::UnknownAddress,
        RowKind::TimeBackwards,
        RowKind::CellCount,
    ];

    /// A short label for reports.
    pub fn label(self) -> &'static str {
        match self {
            RowKind::Value => "unparsable value",
            RowKind::UnknownAddress => "unknown address",
            RowKind::TimeBackwards => "time going backwards",
            RowKind::CellCount => "wrong cell count",
        }
    }
}

impl BadRow {
    /// The kind of the problem.
    pub fn kind(&self) -> RowKind {
        match self {
            BadRow::Value { .. } => RowKind::Value,
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
                write!(f, "column '{column}': cannot read '{cell}'")
            }
            BadRow::UnknownAddress(a) => write!(f, "unknown address '{a}' (not in the mapping)"),
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
    #[error("{file}: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}:{line}: {message}")]
    Mapping {
        file: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{file}:{line}: {message}")]
    Header {
        file: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{file}:{line}: {problem}")]
    Row {
        file: PathBuf,
        line: usize,
        problem: BadRow,
    },
}
