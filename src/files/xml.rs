//! XML as the exporters write it (`.fbt`, PNML, XES): quick-xml's [`Writer`] with one escaping
//! rule, and the layout of the files (one element a line, indented by two spaces a level)
//! kept by hand so that the output stays the same byte for byte.
//!
//! In: elements, attributes and text, in document order. Out: well-formed XML on a
//! [`Write`]. Attribute values are double-quoted; `&`, `<`, `>`, `"` and the line breaks and
//! tabs (which a parser would turn into spaces) are escaped ([`escape_attr`]); text escapes
//! `&`, `<` and `>`.

use quick_xml::events::attributes::Attribute;
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, BytesText, Event};
use quick_xml::name::QName;
use quick_xml::Writer;
use std::borrow::Cow;
use std::io::{self, Write};

/// Escapes text for a double-quoted XML attribute. Line breaks and tabs become character
/// references, because a parser normalizes literal ones in attributes to spaces.
pub(crate) fn escape_attr(value: &str) -> Cow<'_, str> {
    let escaped = quick_xml::escape::partial_escape(value);
    if !escaped.contains(['"', '\n', '\r', '\t']) {
        return escaped;
    }
    let mut out = String::with_capacity(escaped.len() + 16);
    for c in escaped.chars() {
        match c {
            '"' => out.push_str("&quot;"),
            '\n' => out.push_str("&#10;"),
            '\r' => out.push_str("&#13;"),
            '\t' => out.push_str("&#9;"),
            c => out.push(c),
        }
    }
    Cow::Owned(out)
}

/// A document being written; see the module header.
pub(crate) struct XmlWriter<W: Write> {
    w: Writer<W>,
}

impl<W: Write> XmlWriter<W> {
    /// Starts a document on `w` (nothing is written yet).
    pub(crate) fn new(w: W) -> XmlWriter<W> {
        XmlWriter { w: Writer::new(w) }
    }

    /// The underlying writer, after the document.
    pub(crate) fn into_inner(self) -> W {
        self.w.into_inner()
    }

    /// `<?xml version="1.0" encoding="UTF-8"?>` and a line break.
    pub(crate) fn declaration(&mut self) -> io::Result<()> {
        let decl = BytesDecl::new("1.0", Some("UTF-8"), None);
        self.w.write_event(Event::Decl(decl))?;
        self.newline()
    }

    /// `<!DOCTYPE text>` and a line break; `text` is written as it is.
    pub(crate) fn doctype(&mut self, text: &str) -> io::Result<()> {
        self.w
            .write_event(Event::DocType(BytesText::from_escaped(text)))?;
        self.newline()
    }

    /// A start tag with its attributes.
    pub(crate) fn start(&mut self, name: &str, attrs: &[(&str, &str)]) -> io::Result<()> {
        self.w.write_event(Event::Start(tag(name, attrs)))
    }

    /// An empty element `<name .../>`.
    pub(crate) fn empty(&mut self, name: &str, attrs: &[(&str, &str)]) -> io::Result<()> {
        self.w.write_event(Event::Empty(tag(name, attrs)))
    }

    /// An end tag.
    pub(crate) fn end(&mut self, name: &str) -> io::Result<()> {
        self.w.write_event(Event::End(BytesEnd::new(name)))
    }

    /// Escaped text.
    pub(crate) fn text(&mut self, text: &str) -> io::Result<()> {
        let escaped = quick_xml::escape::partial_escape(text);
        self.w
            .write_event(Event::Text(BytesText::from_escaped(escaped)))
    }

    /// `<name>text</name>` on the current line.
    pub(crate) fn text_element(&mut self, name: &str, text: &str) -> io::Result<()> {
        self.start(name, &[])?;
        self.text(text)?;
        self.end(name)
    }

    /// The indentation of a line at `depth` (two spaces a level).
    pub(crate) fn indent(&mut self, depth: usize) -> io::Result<()> {
        self.layout(&"  ".repeat(depth))
    }

    /// A line break.
    pub(crate) fn newline(&mut self) -> io::Result<()> {
        self.layout("\n")
    }

    /// A line at `depth` holding a start tag.
    pub(crate) fn open(
        &mut self,
        depth: usize,
        name: &str,
        attrs: &[(&str, &str)],
    ) -> io::Result<()> {
        self.indent(depth)?;
        self.start(name, attrs)?;
        self.newline()
    }

    /// A line at `depth` holding an empty element.
    pub(crate) fn leaf(
        &mut self,
        depth: usize,
        name: &str,
        attrs: &[(&str, &str)],
    ) -> io::Result<()> {
        self.indent(depth)?;
        self.empty(name, attrs)?;
        self.newline()
    }

    /// A line at `depth` holding an end tag.
    pub(crate) fn close(&mut self, depth: usize, name: &str) -> io::Result<()> {
        self.indent(depth)?;
        self.end(name)?;
        self.newline()
    }

    /// Whitespace between elements, which needs no escaping.
    fn layout(&mut self, blank: &str) -> io::Result<()> {
        self.w
            .write_event(Event::Text(BytesText::from_escaped(blank)))
    }
}

/// A start tag with attributes escaped by [`escape_attr`] (quick-xml's own escaping would
/// leave line breaks to be normalized away).
fn tag<'a>(name: &'a str, attrs: &[(&str, &str)]) -> BytesStart<'a> {
    let mut tag = BytesStart::new(name);
    for (key, value) in attrs {
        tag.push_attribute(Attribute {
            key: QName(key.as_bytes()),
            value: Cow::Owned(escape_attr(value).into_owned().into_bytes()),
        });
    }
    tag
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attributes_and_text_are_escaped_once() {
        assert_eq!(
            escape_attr("a<b & \"c\"\n'"),
            "a&lt;b &amp; &quot;c&quot;&#10;'"
        );
        let mut x = XmlWriter::new(Vec::new());
        x.declaration().unwrap();
        x.open(0, "a", &[("k", "1 < 2")]).unwrap();
        x.indent(1).unwrap();
        x.text_element("t", "x & y").unwrap();
        x.newline().unwrap();
        x.leaf(1, "e", &[("v", "\"q\"")]).unwrap();
        x.close(0, "a").unwrap();
        assert_eq!(
            String::from_utf8(x.into_inner()).unwrap(),
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<a k=\"1 &lt; 2\">\n  <t>x &amp; y</t>\n  <e v=\"&quot;q&quot;\"/>\n</a>\n"
        );
    }
}
