//! The parser of specification files: text in, [`Property`] list or a located [`LtlError`] out.
//!
//! Each line is parsed on its own with the `line` rule of `grammar/ltl.pest`; the parse tree is
//! then turned into [`Ltl`], checking what the grammar leaves open (keywords used as names,
//! comparison operands, integer range, labels). Every error carries the file, the 1-based line
//! and column, and the source line (shown around the column: [`crate::quote`]).

use super::{default_name, CmpOp, Ltl, Property};
use crate::ecc::ident::NUSMV_LEXER_KEYWORDS;
use crate::quote::{around, quote};
use pest::iterators::Pair;
use pest::Parser;
use std::collections::BTreeMap;
use std::fmt;
use std::path::{Path, PathBuf};

#[derive(pest_derive::Parser)]
#[grammar = "grammar/ltl.pest"]
struct LineParser;

/// Why a specification file was rejected.
#[derive(Debug, thiserror::Error)]
pub enum LtlError {
    /// The specification file could not be opened or read.
    #[error("cannot read LTL specification {}", path.display())]
    Io {
        /// The specification file.
        path: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A line over the limit, or a file too large to read.
    #[error(transparent)]
    Read(crate::files::FileReadError),
    /// The file holds only comments and blank lines.
    #[error("{}: no property (the file holds only comments and blank lines)", file.display())]
    Empty {
        /// The specification file.
        file: PathBuf,
    },
    /// A problem at a place in the file. Displayed as `file:line:column: message`, then the
    /// source line (the part around the column, when it is long) and a caret under the column.
    #[error("{}:{line}:{column}: {kind}\n{}", file.display(), Pointed(source_line, *column))]
    At {
        /// The specification file.
        file: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column, in characters.
        column: usize,
        /// What is wrong there.
        kind: LtlErrorKind,
        /// The offending line, as written.
        source_line: String,
    },
}

/// What is wrong at the place an [`LtlError::At`] points to.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum LtlErrorKind {
    /// The formula does not parse, or breaks a rule of the format (the message says which).
    #[error("syntax error: {0}")]
    Syntax(String),
    /// A label that is not an identifier, or is a NuSMV keyword.
    #[error("illegal label {}: a label is an identifier [A-Za-z_][A-Za-z0-9_$#-]*, not a NuSMV keyword", quote(.0))]
    IllegalLabel(String),
    /// A label already given to an earlier property.
    #[error("duplicate label {} (first used on line {first_line})", quote(label))]
    DuplicateLabel {
        /// The repeated label.
        label: String,
        /// 1-based line where the label was first used.
        first_line: usize,
    },
    /// An explicit label equal to the default name given to an unlabelled property.
    #[error(
        "label {} is the default name of the unlabelled property on line {line}",
        quote(label)
    )]
    LabelClash {
        /// The clashing label.
        label: String,
        /// 1-based line of the unlabelled property whose default name it is.
        line: usize,
    },
}

/// A line, indented, and a caret under its 1-based character column on the next line,
/// keeping the line's tabs for alignment.
struct Pointed<'a>(&'a str, usize);

impl fmt::Display for Pointed<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (line, column) = around(self.0, self.1);
        write!(f, "  {line}\n  ")?;
        for c in line.chars().take(column.saturating_sub(1)) {
            f.write_str(if c == '\t' { "\t" } else { " " })?;
        }
        f.write_str("^")
    }
}

/// Reads and parses a specification file.
pub fn parse_spec_file(path: &Path) -> Result<Vec<Property>, LtlError> {
    use crate::files::{read_text, ReadError, MAX_LINE_BYTES};
    let text = read_text(path, Some(MAX_LINE_BYTES)).map_err(|e| match e.error {
        ReadError::Io(source) => LtlError::Io {
            path: path.to_path_buf(),
            source,
        },
        _ => LtlError::Read(e),
    })?;
    parse_spec(path, &text)
}

/// Parses the text of a specification file; `file` is only used in error messages.
pub(crate) fn parse_spec(file: &Path, text: &str) -> Result<Vec<Property>, LtlError> {
    // `lines` keeps the `\r` of a last line that has no `\n`.
    let lines: Vec<&str> = text
        .lines()
        .map(|l| l.strip_suffix('\r').unwrap_or(l))
        .collect();
    let at = |line_no: usize, offset: usize, kind: LtlErrorKind| {
        let src = lines[line_no - 1];
        LtlError::At {
            file: file.to_path_buf(),
            line: line_no,
            column: src[..offset].chars().count() + 1,
            kind,
            source_line: src.to_string(),
        }
    };
    let mut props = Vec::new();
    // Label -> (line, byte offset of the label in its line), to report duplicates and clashes.
    let mut labels: BTreeMap<String, (usize, usize)> = BTreeMap::new();
    for (i, src) in lines.iter().enumerate() {
        let line_no = i + 1;
        let parsed = parse_line(src).map_err(|(pos, kind)| at(line_no, pos, kind))?;
        let Some(parsed) = parsed else { continue };
        if let Some((label, pos)) = &parsed.label {
            if let Some(&(first_line, _)) = labels.get(label) {
                let label = label.clone();
                let kind = LtlErrorKind::DuplicateLabel { label, first_line };
                return Err(at(line_no, *pos, kind));
            }
            labels.insert(label.clone(), (line_no, *pos));
        }
        props.push(Property {
            label: parsed.label.map(|(l, _)| l),
            formula: parsed.formula,
            line: line_no,
            text: parsed.text,
        });
    }
    if props.is_empty() {
        return Err(LtlError::Empty {
            file: file.to_path_buf(),
        });
    }
    // A label may not take the default name `p{k}` of the unlabelled property at position k.
    for (index, p) in props.iter().enumerate() {
        let label = default_name(index);
        match labels.get(&label) {
            Some(&(line_no, pos)) if p.label.is_none() => {
                let kind = LtlErrorKind::LabelClash {
                    label,
                    line: p.line,
                };
                return Err(at(line_no, pos, kind));
            }
            _ => {}
        }
    }
    Ok(props)
}

/// A property read from one line, before it gets its line number.
struct ParsedLine {
    /// The label and its byte offset in the line.
    label: Option<(String, usize)>,
    formula: Ltl,
    text: String,
}

/// A problem at a byte offset of the line being parsed.
type LineError = (usize, LtlErrorKind);

fn syntax(pos: usize, msg: impl Into<String>) -> LineError {
    (pos, LtlErrorKind::Syntax(msg.into()))
}

/// The most operators and parentheses one formula may hold. The parser, the formula tree and
/// every walk over it recurse once per level; a formula beyond any real specification (a
/// thousand nested parentheses, a hundred thousand `!`) must be refused, not overflow the stack.
pub(crate) const MAX_OPERATORS: usize = 1000;

/// Refuses a line with more than [`MAX_OPERATORS`] operators and open parentheses, at the
/// place where the limit is passed.
fn check_size(src: &str) -> Result<(), LineError> {
    let code = src.split("--").next().unwrap_or("");
    let bytes = code.as_bytes();
    let ident = |b: u8| b.is_ascii_alphanumeric() || b == b'_' || b == b'$' || b == b'#';
    let mut count = 0;
    for (k, &b) in bytes.iter().enumerate() {
        let word_op = matches!(
            b,
            b'X' | b'F' | b'G' | b'Y' | b'Z' | b'O' | b'H' | b'U' | b'V' | b'S' | b'T'
        ) && (k == 0 || !ident(bytes[k - 1]))
            && bytes.get(k + 1).is_none_or(|&n| !ident(n));
        if matches!(b, b'!' | b'&' | b'|' | b'(' | b'>' | b'=' | b'<') || word_op {
            count += 1;
            if count > MAX_OPERATORS {
                return Err(syntax(
                    k,
                    format!(
                        "the formula holds more than {MAX_OPERATORS} operators and parentheses; split it into several properties"
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// Parses one line: `None` for a blank or comment line.
fn parse_line(src: &str) -> Result<Option<ParsedLine>, LineError> {
    check_size(src)?;
    let mut pairs = LineParser::parse(Rule::line, src).map_err(|e| explain(src, &e))?;
    let line = pairs.next().expect("the line rule always yields one pair");
    let Some(property) = line.into_inner().find(|p| p.as_rule() == Rule::property) else {
        return Ok(None);
    };
    let mut label = None;
    let mut formula = None;
    for p in property.into_inner() {
        match p.as_rule() {
            Rule::label => label = Some(check_label(&p)?),
            Rule::formula => formula = Some(p),
            r => unreachable!("property holds only a label and a formula, not {r:?}"),
        }
    }
    let formula = formula.expect("a property always has a formula");
    Ok(Some(ParsedLine {
        label,
        text: written(formula.as_str()).to_string(),
        formula: operand(formula)?,
    }))
}

/// The code of a span: pest's implicit whitespace leaves trailing blanks and the comment in it.
fn written(span: &str) -> &str {
    span[..span.find("--").unwrap_or(span.len())].trim_end()
}

fn check_label(p: &Pair<Rule>) -> Result<(String, usize), LineError> {
    let text = p.as_str().trim_end();
    let pos = p.as_span().start();
    if is_identifier(text) {
        Ok((text.to_string(), pos))
    } else {
        Err((pos, LtlErrorKind::IllegalLabel(text.to_string())))
    }
}

/// Whether `s` is a plain (undotted) SMV identifier that is not a keyword, and one that this
/// grammar reads back as a single name (no `->` or `--` inside).
fn is_identifier(s: &str) -> bool {
    s.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_')
        && s.chars()
            .all(|c| c.is_ascii_alphanumeric() || "_$#-".contains(c))
        && !s.contains("->")
        && !s.contains("--")
        && !is_keyword(s)
}

fn is_keyword(s: &str) -> bool {
    NUSMV_LEXER_KEYWORDS.contains(&s)
}

/// Builds a formula that stands where a Boolean formula is expected (not a bare integer).
fn operand(p: Pair<Rule>) -> Result<Ltl, LineError> {
    let pos = p.as_span().start();
    not_integer(pos, build(p)?)
}

/// Refuses a bare integer where a formula is expected, at `pos`.
fn not_integer(pos: usize, f: Ltl) -> Result<Ltl, LineError> {
    match f {
        Ltl::Int(i) => Err(syntax(
            pos,
            format!("an integer is not a formula; compare it with a name, as in `n = {i}`"),
        )),
        f => Ok(f),
    }
}

/// A level of the precedence climb: a formula of that level, or with one operand and no
/// operator, just the level below.
fn is_level(rule: Rule) -> bool {
    matches!(
        rule,
        Rule::formula
            | Rule::implies
            | Rule::iff
            | Rule::or
            | Rule::and
            | Rule::binary
            | Rule::unary
            | Rule::cmp
            | Rule::primary
    )
}

/// The node below `p` that does something: levels with one operand and no operator, and
/// parentheses, only wrap it. Found in a loop, so that nested parentheses cost no stack:
/// recursing through the nine levels of each one, the thousand the size limit lets through
/// overflowed 4 MiB of stack in a debug build. Also says whether the way down passed a
/// `unary` level, where a formula is expected and a bare integer is refused.
fn innermost(mut p: Pair<Rule>) -> (Pair<Rule>, bool) {
    let mut through_unary = false;
    loop {
        let mut inner = p.clone().into_inner();
        let next = match (p.as_rule(), inner.next(), inner.next(), inner.next()) {
            (rule, Some(only), None, _) if is_level(rule) => {
                through_unary |= p.as_rule() == Rule::unary;
                only
            }
            (Rule::primary, Some(_open), Some(formula), Some(_close)) => formula,
            _ => return (p, through_unary),
        };
        p = next;
    }
}

/// Builds the formula of a parse-tree node. A bare integer comes out as [`Ltl::Int`]; the
/// caller decides whether one is allowed there.
fn build(p: Pair<Rule>) -> Result<Ltl, LineError> {
    let (p, through_unary) = innermost(p);
    let pos = p.as_span().start();
    let f = build_level(p)?;
    match through_unary {
        true => not_integer(pos, f),
        false => Ok(f),
    }
}

/// Builds a node that is no wrapper ([`innermost`]).
fn build_level(p: Pair<Rule>) -> Result<Ltl, LineError> {
    match p.as_rule() {
        Rule::implies => implication(p),
        Rule::iff | Rule::or | Rule::and | Rule::binary => left_chain(p),
        Rule::unary => prefixed(p),
        Rule::cmp => build_cmp(p),
        Rule::constant => Ok(if p.as_str() == "TRUE" {
            Ltl::True
        } else {
            Ltl::False
        }),
        Rule::integer => integer(p),
        Rule::name => atom(p),
        r => unreachable!("no formula is built from rule {r:?}"),
    }
}

/// `a -> b -> c`, which is `a -> (b -> c)`: the chain is collected in a loop and folded from
/// the right, so that a long chain costs no stack either.
fn implication(p: Pair<Rule>) -> Result<Ltl, LineError> {
    let mut operands = Vec::new();
    let mut level = p;
    loop {
        let mut inner = level.into_inner();
        operands.push(next_operand(&mut inner)?);
        match inner.next() {
            None => break,
            Some(_op) => level = inner.next().expect("-> has a right operand"),
        }
    }
    let mut acc = operands.pop().expect("a chain has an operand");
    while let Some(left) = operands.pop() {
        acc = Ltl::Implies(Box::new(left), Box::new(acc));
    }
    Ok(acc)
}

/// A chain of binary operators of one level, folded from the left.
fn left_chain(p: Pair<Rule>) -> Result<Ltl, LineError> {
    let mut inner = p.into_inner();
    let mut acc = next_operand(&mut inner)?;
    while let Some(op) = inner.next() {
        let a = Box::new(acc);
        let b = Box::new(next_operand(&mut inner)?);
        acc = match op.as_str() {
            "<->" => Ltl::Iff(a, b),
            "|" => Ltl::Or(a, b),
            "xor" => Ltl::Xor(a, b),
            "xnor" => Ltl::Xnor(a, b),
            "&" => Ltl::And(a, b),
            "U" => Ltl::U(a, b),
            "V" => Ltl::V(a, b),
            "S" => Ltl::S(a, b),
            "T" => Ltl::T(a, b),
            other => unreachable!("binary operator {other:?}"),
        };
    }
    Ok(acc)
}

/// Prefix operators before a comparison level, the innermost last.
fn prefixed(p: Pair<Rule>) -> Result<Ltl, LineError> {
    let mut ops: Vec<Pair<Rule>> = p.into_inner().collect();
    let body = ops.pop().expect("unary ends with a comparison level");
    let mut acc = operand(body)?;
    for op in ops.iter().rev() {
        let a = Box::new(acc);
        acc = match op.as_str() {
            "!" => Ltl::Not(a),
            "X" => Ltl::X(a),
            "F" => Ltl::F(a),
            "G" => Ltl::G(a),
            "Y" => Ltl::Y(a),
            "Z" => Ltl::Z(a),
            "H" => Ltl::H(a),
            "O" => Ltl::O(a),
            other => unreachable!("prefix operator {other:?}"),
        };
    }
    Ok(acc)
}

/// An integer literal, within NuSMV's range.
fn integer(p: Pair<Rule>) -> Result<Ltl, LineError> {
    let text = p.as_str();
    // NuSMV integers are C ints; a larger one would only fail later inside NuSMV.
    match text.parse::<i64>() {
        Ok(i) if i.unsigned_abs() <= i32::MAX as u64 => Ok(Ltl::Int(i)),
        _ => Err(syntax(
            p.as_span().start(),
            format!(
                "integer {} is out of NuSMV's range (at most {})",
                crate::quote::cut(text),
                i32::MAX
            ),
        )),
    }
}

/// A (dotted) name, none of whose segments is a NuSMV keyword.
fn atom(p: Pair<Rule>) -> Result<Ltl, LineError> {
    let mut offset = p.as_span().start();
    for segment in p.as_str().split('.') {
        if is_keyword(segment) {
            return Err(syntax(
                offset,
                format!("'{segment}' is a NuSMV keyword, not a name"),
            ));
        }
        offset += segment.len() + 1;
    }
    Ok(Ltl::Atom(p.as_str().to_string()))
}

fn next_operand<'i>(inner: &mut impl Iterator<Item = Pair<'i, Rule>>) -> Result<Ltl, LineError> {
    operand(
        inner
            .next()
            .expect("an operator is followed by its operand"),
    )
}

/// A comparison level: one operand, or two atoms related by one comparison operator.
fn build_cmp(p: Pair<Rule>) -> Result<Ltl, LineError> {
    let mut inner = p.into_inner();
    let first = inner.next().expect("cmp starts with an operand");
    let Some(op) = inner.next() else {
        return build(first);
    };
    let second = inner
        .next()
        .expect("a comparison operator has a right operand");
    if let Some(extra) = inner.next() {
        return Err(syntax(
            extra.as_span().start(),
            "comparisons cannot be chained",
        ));
    }
    let op_pos = op.as_span().start();
    let op = match op.as_str() {
        "=" => CmpOp::Eq,
        "!=" => CmpOp::Ne,
        "<" => CmpOp::Lt,
        "<=" => CmpOp::Le,
        ">" => CmpOp::Gt,
        ">=" => CmpOp::Ge,
        other => unreachable!("comparison operator {other:?}"),
    };
    let mut sides = Vec::with_capacity(2);
    for side in [first, second] {
        let pos = side.as_span().start();
        let term = build(side)?;
        let ok = match term {
            Ltl::Atom(_) | Ltl::Int(_) => true,
            Ltl::True | Ltl::False => !op.is_ordering(),
            _ => false,
        };
        if !ok {
            let what = if op.is_ordering() {
                "a name or an integer"
            } else {
                "a name, an integer, TRUE or FALSE"
            };
            return Err(syntax(
                pos,
                format!("each side of '{}' must be {what}", op.symbol()),
            ));
        }
        sides.push(term);
    }
    let right = sides.pop().expect("two sides");
    let left = sides.pop().expect("two sides");
    if !matches!(left, Ltl::Atom(_)) && !matches!(right, Ltl::Atom(_)) {
        return Err(syntax(
            op_pos,
            format!(
                "'{}' compares no name: one side must be a name",
                op.symbol()
            ),
        ));
    }
    Ok(Ltl::Cmp(op, Box::new(left), Box::new(right)))
}

/// Turns a pest error into a position and a message in the user's terms.
///
/// pest reports the rules it could have matched at the failure point; here they only tell
/// whether a formula (an operand) or an operator was expected. The rest of the message comes
/// from the tokens around the failure point.
fn explain(src: &str, e: &pest::error::Error<Rule>) -> LineError {
    let mut pos = match e.location {
        pest::error::InputLocation::Pos(p) => p,
        pest::error::InputLocation::Span((s, _)) => s,
    };
    // `--` never occurs in code, so its first occurrence starts the comment; a failure found
    // after skipping the comment is reported where the comment starts.
    let code = &src[..src.find("--").unwrap_or(src.len())];
    pos = pos.min(code.len());
    let positives = match &e.variant {
        pest::error::ErrorVariant::ParsingError { positives, .. } => positives.as_slice(),
        // pest's own limits (its stack guard) are the only custom errors.
        pest::error::ErrorVariant::CustomError { message } => {
            return syntax(
                pos,
                format!(
                    "the formula nests too deeply for the parser here ({message}); split it into \
                     several properties"
                ),
            )
        }
    };
    let operand_expected = positives.iter().any(|r| {
        is_level(*r)
            || matches!(
                r,
                Rule::op_not | Rule::op_unary | Rule::name | Rule::integer | Rule::constant
            )
    });
    let (prev_pos, prev) = token_before(code, pos);
    if operand_expected {
        return syntax(pos, operand_expected_after(prev));
    }
    let found = token_at(code, pos);
    if found == ":" {
        return syntax(
            pos,
            "unexpected ':' (a label stands only at the start of a line)",
        );
    }
    // A keyword read as a name stops the parse at the token after it: blame the keyword.
    if is_keyword(prev) {
        return syntax(prev_pos, format!("'{prev}' is a NuSMV keyword, not a name"));
    }
    operator_expected(code, pos, prev, found, positives.contains(&Rule::close))
}

/// The message where an operand was expected after the token `prev`.
fn operand_expected_after(prev: &str) -> String {
    match prev {
        "" => "expected formula".to_string(),
        ":" => "expected formula after the label".to_string(),
        "=" | "!=" => format!("expected a name, an integer, TRUE or FALSE after '{prev}'"),
        "<" | "<=" | ">" | ">=" => format!("expected a name or an integer after '{prev}'"),
        _ => format!("expected formula after {}", quote(prev)),
    }
}

/// The error where an operator (or `)`, when `close_allowed`) was expected at `pos` of
/// `code`, after `prev`, and `found` stands: a missing or unmatched parenthesis named as such.
fn operator_expected(
    code: &str,
    pos: usize,
    prev: &str,
    found: &str,
    close_allowed: bool,
) -> LineError {
    match found {
        "" if close_allowed => match unclosed_paren(&code[..pos]) {
            Some(open) => syntax(
                pos,
                format!(
                    "missing ')' for the '(' at column {}",
                    code[..open].chars().count() + 1
                ),
            ),
            None => syntax(pos, "missing ')'"),
        },
        ")" if !close_allowed => syntax(pos, "unmatched ')'"),
        _ => {
            let expected = match close_allowed {
                true => "an operator or ')'",
                false => "an operator or the end of the line",
            };
            let (prev, found) = (quote(prev), quote(found));
            syntax(
                pos,
                format!("expected {expected} after {prev}, found {found}"),
            )
        }
    }
}

/// Operators and punctuation, longest first so that a prefix never shadows a longer token.
const SYMBOLS: &[&str] = &[
    "<->", "->", "!=", "<=", ">=", "=", "<", ">", "&", "|", "!", "(", ")", ":",
];

fn is_word_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || "_$#-.".contains(c)
}

/// The token starting at byte `pos` (empty at the end of the line).
fn token_at(src: &str, pos: usize) -> &str {
    let rest = &src[pos..];
    if rest.starts_with(|c: char| c.is_ascii_alphanumeric() || c == '_') {
        let end = rest.find(|c| !is_word_char(c)).unwrap_or(rest.len());
        return &rest[..end];
    }
    if let Some(sym) = SYMBOLS.iter().find(|s| rest.starts_with(*s)) {
        return sym;
    }
    rest.chars().next().map_or("", |c| &rest[..c.len_utf8()])
}

/// The last token ending before byte `pos`, and its offset (`""` at the start of the line).
fn token_before(src: &str, pos: usize) -> (usize, &str) {
    let code = src[..pos].trim_end();
    if code.ends_with(is_word_char) {
        let start = code.rfind(|c| !is_word_char(c)).map_or(0, |i| {
            i + code[i..].chars().next().map_or(1, char::len_utf8)
        });
        return (start, &code[start..]);
    }
    if let Some(sym) = SYMBOLS.iter().find(|s| code.ends_with(*s)) {
        return (code.len() - sym.len(), sym);
    }
    match code.char_indices().next_back() {
        Some((i, _)) => (i, &code[i..]),
        None => (0, ""),
    }
}

/// Byte offset of the last '(' of `code` that no ')' closes.
fn unclosed_paren(code: &str) -> Option<usize> {
    let mut open = Vec::new();
    for (i, c) in code.char_indices() {
        match c {
            '(' => open.push(i),
            ')' => {
                open.pop();
            }
            _ => {}
        }
    }
    open.pop()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<Property>, LtlError> {
        parse_spec(Path::new("specs/pnp.ltl"), text)
    }

    /// Formulas no specification needs are refused with a located error instead of
    /// overflowing the stack.
    #[test]
    fn huge_formulas_are_refused_not_a_crash() {
        let deep = format!("G {}a{}\n", "(".repeat(1000), ")".repeat(1000));
        let nots = format!("G {}a\n", "!".repeat(100_000));
        let ors = format!("G ({})\n", vec!["a"; 200_000].join(" | "));
        let nested_10k = format!("G {}a{}\n", "(".repeat(10_000), ")".repeat(10_000));
        for text in [deep, nots, ors, nested_10k] {
            let e = parse(&text).unwrap_err().to_string();
            assert!(
                e.contains("more than 1000 operators and parentheses"),
                "{}",
                &e[..200.min(e.len())]
            );
            assert!(e.starts_with("specs/pnp.ltl:1:"), "{}", &e[..60]);
        }
        // Large but reasonable formulas still parse.
        let wide = format!("G ({})\n", vec!["a"; 300].join(" | "));
        assert_eq!(parse(&wide).unwrap().len(), 1);
    }

    /// Formulas as deep as the size limit lets through are built without recursing once per
    /// parenthesis or `->`: they parse within half the stack of a test thread, even in a debug
    /// build, where 400 nested parentheses once overflowed 2 MiB. (pest's own recursion, about
    /// 2 KB per parenthesis in a debug build, stops at its stack guard: half the limit here.)
    #[test]
    fn the_deepest_accepted_formulas_fit_in_one_mebibyte_of_stack() {
        let n = MAX_OPERATORS - 1;
        let texts = [
            format!("G {}a{}\n", "(".repeat(n / 2), ")".repeat(n / 2)),
            format!("{}a\n", "!".repeat(n)),
            format!("{}a\n", "X ".repeat(n)),
            format!("{}\n", vec!["a"; n + 1].join(" -> ")),
            format!("{}\n", vec!["a"; n + 1].join(" U ")),
            format!("{}a{}\n", "(a U ".repeat(n / 2), ")".repeat(n / 2)),
            format!("{}a{}\n", "(a -> ".repeat(n / 2), ")".repeat(n / 2)),
            format!("{}a{}\n", "!(".repeat(n / 2), ")".repeat(n / 2)),
        ];
        std::thread::Builder::new()
            .stack_size(1 << 20)
            .spawn(move || {
                for text in texts {
                    let props = parse(&text)
                        .unwrap_or_else(|e| panic!("{}", crate::quote::cut(&e.to_string())));
                    assert_eq!(props.len(), 1);
                }
            })
            .unwrap()
            .join()
            .unwrap();
    }

    /// pest stops at its stack guard rather than overflow; the message says so instead of
    /// blaming a parenthesis, as it once did ("expected an operator ... found '('").
    #[test]
    fn parentheses_beyond_the_stack_are_refused_as_too_deep() {
        let text = format!("G {}a{}\n", "(".repeat(998), ")".repeat(998));
        let e = std::thread::Builder::new()
            .stack_size(128 << 10)
            .spawn(move || parse(&text).unwrap_err().to_string())
            .unwrap()
            .join()
            .unwrap();
        assert!(
            e.contains("nests too deeply for the parser here (stack limit reached)"),
            "{}",
            crate::quote::cut(&e)
        );
        assert!(
            e.starts_with("specs/pnp.ltl:1:"),
            "{}",
            crate::quote::cut(&e)
        );
    }

    fn error(text: &str) -> String {
        match parse(text) {
            Ok(p) => panic!("{text:?} parsed as {p:?}"),
            Err(e) => e.to_string(),
        }
    }

    #[test]
    fn reads_labels_comments_and_blank_lines() {
        let text = "-- Pick-and-Place safety\r\n\
                    c1_exclusive: G !(c1Extend & c1Retract)\r\n\
                    \r\n\
                    \t G (pp1 -> F vp1)   -- liveness: pp1 is served\n\
                    lbl$2 :F plant.pos=3--no space before the comment\n";
        let props = parse(text).unwrap();
        let summary: Vec<(Option<&str>, usize, &str, String)> = props
            .iter()
            .map(|p| {
                (
                    p.label.as_deref(),
                    p.line,
                    p.text.as_str(),
                    p.formula.to_string(),
                )
            })
            .collect();
        assert_eq!(
            summary,
            [
                (
                    Some("c1_exclusive"),
                    2,
                    "G !(c1Extend & c1Retract)",
                    "G !(c1Extend & c1Retract)".to_string()
                ),
                (None, 4, "G (pp1 -> F vp1)", "G (pp1 -> F vp1)".to_string()),
                (
                    Some("lbl$2"),
                    5,
                    "F plant.pos=3",
                    "F (plant.pos = 3)".to_string()
                ),
            ]
        );
    }

    #[test]
    fn a_last_line_may_end_in_a_carriage_return() {
        assert_eq!(parse("G a\r\nF b\r").unwrap()[1].text, "F b");
    }

    #[test]
    fn names_may_hold_dashes_but_not_arrows_or_comments() {
        let props = parse("a-1 & b#c$ ->x-y--z").unwrap();
        assert_eq!(props[0].formula.to_string(), "a-1 & b#c$ -> x-y");
    }

    /// Malformed lines and the exact message each gets, caret included.
    const ERRORS: &[(&str, &str)] = &[
        (
            "G a\n-- comment\nG (pp1 -> )\n",
            "specs/pnp.ltl:3:11: syntax error: expected formula after '->'\n  G (pp1 -> )\n            ^",
        ),
        (
            "G (a b)",
            "specs/pnp.ltl:1:6: syntax error: expected an operator or ')' after 'a', found 'b'\n  G (a b)\n       ^",
        ),
        (
            "\tG ((a) -- open",
            "specs/pnp.ltl:1:9: syntax error: missing ')' for the '(' at column 4\n  \tG ((a) -- open\n  \t       ^",
        ),
        (
            "G (a -> F b))",
            "specs/pnp.ltl:1:13: syntax error: unmatched ')'\n  G (a -> F b))\n              ^",
        ),
        (
            "a & -- nothing after",
            "specs/pnp.ltl:1:5: syntax error: expected formula after '&'\n  a & -- nothing after\n      ^",
        ),
        (
            "ok:",
            "specs/pnp.ltl:1:4: syntax error: expected formula after the label\n  ok:\n     ^",
        ),
        (
            "G pos =",
            "specs/pnp.ltl:1:8: syntax error: expected a name, an integer, TRUE or FALSE after '='\n  G pos =\n         ^",
        ),
        (
            "G next(a)",
            "specs/pnp.ltl:1:3: syntax error: 'next' is a NuSMV keyword, not a name\n  G next(a)\n    ^",
        ),
        (
            "G (a & plant.X)",
            "specs/pnp.ltl:1:14: syntax error: 'X' is a NuSMV keyword, not a name\n  G (a & plant.X)\n               ^",
        ),
        (
            "a = b = c",
            "specs/pnp.ltl:1:7: syntax error: comparisons cannot be chained\n  a = b = c\n        ^",
        ),
        (
            "G (F a) = b",
            "specs/pnp.ltl:1:3: syntax error: each side of '=' must be a name, an integer, TRUE or FALSE\n  G (F a) = b\n    ^",
        ),
        (
            "n < TRUE",
            "specs/pnp.ltl:1:5: syntax error: each side of '<' must be a name or an integer\n  n < TRUE\n      ^",
        ),
        (
            "G 3 = 4",
            "specs/pnp.ltl:1:5: syntax error: '=' compares no name: one side must be a name\n  G 3 = 4\n      ^",
        ),
        (
            "F 1",
            "specs/pnp.ltl:1:3: syntax error: an integer is not a formula; compare it with a name, as in `n = 1`\n  F 1\n    ^",
        ),
        (
            "n = 4294967296",
            "specs/pnp.ltl:1:5: syntax error: integer 4294967296 is out of NuSMV's range (at most 2147483647)\n  n = 4294967296\n      ^",
        ),
        (
            "a: b: c",
            "specs/pnp.ltl:1:5: syntax error: unexpected ':' (a label stands only at the start of a line)\n  a: b: c\n      ^",
        ),
        (
            "G (vac : pp1)",
            "specs/pnp.ltl:1:8: syntax error: unexpected ':' (a label stands only at the start of a line)\n  G (vac : pp1)\n         ^",
        ),
        (
            "p: G (TRUE : pp1)",
            "specs/pnp.ltl:1:12: syntax error: unexpected ':' (a label stands only at the start of a line)\n  p: G (TRUE : pp1)\n             ^",
        ),
        (
            "G a ~ b",
            "specs/pnp.ltl:1:5: syntax error: expected an operator or the end of the line after 'a', found '~'\n  G a ~ b\n      ^",
        ),
        (
            "G a\n  1st: G b",
            "specs/pnp.ltl:2:3: illegal label '1st': a label is an identifier [A-Za-z_][A-Za-z0-9_$#-]*, not a NuSMV keyword\n    1st: G b\n    ^",
        ),
        (
            "X: G b",
            "specs/pnp.ltl:1:1: illegal label 'X': a label is an identifier [A-Za-z_][A-Za-z0-9_$#-]*, not a NuSMV keyword\n  X: G b\n  ^",
        ),
        (
            "safe: G a\nlive: F b\nsafe: G c",
            "specs/pnp.ltl:3:1: duplicate label 'safe' (first used on line 1)\n  safe: G c\n  ^",
        ),
        (
            "G a\nG b\n\np2: G c",
            "specs/pnp.ltl:4:1: label 'p2' is the default name of the unlabelled property on line 2\n  p2: G c\n  ^",
        ),
        (
            "-- nothing here\n\n",
            "specs/pnp.ltl: no property (the file holds only comments and blank lines)",
        ),
        ("", "specs/pnp.ltl: no property (the file holds only comments and blank lines)"),
    ];

    #[test]
    fn errors_point_at_line_and_column() {
        for (text, message) in ERRORS {
            assert_eq!(error(text), *message, "for {text:?}");
        }
    }

    #[test]
    fn errors_carry_their_place() {
        let e = parse("G a\n  G (b &").unwrap_err();
        let LtlError::At {
            file,
            line,
            column,
            kind,
            source_line,
        } = e
        else {
            panic!("{e:?}")
        };
        assert_eq!(file, Path::new("specs/pnp.ltl"));
        assert_eq!((line, column), (2, 9));
        assert_eq!(
            kind,
            LtlErrorKind::Syntax("expected formula after '&'".into())
        );
        assert_eq!(source_line, "  G (b &");
    }

    /// A line of megabytes is shown around the column, the token cut to its start.
    #[test]
    fn giant_lines_and_tokens_are_cut_in_messages() {
        let giant = "a".repeat(1_000_000);
        let e = error(&format!("G (b {giant} & c)"));
        assert!(e.len() < 600, "{} bytes: {}", e.len(), &e[..600]);
        let expected = format!(
            "specs/pnp.ltl:1:6: syntax error: expected an operator or ')' after 'b', found '{}…' \
             (1000000 characters)\n  G (b {}…\n       ^",
            &giant[..40],
            &giant[..60]
        );
        assert_eq!(e, expected);
        // The place is at the end of the line: the caret stays under it.
        let e = error(&format!("G ({giant} & b"));
        let expected = format!(
            "specs/pnp.ltl:1:1000008: syntax error: missing ')' for the '(' at column 3\n  …{} & b\n  {}^",
            &giant[..56],
            " ".repeat(61)
        );
        assert_eq!(e, expected);
    }

    #[test]
    fn columns_count_characters_not_bytes() {
        let e = error("G (é_ok & )");
        assert!(e.starts_with("specs/pnp.ltl:1:4: "), "{e}");
    }

    #[test]
    fn unreadable_file_names_its_path() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing.ltl");
        let e = parse_spec_file(&path).unwrap_err();
        assert!(matches!(&e, LtlError::Io { path: p, .. } if *p == path));
        assert!(e.to_string().contains("missing.ltl"));
    }

    #[test]
    fn reads_a_file() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("pnp.ltl");
        std::fs::write(&path, "G (pp1 -> F vp1)\n").unwrap();
        let props = parse_spec_file(&path).unwrap();
        assert_eq!(props.len(), 1);
        assert_eq!(props[0].text, "G (pp1 -> F vp1)");
    }
}
