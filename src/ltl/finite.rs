//! Three-valued evaluation of a formula on a finite prefix of a run: what a recording already
//! decides, whatever comes after it.
//!
//! In: a formula and, for every name it reads, a column of values over the positions
//! `0..len` of a prefix, each value known or not. Out: per position a [`Truth`]: `True`
//! (`False`) when the formula holds (fails) there on *every* infinite run that starts with the
//! prefix, for every choice of the unknown values; `Unknown` otherwise.
//!
//! The semantics is NuSMV's, on infinite runs: a prefix never makes `F p` false (`p` may come
//! later) nor `G p` true (it may fail later), while `G p` is false as soon as `p` is false at
//! one position and `G (a -> X b)` as soon as `a` holds at some `t < len - 1` and `b` fails at
//! `t + 1`. A `False` here is therefore a violation of every continuation, the only verdict a
//! caller may report as certain.
//!
//! # Method
//! Kleene's strong three-valued logic for the Boolean operators (`Unknown & False` is
//! `False`). Every position at or after `len` is summarized by one *tail* value, sound for all
//! of them at once: with every name unknown there, a formula without names and past operators
//! has one value everywhere (`G TRUE`, `F FALSE`), and anything else is `Unknown` (past
//! operators too: their value after the prefix depends on it, and `Unknown` is always sound).
//! The future operators are then evaluated backward from the tail by their expansion laws,
//! `a U b = b | a & X (a U b)` and `a V b = b & (a | X (a V b))` (`F`, `G` as special cases),
//! and the past operators forward from position 0 as on a lasso ([`super::lasso`]). The laws
//! hold on every infinite run and Kleene's operators are monotone in information, so a value
//! computed from sound values is sound.
//!
//! Comparisons are evaluated only as equalities of Boolean names, `TRUE` and `FALSE`; anything
//! else (integers, symbolic constants, orderings) makes the formula [`NotEvaluable`].

use super::{CmpOp, Ltl};

/// A truth value decided by a prefix, or not.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Truth {
    /// Holds on every continuation.
    True,
    /// Fails on every continuation.
    False,
    /// Depends on the continuation or on an unknown value.
    Unknown,
}

impl Truth {
    fn of(b: bool) -> Truth {
        if b {
            Truth::True
        } else {
            Truth::False
        }
    }

    fn not(self) -> Truth {
        match self {
            Truth::True => Truth::False,
            Truth::False => Truth::True,
            Truth::Unknown => Truth::Unknown,
        }
    }

    fn and(self, other: Truth) -> Truth {
        match (self, other) {
            (Truth::False, _) | (_, Truth::False) => Truth::False,
            (Truth::True, Truth::True) => Truth::True,
            _ => Truth::Unknown,
        }
    }

    fn or(self, other: Truth) -> Truth {
        self.not().and(other.not()).not()
    }

    fn iff(self, other: Truth) -> Truth {
        match (self, other) {
            (Truth::Unknown, _) | (_, Truth::Unknown) => Truth::Unknown,
            (a, b) => Truth::of(a == b),
        }
    }
}

/// Why a formula cannot be evaluated on recorded Boolean values.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub(crate) enum NotEvaluable {
    /// A name with no recorded column (a name of the plant, for instance).
    #[error("{} is not recorded", crate::quote::quote(.0))]
    Name(String),
    /// A comparison other than an equality of Boolean names and constants.
    #[error("the comparison {} is not over recorded Boolean values", crate::quote::quote(.0))]
    Comparison(String),
    /// An [`Ltl::Int`] outside a comparison (the parser never builds one).
    #[error("integer {0} used as a formula")]
    IntAsFormula(i64),
}

/// The values of one subformula: at every position of the prefix, and after it.
struct Values {
    at: Vec<Truth>,
    tail: Truth,
}

impl Ltl {
    /// The formula's [`Truth`] at every position `0..len` of a prefix. `column(name)` gives
    /// the values of a name the formula reads (`None` at a position where it is unknown);
    /// positions past the end of a column are unknown, and a name without a column makes the
    /// formula [`NotEvaluable`].
    pub(crate) fn truth_on_prefix<'c>(
        &self,
        len: usize,
        column: &dyn Fn(&str) -> Option<&'c [Option<bool>]>,
    ) -> Result<Vec<Truth>, NotEvaluable> {
        Ok(self.finite_values(len, column)?.at)
    }

    fn finite_values<'c>(
        &self,
        len: usize,
        column: &dyn Fn(&str) -> Option<&'c [Option<bool>]>,
    ) -> Result<Values, NotEvaluable> {
        use Ltl::*;
        let eval = |f: &Ltl| f.finite_values(len, column);
        let pointwise = |a: &Ltl, b: &Ltl, op: fn(Truth, Truth) -> Truth| {
            let (a, b) = (eval(a)?, eval(b)?);
            Ok::<_, NotEvaluable>(Values {
                at: a.at.iter().zip(&b.at).map(|(&x, &y)| op(x, y)).collect(),
                tail: op(a.tail, b.tail),
            })
        };
        let constant = |t: Truth| Values {
            at: vec![t; len],
            tail: t,
        };
        Ok(match self {
            True => constant(Truth::True),
            False => constant(Truth::False),
            Int(i) => return Err(NotEvaluable::IntAsFormula(*i)),
            Atom(name) => Values {
                at: recorded(name, len, column)?,
                tail: Truth::Unknown,
            },
            Cmp(op, l, r) => match (op, l.as_ref(), r.as_ref()) {
                (CmpOp::Eq, l, r) if is_boolean(l) && is_boolean(r) => pointwise(l, r, Truth::iff)?,
                (CmpOp::Ne, l, r) if is_boolean(l) && is_boolean(r) => {
                    negate(pointwise(l, r, Truth::iff)?)
                }
                _ => return Err(NotEvaluable::Comparison(self.to_string())),
            },
            Not(a) => negate(eval(a)?),
            And(a, b) => pointwise(a, b, Truth::and)?,
            Or(a, b) => pointwise(a, b, Truth::or)?,
            Xor(a, b) => pointwise(a, b, |x, y| x.iff(y).not())?,
            Xnor(a, b) | Iff(a, b) => pointwise(a, b, Truth::iff)?,
            Implies(a, b) => pointwise(a, b, |x, y| x.not().or(y))?,
            X(a) => one_ahead(len, eval(a)?),
            F(a) => until(&constant(Truth::True), &eval(a)?),
            G(a) => release(&constant(Truth::False), &eval(a)?),
            U(a, b) => until(&eval(a)?, &eval(b)?),
            V(a, b) => release(&eval(a)?, &eval(b)?),
            Y(a) => one_back(eval(a)?, Truth::False),
            Z(a) => one_back(eval(a)?, Truth::True),
            H(a) => triggered(len, &constant(Truth::False), &eval(a)?),
            O(a) => since(len, &constant(Truth::True), &eval(a)?),
            S(a, b) => since(len, &eval(a)?, &eval(b)?),
            T(a, b) => triggered(len, &eval(a)?, &eval(b)?),
        })
    }
}

/// Whether a comparison operand is Boolean here: a name (its column decides) or a constant.
fn is_boolean(f: &Ltl) -> bool {
    matches!(f, Ltl::Atom(_) | Ltl::True | Ltl::False)
}

fn recorded<'c>(
    name: &str,
    len: usize,
    column: &dyn Fn(&str) -> Option<&'c [Option<bool>]>,
) -> Result<Vec<Truth>, NotEvaluable> {
    let values = column(name).ok_or_else(|| NotEvaluable::Name(name.to_string()))?;
    Ok((0..len)
        .map(|i| match values.get(i) {
            Some(Some(b)) => Truth::of(*b),
            _ => Truth::Unknown,
        })
        .collect())
}

fn negate(v: Values) -> Values {
    Values {
        at: v.at.into_iter().map(Truth::not).collect(),
        tail: v.tail.not(),
    }
}

/// `a U b`, backward from the tail: `v(i) = b(i) | a(i) & v(i+1)`. After the prefix it is
/// decided only where `b` is (always true, or never).
fn until(a: &Values, b: &Values) -> Values {
    backward(b.tail, a, b, |a, b, next| b.or(a.and(next)))
}

/// `a V b`, backward from the tail: `v(i) = b(i) & (a(i) | v(i+1))`. After the prefix it is
/// decided only where `b` is.
fn release(a: &Values, b: &Values) -> Values {
    backward(b.tail, a, b, |a, b, next| b.and(a.or(next)))
}

fn backward(tail: Truth, a: &Values, b: &Values, step: fn(Truth, Truth, Truth) -> Truth) -> Values {
    let mut at = vec![Truth::Unknown; a.at.len()];
    let mut next = tail;
    for i in (0..at.len()).rev() {
        next = step(a.at[i], b.at[i], next);
        at[i] = next;
    }
    Values { at, tail }
}

/// A past operator, forward from position 0: `v(i) = step(v(i-1), i)`, `v(-1)` being `None`.
/// After the prefix it depends on the prefix, so the tail is unknown.
fn past(len: usize, step: impl Fn(Option<Truth>, usize) -> Truth) -> Values {
    let mut at: Vec<Truth> = Vec::with_capacity(len);
    for i in 0..len {
        let prev = i.checked_sub(1).map(|j| at[j]);
        at.push(step(prev, i));
    }
    Values {
        at,
        tail: Truth::Unknown,
    }
}

/// `a S b`, forward: `v(i) = b(i) | a(i) & v(i-1)`, false before position 0 (`O b` is
/// `TRUE S b`).
fn since(len: usize, a: &Values, b: &Values) -> Values {
    past(len, |prev, i| {
        b.at[i].or(a.at[i].and(prev.unwrap_or(Truth::False)))
    })
}

/// `a T b`, forward: `v(i) = b(i) & (a(i) | v(i-1))`, true before position 0 (`H b` is
/// `FALSE T b`).
fn triggered(len: usize, a: &Values, b: &Values) -> Values {
    past(len, |prev, i| {
        b.at[i].and(a.at[i].or(prev.unwrap_or(Truth::True)))
    })
}

/// `X a`: position `i` is `a` at `i + 1`, the tail's past the prefix.
fn one_ahead(len: usize, a: Values) -> Values {
    let at = (0..len)
        .map(|i| a.at.get(i + 1).copied().unwrap_or(a.tail))
        .collect();
    Values { at, tail: a.tail }
}

/// `Y a` (`at_start` false) and `Z a` (`at_start` true).
fn one_back(a: Values, at_start: Truth) -> Values {
    let at = (0..a.at.len())
        .map(|i| i.checked_sub(1).map_or(at_start, |j| a.at[j]))
        .collect();
    Values {
        at,
        tail: Truth::Unknown,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::collections::BTreeMap;
    use std::path::Path;

    fn parse(text: &str) -> Ltl {
        crate::ltl::parse_spec(Path::new("t.ltl"), text)
            .unwrap()
            .remove(0)
            .formula
    }

    /// `text` on the prefix given as columns `a`, `b` (`1`, `0`, `?` per position).
    fn truth(text: &str, a: &str, b: &str) -> Vec<Truth> {
        let col = |s: &str| -> Vec<Option<bool>> {
            s.chars()
                .map(|c| match c {
                    '1' => Some(true),
                    '0' => Some(false),
                    _ => None,
                })
                .collect()
        };
        let (a, b) = (col(a), col(b));
        let len = a.len().max(b.len());
        parse(text)
            .truth_on_prefix(len, &|n| match n {
                "a" => Some(&a[..]),
                "b" => Some(&b[..]),
                _ => None,
            })
            .unwrap()
    }

    fn at0(text: &str, a: &str, b: &str) -> Truth {
        truth(text, a, b)[0]
    }

    use Truth::{False as F, True as T, Unknown as U};

    #[test]
    fn safety_fails_definitely_liveness_never() {
        assert_eq!(at0("G a", "1101", ""), F);
        assert_eq!(at0("G a", "1111", ""), U);
        assert_eq!(at0("G a", "11?1", ""), U);
        assert_eq!(at0("F a", "0000", ""), U);
        assert_eq!(at0("F a", "0010", ""), T);
        assert_eq!(at0("G F a", "0000", ""), U);
        assert_eq!(at0("F G a", "0000", ""), U);
        // An `a` at the last position wants its `b` after the prefix: not decided.
        assert_eq!(at0("G (a -> X b)", "0001", "0000"), U);
        assert_eq!(at0("G (a -> X b)", "0010", "0000"), F);
        assert_eq!(at0("G (a -> X b)", "0010", "0001"), U);
        // Until: `a` fails before `b` came.
        assert_eq!(at0("a U b", "110", "000"), F);
        assert_eq!(at0("a U b", "111", "000"), U);
        assert_eq!(at0("a U b", "110", "001"), T);
        assert_eq!(at0("a V b", "000", "110"), F);
        assert_eq!(at0("a V b", "010", "110"), T);
        // Constants after the prefix are still constants.
        assert_eq!(at0("G TRUE", "0", ""), T);
        assert_eq!(at0("F FALSE", "0", ""), F);
        assert_eq!(at0("X X X FALSE", "0", ""), F);
    }

    #[test]
    fn kleene_connectives_decide_what_they_can() {
        assert_eq!(truth("a & b", "?0?1", "0?11"), vec![F, F, U, T]);
        assert_eq!(truth("a | b", "?0?1", "1?01"), vec![T, U, U, T]);
        assert_eq!(truth("a -> b", "0?1", "?1?"), vec![T, T, U]);
        assert_eq!(truth("a xor b", "01?", "00?"), vec![F, T, U]);
        assert_eq!(truth("a = b", "01", "00"), vec![T, F]);
        assert_eq!(truth("a != TRUE", "01", ""), vec![T, F]);
    }

    #[test]
    fn past_operators_read_the_prefix() {
        assert_eq!(truth("Y a", "10", ""), vec![F, T]);
        assert_eq!(truth("Z a", "00", ""), vec![T, F]);
        assert_eq!(truth("O a", "0100", ""), vec![F, T, T, T]);
        assert_eq!(truth("H a", "1101", ""), vec![T, T, F, F]);
        assert_eq!(truth("a S b", "0110", "1000"), vec![T, T, T, F]);
        assert_eq!(truth("a T b", "0010", "1011"), vec![T, F, T, T]);
        // After the prefix a past operator is unknown: `X Y a` at the last position is `a`
        // there, but the evaluation only claims what it can prove.
        assert_eq!(truth("G (X Y a)", "11", ""), vec![U, U]);
    }

    #[test]
    fn unrecorded_names_and_integer_comparisons_are_not_evaluable() {
        let f = parse("G (a -> F vp1)");
        assert_eq!(
            f.truth_on_prefix(1, &|n| (n == "a").then_some(&[Some(true)][..])),
            Err(NotEvaluable::Name("vp1".into()))
        );
        let f = parse("G (pos = 3)");
        assert!(matches!(
            f.truth_on_prefix(1, &|_| Some(&[Some(true)][..])),
            Err(NotEvaluable::Comparison(_))
        ));
    }

    proptest! {
        /// Soundness: a decided value is the value on every lasso that extends the prefix
        /// (the unknown values of the prefix filled in arbitrarily).
        #[test]
        fn decided_values_hold_on_every_extension(
            f in crate::ltl::arb::formula(false),
            prefix in proptest::collection::vec((0u8..3, 0u8..3), 0..5),
            extension in proptest::collection::vec((any::<bool>(), any::<bool>()), 1..6),
            fill in proptest::collection::vec((any::<bool>(), any::<bool>()), 5),
            loop_start in 0usize..6,
        ) {
            let known = |v: u8| match v { 0 => Some(false), 1 => Some(true), _ => None };
            let a: Vec<Option<bool>> = prefix.iter().map(|p| known(p.0)).collect();
            let b: Vec<Option<bool>> = prefix.iter().map(|p| known(p.1)).collect();
            let len = prefix.len();
            let truths = f
                .truth_on_prefix(len, &|n| match n {
                    "a" => Some(&a[..]),
                    "b" => Some(&b[..]),
                    _ => None,
                })
                .unwrap();
            let mut states: Vec<BTreeMap<String, String>> = Vec::new();
            for (i, (x, y)) in a.iter().zip(&b).enumerate() {
                let x = x.unwrap_or(fill[i].0);
                let y = y.unwrap_or(fill[i].1);
                states.push(state(x, y));
            }
            for &(x, y) in &extension {
                states.push(state(x, y));
            }
            let loop_start = len + loop_start % extension.len();
            for (i, t) in truths.iter().enumerate() {
                if *t == Truth::Unknown {
                    continue;
                }
                // The value at position i of the run is the value at 0 of its suffix from i;
                // past operators need the whole run, so shift the formula with X instead.
                let shifted = (0..i).fold(f.clone(), |g, _| Ltl::X(Box::new(g)));
                let holds = shifted.holds_on_lasso(&states, loop_start).unwrap();
                prop_assert_eq!(holds, *t == Truth::True, "position {} of {:?}", i, states);
            }
        }
    }

    fn state(a: bool, b: bool) -> BTreeMap<String, String> {
        let v = |x: bool| if x { "TRUE" } else { "FALSE" }.to_string();
        BTreeMap::from([("a".to_string(), v(a)), ("b".to_string(), v(b))])
    }
}
