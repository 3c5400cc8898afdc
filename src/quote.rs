//! User input quoted in messages: short text whole, long text cut.
//!
//! In: a token, name, cell or line taken from a file the user gave. Out: something to put in
//! an error message ([`quote`], [`backquote`], [`cut`], [`message`] for another library's
//! message, and [`around`] for a line with a caret under a column), never much longer than a
//! line of a terminal. A file may hold one 50 MB token,
//! and a message that echoed it whole would write 50 MB to stderr; every message that shows
//! user input goes through here, so none can.

use std::fmt;

/// Text of at most this many characters is shown whole.
pub(crate) const WHOLE: usize = 60;

/// Longer text shows this many characters, then `…` and its length.
pub(crate) const SHOWN: usize = 40;

/// A message of another library is shown whole up to this many characters.
pub(crate) const MESSAGE: usize = 300;

/// Text as a message shows it; see [`quote`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct Quoted<'a> {
    text: &'a str,
    mark: &'static str,
    whole: usize,
    shown: usize,
}

/// `'text'`, or for text longer than [`WHOLE`] characters its first [`SHOWN`] ones:
/// `'abc…' (123456 characters)`.
pub(crate) fn quote(text: &str) -> Quoted<'_> {
    Quoted {
        text,
        mark: "'",
        whole: WHOLE,
        shown: SHOWN,
    }
}

/// Like [`quote`], between backquotes: `` `text` ``.
pub(crate) fn backquote(text: &str) -> Quoted<'_> {
    Quoted {
        mark: "`",
        ..quote(text)
    }
}

/// Like [`quote`], without quotes: for text that a message shows as it is (a number, a list).
pub(crate) fn cut(text: &str) -> Quoted<'_> {
    Quoted {
        mark: "",
        ..quote(text)
    }
}

/// A whole message of another library (serde, pest), which may quote the input it choked on
/// whatever its length: up to [`MESSAGE`] characters whole, else cut like [`cut`].
pub(crate) fn message(text: &str) -> Quoted<'_> {
    Quoted {
        text,
        mark: "",
        whole: MESSAGE,
        shown: MESSAGE,
    }
}

/// The byte offset of the `n`th character of `text`, or its length when it is shorter.
fn offset_of_char(text: &str, n: usize) -> usize {
    text.char_indices().nth(n).map_or(text.len(), |(i, _)| i)
}

/// Whether `c` would act on a terminal instead of showing: C0 and C1 controls and DEL, but
/// not the line break and tab that other tools' messages hold.
fn acts_on_terminal(c: char) -> bool {
    c.is_control() && c != '\n' && c != '\t'
}

/// Writes `text` with every control character as its Rust escape (`\u{1b}`): a file or
/// another program could otherwise move the cursor, recolour or retitle the terminal, or
/// clear the screen the message is on.
fn write_visible(f: &mut fmt::Formatter<'_>, text: &str) -> fmt::Result {
    let mut rest = text;
    while let Some(at) = rest.find(acts_on_terminal) {
        let c = rest[at..].chars().next().expect("found at a char boundary");
        write!(f, "{}{}", &rest[..at], c.escape_unicode())?;
        rest = &rest[at + c.len_utf8()..];
    }
    f.write_str(rest)
}

impl fmt::Display for Quoted<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let m = self.mark;
        if self.text.char_indices().nth(self.whole).is_none() {
            f.write_str(m)?;
            write_visible(f, self.text)?;
            return f.write_str(m);
        }
        let shown = &self.text[..offset_of_char(self.text, self.shown)];
        let n = self.text.chars().count();
        f.write_str(m)?;
        write_visible(f, shown)?;
        write!(f, "…{m} ({n} characters)")
    }
}

/// A path as a line of output shows it: whole, with every control character escaped, line
/// breaks and tabs included (a name holding a line break would otherwise print as two
/// lines, the second one of its choosing).
pub(crate) fn path(path: &std::path::Path) -> String {
    let text = path.to_string_lossy();
    let mut shown = String::with_capacity(text.len());
    for c in text.chars() {
        match c.is_control() {
            true => shown.extend(c.escape_default()),
            false => shown.push(c),
        }
    }
    shown
}

/// A line as an error message shows it under the place it points to: the whole line when it
/// has at most 2 × [`WHOLE`] characters, otherwise [`WHOLE`] characters on each side of the
/// 1-based character `column`, with `…` where the line goes on. Returns the text and the
/// column in it.
pub(crate) fn around(line: &str, column: usize) -> (String, usize) {
    // One character for one keeps the caret under its column.
    let visible: String = line
        .chars()
        .map(|c| if acts_on_terminal(c) { '\u{FFFD}' } else { c })
        .collect();
    let line = visible.as_str();
    let len = line.chars().count();
    if len <= 2 * WHOLE {
        return (line.to_string(), column);
    }
    let at = column.saturating_sub(1).min(len);
    let first = at.saturating_sub(WHOLE);
    let last = (at + WHOLE).min(len);
    let (start, end) = (offset_of_char(line, first), offset_of_char(line, last));
    let mut shown = String::new();
    let mut column = at - first + 1;
    if first > 0 {
        shown.push('…');
        column += 1;
    }
    shown.push_str(&line[start..end]);
    if last < len {
        shown.push('…');
    }
    (shown, column)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_text_is_shown_whole_and_long_text_cut_with_its_length() {
        assert_eq!(quote("REQ01").to_string(), "'REQ01'");
        assert_eq!(backquote("a_b").to_string(), "`a_b`");
        let edge = "é".repeat(WHOLE);
        assert_eq!(quote(&edge).to_string(), format!("'{edge}'"));
        let long = "é".repeat(WHOLE + 1);
        assert_eq!(
            quote(&long).to_string(),
            format!("'{}…' ({} characters)", "é".repeat(SHOWN), WHOLE + 1)
        );
        assert_eq!(
            cut(&"x".repeat(1_000_000)).to_string(),
            format!("{}… (1000000 characters)", "x".repeat(SHOWN))
        );
    }

    #[test]
    fn control_characters_are_shown_not_sent_to_the_terminal() {
        assert_eq!(
            message("\u{1b}[31mred\u{7}\tok\n").to_string(),
            "\\u{1b}[31mred\\u{7}\tok\n"
        );
        assert_eq!(quote("a\u{9b}b").to_string(), "'a\\u{9b}b'");
        let long = format!("\u{1b}{}", "x".repeat(100));
        assert!(quote(&long).to_string().starts_with("'\\u{1b}xxx"));
        assert_eq!(around("a\u{1b}b", 3), ("a\u{FFFD}b".to_string(), 3));
    }

    #[test]
    fn a_long_line_is_shown_around_its_column() {
        assert_eq!(around("G (a b)", 6), ("G (a b)".to_string(), 6));
        let line = format!("G ({} b)", "a".repeat(10_000));
        let column = 10_005;
        let (shown, at) = around(&line, column);
        assert_eq!(shown.chars().nth(at - 1), Some('b'));
        assert!(shown.starts_with('…') && shown.ends_with("a b)"), "{shown}");
        assert!(shown.chars().count() <= 2 * WHOLE + 2);
        let (shown, at) = around(&line, 1);
        assert_eq!((at, shown.chars().next()), (1, Some('G')));
        assert!(shown.ends_with('…'));
    }
}
