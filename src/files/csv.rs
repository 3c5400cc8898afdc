//! CSV as PLC data collectors write it: the one reader behind every log format of this crate.
//!
//! In: a byte stream (a file, possibly gunzipped by [`super::open_input`], or text in memory)
//! and its delimiter. Out: records of trimmed cells, each with the line it starts on, and the
//! Boolean values the cells hold ([`parse_bool`]). Quoting follows RFC 4180 (the `csv` crate);
//! a UTF-8 byte order mark before the first record is dropped, as spreadsheet programs write
//! one; blank lines, even ones holding only spaces, are skipped.

use std::io::{self, BufRead};

/// The UTF-8 encoding of U+FEFF, which some programs put before the first byte of text.
const UTF8_BOM: &[u8] = b"\xEF\xBB\xBF";

/// Reads records one at a time; see the module header.
///
/// Lines are read here and each record's cells are split by one reused `csv` reader: the
/// crate's own line count skips blank lines, and every error message of a log names the line
/// of the file. Memory holds one record, whatever the length of the file.
pub struct Records<R: BufRead> {
    src: R,
    /// Splits the record held in its cursor; rewound for every record.
    csv: ::csv::Reader<io::Cursor<Vec<u8>>>,
    /// Lines read so far.
    line: usize,
    record: ::csv::ByteRecord,
}

impl<R: BufRead> Records<R> {
    /// A reader over `src` whose cells are separated by `delimiter` (e.g. `b','`).
    pub fn new(mut src: R, delimiter: u8) -> io::Result<Records<R>> {
        if src.fill_buf()?.starts_with(UTF8_BOM) {
            src.consume(UTF8_BOM.len());
        }
        let mut csv = ::csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .delimiter(delimiter)
            .from_reader(io::Cursor::new(Vec::with_capacity(256)));
        // The first seek reads the (empty) cursor as the header row, once, so that later
        // rewinds only reset the parser.
        rewind(&mut csv)?;
        Ok(Records {
            src,
            csv,
            line: 0,
            record: ::csv::ByteRecord::new(),
        })
    }

    /// The next non-blank record and the 1-based line it starts on, or `None` at the end.
    pub fn next_record(&mut self) -> io::Result<Option<(usize, Record<'_>)>> {
        loop {
            let buf = self.csv.get_mut().get_mut();
            buf.clear();
            if self.src.read_until(b'\n', buf)? == 0 {
                return Ok(None);
            }
            self.line += 1;
            let start = self.line;
            // A quoted cell may hold line breaks (RFC 4180): while a quote is open, the record
            // goes on in the next line. Doubled quotes inside a cell count twice, so the parity
            // of all quotes says whether one is open.
            while buf.iter().filter(|&&b| b == b'"').count() % 2 == 1 {
                if self.src.read_until(b'\n', buf)? == 0 {
                    break;
                }
                self.line += 1;
            }
            if buf.trim_ascii().is_empty() {
                continue;
            }
            rewind(&mut self.csv)?;
            self.csv
                .read_byte_record(&mut self.record)
                .map_err(io_error)?;
            return Ok(Some((start, Record(&self.record))));
        }
    }
}

/// One record: its cells, each trimmed of surrounding blanks.
///
/// Trimming on access spares the copy the `csv` crate's own trimming makes of every record.
#[derive(Clone, Copy)]
pub struct Record<'a>(&'a ::csv::ByteRecord);

impl<'a> Record<'a> {
    /// The number of cells.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// Whether the record has no cells (never true for a record [`Records`] returns).
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// Cell `k` (0-based), if the record has it.
    pub fn get(&self, k: usize) -> Option<&'a [u8]> {
        self.0.get(k).map(<[u8]>::trim_ascii)
    }

    /// The cells in order.
    pub fn iter(&self) -> impl Iterator<Item = &'a [u8]> {
        self.0.iter().map(<[u8]>::trim_ascii)
    }
}

/// Points the splitter at the start of its cursor with a fresh parser state.
fn rewind(csv: &mut ::csv::Reader<io::Cursor<Vec<u8>>>) -> io::Result<()> {
    csv.seek_raw(io::SeekFrom::Start(0), ::csv::Position::new())
        .map_err(io_error)
}

/// The I/O error behind a CSV error. With flexible records and byte cells, splitting a record
/// in memory cannot fail; anything but I/O is still reported, as invalid data.
fn io_error(e: ::csv::Error) -> io::Error {
    match e.into_kind() {
        ::csv::ErrorKind::Io(e) => e,
        other => io::Error::new(io::ErrorKind::InvalidData, format!("{other:?}")),
    }
}

/// Reads a Boolean cell: `0`, `1`, `true` or `false` in any case (surrounding blanks are the
/// caller's to trim).
pub fn parse_bool(cell: &[u8]) -> Option<bool> {
    match cell {
        b"0" => Some(false),
        b"1" => Some(true),
        _ if cell.eq_ignore_ascii_case(b"false") => Some(false),
        _ if cell.eq_ignore_ascii_case(b"true") => Some(true),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str, delimiter: u8) -> Vec<(usize, Vec<String>)> {
        let mut records = Records::new(text.as_bytes(), delimiter).unwrap();
        let mut out = Vec::new();
        while let Some((line, r)) = records.next_record().unwrap() {
            let cells = r.iter().map(|c| String::from_utf8_lossy(c).into_owned());
            out.push((line, cells.collect()));
        }
        out
    }

    #[test]
    fn quotes_bom_blank_lines_and_line_numbers() {
        let text = "\u{feff}time,\"in:a\"\n\n  \r\n0,\"1\"\r\n\"x,\"\"y\"\"\",0\n";
        assert_eq!(
            read(text, b','),
            [
                (1, vec!["time".to_string(), "in:a".into()]),
                (4, vec!["0".into(), "1".into()]),
                (5, vec!["x,\"y\"".into(), "0".into()]),
            ]
        );
        assert_eq!(read("a;b\n", b';'), [(1, vec!["a".into(), "b".into()])]);
        // A line break inside quotes continues the record; the next record's line is counted.
        assert_eq!(
            read("\"a\nb\",c\nd\n", b','),
            [
                (1, vec!["a\nb".to_string(), "c".into()]),
                (3, vec!["d".to_string()])
            ]
        );
        assert!(read("", b',').is_empty());
    }

    #[test]
    fn booleans_in_any_case_and_digits() {
        for (cell, v) in [("0", false), ("1", true), ("TRUE", true), ("False", false)] {
            assert_eq!(parse_bool(cell.as_bytes()), Some(v), "{cell}");
        }
        for cell in ["", "2", "yes", "01", " 1"] {
            assert_eq!(parse_bool(cell.as_bytes()), None, "{cell:?}");
        }
    }
}
