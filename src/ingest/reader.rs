//! The streaming log reader: lines in, samples out.
//!
//! In: a log (long or wide format, plain or gzip; see the [`super`] module header) and its
//! [`Mapping`]. Out: [`Sample`]s, one per scan (wide) or per timestamp (long), via
//! [`Iterator`]. Holds one record and one sample at a time, whatever the log's length; records
//! come from the crate's one CSV reader ([`Records`]), so quoted cells are read as in every
//! other log.

use super::{BadRow, IngestError, Mapping, RowKind, Sample, Slot, MAX_TIMESTAMP};
use crate::files::csv::{parse_bool_cell, Record, Records};
use crate::files::ReadError;
use crate::quote::quote;
use std::io::BufRead;
use std::path::{Path, PathBuf};

/// The two layouts a tapping device writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum LogFormat {
    /// `timestamp,address,value`: one row per changed signal.
    Long,
    /// `timestamp,COL,...`: one row per scan.
    Wide,
}

/// Counts of what a reader has seen so far.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct ReadStats {
    /// Non-blank data rows (after the header), including skipped ones.
    pub(crate) rows: u64,
    /// Samples produced.
    pub(crate) samples: u64,
    /// Skipped rows per kind, indexed like [`RowKind::ALL`] (lenient mode only).
    pub(crate) skipped: [u64; 5],
}

impl ReadStats {
    /// Skipped rows of one kind.
    pub(crate) fn skipped(&self, kind: RowKind) -> u64 {
        self.skipped[kind as usize]
    }

    /// Skipped rows of every kind.
    pub(crate) fn skipped_total(&self) -> u64 {
        self.skipped.iter().sum()
    }
}

/// Reads samples from a log, record by record.
pub struct LogReader<R: BufRead = Box<dyn BufRead>> {
    file: PathBuf,
    records: Records<R>,
    lenient: bool,
    rows: Rows,
    done: bool,
    stats: ReadStats,
}

/// What the reader knows between records: the header and the signal values so far. Kept
/// apart from [`Records`], whose current record it reads.
struct Rows {
    format: LogFormat,
    /// Wide format: the slot of every column after the timestamp.
    columns: Vec<Slot>,
    /// Header cells, for error messages.
    headers: Vec<String>,
    mapping: Mapping,
    /// Long format: the signal values so far.
    current: Sample,
    /// Long format: timestamp of the group being collected, if any row was applied.
    group_time: Option<f64>,
    /// Timestamp of the last accepted row.
    last_time: Option<f64>,
    /// Timestamp of the sample last returned.
    sample_time: Option<f64>,
}

impl LogReader {
    /// Opens a log file, gunzipping it on the fly when it starts with the gzip magic bytes,
    /// and reads its header.
    ///
    /// A Parquet file (`.parquet`, [`crate::scenario::parquet`]) is decoded into the same CSV
    /// text first, in memory: its columns are those of a CSV log of either format.
    pub fn open(path: &Path, mapping: &Mapping, lenient: bool) -> Result<LogReader, IngestError> {
        let src: Box<dyn BufRead> = if crate::scenario::parquet::is_parquet(path) {
            let text = crate::scenario::parquet::to_csv(path)
                .map_err(|e| IngestError::Parquet(Box::new(e)))?;
            Box::new(std::io::Cursor::new(text.into_bytes()))
        } else {
            crate::files::open_input(path)
                .map_err(|source| IngestError::Io {
                    file: path.to_path_buf(),
                    source,
                })?
                .reader
        };
        LogReader::new(path.to_path_buf(), src, mapping, lenient)
    }
}

impl<R: BufRead> LogReader<R> {
    /// A reader over `src` (already decompressed); `file` names it in errors. Reads the header.
    pub(crate) fn new(
        file: PathBuf,
        mut src: R,
        mapping: &Mapping,
        lenient: bool,
    ) -> Result<LogReader<R>, IngestError> {
        let delimiter = sniff_delimiter(&mut src).map_err(|source| IngestError::Io {
            file: file.clone(),
            source,
        })?;
        let mut records = Records::new(src, delimiter);
        let read = |e| read_error(&file, e);
        let mut rows = Rows {
            format: LogFormat::Long,
            columns: Vec::new(),
            headers: Vec::new(),
            mapping: mapping.clone(),
            current: Sample {
                inputs: vec![false; mapping.inputs().len()],
                outputs: vec![false; mapping.outputs().len()],
            },
            group_time: None,
            last_time: None,
            sample_time: None,
        };
        let header_err = |line: usize, message: String| IngestError::Header {
            file: file.clone(),
            line,
            message,
        };
        match records.next_record().map_err(read)? {
            None => return Err(header_err(1, "empty log: expected a header row".into())),
            Some((line, header)) => {
                let cells = header
                    .iter()
                    .map(|c| String::from_utf8_lossy(c).into_owned())
                    .collect();
                rows.read_header(cells).map_err(|m| header_err(line, m))?;
            }
        }
        Ok(LogReader {
            file,
            records,
            lenient,
            rows,
            done: false,
            stats: ReadStats::default(),
        })
    }

    /// The detected format.
    pub(crate) fn format(&self) -> LogFormat {
        self.rows.format
    }

    /// What has been read so far.
    pub(crate) fn stats(&self) -> &ReadStats {
        &self.stats
    }

    /// The timestamp of the sample the iterator returned last (`None` before the first).
    pub(crate) fn sample_time(&self) -> Option<f64> {
        self.rows.sample_time
    }
}

impl Rows {
    /// Takes the header row's cells: tells the format and, for a wide log, the slot of every
    /// column. The error is the message; the caller adds the place.
    fn read_header(&mut self, cells: Vec<String>) -> Result<(), String> {
        let text = cells.join(",");
        let lower: Vec<String> = cells.iter().map(|c| c.to_ascii_lowercase()).collect();
        if lower == ["timestamp", "address", "value"] {
            self.format = LogFormat::Long;
            self.headers = cells;
            return Ok(());
        }
        if lower[0] != "timestamp" && lower[0] != "time" {
            return Err(format!(
                "expected 'timestamp,address,value' (long format) or 'timestamp,<signal>,...' (wide format), found {}",
                quote(&text)
            ));
        }
        self.format = LogFormat::Wide;
        let mut seen = vec![None; self.mapping.addresses().len()];
        for (k, cell) in cells.iter().enumerate().skip(1) {
            let slot = self.mapping.slot(cell.as_bytes()).ok_or_else(|| {
                format!(
                    "column {}: {} is not an address or name of the mapping",
                    k + 1,
                    quote(cell)
                )
            })?;
            let index = self.slot_index(slot);
            if let Some(first) = seen[index].replace(k + 1) {
                return Err(format!(
                    "column {}: {} is the same signal as column {first}",
                    k + 1,
                    quote(cell)
                ));
            }
            self.columns.push(slot);
        }
        if let Some(i) = seen.iter().position(Option::is_none) {
            let (address, slot) = &self.mapping.addresses()[i];
            let name = match slot {
                Slot::Input(x) => &self.mapping.inputs()[x.0],
                Slot::Output(z) => &self.mapping.outputs()[z.0],
            };
            return Err(format!(
                "no column for signal {} ({}) of the mapping",
                quote(name),
                crate::quote::cut(address)
            ));
        }
        self.headers = cells;
        Ok(())
    }

    /// Position of a slot in the mapping's address list.
    fn slot_index(&self, slot: Slot) -> usize {
        match slot {
            Slot::Input(x) => x.0,
            Slot::Output(z) => self.mapping.inputs().len() + z.0,
        }
    }

    fn check_time(&self, time: f64) -> Result<(), BadRow> {
        match self.last_time {
            Some(previous) if time < previous => Err(BadRow::TimeBackwards { time, previous }),
            _ => Ok(()),
        }
    }

    /// Long format: applies one change; returns the finished sample when a new timestamp
    /// starts.
    fn long_row(&mut self, row: Record<'_>) -> Result<Option<Sample>, BadRow> {
        let [t, address, v] = [0, 1, 2].map(|k| row.get(k).unwrap_or_default());
        if row.len() != 3 {
            return Err(BadRow::CellCount {
                found: row.len(),
                expected: 3,
            });
        }
        let time = parse_time(&self.headers[0], t)?;
        let slot = self
            .mapping
            .slot(address)
            .ok_or_else(|| BadRow::UnknownAddress(String::from_utf8_lossy(address).into_owned()))?;
        let value = parse_bool_cell(v).ok_or_else(|| bad_value(&self.headers[2], v))?;
        self.check_time(time)?;
        let finished = match self.group_time {
            Some(g) if g != time => {
                self.sample_time = Some(g);
                Some(self.current.clone())
            }
            _ => None,
        };
        match slot {
            Slot::Input(x) => self.current.inputs[x.0] = value,
            Slot::Output(z) => self.current.outputs[z.0] = value,
        }
        self.group_time = Some(time);
        self.last_time = Some(time);
        Ok(finished)
    }

    /// Wide format: one row, one sample.
    fn wide_row(&mut self, row: Record<'_>) -> Result<Sample, BadRow> {
        let expected = self.columns.len() + 1;
        if row.len() != expected {
            return Err(BadRow::CellCount {
                found: row.len(),
                expected,
            });
        }
        let mut cells = row.iter();
        let t = cells.next().unwrap_or_default();
        let time = parse_time(&self.headers[0], t)?;
        let mut sample = Sample {
            inputs: vec![false; self.mapping.inputs().len()],
            outputs: vec![false; self.mapping.outputs().len()],
        };
        for (k, (cell, slot)) in cells.zip(&self.columns).enumerate() {
            let value =
                parse_bool_cell(cell).ok_or_else(|| bad_value(&self.headers[k + 1], cell))?;
            match slot {
                Slot::Input(x) => sample.inputs[x.0] = value,
                Slot::Output(z) => sample.outputs[z.0] = value,
            }
        }
        self.check_time(time)?;
        self.last_time = Some(time);
        self.sample_time = Some(time);
        Ok(sample)
    }
}

impl<R: BufRead> Iterator for LogReader<R> {
    type Item = Result<Sample, IngestError>;

    fn next(&mut self) -> Option<Self::Item> {
        while !self.done {
            let (line, record) = match self.records.next_record() {
                Err(e) => {
                    self.done = true;
                    return Some(Err(read_error(&self.file, e)));
                }
                Ok(None) => {
                    self.done = true;
                    // The last timestamp group of a long log ends with the file.
                    if let Some(g) = self.rows.group_time.take() {
                        self.rows.sample_time = Some(g);
                        self.stats.samples += 1;
                        return Some(Ok(self.rows.current.clone()));
                    }
                    return None;
                }
                Ok(Some(r)) => r,
            };
            self.stats.rows += 1;
            let row = match self.rows.format {
                LogFormat::Long => self.rows.long_row(record),
                LogFormat::Wide => self.rows.wide_row(record).map(Some),
            };
            match row {
                Ok(Some(sample)) => {
                    self.stats.samples += 1;
                    return Some(Ok(sample));
                }
                Ok(None) => {}
                Err(problem) if self.lenient => self.stats.skipped[problem.kind() as usize] += 1,
                Err(problem) => {
                    self.done = true;
                    return Some(Err(IngestError::Row {
                        file: self.file.clone(),
                        line,
                        problem,
                    }));
                }
            }
        }
        None
    }
}

/// A failed read of the log: an I/O error (a broken gzip stream, say) stays
/// [`IngestError::Io`].
fn read_error(file: &Path, e: ReadError) -> IngestError {
    match e {
        ReadError::Io(source) => IngestError::Io {
            file: file.to_path_buf(),
            source,
        },
        e => IngestError::Read(e.at(file)),
    }
}

fn bad_value(column: &str, cell: &[u8]) -> BadRow {
    BadRow::Value {
        column: column.to_string(),
        cell: String::from_utf8_lossy(cell).into_owned(),
    }
}

/// An ISO 8601 date and time as seconds since 1970-01-01T00:00:00Z: RFC 3339
/// (`2024-05-01T10:00:00.123Z`, `...+02:00`), also with a space for the `T` (as spreadsheets
/// write it) or without an offset, which is then read as UTC.
fn iso_seconds(text: &str) -> Option<f64> {
    use time::format_description::well_known::Rfc3339;
    let t = text.trim().replacen(' ', "T", 1);
    let has_offset = t.ends_with('Z')
        || t.ends_with('z')
        || t.get(19..)
            .is_some_and(|rest| rest.contains('+') || rest.contains('-'));
    let t = if has_offset { t } else { format!("{t}Z") };
    let at = time::OffsetDateTime::parse(&t, &Rfc3339).ok()?;
    Some(at.unix_timestamp_nanos() as f64 / 1e9)
}

/// The cell delimiter of a log: `;` when the header line (as far as the reader's buffer holds
/// it) has a `;` and no `,`, as Excel writes CSV in locales with a decimal comma; `,`
/// otherwise. Nothing is consumed; a read error (a broken gzip stream) is returned.
fn sniff_delimiter(src: &mut impl BufRead) -> std::io::Result<u8> {
    let buffer = src.fill_buf()?;
    let line = buffer.split(|&b| b == b'\n').next().unwrap_or_default();
    Ok(if line.contains(&b';') && !line.contains(&b',') {
        b';'
    } else {
        b','
    })
}

fn parse_time(column: &str, cell: &[u8]) -> Result<f64, BadRow> {
    // A decimal comma (`5,25`) can only reach here from a `;`-separated log.
    let decimal = |c: &str| {
        c.parse::<f64>()
            .ok()
            .or_else(|| c.replacen(',', ".", 1).parse().ok())
    };
    let time = std::str::from_utf8(cell)
        .ok()
        .and_then(|c| decimal(c).or_else(|| iso_seconds(c)))
        .filter(|t| t.is_finite())
        .ok_or_else(|| bad_value(column, cell))?;
    match time.abs() <= MAX_TIMESTAMP {
        true => Ok(time),
        false => Err(BadRow::TimeRange {
            column: column.to_string(),
            cell: String::from_utf8_lossy(cell).into_owned(),
        }),
    }
}

/// What reading a raw log took, one a line: rows, samples, rows skipped by kind, time and
/// throughput.
pub struct Throughput<'a> {
    /// What the reader counted.
    pub stats: &'a ReadStats,
    /// Seconds the reading took.
    pub seconds: f64,
}

impl std::fmt::Display for Throughput<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let stats = self.stats;
        writeln!(f, "rows:    {}", stats.rows)?;
        writeln!(f, "samples: {}", stats.samples)?;
        for kind in RowKind::ALL {
            let n = stats.skipped(kind);
            if n > 0 {
                writeln!(f, "skipped: {n} rows ({})", kind.label())?;
            }
        }
        write!(
            f,
            "time:    {:.2} s ({:.2} M rows/s)",
            self.seconds,
            stats.rows as f64 / self.seconds.max(1e-9) / 1e6
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Write;

    const MAP: &str = "%IX0.0 in a\n%IX0.1 in b\n%QX0.0 out z\n";

    fn mapping() -> Mapping {
        Mapping::parse(Path::new("m.map"), MAP).unwrap()
    }

    fn reader(log: &str, lenient: bool) -> Result<LogReader<&[u8]>, IngestError> {
        LogReader::new(PathBuf::from("l.csv"), log.as_bytes(), &mapping(), lenient)
    }

    /// Samples as `ab/z` bit strings, or the first error's message.
    fn read(log: &str, lenient: bool) -> Result<Vec<String>, String> {
        let r = reader(log, lenient).map_err(|e| e.to_string())?;
        r.map(|s| {
            s.map(|s| {
                let bits = |v: &[bool]| {
                    v.iter()
                        .map(|&b| if b { '1' } else { '0' })
                        .collect::<String>()
                };
                format!("{}/{}", bits(&s.inputs), bits(&s.outputs))
            })
            .map_err(|e| e.to_string())
        })
        .collect()
    }

    #[test]
    fn long_rows_with_one_timestamp_form_one_sample() {
        let log = "timestamp,address,value\n\
                   0.0,%IX0.0,1\n\
                   0.0,%IX0.1,TRUE\n\
                   \n\
                   0.5,%QX0.0,1\r\n\
                   1,a,false\n\
                   1,%IX0.1,0\n";
        assert_eq!(read(log, false).unwrap(), ["11/0", "11/1", "00/1"]);
        let mut r = reader(log, false).unwrap();
        assert_eq!(r.format(), LogFormat::Long);
        assert_eq!(r.by_ref().count(), 3);
        assert_eq!(r.stats().rows, 5);
        assert_eq!(r.stats().samples, 3);
    }

    #[test]
    fn wide_rows_are_samples_in_mapping_order() {
        // Columns in another order than the mapping, by address and by name.
        let log = "time,z,%IX0.1,a\n0,0,1,0\n0.01,1,1,0\n0.01,1,0,1\n";
        assert_eq!(read(log, false).unwrap(), ["01/0", "01/1", "10/1"]);
        assert_eq!(reader(log, false).unwrap().format(), LogFormat::Wide);
    }

    #[test]
    fn header_errors() {
        let cases = [
            ("", "l.csv:1: empty log"),
            (
                "when,address,value\n",
                "l.csv:1: expected 'timestamp,address,value'",
            ),
            (
                "\ntimestamp,a,b,q\n",
                "l.csv:2: column 4: 'q' is not an address or name",
            ),
            (
                "timestamp,a,b,%IX0.0\n",
                "l.csv:1: column 4: '%IX0.0' is the same signal as column 2",
            ),
            (
                "timestamp,a,z\n",
                "l.csv:1: no column for signal 'b' (%IX0.1)",
            ),
        ];
        for (log, want) in cases {
            let got = read(log, false).unwrap_err();
            assert!(got.starts_with(want), "{got:?} should start with {want:?}");
        }
    }

    #[test]
    fn every_bad_row_kind_names_its_line() {
        let long = "timestamp,address,value\n1,a,1\n";
        let wide = "timestamp,a,b,z\n1,1,0,0\n";
        let cases = [
            (long, "2,a,2\n", "l.csv:3: column 'value': cannot read '2'"),
            (
                long,
                "x,a,1\n",
                "l.csv:3: column 'timestamp': cannot read 'x'",
            ),
            (
                long,
                "inf,a,1\n",
                "l.csv:3: column 'timestamp': cannot read 'inf'",
            ),
            (
                long,
                "2,%IX7.7,1\n",
                "l.csv:3: unknown address '%IX7.7' (not in the mapping)",
            ),
            (
                long,
                "0.5,a,0\n",
                "l.csv:3: time goes backwards: 0.5 after 1",
            ),
            (long, "2,a\n", "l.csv:3: 2 cells, the header has 3"),
            (long, "2,a,1,1\n", "l.csv:3: 4 cells, the header has 3"),
            (
                wide,
                "2,1,0,maybe\n",
                "l.csv:3: column 'z': cannot read 'maybe'",
            ),
            (wide, "0,1,0,0\n", "l.csv:3: time goes backwards: 0 after 1"),
            (wide, "2,1,0\n", "l.csv:3: 3 cells, the header has 4"),
            (
                long,
                "1e20,a,1\n",
                "l.csv:3: column 'timestamp': '1e20' is out of range: timestamps are seconds within ±9e12 (about 285,000 years) of 0",
            ),
            (
                wide,
                "-9000000000001,1,0,0\n",
                "l.csv:3: column 'timestamp': '-9000000000001' is out of range: timestamps are seconds within ±9e12 (about 285,000 years) of 0",
            ),
        ];
        for (head, row, want) in cases {
            let got = read(&format!("{head}{row}"), false).unwrap_err();
            assert_eq!(got, want);
        }
    }

    #[test]
    fn iso_8601_timestamps_are_seconds_since_the_unix_epoch() {
        for (text, seconds) in [
            ("2024-05-01T10:00:00.123Z", 1_714_557_600.123),
            ("2024-05-01T12:00:00.123+02:00", 1_714_557_600.123),
            ("2024-05-01 10:00:00.5", 1_714_557_600.5),
            ("2024-05-01T10:00:00", 1_714_557_600.0),
            ("1970-01-01T00:00:00Z", 0.0),
        ] {
            let got = parse_time("t", text.as_bytes()).unwrap();
            assert!((got - seconds).abs() < 1e-6, "{text}: {got}");
        }
        for bad in [
            "2024-13-01T10:00:00Z",
            "2024-05-01",
            "10:00:00",
            "yesterday",
        ] {
            assert!(parse_time("t", bad.as_bytes()).is_err(), "{bad}");
        }
    }

    #[test]
    fn timestamps_in_range_are_read_whatever_their_epoch() {
        // Unix times in seconds and in milliseconds, and the range's ends.
        let log = "timestamp,address,value\n\
                   -9e12,a,1\n\
                   1764659000.25,b,1\n\
                   1764659000250,z,1\n\
                   9e12,a,0\n\
                   9.1e12,b,0\n";
        assert_eq!(read(log, true).unwrap(), ["10/0", "11/0", "11/1", "01/1"]);
        let mut r = reader(log, true).unwrap();
        r.by_ref().for_each(drop);
        assert_eq!(r.stats().skipped(RowKind::TimeRange), 1);
        assert_eq!(r.stats().skipped_total(), 1);
    }

    #[test]
    fn lenient_mode_skips_and_counts_bad_rows() {
        let log = "timestamp,address,value\n\
                   1,a,1\n\
                   1,a,yes\n\
                   2,%IX7.7,1\n\
                   0,b,1\n\
                   2,b\n\
                   2,b,1\n\
                   3,x,1\n";
        assert_eq!(read(log, true).unwrap(), ["10/0", "11/0"]);
        let mut r = reader(log, true).unwrap();
        r.by_ref().for_each(drop);
        let s = r.stats();
        assert_eq!(s.rows, 7);
        assert_eq!(s.skipped(RowKind::Value), 1);
        assert_eq!(s.skipped(RowKind::UnknownAddress), 2);
        assert_eq!(s.skipped(RowKind::TimeBackwards), 1);
        assert_eq!(s.skipped(RowKind::CellCount), 1);
        assert_eq!(s.skipped_total(), 5);
        // Without --lenient the first bad row stops the reader.
        assert_eq!(
            read(log, false).unwrap_err(),
            "l.csv:3: column 'value': cannot read 'yes'"
        );
    }

    #[test]
    fn gzip_logs_are_read_transparently_even_multi_member() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("log.csv.gz");
        let mut bytes = Vec::new();
        for part in ["timestamp,address,value\n0,a,1\n", "1,z,1\n"] {
            let mut gz = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
            gz.write_all(part.as_bytes()).unwrap();
            bytes.extend(gz.finish().unwrap());
        }
        std::fs::write(&path, bytes).unwrap();
        let samples: Vec<Sample> = LogReader::open(&path, &mapping(), false)
            .unwrap()
            .collect::<Result<_, _>>()
            .unwrap();
        assert_eq!(samples.len(), 2);
        assert_eq!(samples[1].outputs, [true]);

        std::fs::write(&path, [0x1f, 0x8b, 8, 0, 1, 2, 3]).unwrap();
        let err = match LogReader::open(&path, &mapping(), false) {
            Err(e) => e,
            Ok(mut r) => r
                .find_map(Result::err)
                .expect("a broken gzip stream is an error"),
        };
        assert!(matches!(err, IngestError::Io { .. }), "{err}");
    }
}
