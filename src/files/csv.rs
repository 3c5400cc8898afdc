//! CSV as PLC data collectors write it: the one reader behind every log format of this crate.
//!
//! In: a byte stream (a file, possibly gunzipped by [`super::open_input`], or text in memory)
//! and its delimiter. Out: records of trimmed cells, each with the line it starts on, and the
//! Boolean values the cells hold ([`parse_bool_cell`]). Quoting follows RFC 4180 (the `csv` crate);
//! a UTF-8 byte order mark at the start of a record is dropped (by `csv_core`; a file has lost
//! the one at its start already in [`super::open_input`]); blank lines, even ones holding only
//! spaces or a byte order mark, are skipped. A record longer than [`MAX_LINE_BYTES`] is an
//! error naming its line, found after reading at most that much of it.

use super::{read_line, LineRead, ReadError, MAX_LINE_BYTES, UTF8_BOM};
use std::io::BufRead;

/// Reads records one at a time; see the module header.
///
/// Lines are read here and each record's cells are split by `csv_core`, the parser under the
/// `csv` crate, into buffers reused from record to record: the `csv` crate's own line count
/// skips blank lines, and every error message of a log names the line of the file. Memory
/// holds one record, whatever the length of the file, and a record holds at most
/// [`MAX_LINE_BYTES`], whatever the length of a line.
pub(crate) struct Records<R: BufRead> {
    src: R,
    splitter: csv_core::Reader,
    /// The record's text (one line, or more while a quoted cell holds line breaks).
    text: Vec<u8>,
    /// The cells, unquoted, one after the other.
    cells: Vec<u8>,
    /// The end of every cell in `cells`; only the first `count` are this record's.
    ends: Vec<usize>,
    count: usize,
    /// Lines read so far.
    line: usize,
}

impl<R: BufRead> Records<R> {
    /// A reader over `src` whose cells are separated by `delimiter` (e.g. `b','`).
    pub(crate) fn new(src: R, delimiter: u8) -> Records<R> {
        Records {
            src,
            splitter: csv_core::ReaderBuilder::new().delimiter(delimiter).build(),
            text: Vec::with_capacity(256),
            cells: Vec::new(),
            ends: vec![0; 16],
            count: 0,
            line: 0,
        }
    }

    /// The next non-blank record and the 1-based line it starts on, or `None` at the end.
    pub(crate) fn next_record(&mut self) -> Result<Option<(usize, Record<'_>)>, ReadError> {
        loop {
            self.text.clear();
            let first = self.line + 1;
            if !self.next_line(first)? {
                return Ok(None);
            }
            // A quoted cell may hold line breaks (RFC 4180): while a quote is open, the record
            // goes on in the next line. Doubled quotes inside a cell count twice, so the parity
            // of all quotes says whether one is open; only the new line's quotes are counted,
            // so a record of many lines is read in linear time.
            let mut open = odd_quotes(&self.text);
            while open {
                let seen = self.text.len();
                if !self.next_line(first)? {
                    break;
                }
                open ^= odd_quotes(&self.text[seen..]);
            }
            // csv_core drops a byte order mark at the start of every record (it is reset for
            // each): a line that holds nothing else is blank too.
            let content = self.text.strip_prefix(UTF8_BOM).unwrap_or(&self.text);
            if content.trim_ascii().is_empty() {
                continue;
            }
            self.split();
            return Ok(Some((
                first,
                Record {
                    cells: &self.cells,
                    ends: &self.ends[..self.count],
                },
            )));
        }
    }

    /// Appends the next line to the record begun on line `first`; `false` at the end of the
    /// input.
    fn next_line(&mut self, first: usize) -> Result<bool, ReadError> {
        let limit = MAX_LINE_BYTES;
        match read_line(&mut self.src, &mut self.text, 0, limit)? {
            LineRead::End => Ok(false),
            LineRead::Line => {
                self.line += 1;
                Ok(true)
            }
            LineRead::TooLong => {
                self.line += 1;
                let line = self.line;
                Err(match first == line {
                    true => ReadError::LineTooLong { line, limit },
                    false => ReadError::RecordTooLong { first, line, limit },
                })
            }
        }
    }

    /// Splits `text` into `cells` and `ends`.
    fn split(&mut self) {
        use csv_core::ReadRecordResult as R;
        self.splitter.reset();
        // Unquoted cells are never longer than the text they come from.
        if self.cells.len() < self.text.len() + 1 {
            self.cells.resize(self.text.len() + 1, 0);
        }
        let mut input: &[u8] = &self.text;
        let (mut out, mut count) = (0, 0);
        loop {
            let (result, read, written, ended) =
                self.splitter
                    .read_record(input, &mut self.cells[out..], &mut self.ends[count..]);
            input = &input[read..];
            out += written;
            count += ended;
            match result {
                // The text is one record: an empty input tells the parser it ended.
                R::InputEmpty => {}
                R::OutputFull => {
                    let n = self.cells.len() * 2;
                    self.cells.resize(n, 0);
                }
                R::OutputEndsFull => {
                    let n = self.ends.len() * 2;
                    self.ends.resize(n, 0);
                }
                R::Record | R::End => break,
            }
        }
        self.count = count;
    }
}

fn odd_quotes(text: &[u8]) -> bool {
    text.iter().filter(|&&b| b == b'"').count() % 2 == 1
}

/// One record: its cells, each trimmed of surrounding blanks.
#[derive(Clone, Copy)]
pub(crate) struct Record<'a> {
    cells: &'a [u8],
    ends: &'a [usize],
}

impl<'a> Record<'a> {
    /// The number of cells.
    pub(crate) fn len(&self) -> usize {
        self.ends.len()
    }

    /// Cell `k` (0-based), if the record has it.
    pub(crate) fn get(&self, k: usize) -> Option<&'a [u8]> {
        let end = *self.ends.get(k)?;
        let start = if k == 0 { 0 } else { self.ends[k - 1] };
        Some(self.cells[start..end].trim_ascii())
    }

    /// The cells in order.
    pub(crate) fn iter(&self) -> impl Iterator<Item = &'a [u8]> + use<'a> {
        let (cells, ends) = (self.cells, self.ends);
        ends.iter().enumerate().map(move |(k, &end)| {
            let start = if k == 0 { 0 } else { ends[k - 1] };
            cells[start..end].trim_ascii()
        })
    }
}

/// One cell as RFC 4180 writes it: quoted, with quotes doubled, when it holds a comma, a quote
/// or a line break; as it is otherwise.
pub(crate) fn quote_cell(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// Reads a Boolean cell: `0`, `1`, `true` or `false` in any case (surrounding blanks are the
/// caller's to trim). Looser than NuSMV's `TRUE`/`FALSE`
/// ([`crate::ecc::ident::parse_bool_literal`]) on purpose: historians and PLC exports write
/// Booleans all these ways.
pub(crate) fn parse_bool_cell(cell: &[u8]) -> Option<bool> {
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
        let mut records = Records::new(text.as_bytes(), delimiter);
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

    /// csv_core drops a byte order mark at the start of every record; a line that held only
    /// one (and blanks) is blank, not a record without cells, which a log's header row once
    /// was: reading its first cell panicked.
    #[test]
    fn a_line_of_only_a_byte_order_mark_is_blank() {
        let text = "\n\u{feff}\n\u{feff}  \r\na,\u{feff}b\n\u{feff}c\n";
        assert_eq!(
            read(text, b','),
            [
                (4, vec!["a".to_string(), "\u{feff}b".into()]),
                (5, vec!["c".to_string()]),
            ]
        );
        assert!(read("\u{feff}", b',').is_empty());
    }

    /// The error of the first record that is not read, as text (`None` when every record of
    /// `src` reads).
    fn first_error(src: impl BufRead) -> Option<String> {
        let mut records = Records::new(src, b',');
        loop {
            match records.next_record() {
                Ok(Some(_)) => {}
                Ok(None) => return None,
                Err(e) => return Some(e.to_string()),
            }
        }
    }

    #[test]
    fn a_line_over_the_limit_is_an_error_naming_it() {
        use std::io::Read;
        let limit = crate::files::MAX_LINE_BYTES;
        // Generated in memory: twice the limit without a line break on line 3.
        let zeros = || std::io::BufReader::new(std::io::repeat(b'0').take(2 * limit as u64));
        assert_eq!(
            first_error(b"a,b\n1,2\n".chain(zeros())).as_deref(),
            Some(format!("line 3 is longer than {limit} bytes").as_str())
        );
        // A line of exactly the limit, then its break (LF or CRLF), is still read.
        let line = |n: usize, end: &'static [u8]| {
            std::io::BufReader::new(std::io::repeat(b'0').take(n as u64))
                .chain(end)
                .chain(&b"2\n"[..])
        };
        assert_eq!(first_error(line(limit, b"\n")), None);
        assert_eq!(first_error(line(limit, b"\r\n")), None);
        assert_eq!(
            first_error(line(limit + 1, b"\n")).as_deref(),
            Some(format!("line 1 is longer than {limit} bytes").as_str())
        );
    }

    #[test]
    fn an_open_quote_cannot_swallow_the_file() {
        use std::io::Read;
        let limit = crate::files::MAX_LINE_BYTES;
        // Short lines after a quote that never closes: each line is fine, the record is not.
        // A million of them also shows the quote count does not restart on every line.
        let lines = std::io::BufReader::new(std::io::repeat(b'\n').take(limit as u64 + 10));
        let got = first_error(b"a,b\n\"x,\n".chain(lines)).unwrap();
        let want = format!(
            "the record from line 2 to line {limit} is longer than {limit} bytes (is a quote left open?)"
        );
        assert_eq!(got, want);
    }

    #[test]
    fn booleans_in_any_case_and_digits() {
        for (cell, v) in [("0", false), ("1", true), ("TRUE", true), ("False", false)] {
            assert_eq!(parse_bool_cell(cell.as_bytes()), Some(v), "{cell}");
        }
        for cell in ["", "2", "yes", "01", " 1"] {
            assert_eq!(parse_bool_cell(cell.as_bytes()), None, "{cell:?}");
        }
    }
}
