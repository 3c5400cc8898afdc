//! LTL to generalized Büchi automaton, by the tableau of Gerth, Peled, Vardi and Wolper.
//!
//! In: a future-only [`Ltl`] formula. Out: a [`Gba`] whose accepting runs are exactly the
//! words (sequences of valuations of the formula's atoms) that satisfy it; a formula with a
//! past operator is refused ([`Refused`]).
//!
//! # Method
//! The formula is put in negation normal form over `&`, `|`, `X`, `U` and `V` (`F a` is
//! `TRUE U a`, `G a` is `FALSE V a`; `->`, `<->`, `xor`, `xnor` are expanded), with atoms
//! (names and comparisons) numbered. The tableau expands nodes `(incoming, new, old, next)`:
//! a formula taken from `new` is decomposed into what must hold now and what must hold next
//! (`a U b = b | (a & X (a U b))`, `a V b = b & (a | X (a V b))`), splitting the node at each
//! disjunction; a fully expanded node is merged with an existing one of the same `old` and
//! `next`, or becomes a state whose successors are expanded from its `next`. A node holding
//! a literal and its negation is dropped. A state reads the literals of its `old` set: the
//! automaton is state-labelled, and a run `q0 q1 ...` accepts a word `w0 w1 ...` when each
//! `wi` satisfies the literals of `qi`. Acceptance: one set per until `a U b` of the formula,
//! the states where `b` holds or `a U b` is not promised, each visited infinitely often.
//!
//! # References
//! - R. Gerth, D. Peled, M. Y. Vardi, P. Wolper: *Simple on-the-fly automatic verification of
//!   linear temporal logic*, PSTV 1995.

use crate::ltl::Ltl;
use rustc_hash::FxHashMap;
use std::collections::BTreeSet;

/// A formula with a past operator, or too large for the automaton's bit sets.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Refused(pub(crate) String);

/// Index of a formula in [`Nnf`].
type F = u32;

/// A node of the negation normal form.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
enum Node {
    True,
    False,
    /// Atom index and polarity.
    Lit(u32, bool),
    And(F, F),
    Or(F, F),
    X(F),
    U(F, F),
    V(F, F),
}

/// Formulas in negation normal form, hash-consed, with their atoms.
#[derive(Debug, Default)]
struct Nnf {
    nodes: Vec<Node>,
    ids: FxHashMap<Node, F>,
    /// The atoms: names and comparisons, as they appear in the formula.
    atoms: Vec<Ltl>,
}

impl Nnf {
    fn add(&mut self, n: Node) -> F {
        if let Some(&f) = self.ids.get(&n) {
            return f;
        }
        let f = self.nodes.len() as F;
        self.nodes.push(n);
        self.ids.insert(n, f);
        f
    }

    fn atom(&mut self, a: &Ltl) -> u32 {
        match self.atoms.iter().position(|x| x == a) {
            Some(i) => i as u32,
            None => {
                self.atoms.push(a.clone());
                (self.atoms.len() - 1) as u32
            }
        }
    }

    /// `f` (or `!f` when `neg`) in negation normal form.
    fn build(&mut self, f: &Ltl, neg: bool) -> Result<F, Refused> {
        use Ltl::*;
        let node = match f {
            True => return Ok(self.add(if neg { Node::False } else { Node::True })),
            False => return Ok(self.add(if neg { Node::True } else { Node::False })),
            Atom(_) | Cmp(..) => {
                let a = self.atom(f);
                Node::Lit(a, !neg)
            }
            Int(i) => return Err(Refused(format!("integer {i} used as a formula"))),
            Not(a) => return self.build(a, !neg),
            And(a, b) | Or(a, b) => {
                let (x, y) = (self.build(a, neg)?, self.build(b, neg)?);
                if matches!(f, And(..)) != neg {
                    Node::And(x, y)
                } else {
                    Node::Or(x, y)
                }
            }
            Implies(a, b) => {
                // a -> b is !a | b; its negation a & !b.
                let (x, y) = (self.build(a, !neg)?, self.build(b, neg)?);
                if neg {
                    Node::And(x, y)
                } else {
                    Node::Or(x, y)
                }
            }
            Iff(a, b) | Xnor(a, b) | Xor(a, b) => {
                // a <-> b is (a & b) | (!a & !b); xor is its negation.
                let equal = !matches!(f, Xor(..)) != neg;
                let (pa, na) = (self.build(a, false)?, self.build(a, true)?);
                let (pb, nb) = (self.build(b, false)?, self.build(b, true)?);
                let (l, r) = if equal {
                    (self.add(Node::And(pa, pb)), self.add(Node::And(na, nb)))
                } else {
                    (self.add(Node::And(pa, nb)), self.add(Node::And(na, pb)))
                };
                Node::Or(l, r)
            }
            X(a) => Node::X(self.build(a, neg)?),
            F(a) | G(a) => {
                let body = self.build(a, neg)?;
                let eventually = matches!(f, F(_)) != neg;
                if eventually {
                    let t = self.add(Node::True);
                    Node::U(t, body)
                } else {
                    let ff = self.add(Node::False);
                    Node::V(ff, body)
                }
            }
            U(a, b) | V(a, b) => {
                // !(a U b) = !a V !b, !(a V b) = !a U !b.
                let (x, y) = (self.build(a, neg)?, self.build(b, neg)?);
                if matches!(f, U(..)) != neg {
                    Node::U(x, y)
                } else {
                    Node::V(x, y)
                }
            }
            Y(_) | Z(_) | H(_) | O(_) | S(..) | T(..) => {
                return Err(Refused(
                    "past operators (Y Z H O S T) are not supported by the in-process checker"
                        .into(),
                ))
            }
        };
        Ok(self.add(node))
    }
}

/// A state-labelled generalized Büchi automaton over the valuations of [`Gba::atoms`].
#[derive(Debug, Clone)]
pub(crate) struct Gba {
    /// The atoms the labels read, numbered as the bits of the masks.
    pub(crate) atoms: Vec<Ltl>,
    /// Per state: atoms that must be true (bit mask).
    pub(crate) pos: Vec<u64>,
    /// Per state: atoms that must be false.
    pub(crate) neg: Vec<u64>,
    /// Per state: the acceptance sets it belongs to (bit `i`: set `i`).
    pub(crate) accepting: Vec<u64>,
    /// Number of acceptance sets.
    pub(crate) sets: usize,
    pub(crate) initial: Vec<u32>,
    pub(crate) successors: Vec<Vec<u32>>,
}

impl Gba {
    /// The automaton of `f`. At most 64 atoms and 64 until subformulas.
    pub(crate) fn of(f: &Ltl) -> Result<Gba, Refused> {
        let mut nnf = Nnf::default();
        let root = nnf.build(f, false)?;
        if nnf.atoms.len() > 64 {
            return Err(Refused(format!(
                "{} atoms (the in-process checker takes at most 64)",
                nnf.atoms.len()
            )));
        }
        let tableau = Tableau::expand(&nnf, root);
        let untils: Vec<(F, F)> = (0..nnf.nodes.len() as F)
            .filter_map(|g| match nnf.nodes[g as usize] {
                Node::U(_, b) => Some((g, b)),
                _ => None,
            })
            .collect();
        if untils.len() > 64 {
            return Err(Refused(format!(
                "{} until subformulas (the in-process checker takes at most 64)",
                untils.len()
            )));
        }
        let n = tableau.states.len();
        let mut gba = Gba {
            atoms: nnf.atoms.clone(),
            pos: vec![0; n],
            neg: vec![0; n],
            accepting: vec![0; n],
            sets: untils.len(),
            initial: Vec::new(),
            successors: vec![Vec::new(); n],
        };
        for (q, s) in tableau.states.iter().enumerate() {
            for &g in &s.old {
                if let Node::Lit(a, p) = nnf.nodes[g as usize] {
                    if p {
                        gba.pos[q] |= 1 << a;
                    } else {
                        gba.neg[q] |= 1 << a;
                    }
                }
            }
            for (i, (u, b)) in untils.iter().enumerate() {
                if !s.old.contains(u) || s.old.contains(b) {
                    gba.accepting[q] |= 1 << i;
                }
            }
            for &p in &s.incoming {
                match p {
                    INIT => gba.initial.push(q as u32),
                    p => gba.successors[p].push(q as u32),
                }
            }
        }
        Ok(gba)
    }

    /// Whether state `q` accepts a letter where exactly the atoms in `valuation` hold.
    pub(crate) fn reads(&self, q: u32, valuation: u64) -> bool {
        let q = q as usize;
        valuation & self.pos[q] == self.pos[q] && valuation & self.neg[q] == 0
    }
}

/// The predecessor of initial states.
const INIT: usize = usize::MAX;

struct Expanded {
    incoming: BTreeSet<usize>,
    old: BTreeSet<F>,
}

#[derive(Clone)]
struct Pending {
    incoming: BTreeSet<usize>,
    new: BTreeSet<F>,
    old: BTreeSet<F>,
    next: BTreeSet<F>,
}

struct Tableau {
    states: Vec<Expanded>,
    /// `(old, next)` of each state, to merge equal nodes.
    index: FxHashMap<(BTreeSet<F>, BTreeSet<F>), usize>,
}

impl Pending {
    /// Each formula of `fs` to be processed, unless it already was.
    fn add_new(&mut self, fs: &[F]) {
        for f in fs {
            if !self.old.contains(f) {
                self.new.insert(*f);
            }
        }
    }
}

impl Tableau {
    fn expand(nnf: &Nnf, root: F) -> Tableau {
        let mut t = Tableau {
            states: Vec::new(),
            index: FxHashMap::default(),
        };
        let mut work = vec![Pending {
            incoming: BTreeSet::from([INIT]),
            new: BTreeSet::from([root]),
            old: BTreeSet::new(),
            next: BTreeSet::new(),
        }];
        while let Some(mut n) = work.pop() {
            let Some(g) = n.new.pop_first() else {
                t.close(n, &mut work);
                continue;
            };
            if n.old.contains(&g) {
                work.push(n);
                continue;
            }
            n.old.insert(g);
            work.extend(decompose(nnf, g, n));
        }
        t
    }

    /// A node with nothing left to process: merged into the state with the same `old` and
    /// `next` when there is one, else a new state, whose successor node starts from `next`.
    fn close(&mut self, n: Pending, work: &mut Vec<Pending>) {
        let key = (n.old, n.next);
        if let Some(&q) = self.index.get(&key) {
            self.states[q].incoming.extend(n.incoming);
            return;
        }
        let q = self.states.len();
        self.index.insert(key.clone(), q);
        work.push(Pending {
            incoming: BTreeSet::from([q]),
            new: key.1.clone(),
            old: BTreeSet::new(),
            next: BTreeSet::new(),
        });
        self.states.push(Expanded {
            incoming: n.incoming,
            old: key.0,
        });
    }
}

/// What node `n` becomes once formula `g` (just added to its `old`) is processed: nothing when
/// `g` contradicts it, else one node, or two for a disjunction, an until or a release, the
/// one to process first last.
fn decompose(nnf: &Nnf, g: F, mut n: Pending) -> Vec<Pending> {
    match nnf.nodes[g as usize] {
        Node::False => vec![],
        Node::True => vec![n],
        Node::Lit(a, p) => {
            let negation = nnf.ids.get(&Node::Lit(a, !p));
            if negation.is_some_and(|c| n.old.contains(c)) {
                return vec![];
            }
            vec![n]
        }
        Node::And(a, b) => {
            n.add_new(&[a, b]);
            vec![n]
        }
        Node::X(a) => {
            n.next.insert(a);
            vec![n]
        }
        Node::Or(a, b) | Node::U(a, b) | Node::V(a, b) => {
            // First branch: what holds now (a | ...: a; a U b: b; a V b: a & b);
            // second: the rest (b; a and X (a U b); b and X (a V b)).
            let mut first = n.clone();
            let mut second = n;
            match nnf.nodes[g as usize] {
                Node::Or(..) => {
                    first.add_new(&[a]);
                    second.add_new(&[b]);
                }
                Node::U(..) => {
                    first.add_new(&[b]);
                    second.add_new(&[a]);
                    second.next.insert(g);
                }
                _ => {
                    first.add_new(&[a, b]);
                    second.add_new(&[b]);
                    second.next.insert(g);
                }
            }
            vec![second, first]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    fn formula(text: &str) -> Ltl {
        crate::ltl::parse_spec(Path::new("t.ltl"), text)
            .unwrap()
            .remove(0)
            .formula
    }

    /// Whether the automaton accepts the lasso word `prefix (cycle)^ω`, each letter a
    /// valuation: a reachable product cycle through every acceptance set, by brute force.
    fn accepts(g: &Gba, prefix: &[u64], cycle: &[u64]) -> bool {
        let word: Vec<u64> = prefix.iter().chain(cycle).copied().collect();
        let n = word.len();
        let succ_pos = |i: usize| if i + 1 < n { i + 1 } else { prefix.len() };
        let nodes = g.pos.len();
        let id = |i: usize, q: u32| i * nodes + q as usize;
        // Reachable product nodes.
        let mut reach = vec![false; n * nodes];
        let mut stack: Vec<(usize, u32)> = g
            .initial
            .iter()
            .filter(|&&q| g.reads(q, word[0]))
            .map(|&q| (0, q))
            .collect();
        while let Some((i, q)) = stack.pop() {
            if std::mem::replace(&mut reach[id(i, q)], true) {
                continue;
            }
            let j = succ_pos(i);
            for &r in &g.successors[q as usize] {
                if g.reads(r, word[j]) {
                    stack.push((j, r));
                }
            }
        }
        // A reachable node on a cycle (within the loop part) that sees every set: take the
        // transitive closure restricted to loop positions.
        let all = if g.sets == 64 {
            u64::MAX
        } else {
            (1 << g.sets) - 1
        };
        let loop_nodes: Vec<(usize, u32)> = (prefix.len()..n)
            .flat_map(|i| (0..nodes as u32).map(move |q| (i, q)))
            .filter(|&(i, q)| reach[id(i, q)])
            .collect();
        for &(i0, q0) in &loop_nodes {
            // The product nodes on a cycle through (i0, q0) (none when it is on no cycle).
            let fwd = closure(g, &word, prefix.len(), (i0, q0), false);
            let bwd = closure(g, &word, prefix.len(), (i0, q0), true);
            let marks = (0..n * nodes)
                .filter(|&k| fwd[k] && bwd[k])
                .fold(0, |m, k| m | g.accepting[k % nodes]);
            if fwd[id(i0, q0)] && marks & all == all {
                return true;
            }
        }
        false
    }

    /// Product nodes reachable from `start` in one or more steps (`back`: that reach it).
    fn closure(g: &Gba, word: &[u64], l: usize, start: (usize, u32), back: bool) -> Vec<bool> {
        let n = word.len();
        let nodes = g.pos.len();
        let succ_pos = |i: usize| if i + 1 < n { i + 1 } else { l };
        let edge = |(a, p): (usize, u32), (b, s): (usize, u32)| {
            succ_pos(a) == b && g.successors[p as usize].contains(&s) && g.reads(s, word[b])
        };
        let neighbours = |v: (usize, u32)| -> Vec<(usize, u32)> {
            (l..n)
                .flat_map(|j| (0..nodes as u32).map(move |r| (j, r)))
                .filter(|&w| if back { edge(w, v) } else { edge(v, w) })
                .collect()
        };
        let mut seen = vec![false; n * nodes];
        let mut stack = neighbours(start);
        while let Some(v) = stack.pop() {
            let k = v.0 * nodes + v.1 as usize;
            if !std::mem::replace(&mut seen[k], true) {
                stack.extend(neighbours(v));
            }
        }
        seen
    }

    /// Every lasso word over atoms `a`, `b` with prefix and cycle of length 1..=2: the
    /// automaton accepts it iff the formula holds on it (by [`Ltl::holds_on_lasso`]).
    #[test]
    fn automata_agree_with_lasso_evaluation() {
        let formulas = [
            "a",
            "!a",
            "X a",
            "F a",
            "G a",
            "a U b",
            "a V b",
            "G F a",
            "F G a",
            "G (a -> F b)",
            "!(G (a -> F b))",
            "(F G !a) -> G (b -> F a)",
            "a xor X b",
            "(a <-> X a) U b",
            "!(a U (b V X a))",
            "G F a & G F b",
            "X X !a",
            "TRUE",
            "FALSE",
            "F (a & X !a) xnor G b",
        ];
        for text in formulas {
            let f = formula(text);
            let g = Gba::of(&f).unwrap();
            let ia = g.atoms.iter().position(|x| *x == Ltl::Atom("a".into()));
            let ib = g.atoms.iter().position(|x| *x == Ltl::Atom("b".into()));
            let letter = |v: u8| {
                let mut m = 0u64;
                if let (Some(i), true) = (ia, v & 1 == 1) {
                    m |= 1 << i;
                }
                if let (Some(i), true) = (ib, v & 2 == 2) {
                    m |= 1 << i;
                }
                m
            };
            for plen in 0..=2usize {
                for clen in 1..=2usize {
                    for code in 0..4u32.pow((plen + clen) as u32) {
                        let vals: Vec<u8> = (0..plen + clen)
                            .map(|k| ((code >> (2 * k)) & 3) as u8)
                            .collect();
                        let states: Vec<std::collections::BTreeMap<String, String>> = vals
                            .iter()
                            .map(|v| {
                                [("a", v & 1 == 1), ("b", v & 2 == 2)]
                                    .into_iter()
                                    .map(|(n, x)| {
                                        (n.to_string(), if x { "TRUE" } else { "FALSE" }.into())
                                    })
                                    .collect()
                            })
                            .collect();
                        let expected = f.holds_on_lasso(&states, plen).unwrap();
                        let letters: Vec<u64> = vals.iter().map(|&v| letter(v)).collect();
                        let got = accepts(&g, &letters[..plen], &letters[plen..]);
                        assert_eq!(got, expected, "{text} on {vals:?} loop at {plen}");
                    }
                }
            }
        }
    }

    #[test]
    fn past_operators_are_refused() {
        for text in ["Y a", "G (a -> O b)", "a S b", "F H a"] {
            assert!(Gba::of(&formula(text)).is_err(), "{text}");
        }
    }
}
