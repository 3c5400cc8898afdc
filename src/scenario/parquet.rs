//! Sampled PLC I/O logs in Apache Parquet, the columnar format historians, Spark and
//! DataFusion write: the columns of a CSV log ([`super::csvlog`]), one row per sample.
//!
//! Column names are the CSV log's header: `in:NAME` / `out:NAME` (or plain names with names
//! files), optional `time`/`timestamp` (ignored) and `scenario` (contiguous rows with the same
//! value form one scenario). Signal columns may be boolean, integer (0/1) or string
//! (`0`/`1`/`true`/`false`); nulls are refused. Rows are numbered as the lines of the CSV log
//! they make: the header is line 1, the first row line 2, so every message names a row.
//!
//! The reader decodes every row group into the CSV log's text and converts that with the CSV
//! log's rules, so both formats give the same scenarios.

use super::{csvlog, ScenarioError, ScenarioSet};
use crate::files::csv::quote_cell as cell;
use parquet::file::reader::{FileReader, SerializedFileReader};
use parquet::record::Field;
use std::path::Path;

/// Whether `path` names a Parquet file (by its extension).
pub(crate) fn is_parquet(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("parquet"))
}

/// Reads a Parquet log into scenarios.
pub(crate) fn read(
    file: &Path,
    input_names: Option<&[String]>,
    output_names: Option<&[String]>,
) -> Result<ScenarioSet, ScenarioError> {
    let text = to_csv(file)?;
    csvlog::parse(file, &text, input_names, output_names)
}

/// The log as CSV text: the column names, then one line per row (booleans as 0/1,
/// timestamps as seconds since the epoch).
pub(crate) fn to_csv(file: &Path) -> Result<String, ScenarioError> {
    let bad = |line: usize, e: parquet::errors::ParquetError| ScenarioError::Syntax {
        file: file.to_path_buf(),
        line,
        message: format!("not a readable Parquet file: {e}"),
    };
    let f = std::fs::File::open(file).map_err(|source| ScenarioError::Io {
        file: file.to_path_buf(),
        source,
    })?;
    let reader = SerializedFileReader::new(f).map_err(|e| bad(1, e))?;
    let schema = reader.metadata().file_metadata().schema_descr_ptr();
    let header: Vec<String> = schema.columns().iter().map(|c| cell(c.name())).collect();
    let mut text = header.join(",");
    text.push('\n');
    let rows = reader.get_row_iter(None).map_err(|e| bad(1, e))?;
    for (i, row) in rows.enumerate() {
        let row = row.map_err(|e| bad(i + 2, e))?;
        let cells: Vec<String> = row
            .get_column_iter()
            .map(|(_, field)| match field {
                Field::Bool(b) => u8::from(*b).to_string(),
                Field::Str(s) => cell(s),
                // Timestamps as seconds since the epoch, which the logs' time columns take.
                Field::TimestampMillis(ms) => format!("{:.3}", *ms as f64 / 1e3),
                Field::TimestampMicros(us) => format!("{:.6}", *us as f64 / 1e6),
                // A null is no sample value: the CSV rules refuse the empty cell, at its row.
                Field::Null => String::new(),
                other => cell(&other.to_string()),
            })
            .collect();
        text.push_str(&cells.join(","));
        text.push('\n');
    }
    Ok(text)
}
