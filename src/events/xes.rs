//! XES (IEEE 1849-2016) output of an event log, streamed.
//!
//! In: traces and events through [`EventSink`]. Out: an XES document declaring the Concept,
//! Time and Lifecycle extensions, the globals every event carries, and two classifiers
//! (`Activity`: `concept:name`; `Activity and class`: `concept:name class`). A trace has
//! `concept:name` = its case number; an event has `concept:name` = the activity,
//! `time:timestamp`, `lifecycle:transition` = `complete` and `class` = `input` or `output`.

use super::{iso_time, Event, EventSink};
use quick_xml::escape::escape;
use std::io::{self, Write};

/// Writes XES as the traces arrive; call [`XesWriter::finish`] to close the document.
pub struct XesWriter<W: Write> {
    w: W,
}

impl<W: Write> XesWriter<W> {
    /// Writes the header; `log_name` becomes the log's `concept:name`.
    pub fn new(mut w: W, log_name: &str) -> io::Result<XesWriter<W>> {
        write!(
            w,
            r#"<?xml version="1.0" encoding="UTF-8"?>
<log xes.version="1849-2016" xes.features="" xmlns="http://www.xes-standard.org/">
  <extension name="Concept" prefix="concept" uri="http://www.xes-standard.org/concept.xesext"/>
  <extension name="Time" prefix="time" uri="http://www.xes-standard.org/time.xesext"/>
  <extension name="Lifecycle" prefix="lifecycle" uri="http://www.xes-standard.org/lifecycle.xesext"/>
  <global scope="trace">
    <string key="concept:name" value="__INVALID__"/>
  </global>
  <global scope="event">
    <string key="concept:name" value="__INVALID__"/>
    <date key="time:timestamp" value="1970-01-01T00:00:00.000+00:00"/>
    <string key="lifecycle:transition" value="complete"/>
    <string key="class" value="input"/>
  </global>
  <classifier name="Activity" keys="concept:name"/>
  <classifier name="Activity and class" keys="concept:name class"/>
  <string key="concept:name" value="{}"/>
"#,
            escape(log_name)
        )?;
        Ok(XesWriter { w })
    }

    /// Closes the document and returns the writer.
    pub fn finish(mut self) -> io::Result<W> {
        writeln!(self.w, "</log>")?;
        Ok(self.w)
    }
}

impl<W: Write> EventSink for XesWriter<W> {
    fn begin_trace(&mut self, case: usize) -> io::Result<()> {
        writeln!(
            self.w,
            "  <trace>\n    <string key=\"concept:name\" value=\"{case}\"/>"
        )
    }

    fn event(&mut self, e: &Event) -> io::Result<()> {
        writeln!(
            self.w,
            "    <event>\n      <string key=\"concept:name\" value=\"{}\"/>\n      <date key=\"time:timestamp\" value=\"{}\"/>\n      <string key=\"lifecycle:transition\" value=\"complete\"/>\n      <string key=\"class\" value=\"{}\"/>\n    </event>",
            escape(e.activity().as_str()),
            iso_time(e.time),
            e.class.label()
        )
    }

    fn end_trace(&mut self) -> io::Result<()> {
        writeln!(self.w, "  </trace>")
    }
}

/// Test helper: checks that `xml` is well-formed with quick-xml and returns, in document
/// order, every element name with its unescaped attributes.
#[cfg(test)]
pub(crate) fn elements(xml: &str) -> Vec<(String, Vec<(String, String)>)> {
    use quick_xml::events::Event as X;
    let mut reader = quick_xml::Reader::from_str(xml);
    let mut open: Vec<String> = Vec::new();
    let mut out = Vec::new();
    let attrs = |e: &quick_xml::events::BytesStart<'_>| -> Vec<(String, String)> {
        e.attributes()
            .map(|a| {
                let a = a.expect("well-formed attribute");
                (
                    String::from_utf8(a.key.as_ref().to_vec()).unwrap(),
                    a.unescape_value().expect("escaped value").into_owned(),
                )
            })
            .collect()
    };
    loop {
        match reader.read_event().expect("well-formed XML") {
            X::Start(e) => {
                let name = String::from_utf8(e.name().as_ref().to_vec()).unwrap();
                out.push((name.clone(), attrs(&e)));
                open.push(name);
            }
            X::Empty(e) => {
                let name = String::from_utf8(e.name().as_ref().to_vec()).unwrap();
                out.push((name, attrs(&e)));
            }
            X::End(e) => {
                let name = String::from_utf8(e.name().as_ref().to_vec()).unwrap();
                assert_eq!(open.pop().as_deref(), Some(name.as_str()), "balanced tags");
            }
            X::Eof => break,
            _ => {}
        }
    }
    assert!(open.is_empty(), "unclosed elements: {open:?}");
    out
}
