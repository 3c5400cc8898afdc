//! Transition guards: Boolean formulas over the inputs of an ECC.
//!
//! Guards are kept as a small AST over [`InputId`]s. Displaying needs the input names, so
//! [`Guard::display`] takes them; the text form is the one of the JSON contract:
//! input names, `!`, `&`, `|`, parentheses and `TRUE` / `FALSE`.

use super::InputId;
use std::fmt;

/// A Boolean formula over the inputs.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Guard {
    /// Always true (`TRUE`).
    True,
    /// Never true (`FALSE`).
    False,
    /// True when this input is 1.
    Var(InputId),
    /// Negation (`!`).
    Not(Box<Guard>),
    /// Conjunction (`&`); true when empty.
    And(Vec<Guard>),
    /// Disjunction (`|`); false when empty.
    Or(Vec<Guard>),
}

/// One literal of a conjunction: input and required value.
pub(crate) type Literal = (InputId, bool);

impl Guard {
    /// Evaluate on an input vector.
    pub(crate) fn eval(&self, x: &[bool]) -> bool {
        match self {
            Guard::True => true,
            Guard::False => false,
            Guard::Var(i) => x[i.0],
            Guard::Not(g) => !g.eval(x),
            Guard::And(gs) => gs.iter().all(|g| g.eval(x)),
            Guard::Or(gs) => gs.iter().any(|g| g.eval(x)),
        }
    }

    /// A conjunction of literals; the empty conjunction is `TRUE`.
    pub(crate) fn cube(lits: &[Literal]) -> Guard {
        let mut parts: Vec<Guard> = lits
            .iter()
            .map(|&(i, v)| {
                if v {
                    Guard::Var(i)
                } else {
                    Guard::Not(Box::new(Guard::Var(i)))
                }
            })
            .collect();
        match parts.len() {
            0 => Guard::True,
            1 => parts.pop().unwrap(),
            _ => Guard::And(parts),
        }
    }

    /// A disjunction of cubes (sum of products); the empty disjunction is `FALSE`.
    pub(crate) fn dnf(cubes: &[Vec<Literal>]) -> Guard {
        let mut parts: Vec<Guard> = cubes.iter().map(|c| Guard::cube(c)).collect();
        if parts.contains(&Guard::True) {
            return Guard::True;
        }
        match parts.len() {
            0 => Guard::False,
            1 => parts.pop().unwrap(),
            _ => Guard::Or(parts),
        }
    }

    /// The literals of a conjunction of literals (`TRUE` is the empty one); `None` for any other
    /// guard. The inverse of [`Guard::cube`].
    pub(crate) fn as_cube(&self) -> Option<Vec<Literal>> {
        fn literal(g: &Guard) -> Option<Literal> {
            match g {
                Guard::Var(v) => Some((*v, true)),
                Guard::Not(inner) => match inner.as_ref() {
                    Guard::Var(v) => Some((*v, false)),
                    _ => None,
                },
                _ => None,
            }
        }
        match self {
            Guard::True => Some(vec![]),
            Guard::And(parts) => parts.iter().map(literal).collect(),
            other => Some(vec![literal(other)?]),
        }
    }

    /// The cubes of a disjunction of conjunctions of literals (`FALSE` is the empty one);
    /// `None` for any other guard. The inverse of [`Guard::dnf`].
    pub(crate) fn as_dnf(&self) -> Option<Vec<Vec<Literal>>> {
        match self {
            Guard::False => Some(vec![]),
            Guard::Or(parts) => parts.iter().map(Guard::as_cube).collect(),
            other => Some(vec![other.as_cube()?]),
        }
    }

    /// The negation of `g` without a double negation: `!!h` is `h`, `!TRUE` is `FALSE` and
    /// `!FALSE` is `TRUE`.
    pub(crate) fn negate(g: Guard) -> Guard {
        match g {
            Guard::True => Guard::False,
            Guard::False => Guard::True,
            Guard::Not(h) => *h,
            other => Guard::Not(Box::new(other)),
        }
    }

    /// Whether some input vector makes the guard true: a search over the inputs it reads that
    /// fixes one at a time and stops a branch as soon as the guard's value is known.
    pub(crate) fn satisfiable(&self) -> bool {
        let width = self.max_var().map_or(0, |v| v.0 + 1);
        self.satisfiable_under(&mut vec![None; width])
    }

    fn satisfiable_under(&self, x: &mut [Option<bool>]) -> bool {
        if let Some(value) = self.eval_partial(x) {
            return value;
        }
        let Some(free) = self.unassigned_var(x) else {
            return false;
        };
        [true, false].into_iter().any(|v| {
            x[free] = Some(v);
            let sat = self.satisfiable_under(x);
            x[free] = None;
            sat
        })
    }

    /// The guard's value when the assigned inputs decide it, `None` when it depends on the
    /// others.
    fn eval_partial(&self, x: &[Option<bool>]) -> Option<bool> {
        match self {
            Guard::True => Some(true),
            Guard::False => Some(false),
            Guard::Var(i) => x[i.0],
            Guard::Not(g) => g.eval_partial(x).map(|v| !v),
            Guard::And(gs) => gs
                .iter()
                .try_fold(true, |all, g| match g.eval_partial(x) {
                    Some(false) => Err(()),
                    Some(true) => Ok(all),
                    None => Ok(false),
                })
                .map_or(Some(false), |all| all.then_some(true)),
            Guard::Or(gs) => gs
                .iter()
                .try_fold(false, |open, g| match g.eval_partial(x) {
                    Some(true) => Err(()),
                    Some(false) => Ok(open),
                    None => Ok(true),
                })
                .map_or(Some(true), |open| (!open).then_some(false)),
        }
    }

    /// The first input the guard reads that `x` leaves open.
    fn unassigned_var(&self, x: &[Option<bool>]) -> Option<usize> {
        match self {
            Guard::True | Guard::False => None,
            Guard::Var(i) => x[i.0].is_none().then_some(i.0),
            Guard::Not(g) => g.unassigned_var(x),
            Guard::And(gs) | Guard::Or(gs) => gs.iter().find_map(|g| g.unassigned_var(x)),
        }
    }

    /// Number of variable occurrences (the guard size N of the papers).
    pub(crate) fn literal_count(&self) -> usize {
        match self {
            Guard::True | Guard::False => 0,
            Guard::Var(_) => 1,
            Guard::Not(g) => g.literal_count(),
            Guard::And(gs) | Guard::Or(gs) => gs.iter().map(|g| g.literal_count()).sum(),
        }
    }

    /// Nodes of the guard as a parse tree with binary `&` and `|`, unary `!`, variables and
    /// constants: the guard size of fbSAT's extended guards (its `N`, with `P` the largest per
    /// guard), for comparing with its published sizes.
    pub fn tree_size(&self) -> usize {
        match self {
            Guard::True | Guard::False | Guard::Var(_) => 1,
            Guard::Not(g) => 1 + g.tree_size(),
            Guard::And(gs) | Guard::Or(gs) => {
                gs.iter().map(|g| g.tree_size()).sum::<usize>() + gs.len().saturating_sub(1)
            }
        }
    }

    /// Largest input index the guard reads, if any.
    pub(crate) fn max_var(&self) -> Option<InputId> {
        match self {
            Guard::True | Guard::False => None,
            Guard::Var(i) => Some(*i),
            Guard::Not(g) => g.max_var(),
            Guard::And(gs) | Guard::Or(gs) => gs.iter().filter_map(|g| g.max_var()).max(),
        }
    }

    /// Display with input names in the project's guard syntax (`!`, `&`, `|`).
    pub(crate) fn display<'a>(&'a self, names: &'a [String]) -> GuardDisplay<'a> {
        GuardDisplay {
            guard: self,
            names,
            syntax: Syntax::C,
        }
    }

    /// Display in IEC 61131-3 Structured Text syntax (`NOT`, `AND`, `OR`), where a run of
    /// negations is written by its parity: never `NOT NOT`.
    pub(crate) fn display_st<'a>(&'a self, names: &'a [String]) -> GuardDisplay<'a> {
        GuardDisplay {
            guard: self,
            names,
            syntax: Syntax::St,
        }
    }
}

#[derive(Clone, Copy)]
enum Syntax {
    /// `!a & b | c`, `TRUE`, `FALSE`: the JSON contract, SMV and DOT.
    C,
    /// `NOT a AND b OR c`: Structured Text.
    St,
}

/// A guard paired with input names, ready to print.
pub(crate) struct GuardDisplay<'a> {
    guard: &'a Guard,
    names: &'a [String],
    syntax: Syntax,
}

impl GuardDisplay<'_> {
    // Precedence: Or = 1, And = 2, Not/atoms = 3. Parentheses only where needed.
    fn write(&self, mut g: &Guard, parent: u8, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        // IEC 61131-3 allows one unary operator before a primary (`NOT NOT a` is no
        // expression), so Structured Text writes a run of negations by its parity.
        if let Syntax::St = self.syntax {
            while let Guard::Not(inner) = g {
                match inner.as_ref() {
                    Guard::Not(h) => g = h,
                    _ => break,
                }
            }
        }
        let (not, and, or) = match self.syntax {
            Syntax::C => ("!", " & ", " | "),
            Syntax::St => ("NOT ", " AND ", " OR "),
        };
        match g {
            Guard::True => write!(f, "TRUE"),
            Guard::False => write!(f, "FALSE"),
            Guard::Var(i) => match self.names.get(i.0) {
                Some(n) => write!(f, "{n}"),
                None => write!(f, "x{}", i.0 + 1),
            },
            Guard::Not(inner) => {
                write!(f, "{not}")?;
                self.write(inner, 3, f)
            }
            Guard::And(gs) | Guard::Or(gs) => {
                let (prec, sep) = if matches!(g, Guard::And(_)) {
                    (2, and)
                } else {
                    (1, or)
                };
                if prec < parent {
                    write!(f, "(")?;
                }
                for (k, sub) in gs.iter().enumerate() {
                    if k > 0 {
                        write!(f, "{sep}")?;
                    }
                    self.write(sub, prec + 1, f)?;
                }
                if prec < parent {
                    write!(f, ")")?;
                }
                Ok(())
            }
        }
    }
}

impl fmt::Display for GuardDisplay<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        self.write(self.guard, 0, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names() -> Vec<String> {
        vec!["a".into(), "b".into(), "c".into()]
    }

    #[test]
    fn display_uses_minimal_parentheses() {
        let g = Guard::And(vec![
            Guard::Or(vec![Guard::Var(InputId(0)), Guard::Var(InputId(1))]),
            Guard::Not(Box::new(Guard::Var(InputId(2)))),
        ]);
        assert_eq!(g.display(&names()).to_string(), "(a | b) & !c");
        assert_eq!(g.display_st(&names()).to_string(), "(a OR b) AND NOT c");
        let h = Guard::Not(Box::new(Guard::And(vec![
            Guard::Var(InputId(0)),
            Guard::Var(InputId(1)),
        ])));
        assert_eq!(h.display(&names()).to_string(), "!(a & b)");
    }

    fn not(g: Guard) -> Guard {
        Guard::Not(Box::new(g))
    }

    #[test]
    fn structured_text_never_doubles_a_negation() {
        let a = || Guard::Var(InputId(0));
        let ab = || Guard::And(vec![a(), Guard::Var(InputId(1))]);
        for (g, st) in [
            (not(not(a())), "a"),
            (not(not(not(a()))), "NOT a"),
            (not(not(ab())), "a AND b"),
            (not(not(not(ab()))), "NOT (a AND b)"),
            (
                Guard::Or(vec![not(not(ab())), Guard::Var(InputId(2))]),
                "a AND b OR c",
            ),
            (
                Guard::And(vec![
                    not(not(Guard::Or(vec![a(), Guard::Var(InputId(2))]))),
                    a(),
                ]),
                "(a OR c) AND a",
            ),
        ] {
            let text = g.display_st(&names()).to_string();
            assert_eq!(text, st);
            assert!(!text.contains("NOT NOT"), "{text}");
        }
        // The project's own syntax writes the tree as it is: its parser reads `!!a` back.
        assert_eq!(not(not(a())).display(&names()).to_string(), "!!a");
    }

    #[test]
    fn negate_removes_a_double_negation() {
        let a = Guard::Var(InputId(0));
        assert_eq!(Guard::negate(not(a.clone())), a);
        assert_eq!(Guard::negate(a.clone()), not(a.clone()));
        assert_eq!(Guard::negate(Guard::True), Guard::False);
        assert_eq!(Guard::negate(Guard::False), Guard::True);
    }

    #[test]
    fn satisfiable_finds_a_model_or_a_contradiction() {
        let v = |i| Guard::Var(InputId(i));
        assert!(!Guard::And(vec![v(0), v(1), not(v(0))]).satisfiable());
        assert!(!Guard::And(vec![not(not(v(0))), not(v(0))]).satisfiable());
        assert!(!Guard::False.satisfiable());
        assert!(!Guard::And(vec![Guard::Or(vec![v(0), v(1)]), not(v(0)), not(v(1))]).satisfiable());
        assert!(Guard::True.satisfiable());
        assert!(Guard::And(vec![Guard::Or(vec![v(0), v(1)]), not(v(0))]).satisfiable());
        assert!(not(Guard::And(vec![v(3), v(7)])).satisfiable());
        assert!(Guard::And(vec![]).satisfiable());
        assert!(!Guard::Or(vec![]).satisfiable());
    }

    #[test]
    fn dnf_counts_literals_and_evaluates() {
        let g = Guard::dnf(&[
            vec![(InputId(0), true), (InputId(2), false)],
            vec![(InputId(1), true)],
        ]);
        assert_eq!(g.literal_count(), 3);
        assert!(g.eval(&[true, false, false]));
        assert!(!g.eval(&[true, false, true]));
        assert!(g.eval(&[false, true, true]));
        assert_eq!(g.display(&names()).to_string(), "a & !c | b");
        assert_eq!(Guard::dnf(&[vec![]]), Guard::True);
        assert_eq!(Guard::dnf(&[]), Guard::False);
        // a & !c | b: the variables a, c, b, one NOT, one AND, one OR.
        assert_eq!(g.tree_size(), 6);
        assert_eq!(Guard::True.tree_size(), 1);
    }
}
