//! LTL properties: the `specs/*.ltl` files, their formulas, NuSMV text, and evaluation on a lasso.
//!
//! In: the text of a specification file. Out: a list of [`Property`] (label, formula, line),
//! checked before NuSMV ever runs, so that a mistake is reported at the line of the user's file.
//! A formula can then be printed as NuSMV text ([`Ltl::to_smv`]) or evaluated on a lasso-shaped
//! run ([`Ltl::holds_on_lasso`]), which is how a counterexample's real loop point is chosen, or
//! in three values on a finite prefix ([`Ltl::truth_on_prefix`]), which is how recordings that
//! already violate a property are found.
//!
//! # File format
//! ```text
//! -- Pick-and-Place safety
//! c1_exclusive: G !(c1Extend & c1Retract)
//! G (pp1 -> F vp1)   -- liveness
//! ```
//! - One property per line, written in NuSMV's LTL syntax over bare names.
//! - `--` starts a comment, on a line of its own or after a formula; blank lines are ignored.
//! - A property may start with a label `name:`. A label is an SMV identifier
//!   (`[A-Za-z_][A-Za-z0-9_$#-]*`, not a NuSMV keyword) and is unique in the file. Unlabelled
//!   properties are named `p1`, `p2`, ... by their position ([`property_name`]); a label may not
//!   take the default name of another property.
//! - A file must contain at least one property.
//!
//! # Formulas
//! Operators, from loosest to tightest binding (NuSMV 2.5's grammar):
//! `->` (right associative); `<->`; `|`, `xor`, `xnor`; `&`; the binary temporal operators `U`
//! (until), `V` (releases), `S` (since), `T` (triggered), left associative; the prefixes `!`,
//! `X`, `F`, `G` and the past `Y`, `Z`, `H`, `O`; comparisons `=`, `!=`, `<`, `<=`, `>`, `>=`.
//! Comparisons bind tightest, as in NuSMV: `X pos = 3` is `X (pos = 3)`, and `!pos = 3` is
//! `!(pos = 3)` (NuSMV reads `(!pos) = 3`, which has the same truth value whenever NuSMV
//! accepts it).
//!
//! Atoms are names (SMV identifiers, possibly dotted as `plant.pos`), `TRUE`, `FALSE` and, only
//! as an operand of a comparison, decimal integers. A comparison relates two such atoms, at least
//! one of them a name, and cannot be chained; the ordering comparisons need names or integers.
//!
//! Two deliberate departures from NuSMV's lexer, which reads `a->b` as the name `a-` followed by
//! `>`, and `a--b` as one name: here `->` is always an implication and `--` always a comment.

mod finite;
mod lasso;
mod parse;

pub(crate) use finite::{NotEvaluable, Truth};
pub use lasso::EvalError;
#[cfg(test)]
pub(crate) use parse::parse_spec;
pub use parse::LtlErrorKind;
pub use parse::{parse_spec_file, LtlError};

use std::collections::BTreeSet;
use std::fmt;

/// A comparison operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum CmpOp {
    /// `=`: equal.
    Eq,
    /// `!=`: not equal.
    Ne,
    /// `<`: less than (integers).
    Lt,
    /// `<=`: less than or equal (integers).
    Le,
    /// `>`: greater than (integers).
    Gt,
    /// `>=`: greater than or equal (integers).
    Ge,
}

impl CmpOp {
    /// The NuSMV spelling.
    pub(crate) fn symbol(self) -> &'static str {
        match self {
            CmpOp::Eq => "=",
            CmpOp::Ne => "!=",
            CmpOp::Lt => "<",
            CmpOp::Le => "<=",
            CmpOp::Gt => ">",
            CmpOp::Ge => ">=",
        }
    }

    /// Whether the operator orders integers (as opposed to testing equality).
    pub(crate) fn is_ordering(self) -> bool {
        !matches!(self, CmpOp::Eq | CmpOp::Ne)
    }
}

/// An LTL formula with past operators, in NuSMV's operator set.
///
/// Binary operators keep the shape of the parse (`a & b & c` is `And(And(a, b), c)`), so
/// [`Ltl::to_smv`] prints back what was written, up to spacing and redundant parentheses.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Ltl {
    /// The constant `TRUE`.
    True,
    /// The constant `FALSE`.
    False,
    /// A name: a Boolean variable as a formula, a variable or symbolic constant in a comparison.
    Atom(String),
    /// An integer; only ever an operand of [`Ltl::Cmp`].
    Int(i64),
    /// Negation `!a`.
    Not(Box<Ltl>),
    /// Conjunction `a & b`.
    And(Box<Ltl>, Box<Ltl>),
    /// Disjunction `a | b`.
    Or(Box<Ltl>, Box<Ltl>),
    /// Exclusive or `a xor b`.
    Xor(Box<Ltl>, Box<Ltl>),
    /// Negated exclusive or `a xnor b` (true when both agree).
    Xnor(Box<Ltl>, Box<Ltl>),
    /// Implication `a -> b`.
    Implies(Box<Ltl>, Box<Ltl>),
    /// Equivalence `a <-> b`.
    Iff(Box<Ltl>, Box<Ltl>),
    /// A comparison; both operands are [`Ltl::Atom`], [`Ltl::Int`], [`Ltl::True`] or
    /// [`Ltl::False`] (the parser guarantees it).
    Cmp(CmpOp, Box<Ltl>, Box<Ltl>),
    /// Next.
    X(Box<Ltl>),
    /// Eventually (finally).
    F(Box<Ltl>),
    /// Always (globally).
    G(Box<Ltl>),
    /// `a U b`: `b` eventually holds, and `a` holds at every step before.
    U(Box<Ltl>, Box<Ltl>),
    /// `a V b`: `b` holds up to and including the first step where `a` holds, or forever.
    V(Box<Ltl>, Box<Ltl>),
    /// Previous step (false at the first step).
    Y(Box<Ltl>),
    /// Previous step, true at the first step.
    Z(Box<Ltl>),
    /// Historically: at every step so far.
    H(Box<Ltl>),
    /// Once: at some step so far.
    O(Box<Ltl>),
    /// `a S b`: `b` held at some step so far, and `a` at every step after it.
    S(Box<Ltl>, Box<Ltl>),
    /// `a T b`: `b` held at every step so far, or since (and including) a step where `a` held.
    T(Box<Ltl>, Box<Ltl>),
}

/// One property of a specification file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Property {
    /// The label written before the formula, if any.
    pub label: Option<String>,
    /// The parsed formula.
    pub formula: Ltl,
    /// 1-based line of the file.
    pub(crate) line: usize,
    /// The formula as written, without label and comment.
    pub(crate) text: String,
}

/// The SMV name of the property at 0-based position `index` in its file: its label, or
/// `p{index+1}`. The parser guarantees these names are unique within a file.
pub(crate) fn property_name(index: usize, p: &Property) -> String {
    match &p.label {
        Some(l) => l.clone(),
        None => default_name(index),
    }
}

fn default_name(index: usize) -> String {
    format!("p{}", index + 1)
}

/// Binding strength when printing; larger binds tighter.
///
/// A comparison is printed as if it bound looser than every temporal operator and `!`, so it
/// gets parentheses under them (`X (pos = 3)`, `!(pos = 3)`). NuSMV would not need them under
/// the temporal operators, but they keep the text unambiguous to a reader, and NuSMV does need
/// them under `!`.
mod prec {
    pub(crate) const IMPLIES: u8 = 1;
    pub(crate) const IFF: u8 = 2;
    pub(crate) const OR: u8 = 3;
    pub(crate) const AND: u8 = 4;
    pub(crate) const CMP: u8 = 5;
    pub(crate) const BINARY_TEMPORAL: u8 = 6;
    pub(crate) const PREFIX: u8 = 7;
    pub(crate) const ATOM: u8 = 8;
}

impl Ltl {
    /// Names the formula reads as variables: the Boolean atoms, and the left operand of each
    /// comparison (the right one when the left is not a name).
    ///
    /// A name on the right of a comparison whose left side is a name is left out: it may be a
    /// symbolic constant (`pos = idle`), which only the model can tell from a variable.
    pub(crate) fn names(&self) -> BTreeSet<String> {
        let mut out = BTreeSet::new();
        self.visit(&mut |f| match f {
            Ltl::Atom(n) => {
                out.insert(n.clone());
            }
            Ltl::Cmp(_, l, r) => {
                if let Some(n) = l.var_operand(r) {
                    out.insert(n.to_string());
                }
            }
            _ => {}
        });
        out
    }

    /// The variable of a comparison `self op other`: see [`Ltl::names`].
    fn var_operand<'a>(&'a self, other: &'a Ltl) -> Option<&'a str> {
        match (self, other) {
            (Ltl::Atom(n), _) | (_, Ltl::Atom(n)) => Some(n),
            _ => None,
        }
    }

    /// Calls `f` on every subformula, outermost first, not descending into comparisons.
    fn visit(&self, f: &mut impl FnMut(&Ltl)) {
        f(self);
        let (a, b) = self.children();
        if !matches!(self, Ltl::Cmp(..)) {
            for c in [a, b].into_iter().flatten() {
                c.visit(f);
            }
        }
    }

    /// The operands, left first.
    fn children(&self) -> (Option<&Ltl>, Option<&Ltl>) {
        use Ltl::*;
        match self {
            True | False | Atom(_) | Int(_) => (None, None),
            Not(a) | X(a) | F(a) | G(a) | Y(a) | Z(a) | H(a) | O(a) => (Some(a), None),
            And(a, b)
            | Or(a, b)
            | Xor(a, b)
            | Xnor(a, b)
            | Implies(a, b)
            | Iff(a, b)
            | Cmp(_, a, b)
            | U(a, b)
            | V(a, b)
            | S(a, b)
            | T(a, b) => (Some(a), Some(b)),
        }
    }

    /// Whether the formula uses no past operator (`Y Z H O S T`).
    pub(crate) fn is_future_only(&self) -> bool {
        self.past_depth() == 0
    }

    /// The largest number of past operators on one path from the root to a leaf.
    pub(crate) fn past_depth(&self) -> usize {
        self.depth(&|f| {
            matches!(
                f,
                Ltl::Y(_) | Ltl::Z(_) | Ltl::H(_) | Ltl::O(_) | Ltl::S(..) | Ltl::T(..)
            )
        })
    }

    /// The largest number of `X` on one path from the root to a leaf: how many steps past a
    /// position the formula reads, apart from `G F U V`.
    pub(crate) fn next_depth(&self) -> usize {
        self.depth(&|f| matches!(f, Ltl::X(_)))
    }

    /// The largest number of subformulas `counts` on one path from the root to a leaf.
    fn depth(&self, counts: &dyn Fn(&Ltl) -> bool) -> usize {
        let (a, b) = self.children();
        let below = [a, b]
            .into_iter()
            .flatten()
            .map(|c| c.depth(counts))
            .max()
            .unwrap_or(0);
        below + usize::from(counts(self))
    }

    /// NuSMV text of the formula, with parentheses where NuSMV's precedence needs them (and
    /// around comparisons under prefix and temporal operators, for the reader).
    ///
    /// `resolve` maps each name in [`Ltl::names`] to its SMV expression (for example
    /// `c1Extend` to `ctrl.c1Extend`); other names (possible symbolic constants on the right
    /// of a comparison) are printed as written.
    pub(crate) fn to_smv(&self, resolve: &dyn Fn(&str) -> String) -> String {
        let mut out = String::new();
        self.write_smv(resolve, &mut out);
        out
    }

    fn prec(&self) -> u8 {
        use Ltl::*;
        match self {
            True | False | Atom(_) | Int(_) => prec::ATOM,
            Not(_) | X(_) | F(_) | G(_) | Y(_) | Z(_) | H(_) | O(_) => prec::PREFIX,
            U(..) | V(..) | S(..) | T(..) => prec::BINARY_TEMPORAL,
            Cmp(..) => prec::CMP,
            And(..) => prec::AND,
            Or(..) | Xor(..) | Xnor(..) => prec::OR,
            Iff(..) => prec::IFF,
            Implies(..) => prec::IMPLIES,
        }
    }

    fn write_smv(&self, resolve: &dyn Fn(&str) -> String, out: &mut String) {
        use Ltl::*;
        match self {
            True => out.push_str("TRUE"),
            False => out.push_str("FALSE"),
            Atom(n) => out.push_str(&resolve(n)),
            Int(i) => out.push_str(&i.to_string()),
            Cmp(op, l, r) => {
                let var = l.var_operand(r);
                for (k, side) in [l, r].into_iter().enumerate() {
                    if k == 1 {
                        out.push(' ');
                        out.push_str(op.symbol());
                        out.push(' ');
                    }
                    match side.as_ref() {
                        Atom(n) if Some(n.as_str()) == var => out.push_str(&resolve(n)),
                        Atom(n) => out.push_str(n),
                        other => other.write_smv(resolve, out),
                    }
                }
            }
            Not(a) => {
                out.push('!');
                a.write_operand(prec::PREFIX, resolve, out);
            }
            X(a) | F(a) | G(a) | Y(a) | Z(a) | H(a) | O(a) => {
                out.push_str(self.operator());
                out.push(' ');
                a.write_operand(prec::PREFIX, resolve, out);
            }
            // `->` groups to the right, every other binary operator to the left.
            Implies(a, b) => self.write_binary(a, b, (prec::IFF, prec::IMPLIES), resolve, out),
            And(a, b)
            | Or(a, b)
            | Xor(a, b)
            | Xnor(a, b)
            | Iff(a, b)
            | U(a, b)
            | V(a, b)
            | S(a, b)
            | T(a, b) => {
                let p = self.prec();
                self.write_binary(a, b, (p, p + 1), resolve, out)
            }
        }
    }

    fn write_binary(
        &self,
        a: &Ltl,
        b: &Ltl,
        (left, right): (u8, u8),
        resolve: &dyn Fn(&str) -> String,
        out: &mut String,
    ) {
        a.write_operand(left, resolve, out);
        out.push(' ');
        out.push_str(self.operator());
        out.push(' ');
        b.write_operand(right, resolve, out);
    }

    /// Writes `self` as an operand that must bind at least as tight as `min`.
    fn write_operand(&self, min: u8, resolve: &dyn Fn(&str) -> String, out: &mut String) {
        if self.prec() < min {
            out.push('(');
            self.write_smv(resolve, out);
            out.push(')');
        } else {
            self.write_smv(resolve, out);
        }
    }

    /// The NuSMV spelling of the top operator (empty for atoms).
    fn operator(&self) -> &'static str {
        use Ltl::*;
        match self {
            True | False | Atom(_) | Int(_) => "",
            Cmp(op, ..) => op.symbol(),
            Not(_) => "!",
            And(..) => "&",
            Or(..) => "|",
            Xor(..) => "xor",
            Xnor(..) => "xnor",
            Implies(..) => "->",
            Iff(..) => "<->",
            X(_) => "X",
            F(_) => "F",
            G(_) => "G",
            U(..) => "U",
            V(..) => "V",
            Y(_) => "Y",
            Z(_) => "Z",
            H(_) => "H",
            O(_) => "O",
            S(..) => "S",
            T(..) => "T",
        }
    }
}

/// The NuSMV text with names as written.
impl fmt::Display for Ltl {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.to_smv(&|n| n.to_string()))
    }
}

#[cfg(test)]
pub(crate) mod arb {
    //! Random formulas for property tests.
    use super::{CmpOp, Ltl};
    use proptest::prelude::*;
    use proptest::sample::select;

    type Unary = fn(Box<Ltl>) -> Ltl;
    type Binary = fn(Box<Ltl>, Box<Ltl>) -> Ltl;

    fn b(f: Ltl) -> Box<Ltl> {
        Box::new(f)
    }

    /// Trees of depth at most 4 over `leaf`, built with the given operators.
    fn trees(
        leaf: impl Strategy<Value = Ltl> + 'static,
        unary: &'static [Unary],
        binary: &'static [Binary],
    ) -> impl Strategy<Value = Ltl> {
        leaf.prop_recursive(4, 24, 2, move |inner| {
            prop_oneof![
                (select(unary), inner.clone()).prop_map(|(op, f)| op(b(f))),
                (select(binary), inner.clone(), inner).prop_map(|(op, l, r)| op(b(l), b(r))),
            ]
        })
    }

    /// Formulas over the Boolean atoms `a`, `b` (and, with `with_cmp`, comparisons of the
    /// integer `n` and the enumeration `s`), using every operator.
    pub(crate) fn formula(with_cmp: bool) -> impl Strategy<Value = Ltl> {
        let mut leaves = vec![
            Just(Ltl::Atom("a".into())).boxed(),
            Just(Ltl::Atom("b".into())).boxed(),
            Just(Ltl::True).boxed(),
            Just(Ltl::False).boxed(),
        ];
        if with_cmp {
            let ops = vec![
                CmpOp::Eq,
                CmpOp::Ne,
                CmpOp::Lt,
                CmpOp::Le,
                CmpOp::Gt,
                CmpOp::Ge,
            ];
            leaves.push(
                (select(ops), -2i64..3)
                    .prop_map(|(op, k)| Ltl::Cmp(op, b(Ltl::Atom("n".into())), b(Ltl::Int(k))))
                    .boxed(),
            );
            leaves.push(
                select(&["idle", "busy"][..])
                    .prop_map(|c| {
                        Ltl::Cmp(CmpOp::Eq, b(Ltl::Atom("s".into())), b(Ltl::Atom(c.into())))
                    })
                    .boxed(),
            );
        }
        trees(
            proptest::strategy::Union::new(leaves),
            &[
                Ltl::Not,
                Ltl::X,
                Ltl::F,
                Ltl::G,
                Ltl::Y,
                Ltl::Z,
                Ltl::H,
                Ltl::O,
            ],
            &[
                Ltl::And,
                Ltl::Or,
                Ltl::Xor,
                Ltl::Xnor,
                Ltl::Implies,
                Ltl::Iff,
                Ltl::U,
                Ltl::V,
                Ltl::S,
                Ltl::T,
            ],
        )
    }

    /// Past operators nested under a future one: the formulas whose value at a loop state
    /// depends on how often the loop has been run through.
    pub(crate) fn past_under_future() -> impl Strategy<Value = Ltl> {
        let literal = (select(&["a", "b"][..]), any::<bool>()).prop_map(|(n, positive)| {
            let atom = Ltl::Atom(n.into());
            if positive {
                atom
            } else {
                Ltl::Not(b(atom))
            }
        });
        let past = trees(
            literal,
            &[Ltl::Y, Ltl::Z, Ltl::H, Ltl::O, Ltl::Not],
            &[Ltl::S, Ltl::T, Ltl::And, Ltl::Or],
        );
        let future: &[Unary] = &[
            Ltl::F,
            Ltl::G,
            |p| Ltl::G(b(Ltl::F(p))),
            |p| Ltl::F(b(Ltl::G(p))),
        ];
        (select(future), past).prop_map(|(op, p)| op(b(p)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;
    use std::path::Path;

    fn parse(text: &str) -> Ltl {
        match parse_spec(Path::new("t.ltl"), text) {
            Ok(mut props) => props.remove(0).formula,
            Err(e) => panic!("{text:?} does not parse: {e}"),
        }
    }

    fn atom(n: &str) -> Box<Ltl> {
        Box::new(Ltl::Atom(n.into()))
    }

    /// Written form -> printed form. The printed form uses only the parentheses NuSMV needs
    /// (plus those around comparisons under prefix and temporal operators).
    const PRINTED: &[(&str, &str)] = &[
        ("G !(c1Extend & c1Retract)", "G !(c1Extend & c1Retract)"),
        ("G(pp1->F vp1)", "G (pp1 -> F vp1)"),
        ("((a))", "a"),
        ("TRUE & !FALSE", "TRUE & !FALSE"),
        // -> is right associative, <-> left associative, -> looser than <->.
        ("a -> b -> c", "a -> b -> c"),
        ("(a -> b) -> c", "(a -> b) -> c"),
        ("a <-> b <-> c", "a <-> b <-> c"),
        ("a <-> (b <-> c)", "a <-> (b <-> c)"),
        ("a -> b <-> c", "a -> b <-> c"),
        ("(a -> b) <-> c", "(a -> b) <-> c"),
        ("a <-> b | c", "a <-> b | c"),
        ("(a <-> b) | c", "(a <-> b) | c"),
        // | xor xnor share a level, left associative; & binds tighter.
        ("a | b xor c xnor d", "a | b xor c xnor d"),
        ("a | (b xor c)", "a | (b xor c)"),
        ("a | b & c", "a | b & c"),
        ("(a | b) & c", "(a | b) & c"),
        // Binary temporal operators bind tighter than &, looser than prefixes; left associative.
        ("a & b U c", "a & b U c"),
        ("(a & b) U c", "(a & b) U c"),
        ("a U b U c", "a U b U c"),
        ("a U (b U c)", "a U (b U c)"),
        ("a V b S c T d", "a V b S c T d"),
        ("X a U b", "X a U b"),
        ("X (a U b)", "X (a U b)"),
        ("!a U b", "!a U b"),
        ("!(a U b)", "!(a U b)"),
        // Prefixes stack.
        ("G F a", "G F a"),
        ("F G a", "F G a"),
        ("!X !a", "!X !a"),
        ("Y Z H O a", "Y Z H O a"),
        ("G !(a | b)", "G !(a | b)"),
        // Comparisons bind tightest (as in NuSMV) and are printed in parentheses under
        // prefixes and temporal operators.
        ("X pos = 3", "X (pos = 3)"),
        ("!pos = 3", "!(pos = 3)"),
        ("a U pos >= 2", "a U (pos >= 2)"),
        ("a & pos != idle", "a & pos != idle"),
        ("pos < -2 | plant.pos <= 7", "pos < -2 | plant.pos <= 7"),
        ("valve = TRUE -> F ok", "valve = TRUE -> F ok"),
    ];

    #[test]
    fn prints_with_nusmv_precedence() {
        for (written, printed) in PRINTED {
            assert_eq!(parse(written).to_string(), *printed, "written {written:?}");
            // The printed form reads back as the same formula.
            assert_eq!(parse(printed), parse(written), "printed {printed:?}");
        }
    }

    #[test]
    fn parse_trees_follow_precedence() {
        use Ltl::*;
        assert_eq!(
            parse("a | b & c"),
            Or(atom("a"), Box::new(And(atom("b"), atom("c"))))
        );
        assert_eq!(
            parse("a -> b -> c"),
            Implies(atom("a"), Box::new(Implies(atom("b"), atom("c"))))
        );
        assert_eq!(
            parse("a U b U c"),
            U(Box::new(U(atom("a"), atom("b"))), atom("c"))
        );
        assert_eq!(
            parse("X a = b"),
            X(Box::new(Cmp(CmpOp::Eq, atom("a"), atom("b"))))
        );
        assert_eq!(
            parse("!G a U b"),
            U(Box::new(Not(Box::new(G(atom("a"))))), atom("b"))
        );
        assert_eq!(
            parse("x < -1"),
            Cmp(CmpOp::Lt, atom("x"), Box::new(Int(-1)))
        );
    }

    #[test]
    fn to_smv_resolves_variables_only() {
        let f = parse("G (pos = idle -> F (x & 3 < n & n = m))");
        let smv = f.to_smv(&|n| format!("ctrl.{n}"));
        assert_eq!(
            smv,
            "G (ctrl.pos = idle -> F (ctrl.x & 3 < ctrl.n & ctrl.n = m))"
        );
        let names: Vec<String> = f.names().into_iter().collect();
        assert_eq!(names, ["n", "pos", "x"]);
    }

    #[test]
    fn past_operators_are_detected() {
        assert!(parse("G (a -> F b) & X c U d").is_future_only());
        for past in [
            "Y a",
            "Z a",
            "H a",
            "O a",
            "a S b",
            "a T b",
            "G (a -> F O b)",
        ] {
            assert!(!parse(past).is_future_only(), "{past}");
        }
        assert_eq!(parse("O (a S H b) | Y c").past_depth(), 3);
    }

    #[test]
    fn property_names_are_labels_or_positions() {
        let props = parse_spec(Path::new("t.ltl"), "G a\nsafe: G b\nF c\n").unwrap();
        let names: Vec<String> = props
            .iter()
            .enumerate()
            .map(|(i, p)| property_name(i, p))
            .collect();
        assert_eq!(names, ["p1", "safe", "p3"]);
    }

    proptest! {
        #[test]
        fn printing_then_parsing_gives_the_same_formula(f in arb::formula(true)) {
            let text = f.to_string();
            prop_assert_eq!(parse(&text), f, "printed as {}", text);
        }
    }
}
