//! Parser of guard text (grammar: `grammar/guard.pest`), the inverse of
//! [`Guard::display`](crate::ecc::Guard::display).
//!
//! In: text such as `c1Home & !(vac | go)` and the ordered input names of the ECC. Out: a
//! [`Guard`] over [`InputId`]s, or a [`GuardTextError`] with the 1-based column (in characters)
//! where the text goes wrong. Syntax: input names, `TRUE`, `FALSE`, `!`, `&`, `|` and
//! parentheses; `!` binds tighter than `&`, which binds tighter than `|`. Chains such as
//! `a & b & c` become one n-ary node, parentheses keep their own node, so the text of any
//! guard `display` prints parses back to the same tree.

use crate::ecc::{Guard, InputId};
use pest::iterators::Pair;
use pest::Parser;

// The parser and its `Rule` enum stay private: the grammar is an implementation detail of
// `parse_guard`, whose errors are `GuardTextError`.
mod parser {
    #[derive(pest_derive::Parser)]
    #[grammar = "../grammar/guard.pest"]
    pub(super) struct GuardParser;
}
use parser::{GuardParser, Rule};

/// Deepest nesting of parentheses, and longest run of `!`, a guard may have. Far beyond any
/// guard a person writes or synthesis produces; it keeps hostile input from exhausting the
/// stack of the recursive parser and of the recursive [`Guard`] functions.
pub(crate) const MAX_DEPTH: usize = 100;

/// Why guard text could not be parsed; `column` is 1-based, in characters.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum GuardTextError {
    /// Not a guard: `expected` lists what could stand at `column` (an operand, `&`, ...).
    #[error("column {column}: expected {expected}")]
    Syntax {
        /// Where the text stops being a guard.
        column: usize,
        /// What could stand there, in words.
        expected: String,
    },
    /// A name that is none of the machine's inputs.
    #[error("column {column}: unknown input {}", crate::quote::backquote(name))]
    UnknownInput {
        /// Where the name starts.
        column: usize,
        /// The name as written.
        name: String,
    },
    /// Parentheses or `!` nested deeper than [`MAX_DEPTH`].
    #[error("column {column}: the guard nests deeper than {MAX_DEPTH} levels")]
    TooDeep {
        /// Where the nesting passes the limit.
        column: usize,
    },
}

impl GuardTextError {
    /// The 1-based column the error points at.
    pub fn column(&self) -> usize {
        match self {
            GuardTextError::Syntax { column, .. }
            | GuardTextError::UnknownInput { column, .. }
            | GuardTextError::TooDeep { column } => *column,
        }
    }
}

/// Parses guard text over the given input names (see the module header for the syntax).
pub fn parse_guard(text: &str, inputs: &[String]) -> Result<Guard, GuardTextError> {
    check_depth(text)?;
    let mut pairs = GuardParser::parse(Rule::guard, text).map_err(syntax_error)?;
    let guard = pairs.next().expect("the guard rule yields one pair");
    let or_expr = guard
        .into_inner()
        .next()
        .expect("guard starts with or_expr");
    build(or_expr, inputs)
}

fn check_depth(text: &str) -> Result<(), GuardTextError> {
    let (mut parens, mut nots) = (0usize, 0usize);
    for (k, c) in text.chars().enumerate() {
        match c {
            '(' => parens += 1,
            ')' => parens = parens.saturating_sub(1),
            _ => {}
        }
        match c {
            '!' => nots += 1,
            ' ' | '\t' => {}
            _ => nots = 0,
        }
        if parens > MAX_DEPTH || nots > MAX_DEPTH {
            return Err(GuardTextError::TooDeep { column: k + 1 });
        }
    }
    Ok(())
}

fn syntax_error(e: pest::error::Error<Rule>) -> GuardTextError {
    let column = match e.line_col {
        pest::error::LineColLocation::Pos((_, c)) => c,
        pest::error::LineColLocation::Span((_, c), _) => c,
    };
    let positives = match &e.variant {
        pest::error::ErrorVariant::ParsingError { positives, .. } => positives.clone(),
        pest::error::ErrorVariant::CustomError { .. } => Vec::new(),
    };
    // Ranked so the message reads the same whatever order pest found the alternatives in.
    let mut wanted: Vec<(u8, &str)> = Vec::new();
    for r in positives {
        let what = match r {
            Rule::guard | Rule::or_expr | Rule::and_expr | Rule::unary => (0, "an operand"),
            Rule::name => (1, "an input name"),
            Rule::true_lit => (2, "`TRUE`"),
            Rule::false_lit => (3, "`FALSE`"),
            Rule::not_op => (4, "`!`"),
            Rule::lparen => (5, "`(`"),
            Rule::or_op => (6, "`|`"),
            Rule::and_op => (7, "`&`"),
            Rule::rparen => (8, "`)`"),
            Rule::EOI => (9, "the end of the guard"),
            // Silent or inner rules pest never reports as expected.
            Rule::WHITESPACE | Rule::primary | Rule::constant | Rule::name_char => continue,
        };
        if !wanted.contains(&what) {
            wanted.push(what);
        }
    }
    wanted.sort();
    let wanted: Vec<&str> = wanted.into_iter().map(|(_, w)| w).collect();
    let expected = match wanted.split_last() {
        None => "a guard".to_string(),
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    };
    GuardTextError::Syntax { column, expected }
}

fn build(pair: Pair<'_, Rule>, inputs: &[String]) -> Result<Guard, GuardTextError> {
    match pair.as_rule() {
        Rule::or_expr | Rule::and_expr => {
            let is_or = pair.as_rule() == Rule::or_expr;
            let mut parts = pair
                .into_inner()
                .filter(|p| !matches!(p.as_rule(), Rule::or_op | Rule::and_op))
                .map(|p| build(p, inputs))
                .collect::<Result<Vec<_>, _>>()?;
            Ok(match (parts.len(), is_or) {
                (1, _) => parts.pop().expect("one part"),
                (_, true) => Guard::Or(parts),
                (_, false) => Guard::And(parts),
            })
        }
        Rule::unary => {
            let mut nots = 0;
            let mut operand = None;
            for p in pair.into_inner() {
                match p.as_rule() {
                    Rule::not_op => nots += 1,
                    Rule::lparen | Rule::rparen => {}
                    _ => operand = Some(build(p, inputs)?),
                }
            }
            let mut g = operand.expect("unary ends with an operand");
            for _ in 0..nots {
                g = Guard::Not(Box::new(g));
            }
            Ok(g)
        }
        Rule::true_lit => Ok(Guard::True),
        Rule::false_lit => Ok(Guard::False),
        Rule::name => {
            let name = pair.as_str();
            match inputs.iter().position(|n| n == name) {
                Some(i) => Ok(Guard::Var(InputId(i))),
                None => Err(GuardTextError::UnknownInput {
                    column: pair.as_span().start_pos().line_col().1,
                    name: name.to_string(),
                }),
            }
        }
        r => unreachable!("rule {r:?} does not occur below or_expr"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn names(n: usize) -> Vec<String> {
        ["a", "b", "c", "d"][..n]
            .iter()
            .map(|s| s.to_string())
            .collect()
    }

    fn v(i: usize) -> Guard {
        Guard::Var(InputId(i))
    }

    fn not(g: Guard) -> Guard {
        Guard::Not(Box::new(g))
    }

    #[test]
    fn precedence_not_and_or() {
        let g = parse_guard("!a & b | c & !!d", &names(4)).unwrap();
        assert_eq!(
            g,
            Guard::Or(vec![
                Guard::And(vec![not(v(0)), v(1)]),
                Guard::And(vec![v(2), not(not(v(3)))]),
            ])
        );
        let g = parse_guard(" !( a|b )&TRUE ", &names(2)).unwrap();
        assert_eq!(
            g,
            Guard::And(vec![not(Guard::Or(vec![v(0), v(1)])), Guard::True])
        );
        assert_eq!(parse_guard("FALSE", &[]).unwrap(), Guard::False);
    }

    #[test]
    fn keywords_need_a_word_boundary() {
        let inputs = vec!["TRUEish".to_string()];
        assert_eq!(parse_guard("TRUEish", &inputs).unwrap(), v(0));
    }

    #[test]
    fn unknown_input_has_its_column() {
        let e = parse_guard("a & !vac", &names(2)).unwrap_err();
        assert_eq!(
            e,
            GuardTextError::UnknownInput {
                column: 6,
                name: "vac".into()
            }
        );
        assert_eq!(e.to_string(), "column 6: unknown input `vac`");
    }

    #[test]
    fn syntax_errors_have_column_and_expectation() {
        let e = parse_guard("a & (b | c", &names(3)).unwrap_err();
        assert_eq!(e.column(), 11);
        assert!(e.to_string().contains("`)`"), "{e}");
        let e = parse_guard("a b", &names(2)).unwrap_err();
        assert_eq!(e.column(), 3);
        assert_eq!(
            e.to_string(),
            "column 3: expected `|`, `&` or the end of the guard"
        );
        let e = parse_guard("", &names(1)).unwrap_err();
        assert_eq!(e.column(), 1);
        let e = parse_guard("a && b", &names(2)).unwrap_err();
        assert_eq!(e.column(), 4);
        let e = parse_guard("a & é", &names(1)).unwrap_err();
        assert_eq!(e.column(), 5);
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_crash() {
        let deep = format!("{}a{}", "(".repeat(10_000), ")".repeat(10_000));
        let e = parse_guard(&deep, &names(1)).unwrap_err();
        assert_eq!(e, GuardTextError::TooDeep { column: 101 });
        let nots = format!("{}a", "! ".repeat(200));
        assert!(matches!(
            parse_guard(&nots, &names(1)),
            Err(GuardTextError::TooDeep { .. })
        ));
        let ok = format!("{}a{}", "(".repeat(MAX_DEPTH), ")".repeat(MAX_DEPTH));
        assert_eq!(parse_guard(&ok, &names(1)).unwrap(), v(0));
    }

    /// Guards over `n` inputs without degenerate nodes (`And`/`Or` have 2 to 4 parts).
    fn guard(n: usize) -> impl Strategy<Value = Guard> {
        let leaf = prop_oneof![
            Just(Guard::True),
            Just(Guard::False),
            (0..n).prop_map(|i| Guard::Var(InputId(i))),
        ];
        leaf.prop_recursive(4, 24, 4, |inner| {
            prop_oneof![
                inner.clone().prop_map(|g| Guard::Not(Box::new(g))),
                prop::collection::vec(inner.clone(), 2..=4).prop_map(Guard::And),
                prop::collection::vec(inner, 2..=4).prop_map(Guard::Or),
            ]
        })
    }

    fn guard_and_width() -> impl Strategy<Value = (Guard, usize)> {
        (1usize..=4).prop_flat_map(|n| (guard(n), Just(n)))
    }

    proptest! {
        #[test]
        fn display_then_parse_round_trips((g, n) in guard_and_width()) {
            let names = names(n);
            let text = g.display(&names).to_string();
            let back = parse_guard(&text, &names)
                .map_err(|e| TestCaseError::fail(format!("{text}: {e}")))?;
            for bits in 0..(1u32 << n) {
                let x: Vec<bool> = (0..n).map(|i| bits >> i & 1 == 1).collect();
                prop_assert_eq!(g.eval(&x), back.eval(&x), "{} on {:?}", text, x);
            }
            prop_assert_eq!(back, g, "{}", text);
        }
    }
}
