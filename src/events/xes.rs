//! XES (IEEE 1849-2016) output of an event log, streamed.
//!
//! In: traces and events through [`EventSink`]. Out: an XES document declaring the Concept,
//! Time and Lifecycle extensions, the globals every event carries, and two classifiers
//! (`Activity`: `concept:name`; `Activity_and_class`: `concept:name class`). As the IEEE 1849
//! schema types them, `xes.version` is the decimal `1849.2016` and classifier names are XML
//! NCNames (no spaces). A trace has `concept:name` = its case number; an event has
//! `concept:name` = the activity, `time:timestamp`, `lifecycle:transition` = `complete` and
//! `class` = `input` or `output`.

use super::{iso_time, Event, EventSink};
use crate::files::xml::XmlWriter;
use std::io::{self, Write};

/// Writes XES as the traces arrive; call [`XesWriter::finish`] to close the document.
pub(crate) struct XesWriter<W: Write> {
    x: XmlWriter<W>,
}

/// The extensions the log declares: name, prefix, definition.
const EXTENSIONS: [(&str, &str, &str); 3] = [
    (
        "Concept",
        "concept",
        "http://www.xes-standard.org/concept.xesext",
    ),
    ("Time", "time", "http://www.xes-standard.org/time.xesext"),
    (
        "Lifecycle",
        "lifecycle",
        "http://www.xes-standard.org/lifecycle.xesext",
    ),
];

impl<W: Write> XesWriter<W> {
    /// Writes the header; `log_name` becomes the log's `concept:name`.
    pub(crate) fn new(w: W, log_name: &str) -> io::Result<XesWriter<W>> {
        let mut x = XmlWriter::new(w);
        x.declaration()?;
        x.open(
            0,
            "log",
            &[
                ("xes.version", "1849.2016"),
                ("xes.features", ""),
                ("xmlns", "http://www.xes-standard.org/"),
            ],
        )?;
        for (name, prefix, uri) in EXTENSIONS {
            x.leaf(
                1,
                "extension",
                &[("name", name), ("prefix", prefix), ("uri", uri)],
            )?;
        }
        x.open(1, "global", &[("scope", "trace")])?;
        attribute(&mut x, 2, "string", "concept:name", "__INVALID__")?;
        x.close(1, "global")?;
        x.open(1, "global", &[("scope", "event")])?;
        attribute(&mut x, 2, "string", "concept:name", "__INVALID__")?;
        attribute(
            &mut x,
            2,
            "date",
            "time:timestamp",
            "1970-01-01T00:00:00.000+00:00",
        )?;
        attribute(&mut x, 2, "string", "lifecycle:transition", "complete")?;
        attribute(&mut x, 2, "string", "class", "input")?;
        x.close(1, "global")?;
        for (name, keys) in [
            ("Activity", "concept:name"),
            ("Activity_and_class", "concept:name class"),
        ] {
            x.leaf(1, "classifier", &[("name", name), ("keys", keys)])?;
        }
        attribute(&mut x, 1, "string", "concept:name", log_name)?;
        Ok(XesWriter { x })
    }

    /// Closes the document and returns the writer.
    pub(crate) fn finish(mut self) -> io::Result<W> {
        self.x.close(0, "log")?;
        Ok(self.x.into_inner())
    }
}

/// One XES attribute line: `<kind key=".." value=".."/>`.
fn attribute<W: Write>(
    x: &mut XmlWriter<W>,
    depth: usize,
    kind: &str,
    key: &str,
    value: &str,
) -> io::Result<()> {
    x.leaf(depth, kind, &[("key", key), ("value", value)])
}

impl<W: Write> EventSink for XesWriter<W> {
    fn begin_trace(&mut self, case: usize) -> io::Result<()> {
        self.x.open(1, "trace", &[])?;
        attribute(&mut self.x, 2, "string", "concept:name", &case.to_string())
    }

    fn event(&mut self, e: &Event) -> io::Result<()> {
        let x = &mut self.x;
        x.open(2, "event", &[])?;
        attribute(x, 3, "string", "concept:name", &e.activity())?;
        attribute(x, 3, "date", "time:timestamp", &iso_time(e.time))?;
        attribute(x, 3, "string", "lifecycle:transition", "complete")?;
        attribute(x, 3, "string", "class", e.class.label())?;
        x.close(2, "event")
    }

    fn end_trace(&mut self) -> io::Result<()> {
        self.x.close(1, "trace")
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
