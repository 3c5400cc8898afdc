//! Flat CSV output of an event log, streamed: `case_id,activity,timestamp,class`, one row per
//! event in log order, timestamps as in XES. Cells holding `,`, `"` or a line break are quoted.

use super::{iso_time, Event, EventSink};
use crate::files::csv::quote_cell as cell;
use std::io::{self, Write};

/// Writes CSV rows as the events arrive.
pub(crate) struct CsvWriter<W: Write> {
    w: W,
    case: usize,
}

impl<W: Write> CsvWriter<W> {
    /// Writes the header row.
    pub(crate) fn new(mut w: W) -> io::Result<CsvWriter<W>> {
        writeln!(w, "case_id,activity,timestamp,class")?;
        Ok(CsvWriter { w, case: 0 })
    }

    /// Returns the writer.
    pub(crate) fn finish(self) -> W {
        self.w
    }
}

impl<W: Write> EventSink for CsvWriter<W> {
    fn begin_trace(&mut self, case: usize) -> io::Result<()> {
        self.case = case;
        Ok(())
    }

    fn event(&mut self, e: &Event) -> io::Result<()> {
        writeln!(
            self.w,
            "{},{},{},{}",
            self.case,
            cell(&e.activity()),
            iso_time(e.time),
            e.class.label()
        )
    }

    fn end_trace(&mut self) -> io::Result<()> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::cell;

    #[test]
    fn cells_with_separators_are_quoted() {
        assert_eq!(cell("%IX0.1 true"), "%IX0.1 true");
        assert_eq!(cell("a,b"), "\"a,b\"");
        assert_eq!(cell("say \"hi\""), "\"say \"\"hi\"\"\"");
    }
}
