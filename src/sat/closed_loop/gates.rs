//! Tseitin gates with constant folding, and finite-domain values as one-hot literal lists.
//!
//! Every gate output is *equivalent* to its definition (both directions), so a gate's literal
//! can be reused anywhere, in either polarity: the plant's next state is the literal list of
//! its `next` expression, with no fresh variables.

use crate::plant::Value;
use varisat::{ExtendFormula, Lit};

/// A Boolean that is a constant or a literal.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum B {
    /// A constant, folded away by every gate.
    C(bool),
    /// A solver literal.
    L(Lit),
}

impl std::ops::Not for B {
    type Output = B;
    fn not(self) -> B {
        match self {
            B::C(b) => B::C(!b),
            B::L(l) => B::L(!l),
        }
    }
}

/// A value of a finite domain: each possible value with the condition under which it is the
/// value. Exactly one condition holds; values with a false condition are left out.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Fd(pub(crate) Vec<(Value, B)>);

impl Fd {
    /// The value `v` unconditionally.
    pub(crate) fn constant(v: Value) -> Fd {
        Fd(vec![(v, B::C(true))])
    }

    /// A Boolean as a value of the domain `{FALSE, TRUE}`.
    pub(crate) fn of_bool(b: B) -> Fd {
        match b {
            B::C(c) => Fd::constant(Value::Bool(c)),
            l => Fd(vec![(Value::Bool(false), !l), (Value::Bool(true), l)]),
        }
    }

    /// The condition that the value is `v`.
    pub(crate) fn is(&self, v: Value) -> B {
        self.0
            .iter()
            .find(|(w, _)| *w == v)
            .map_or(B::C(false), |&(_, b)| b)
    }
}

/// Gate builder over a clause sink.
pub(crate) struct Gates<'f, F: ExtendFormula> {
    /// The clause sink every gate writes into (the solver, or a `CnfFormula` in tests).
    pub(crate) f: &'f mut F,
}

impl<F: ExtendFormula> Gates<'_, F> {
    /// Adds `OR lits`: skipped when a constant is true, false constants dropped (so all-false
    /// constants add the empty clause and make the formula UNSAT).
    pub(crate) fn clause(&mut self, lits: &[B]) {
        if lits.contains(&B::C(true)) {
            return;
        }
        let ls: Vec<Lit> = lits
            .iter()
            .filter_map(|b| match b {
                B::L(l) => Some(*l),
                B::C(_) => None,
            })
            .collect();
        self.f.add_clause(&ls);
    }

    /// A fresh unconstrained literal.
    pub(crate) fn fresh(&mut self) -> Lit {
        self.f.new_lit()
    }

    /// `o <-> AND xs`.
    pub(crate) fn and(&mut self, xs: &[B]) -> B {
        let mut ls: Vec<Lit> = Vec::with_capacity(xs.len());
        for &x in xs {
            match x {
                B::C(false) => return B::C(false),
                B::C(true) => {}
                B::L(l) => {
                    if ls.contains(&!l) {
                        return B::C(false);
                    }
                    if !ls.contains(&l) {
                        ls.push(l)
                    }
                }
            }
        }
        match ls.len() {
            0 => B::C(true),
            1 => B::L(ls[0]),
            _ => {
                let o = self.f.new_lit();
                for &l in &ls {
                    self.f.add_clause(&[!o, l]);
                }
                let mut back: Vec<Lit> = ls.iter().map(|&l| !l).collect();
                back.push(o);
                self.f.add_clause(&back);
                B::L(o)
            }
        }
    }

    /// `o <-> OR xs`.
    pub(crate) fn or(&mut self, xs: &[B]) -> B {
        let neg: Vec<B> = xs.iter().map(|&x| !x).collect();
        !self.and(&neg)
    }

    /// `o <-> a & b`.
    pub(crate) fn and2(&mut self, a: B, b: B) -> B {
        self.and(&[a, b])
    }

    /// `o <-> a | b`.
    pub(crate) fn or2(&mut self, a: B, b: B) -> B {
        self.or(&[a, b])
    }

    /// `o <-> (a <-> b)`.
    pub(crate) fn iff(&mut self, a: B, b: B) -> B {
        match (a, b) {
            (B::C(x), y) | (y, B::C(x)) => {
                if x {
                    y
                } else {
                    !y
                }
            }
            (B::L(x), B::L(y)) if x == y => B::C(true),
            (B::L(x), B::L(y)) if x == !y => B::C(false),
            (B::L(x), B::L(y)) => {
                let o = self.f.new_lit();
                self.f.add_clause(&[!o, !x, y]);
                self.f.add_clause(&[!o, x, !y]);
                self.f.add_clause(&[o, x, y]);
                self.f.add_clause(&[o, !x, !y]);
                B::L(o)
            }
        }
    }

    #[cfg(test)]
    /// `o <-> (c ? a : b)`.
    pub(crate) fn ite(&mut self, c: B, a: B, b: B) -> B {
        match c {
            B::C(true) => a,
            B::C(false) => b,
            _ if a == b => a,
            _ => {
                let x = self.and2(c, a);
                let y = self.and2(!c, b);
                self.or2(x, y)
            }
        }
    }

    /// Joins `(value, condition)` pairs, which may repeat values, into an [`Fd`]: one `OR`
    /// per value.
    pub(crate) fn join(&mut self, pairs: Vec<(Value, B)>) -> Fd {
        let mut out: Vec<(Value, Vec<B>)> = Vec::new();
        for (v, b) in pairs {
            if b == B::C(false) {
                continue;
            }
            match out.iter_mut().find(|(w, _)| *w == v) {
                Some((_, bs)) => bs.push(b),
                None => out.push((v, vec![b])),
            }
        }
        let joined: Vec<(Value, B)> = out
            .into_iter()
            .map(|(v, bs)| (v, self.or(&bs)))
            .filter(|(_, b)| *b != B::C(false))
            .collect();
        Fd(joined)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use varisat::{CnfFormula, Solver};

    /// Every gate, over every assignment of its inputs: the output literal is forced to the
    /// gate's function.
    #[test]
    fn gates_are_exact() {
        type Gate = fn(&mut Gates<'_, CnfFormula>, B, B, B) -> B;
        type Truth = fn(bool, bool, bool) -> bool;
        let gates: [(Gate, Truth); 4] = [
            (|g, a, b, c| g.and(&[a, b, c]), |a, b, c| a && b && c),
            (|g, a, b, c| g.or(&[a, b, c]), |a, b, c| a || b || c),
            (|g, a, b, _| g.iff(a, b), |a, b, _| a == b),
            (|g, a, b, c| g.ite(a, b, c), |a, b, c| if a { b } else { c }),
        ];
        for (gate, want) in gates {
            for mask in 0..8u32 {
                let mut f = CnfFormula::new();
                let ins = [(); 3].map(|_| f.new_lit());
                let o = gate(
                    &mut Gates { f: &mut f },
                    B::L(ins[0]),
                    B::L(ins[1]),
                    B::L(ins[2]),
                );
                let bit = |i: usize| mask >> i & 1 == 1;
                for expect in [false, true] {
                    let mut s = Solver::new();
                    s.add_formula(&f);
                    let mut assume: Vec<Lit> = (0..3)
                        .map(|i| if bit(i) { ins[i] } else { !ins[i] })
                        .collect();
                    match o {
                        B::L(l) => assume.push(if expect { l } else { !l }),
                        B::C(c) => assert_eq!(c, want(bit(0), bit(1), bit(2))),
                    }
                    s.assume(&assume);
                    let sat = s.solve().unwrap();
                    assert_eq!(sat, expect == want(bit(0), bit(1), bit(2)), "mask {mask}");
                }
            }
        }
    }
}
