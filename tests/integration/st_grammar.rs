//! A checker of Structured Text against the grammar of IEC 61131-3 (2nd edition, annex B),
//! for the subset the exports use: one `FUNCTION_BLOCK` with `VAR_INPUT`, `VAR_OUTPUT` and
//! `VAR` blocks of `name : type [:= constant];`, and a body of assignments, `IF`/`ELSIF`/
//! `ELSE` and `CASE` statements over Boolean expressions (`OR`, `XOR`, `AND`/`&`, one unary
//! `NOT` or `-` before a primary, parentheses, `TRUE`/`FALSE`, integers). It refuses what an
//! IEC compiler such as matiec refuses there: `NOT NOT x` (no expression after the first
//! `NOT`) and reserved words used as names. Written from the standard's productions; the
//! exports' ST goes through it in `iec.rs`.

/// Reserved words a name may not be (ignoring case): the keywords of the subset and of the
/// languages around it, the elementary and generic types, and the standard functions and
/// function blocks (tables of IEC 61131-3's standard functions and function blocks).
#[rustfmt::skip]
const RESERVED: &[&str] = &[
    // Keywords.
    "ACTION", "ARRAY", "AT", "BY", "CASE", "CONFIGURATION", "CONSTANT", "DO", "ELSE", "ELSIF",
    "EN", "ENO", "END_ACTION", "END_CASE", "END_CONFIGURATION", "END_FOR", "END_FUNCTION",
    "END_FUNCTION_BLOCK", "END_IF", "END_PROGRAM", "END_REPEAT", "END_RESOURCE", "END_STEP",
    "END_STRUCT", "END_TRANSITION", "END_TYPE", "END_VAR", "END_WHILE", "EXIT", "FALSE",
    "F_EDGE", "FOR", "FROM", "FUNCTION", "FUNCTION_BLOCK", "IF", "INITIAL_STEP", "INTERVAL",
    "NON_RETAIN", "OF", "ON", "PRIORITY", "PROGRAM", "READ_ONLY", "READ_WRITE", "REPEAT",
    "RESOURCE", "RETAIN", "RETURN", "R_EDGE", "SINGLE", "STEP", "STRUCT", "TASK", "THEN", "TO",
    "TRANSITION", "TRUE", "TYPE", "UNTIL", "VAR", "VAR_ACCESS", "VAR_CONFIG", "VAR_EXTERNAL",
    "VAR_GLOBAL", "VAR_INPUT", "VAR_IN_OUT", "VAR_OUTPUT", "VAR_TEMP", "WHILE", "WITH",
    // Elementary and generic data types.
    "BOOL", "SINT", "INT", "DINT", "LINT", "USINT", "UINT", "UDINT", "ULINT", "REAL", "LREAL",
    "TIME", "DATE", "TIME_OF_DAY", "TOD", "DATE_AND_TIME", "DT", "STRING", "WSTRING", "BYTE",
    "WORD", "DWORD", "LWORD", "ANY", "ANY_DERIVED", "ANY_ELEMENTARY", "ANY_MAGNITUDE", "ANY_NUM",
    "ANY_REAL", "ANY_INT", "ANY_BIT", "ANY_STRING", "ANY_DATE",
    // Standard functions.
    "ABS", "SQRT", "LN", "LOG", "EXP", "SIN", "COS", "TAN", "ASIN", "ACOS", "ATAN", "ADD", "MUL",
    "SUB", "DIV", "MOD", "EXPT", "MOVE", "SHL", "SHR", "ROR", "ROL", "AND", "OR", "XOR", "NOT",
    "SEL", "MAX", "MIN", "LIMIT", "MUX", "GT", "GE", "EQ", "LE", "LT", "NE", "LEN", "LEFT",
    "RIGHT", "MID", "CONCAT", "INSERT", "DELETE", "REPLACE", "FIND", "TRUNC",
    // Standard function blocks.
    "SR", "RS", "R_TRIG", "F_TRIG", "CTU", "CTD", "CTUD", "TP", "TON", "TOF", "RTC",
];

/// The elementary types a conversion function converts between (`INT_TO_BOOL`, ...).
#[rustfmt::skip]
const CONVERTIBLE: &[&str] = &[
    "BOOL", "SINT", "INT", "DINT", "LINT", "USINT", "UINT", "UDINT", "ULINT", "REAL", "LREAL",
    "TIME", "DATE", "TIME_OF_DAY", "TOD", "DATE_AND_TIME", "DT", "STRING", "WSTRING", "BYTE",
    "WORD", "DWORD", "LWORD", "BCD",
];

#[derive(Debug, Clone, PartialEq)]
enum Token {
    /// An identifier or keyword, as written.
    Word(String),
    Int(String),
    Symbol(&'static str),
}

/// Splits the text into tokens, skipping white space and `(* comments *)`.
fn tokens(text: &str) -> Result<Vec<(usize, Token)>, String> {
    let chars: Vec<char> = text.chars().collect();
    let (mut out, mut k, mut line) = (Vec::new(), 0, 1);
    while k < chars.len() {
        let c = chars[k];
        if c == '\n' {
            line += 1;
        }
        if c.is_whitespace() {
            k += 1;
        } else if c == '(' && chars.get(k + 1) == Some(&'*') {
            let rest: String = chars[k + 2..].iter().collect();
            let end = rest
                .find("*)")
                .ok_or(format!("line {line}: unclosed comment"))?;
            line += rest[..end].matches('\n').count();
            k += 2 + rest[..end].chars().count() + 2;
        } else if c.is_ascii_alphabetic() || c == '_' {
            let start = k;
            while k < chars.len() && (chars[k].is_ascii_alphanumeric() || chars[k] == '_') {
                k += 1;
            }
            out.push((line, Token::Word(chars[start..k].iter().collect())));
        } else if c.is_ascii_digit() {
            let start = k;
            while k < chars.len() && chars[k].is_ascii_digit() {
                k += 1;
            }
            out.push((line, Token::Int(chars[start..k].iter().collect())));
        } else {
            let two: String = chars[k..(k + 2).min(chars.len())].iter().collect();
            let symbol = match (two.as_str(), c) {
                (":=", _) => ":=",
                (_, ':') => ":",
                (_, ';') => ";",
                (_, ',') => ",",
                (_, '(') => "(",
                (_, ')') => ")",
                (_, '&') => "&",
                (_, '-') => "-",
                _ => return Err(format!("line {line}: unexpected `{c}`")),
            };
            k += symbol.len();
            out.push((line, Token::Symbol(symbol)));
        }
    }
    Ok(out)
}

/// Whether `word` is a reserved word (ignoring case), a type conversion function included.
fn reserved(word: &str) -> bool {
    let upper = word.to_ascii_uppercase();
    RESERVED.contains(&upper.as_str())
        || upper
            .split_once("_TO_")
            .is_some_and(|(a, b)| CONVERTIBLE.contains(&a) && CONVERTIBLE.contains(&b))
}

struct Parser {
    tokens: Vec<(usize, Token)>,
    at: usize,
}

impl Parser {
    fn line(&self) -> usize {
        self.tokens
            .get(self.at)
            .or(self.tokens.last())
            .map_or(0, |t| t.0)
    }

    fn fail<T>(&self, what: &str) -> Result<T, String> {
        let found = match self.tokens.get(self.at) {
            Some((_, t)) => format!("{t:?}"),
            None => "the end".into(),
        };
        Err(format!(
            "line {}: expected {what}, found {found}",
            self.line()
        ))
    }

    /// Is the next token the keyword (ignoring case) or symbol `s`?
    fn peek(&self, s: &str) -> bool {
        match self.tokens.get(self.at) {
            Some((_, Token::Word(w))) => w.eq_ignore_ascii_case(s),
            Some((_, Token::Symbol(t))) => *t == s,
            _ => false,
        }
    }

    fn eat(&mut self, s: &str) -> bool {
        let found = self.peek(s);
        self.at += found as usize;
        found
    }

    fn expect(&mut self, s: &str) -> Result<(), String> {
        match self.eat(s) {
            true => Ok(()),
            false => self.fail(&format!("`{s}`")),
        }
    }

    /// identifier ::= (letter | '_' (letter | digit)) {['_'] (letter | digit)}, no keyword.
    fn identifier(&mut self) -> Result<String, String> {
        let Some((_, Token::Word(w))) = self.tokens.get(self.at).cloned() else {
            return self.fail("an identifier");
        };
        if w.contains("__") || w.ends_with('_') {
            return self.fail("an identifier without `__` or a trailing `_`");
        }
        if reserved(&w) {
            return self.fail(&format!("an identifier, not the reserved word `{w}`"));
        }
        self.at += 1;
        Ok(w)
    }

    /// function_block_declaration ::= 'FUNCTION_BLOCK' name {var blocks} body
    /// 'END_FUNCTION_BLOCK'
    fn function_block(&mut self) -> Result<(), String> {
        self.expect("FUNCTION_BLOCK")?;
        self.identifier()?;
        while ["VAR_INPUT", "VAR_OUTPUT", "VAR"]
            .iter()
            .any(|k| self.peek(k))
        {
            self.at += 1;
            while !self.eat("END_VAR") {
                self.var_declaration()?;
            }
        }
        self.statements(&["END_FUNCTION_BLOCK"])?;
        self.expect("END_FUNCTION_BLOCK")?;
        match self.at == self.tokens.len() {
            true => Ok(()),
            false => self.fail("the end"),
        }
    }

    /// var_decl ::= identifier {',' identifier} ':' type ([':=' constant]) ';'
    fn var_declaration(&mut self) -> Result<(), String> {
        self.identifier()?;
        while self.eat(",") {
            self.identifier()?;
        }
        self.expect(":")?;
        if !["BOOL", "INT"].iter().any(|t| self.eat(t)) {
            return self.fail("an elementary type");
        }
        if self.eat(":=") {
            self.constant()?;
        }
        self.expect(";")
    }

    /// constant ::= ['-'] integer | 'TRUE' | 'FALSE'
    fn constant(&mut self) -> Result<(), String> {
        self.eat("-");
        if let Some((_, Token::Int(_))) = self.tokens.get(self.at) {
            self.at += 1;
            return Ok(());
        }
        match self.eat("TRUE") || self.eat("FALSE") {
            true => Ok(()),
            false => self.fail("a constant"),
        }
    }

    /// statement_list ::= {statement ';'}, up to one of the keywords in `end`.
    fn statements(&mut self, end: &[&str]) -> Result<(), String> {
        while !end.iter().any(|e| self.peek(e)) {
            self.statement()?;
        }
        Ok(())
    }

    /// 'IF' expr 'THEN' stmts {'ELSIF' expr 'THEN' stmts} ['ELSE' stmts] 'END_IF'
    fn if_statement(&mut self) -> Result<(), String> {
        loop {
            self.expression()?;
            self.expect("THEN")?;
            self.statements(&["ELSIF", "ELSE", "END_IF"])?;
            if !self.eat("ELSIF") {
                break;
            }
        }
        if self.eat("ELSE") {
            self.statements(&["END_IF"])?;
        }
        self.expect("END_IF")
    }

    /// 'CASE' expr 'OF' {int {',' int} ':' stmts} ['ELSE' stmts] 'END_CASE'
    fn case_statement(&mut self) -> Result<(), String> {
        self.expression()?;
        self.expect("OF")?;
        while let Some((_, Token::Int(_))) = self.tokens.get(self.at) {
            self.at += 1;
            while self.eat(",") {
                self.constant()?;
            }
            self.expect(":")?;
            // A case element's statements end where the next label (an integer) starts.
            let label = |p: &Parser| matches!(p.tokens.get(p.at), Some((_, Token::Int(_))));
            while !(self.peek("ELSE") || self.peek("END_CASE") || label(self)) {
                self.statement()?;
            }
        }
        if self.eat("ELSE") {
            self.statements(&["END_CASE"])?;
        }
        self.expect("END_CASE")
    }

    /// statement ';' with statement ::= assignment | if_statement | case_statement
    fn statement(&mut self) -> Result<(), String> {
        if self.eat("IF") {
            self.if_statement()?;
        } else if self.eat("CASE") {
            self.case_statement()?;
        } else {
            self.identifier()?;
            self.expect(":=")?;
            self.expression()?;
        }
        self.expect(";")
    }

    /// expression ::= xor_expression {'OR' xor_expression}
    fn expression(&mut self) -> Result<(), String> {
        self.xor_expression()?;
        while self.eat("OR") {
            self.xor_expression()?;
        }
        Ok(())
    }

    /// xor_expression ::= and_expression {'XOR' and_expression}
    fn xor_expression(&mut self) -> Result<(), String> {
        self.and_expression()?;
        while self.eat("XOR") {
            self.and_expression()?;
        }
        Ok(())
    }

    /// and_expression ::= unary_expression {('&' | 'AND') unary_expression} (the comparison
    /// and arithmetic levels between them are not used by the exports).
    fn and_expression(&mut self) -> Result<(), String> {
        self.unary_expression()?;
        while self.eat("&") || self.eat("AND") {
            self.unary_expression()?;
        }
        Ok(())
    }

    /// unary_expression ::= [unary_operator] primary_expression: one operator at most.
    fn unary_expression(&mut self) -> Result<(), String> {
        let _ = self.eat("NOT") || self.eat("-");
        self.primary_expression()
    }

    /// primary_expression ::= constant | variable | '(' expression ')'
    fn primary_expression(&mut self) -> Result<(), String> {
        if self.eat("(") {
            self.expression()?;
            return self.expect(")");
        }
        if self.eat("TRUE") || self.eat("FALSE") {
            return Ok(());
        }
        if let Some((_, Token::Int(_))) = self.tokens.get(self.at) {
            self.at += 1;
            return Ok(());
        }
        self.identifier().map(|_| ())
    }
}

/// Checks one Structured Text `FUNCTION_BLOCK` against the grammar: `Err` gives the line and
/// what was expected there.
pub fn check(text: &str) -> Result<(), String> {
    let mut parser = Parser {
        tokens: tokens(text)?,
        at: 0,
    };
    parser.function_block()
}

#[test]
fn the_checker_refuses_what_the_standard_refuses() {
    let block = |decl: &str, body: &str| {
        format!(
            "FUNCTION_BLOCK Fb\nVAR_INPUT\n    REQ : BOOL;\n    {decl} : BOOL;\nEND_VAR\n\
             VAR_OUTPUT\n    z : BOOL := FALSE;\nEND_VAR\nVAR\n    state : INT := 0; (* c *)\n\
             END_VAR\n{body}\nEND_FUNCTION_BLOCK\n"
        )
    };
    let ok = "IF REQ THEN\n CASE state OF\n 0: IF NOT (a AND NOT z) OR a & z THEN state := 1; \
              z := NOT z; ELSIF a THEN z := TRUE; END_IF;\n 1: z := a;\n END_CASE;\nEND_IF;";
    assert_eq!(check(&block("a", ok)), Ok(()));
    for (decl, body, why) in [
        ("a", "z := NOT NOT a;", "expected an identifier"),
        (
            "a",
            "IF NOT NOT a THEN z := TRUE; END_IF;",
            "expected an identifier",
        ),
        ("TON", "z := TON;", "reserved word `TON`"),
        ("r_trig", "z := TRUE;", "reserved word `r_trig`"),
        ("Int_To_Bool", "z := TRUE;", "reserved word `Int_To_Bool`"),
        ("end_if", "z := TRUE;", "reserved word `end_if`"),
        ("a__b", "z := TRUE;", "`__`"),
        ("a", "z := a AND;", "expected an identifier"),
        (
            "a",
            "IF a THEN z := TRUE; END_CASE;",
            "reserved word `END_CASE`",
        ),
        (
            "a",
            "IF a THEN z := TRUE;",
            "reserved word `END_FUNCTION_BLOCK`",
        ),
        ("a", "z := (a;", "`)`"),
    ] {
        let e = check(&block(decl, body)).unwrap_err();
        assert!(e.contains(why), "{decl} / {body}: {e}");
    }
}
