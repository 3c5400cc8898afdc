//! A property on a bounded closed-loop run, as clauses that every correct machine satisfies
//! (up to the response bound below).
//!
//! The run is unrolled to positions `0..=L`. In negation normal form each subformula `φ` at
//! position `t` gets a literal `⟦φ⟧t` that is *implied* by "`φ` holds at `t` on every infinite
//! continuation of the run", with three kinds of positions:
//! - safety operators (`G`, `V`, `X`) are weak at the end: past `L` they are taken as true, so
//!   nothing beyond the horizon is ruled out;
//! - eventualities (`F`, `U`) at positions `t <= D` (the *deadline*) are strong: they must be
//!   fulfilled by `L`, that is within `L - D` steps (the response bound); at `t > D` they are
//!   weak. This is the one place the encoding is stronger than the property: a machine that
//!   answers later than the bound is treated as wrong. NuSMV decides in the end either way;
//! - subformulas over the environment alone (free variables of the plant) are evaluated
//!   exactly on the environment's lasso, which is known: so an assumption such as
//!   `(F G !p1) -> ...` is a constant at each position, never weakened.
//!
//! The definitions (`⟦·⟧` with `L+1` read as "past the end"):
//! - atoms and comparisons: the literal of the value at `t`;
//! - `⟦G φ⟧t = ⟦φ⟧t & ⟦G φ⟧t+1`, past the end true; `⟦X φ⟧t = ⟦φ⟧t+1`, past the end true;
//! - `⟦φ V ψ⟧t = ⟦ψ⟧t & (⟦φ⟧t | ⟦φ V ψ⟧t+1)`, past the end true;
//! - `⟦φ U ψ⟧t = s(t)` if `t <= D`, else `w(t)`, where `s(t) = ⟦ψ⟧t | ⟦φ⟧t & s(t+1)` with
//!   `s(L+1)` false and `w` the same with `w(L+1)` true; `F ψ = TRUE U ψ`.

use super::gates::{Fd, Gates, B};
use crate::ltl::{CmpOp, Ltl};
use crate::plant::Value;
use std::collections::{BTreeSet, HashMap};
use varisat::ExtendFormula;

/// What the positions of the run hold.
pub(crate) struct Run<'a> {
    /// Per position `0..=L`: the value of every name the properties read.
    pub(crate) atoms: &'a [HashMap<String, Fd>],
    /// Per position: the value of every environment name (free plant variable).
    pub(crate) env: &'a [HashMap<String, Value>],
    /// The environment's lasso: position `t` of the run is environment position `lasso(t)`.
    pub(crate) env_len: usize,
    /// Where the environment's loop starts: environment position `p >= env_len` is
    /// `env_loop + (p - env_loop) % (env_len - env_loop)`.
    pub(crate) env_loop: usize,
    /// Symbolic constants of the plant, for comparisons such as `mode = idle`.
    pub(crate) symbol: &'a dyn Fn(&str) -> Option<Value>,
    /// Last position with strong eventualities.
    pub(crate) deadline: usize,
}

impl Run<'_> {
    fn last(&self) -> usize {
        self.atoms.len() - 1
    }

    /// Whether `name` is the environment's alone: a free variable of the plant, or a symbolic
    /// constant that names nothing of the closed loop.
    fn is_env(&self, name: &str) -> bool {
        self.env.first().is_some_and(|m| m.contains_key(name))
            || (!self.atoms[0].contains_key(name) && (self.symbol)(name).is_some())
    }
}

/// Every name a formula reads: its atoms and both operands of its comparisons. A name there
/// may be a machine output, a plant variable or define, or a symbolic constant
/// ([`Ltl::names`] keeps one operand of a comparison only, the one it takes for the variable:
/// in `on_for != k` the define `k` is read too).
pub fn operand_names(f: &Ltl) -> BTreeSet<String> {
    fn walk(f: &Ltl, out: &mut BTreeSet<String>) {
        use Ltl::*;
        match f {
            True | False | Int(_) => {}
            Atom(n) => {
                out.insert(n.clone());
            }
            Cmp(_, a, b) => {
                walk(a, out);
                walk(b, out);
            }
            Not(a) | X(a) | F(a) | G(a) | Y(a) | Z(a) | H(a) | O(a) => walk(a, out),
            And(a, b)
            | Or(a, b)
            | Xor(a, b)
            | Xnor(a, b)
            | Implies(a, b)
            | Iff(a, b)
            | U(a, b)
            | V(a, b)
            | S(a, b)
            | T(a, b) => {
                walk(a, out);
                walk(b, out);
            }
        }
    }
    let mut out = BTreeSet::new();
    walk(f, &mut out);
    out
}

/// Whether the formula is a safety property once its environment-only subformulas are read
/// as constants: in negation normal form no `F` or `U` (an eventuality) outside them. Only
/// such properties are encoded by default. `env(n)`: name `n` is the environment's alone, a
/// free variable of the plant or a symbolic constant ([`super::is_environment`]).
pub(crate) fn is_safety(f: &Ltl, env: &dyn Fn(&str) -> bool) -> bool {
    safety_at(f, true, env)
}

/// Whether `f` in positive (`pos`) or negative position has no eventuality outside its
/// environment-only subformulas ([`is_safety`]).
fn safety_at(f: &Ltl, pos: bool, env: &dyn Fn(&str) -> bool) -> bool {
    use Ltl::*;
    let walk = safety_at;
    if f.is_future_only() && operand_names(f).iter().all(|n| env(n)) {
        return true;
    }
    match f {
        True | False | Atom(_) | Int(_) | Cmp(..) => true,
        Not(a) => walk(a, !pos, env),
        And(a, b) | Or(a, b) => walk(a, pos, env) && walk(b, pos, env),
        Implies(a, b) => walk(a, !pos, env) && walk(b, pos, env),
        Iff(a, b) | Xnor(a, b) | Xor(a, b) => {
            walk(a, pos, env) && walk(a, !pos, env) && walk(b, pos, env) && walk(b, !pos, env)
        }
        X(a) => walk(a, pos, env),
        // F and U are eventualities in positive position, G and V in negative.
        F(a) => !pos && walk(a, pos, env),
        G(a) => pos && walk(a, pos, env),
        U(a, b) => !pos && walk(a, pos, env) && walk(b, pos, env),
        V(a, b) => pos && walk(a, pos, env) && walk(b, pos, env),
        Y(_) | Z(_) | H(_) | O(_) | S(..) | T(..) => false,
    }
}

/// The safety part of a property: a formula that every run satisfying `f` satisfies, with no
/// eventuality left (`None` when it says nothing, `TRUE`, or
/// `f` has past operators or eventualities under `<->` or `xor`). Each eventuality is made
/// weak, by polarity: in positive position `a U b` becomes `a W b` (`b V (a | b)`) and `F a`
/// becomes `TRUE`; in negative position `G a` becomes `FALSE` and `a V b` becomes `b U (a & b)`
/// (whose negation is the weak until). Environment-only subformulas stay as they are: the
/// encoding reads them exactly.
///
/// Why: a liveness property's lassos come back one behaviour at a time, while a safety
/// property's counterexamples rule out, along their environment, every machine that fails
/// there ([`super`]). `G (vac -> (vac U placed))` ("a held piece is held until it is placed")
/// contains "a held piece is not dropped before it is placed", which the encoding can carry.
pub(crate) fn safety_part(f: &Ltl, env: &dyn Fn(&str) -> bool) -> Option<Ltl> {
    fn b(f: Ltl) -> Box<Ltl> {
        Box::new(f)
    }
    fn walk(f: &Ltl, pos: bool, env: &dyn Fn(&str) -> bool) -> Option<Ltl> {
        use Ltl::*;
        if safety_at(f, true, env) && safety_at(f, false, env) {
            // No eventuality in either polarity (environment-only parts included).
            return Some(f.clone());
        }
        Some(match f {
            Not(a) => Not(b(walk(a, !pos, env)?)),
            And(x, y) => And(b(walk(x, pos, env)?), b(walk(y, pos, env)?)),
            Or(x, y) => Or(b(walk(x, pos, env)?), b(walk(y, pos, env)?)),
            Implies(x, y) => Implies(b(walk(x, !pos, env)?), b(walk(y, pos, env)?)),
            X(a) => X(b(walk(a, pos, env)?)),
            F(_) if pos => True,
            F(a) => F(b(walk(a, pos, env)?)),
            G(_) if !pos => False,
            G(a) => G(b(walk(a, pos, env)?)),
            U(x, y) if pos => {
                let (x, y) = (walk(x, pos, env)?, walk(y, pos, env)?);
                V(b(y.clone()), b(Or(b(x), b(y))))
            }
            U(x, y) => U(b(walk(x, pos, env)?), b(walk(y, pos, env)?)),
            V(x, y) if !pos => {
                let (x, y) = (walk(x, pos, env)?, walk(y, pos, env)?);
                U(b(y.clone()), b(And(b(x), b(y))))
            }
            V(x, y) => V(b(walk(x, pos, env)?), b(walk(y, pos, env)?)),
            // Eventualities in both polarities, or past operators: not weakened.
            _ => return None,
        })
    }
    if !covered(f) {
        return None;
    }
    let weak = constants_folded(walk(f, true, env)?);
    (weak != Ltl::True && is_safety(&weak, env)).then_some(weak)
}

/// `f` with `TRUE` and `FALSE` folded into the operators above them, so that a weakening
/// that says nothing comes out as `TRUE`.
fn constants_folded(f: Ltl) -> Ltl {
    use Ltl::*;
    let fold = |f: Box<Ltl>| constants_folded(*f);
    match f {
        Not(a) => match fold(a) {
            True => False,
            False => True,
            a => Not(Box::new(a)),
        },
        And(x, y) => match (fold(x), fold(y)) {
            (False, _) | (_, False) => False,
            (True, z) | (z, True) => z,
            (x, y) => And(Box::new(x), Box::new(y)),
        },
        Or(x, y) => match (fold(x), fold(y)) {
            (True, _) | (_, True) => True,
            (False, z) | (z, False) => z,
            (x, y) => Or(Box::new(x), Box::new(y)),
        },
        Implies(x, y) => match (fold(x), fold(y)) {
            (False, _) | (_, True) => True,
            (True, z) => z,
            (z, False) => Not(Box::new(z)),
            (x, y) => Implies(Box::new(x), Box::new(y)),
        },
        X(a) => match fold(a) {
            c @ (True | False) => c,
            a => X(Box::new(a)),
        },
        G(a) => match fold(a) {
            c @ (True | False) => c,
            a => G(Box::new(a)),
        },
        F(a) => match fold(a) {
            c @ (True | False) => c,
            a => F(Box::new(a)),
        },
        // `a V TRUE` and `a U TRUE` hold; `a V FALSE` and `a U FALSE` do not.
        V(x, y) => match fold(y) {
            c @ (True | False) => c,
            y => V(Box::new(fold(x)), Box::new(y)),
        },
        U(x, y) => match fold(y) {
            c @ (True | False) => c,
            y => U(Box::new(fold(x)), Box::new(y)),
        },
        f => f,
    }
}

/// Whether the encoding covers the formula: no past operators.
pub(crate) fn covered(f: &Ltl) -> bool {
    f.is_future_only()
}

/// The bounded encoding of one run; subformula literals are shared between the properties
/// encoded on it.
pub(crate) struct Bounded<'r> {
    run: &'r Run<'r>,
    memo: HashMap<(usize, usize, bool), B>,
    chains: HashMap<ChainKey, B>,
    exact: HashMap<usize, Vec<bool>>,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Chain {
    StrongUntil,
    WeakUntil,
    Release,
}

/// A chain position: operands by address and polarity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
struct ChainKey {
    a: Option<(usize, bool)>,
    b: (usize, bool),
    kind: Chain,
    t: usize,
}

impl<'r> Bounded<'r> {
    /// An encoding of `run` with nothing required yet.
    pub(crate) fn new(run: &'r Run<'r>) -> Bounded<'r> {
        Bounded {
            run,
            memo: HashMap::new(),
            chains: HashMap::new(),
            exact: HashMap::new(),
        }
    }

    /// Forces `φ` at position 0.
    pub(crate) fn require<F: ExtendFormula>(&mut self, g: &mut Gates<'_, F>, f: &Ltl) {
        let b = self.at(g, f, 0, true);
        g.clause(&[b]);
    }

    /// `⟦φ⟧t` (`pos`) or `⟦¬φ⟧t` (`!pos`).
    fn at<F: ExtendFormula>(&mut self, g: &mut Gates<'_, F>, f: &Ltl, t: usize, pos: bool) -> B {
        let key = (f as *const Ltl as usize, t, pos);
        if let Some(&b) = self.memo.get(&key) {
            return b;
        }
        let b = self.compute(g, f, t, pos);
        self.memo.insert(key, b);
        b
    }

    fn compute<F: ExtendFormula>(
        &mut self,
        g: &mut Gates<'_, F>,
        f: &Ltl,
        t: usize,
        pos: bool,
    ) -> B {
        use Ltl::*;
        if self.env_only(f) {
            let v = self.exact_at(f, t);
            return B::C(v == pos);
        }
        let last = self.run.last();
        match f {
            True => B::C(pos),
            False => B::C(!pos),
            Atom(_) | Cmp(..) => {
                let v = self.value(g, f, t);
                if pos {
                    v
                } else {
                    !v
                }
            }
            Int(_) => B::C(false),
            Not(a) => self.at(g, a, t, !pos),
            And(a, b) | Or(a, b) => {
                let x = self.at(g, a, t, pos);
                let y = self.at(g, b, t, pos);
                if matches!(f, And(..)) == pos {
                    g.and2(x, y)
                } else {
                    g.or2(x, y)
                }
            }
            Implies(a, b) => {
                let x = self.at(g, a, t, !pos);
                let y = self.at(g, b, t, pos);
                if pos {
                    g.or2(x, y)
                } else {
                    g.and2(x, y)
                }
            }
            Iff(a, b) | Xnor(a, b) => self.equivalence(g, (a, b), t, pos),
            Xor(a, b) => self.equivalence(g, (a, b), t, !pos),
            X(a) => {
                if t >= last {
                    B::C(true)
                } else {
                    self.at(g, a, t + 1, pos)
                }
            }
            // Each temporal operator in NNF is an until or a release; negation swaps them.
            F(a) => self.until_or_release(g, None, a, t, pos, true),
            G(a) => self.until_or_release(g, None, a, t, pos, false),
            U(a, b) => self.until_or_release(g, Some(a), b, t, pos, true),
            V(a, b) => self.until_or_release(g, Some(a), b, t, pos, false),
            // Not covered (see `covered`): never reached for an encoded property.
            Y(_) | Z(_) | H(_) | O(_) | S(..) | T(..) => B::C(true),
        }
    }

    /// `a <-> b` at `t` (`pos`), or its negation: `(a & b) | (!a & !b)`, negated
    /// `(a & !b) | (!a & b)`.
    fn equivalence<F: ExtendFormula>(
        &mut self,
        g: &mut Gates<'_, F>,
        (a, b): (&Ltl, &Ltl),
        t: usize,
        pos: bool,
    ) -> B {
        let (pa, na) = (self.at(g, a, t, true), self.at(g, a, t, false));
        let (pb, nb) = (self.at(g, b, t, true), self.at(g, b, t, false));
        let (x, y) = if pos {
            (g.and2(pa, pb), g.and2(na, nb))
        } else {
            (g.and2(pa, nb), g.and2(na, pb))
        };
        g.or2(x, y)
    }

    /// `a U b` (`is_until`) or `a V b` at `t` (with `a` absent: `F b` or `G b`), or with `pos`
    /// false its negation: the dual operator on the negated operands.
    fn until_or_release<F: ExtendFormula>(
        &mut self,
        g: &mut Gates<'_, F>,
        a: Option<&Ltl>,
        b: &Ltl,
        t: usize,
        pos: bool,
        is_until: bool,
    ) -> B {
        let (a, b) = (a.map(|a| (a, pos)), (b, pos));
        if is_until == pos {
            self.until(g, a, b, t)
        } else {
            self.release(g, a, b, t)
        }
    }

    /// `a U b` (with `a` absent: `F b`) at `t`, strong up to the deadline.
    fn until<F: ExtendFormula>(
        &mut self,
        g: &mut Gates<'_, F>,
        a: Option<(&Ltl, bool)>,
        b: (&Ltl, bool),
        t: usize,
    ) -> B {
        let kind = if t <= self.run.deadline {
            Chain::StrongUntil
        } else {
            Chain::WeakUntil
        };
        self.chain(g, a, b, t, kind)
    }

    fn release<F: ExtendFormula>(
        &mut self,
        g: &mut Gates<'_, F>,
        a: Option<(&Ltl, bool)>,
        b: (&Ltl, bool),
        t: usize,
    ) -> B {
        self.chain(g, a, b, t, Chain::Release)
    }

    /// The chain of `kind` over `a` and `b` at `t`, built from the end of the run (or from the
    /// first position already built) backwards, so that nothing recurses `L` deep.
    fn chain<F: ExtendFormula>(
        &mut self,
        g: &mut Gates<'_, F>,
        a: Option<(&Ltl, bool)>,
        b: (&Ltl, bool),
        t: usize,
        kind: Chain,
    ) -> B {
        let last = self.run.last();
        let id = |f: &Ltl| f as *const Ltl as usize;
        let key = |s: usize| ChainKey {
            a: a.map(|(f, p)| (id(f), p)),
            b: (id(b.0), b.1),
            kind,
            t: s,
        };
        let mut built = t;
        while built <= last && !self.chains.contains_key(&key(built)) {
            built += 1;
        }
        let mut after = if built > last {
            B::C(kind != Chain::StrongUntil)
        } else {
            self.chains[&key(built)]
        };
        for s in (t..built).rev() {
            let vb = self.at(g, b.0, s, b.1);
            let va = match a {
                Some((f, p)) => self.at(g, f, s, p),
                // `F b` is `TRUE U b`, `G b` is `FALSE V b`.
                None => B::C(kind != Chain::Release),
            };
            let v = if kind == Chain::Release {
                let keep = g.or2(va, after);
                g.and2(vb, keep)
            } else {
                let go = g.and2(va, after);
                g.or2(vb, go)
            };
            self.chains.insert(key(s), v);
            after = v;
        }
        after
    }

    /// The literal of an atom or comparison at `t`.
    fn value<F: ExtendFormula>(&self, g: &mut Gates<'_, F>, f: &Ltl, t: usize) -> B {
        let (x, y, op) = match f {
            Ltl::Cmp(op, l, r) => (self.operand(l, t), self.operand(r, t), *op),
            _ => (
                self.operand(f, t),
                Some(Fd::constant(Value::Bool(true))),
                CmpOp::Eq,
            ),
        };
        // Every name a property reads is in `atoms` (outputs, plant variables and defines,
        // both operands of a comparison) or a symbolic constant; the coupling check resolved
        // them before anything was encoded. Should one not resolve, nothing is ruled out: the
        // literal is free, and NuSMV judges the property.
        let (Some(x), Some(y)) = (x, y) else {
            return B::L(g.fresh());
        };
        let mut hits = Vec::new();
        for &(v, bv) in &x.0 {
            for &(w, bw) in &y.0 {
                if cmp(op, v, w) {
                    hits.push(g.and2(bv, bw));
                }
            }
        }
        g.or(&hits)
    }

    fn operand(&self, f: &Ltl, t: usize) -> Option<Fd> {
        match f {
            Ltl::Atom(n) => self.run.atoms[t]
                .get(n)
                .cloned()
                .or_else(|| (self.run.symbol)(n).map(Fd::constant)),
            Ltl::Int(i) => Some(Fd::constant(Value::Int(*i))),
            Ltl::True => Some(Fd::constant(Value::Bool(true))),
            Ltl::False => Some(Fd::constant(Value::Bool(false))),
            _ => None,
        }
    }

    fn env_only(&self, f: &Ltl) -> bool {
        f.is_future_only() && operand_names(f).iter().all(|n| self.run.is_env(n))
    }

    /// Exact value of an environment-only formula at run position `t`.
    fn exact_at(&mut self, f: &Ltl, t: usize) -> bool {
        let (n, l) = (self.run.env_len, self.run.env_loop);
        let p = if t < n { t } else { l + (t - l) % (n - l) };
        let id = f as *const Ltl as usize;
        if !self.exact.contains_key(&id) {
            let v = exact(self.run, f);
            self.exact.insert(id, v);
        }
        self.exact[&id][p]
    }
}

/// `v op w` on constants.
pub(crate) fn cmp(op: CmpOp, v: Value, w: Value) -> bool {
    match (op, v, w) {
        (CmpOp::Eq, _, _) => v == w,
        (CmpOp::Ne, _, _) => v != w,
        (CmpOp::Lt, Value::Int(a), Value::Int(b)) => a < b,
        (CmpOp::Le, Value::Int(a), Value::Int(b)) => a <= b,
        (CmpOp::Gt, Value::Int(a), Value::Int(b)) => a > b,
        (CmpOp::Ge, Value::Int(a), Value::Int(b)) => a >= b,
        _ => false,
    }
}

/// Values of an environment-only formula at every environment position, on its lasso.
fn exact(run: &Run<'_>, f: &Ltl) -> Vec<bool> {
    let (n, l) = (run.env_len, run.env_loop);
    let succ = |i: usize| if i + 1 < n { i + 1 } else { l };
    let value = |name: &str, i: usize| -> Option<Value> {
        run.env[i].get(name).copied().or_else(|| (run.symbol)(name))
    };
    let operand = |o: &Ltl, i: usize| -> Option<Value> {
        match o {
            Ltl::Atom(n) => value(n, i),
            Ltl::Int(k) => Some(Value::Int(*k)),
            Ltl::True => Some(Value::Bool(true)),
            Ltl::False => Some(Value::Bool(false)),
            _ => None,
        }
    };
    use Ltl::*;
    let fix = |a: &[bool], b: &[bool], least: bool| -> Vec<bool> {
        // least: v = b | a & v'; greatest: v = b & (a | v').
        let mut v = vec![!least; n];
        loop {
            let mut changed = false;
            for i in (0..n).rev() {
                let next = v[succ(i)];
                let new = if least {
                    b[i] || (a[i] && next)
                } else {
                    b[i] && (a[i] || next)
                };
                if new != v[i] {
                    v[i] = new;
                    changed = true;
                }
            }
            if !changed {
                return v;
            }
        }
    };
    match f {
        True => vec![true; n],
        False | Int(_) => vec![false; n],
        Atom(name) => (0..n)
            .map(|i| value(name, i) == Some(Value::Bool(true)))
            .collect(),
        Cmp(op, x, y) => (0..n)
            .map(|i| match (operand(x, i), operand(y, i)) {
                (Some(v), Some(w)) => cmp(*op, v, w),
                _ => false,
            })
            .collect(),
        Not(a) => exact(run, a).into_iter().map(|v| !v).collect(),
        And(a, b) | Or(a, b) | Implies(a, b) | Iff(a, b) | Xnor(a, b) | Xor(a, b) => {
            let (x, y) = (exact(run, a), exact(run, b));
            x.iter()
                .zip(&y)
                .map(|(&p, &q)| match f {
                    And(..) => p && q,
                    Or(..) => p || q,
                    Implies(..) => !p || q,
                    Iff(..) | Xnor(..) => p == q,
                    _ => p != q,
                })
                .collect()
        }
        X(a) => {
            let x = exact(run, a);
            (0..n).map(|i| x[succ(i)]).collect()
        }
        F(a) => fix(&vec![true; n], &exact(run, a), true),
        G(a) => fix(&vec![false; n], &exact(run, a), false),
        U(a, b) => fix(&exact(run, a), &exact(run, b), true),
        V(a, b) => fix(&exact(run, a), &exact(run, b), false),
        // Past operators are never environment-only here (`covered`).
        Y(_) | Z(_) | H(_) | O(_) | S(..) | T(..) => vec![true; n],
    }
}
