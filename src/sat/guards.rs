//! Guard minimization: the smallest guards (fewest literals) for a fixed structure.
//!
//! For one state `q` with transitions `i = 0..k` (one per distinct target), the scenarios fix:
//! - `P_i`: input vectors on which transition `i` must fire;
//! - `N`: input vectors on which nothing may fire (passive steps in state `q`).
//!
//! Every other input vector is a don't-care. Transitions are tried in priority order, so guard
//! `g_i` must hold on `P_i`, and be false on `N` and on `P_j` for every `j` *after* `i`; it may
//! be true on `P_j` for `j` before `i` (those fire first). The priority order is a variable
//! too: the encoding picks the order and the guards (each a DNF of at most `M` terms) with the
//! least total number of literals, by descending search on a totalizer bound.
//!
//! States are independent given the structure, so the sum of per-state minima is the global
//! minimum N for that structure ([`super::basic`] takes the least over every structure of the
//! least size). A time budget bounds the search: when it runs out, the best
//! guards found so far are kept (still correct, maybe not minimal), and the result says so.

use super::card::Totalizer;
use super::decode::Structure;
use super::solver::{Bounded, Model, Solver};
use crate::ecc::{guard::Literal, Guard, InputId, State, StateId, Transition};
use crate::scenario::tree::{NodeId, ScenarioTree};
use std::time::Instant;
use varisat::{ExtendFormula, Lit};

/// Guards of one state, in priority order.
#[derive(Debug, Clone)]
pub(crate) struct StateGuards {
    /// The state's transitions in priority order (the first whose guard holds fires).
    pub(crate) transitions: Vec<Transition>,
    /// Whether the literal count is proven minimal.
    pub(crate) exact: bool,
}

/// What the scenarios require of one state's guards.
#[derive(Debug, Clone, Default)]
pub(crate) struct GuardProblem {
    /// Targets, one transition each.
    pub(crate) targets: Vec<usize>,
    /// `positive[i]`: input vectors on which transition `i` fires.
    pub(crate) positive: Vec<Vec<Vec<bool>>>,
    /// Input vectors on which nothing fires.
    pub(crate) negative: Vec<Vec<bool>>,
    /// Number of input variables `X` the guards range over (the length of every vector).
    pub(crate) inputs: usize,
}

impl GuardProblem {
    /// The requirements on state `q` of a decoded structure. Inputs that negative scenarios
    /// need in state `q` (`Structure::care_inputs`) are cared for too: the solver's machine
    /// leaves those lassos through its choices there, so the guards must reproduce them.
    pub(crate) fn of_state(s: &Structure, tree: &ScenarioTree, q: usize) -> GuardProblem {
        let targets = s.targets(q);
        let positive = targets
            .iter()
            .map(|&t| {
                s.delta[q]
                    .iter()
                    .enumerate()
                    .filter(|(_, d)| **d == Some(t))
                    .map(|(u, _)| s.alphabet[u].clone())
                    .collect()
            })
            .collect();
        let mut negative: Vec<Vec<bool>> = Vec::new();
        for (n, node) in tree.nodes.iter().enumerate() {
            if s.colors[NodeId(n).0] != q {
                continue;
            }
            for &u in &node.passive {
                let x = &tree.input_vectors[u.0];
                if !negative.contains(x) {
                    negative.push(x.clone());
                }
            }
        }
        for &u in &s.care_inputs[q] {
            if s.delta[q][u].is_none() && !negative.contains(&s.alphabet[u]) {
                negative.push(s.alphabet[u].clone());
            }
        }
        GuardProblem {
            targets,
            positive,
            negative,
            inputs: tree.input_vectors.first().map_or(0, Vec::len),
        }
    }
}

/// One DNF term: (used, pos[x], neg[x]).
type Term = (Lit, Vec<Lit>, Vec<Lit>);

/// Variables of the guard encoding for one state.
struct GuardVars {
    /// `before[i][j]`: transition `i` has priority over `j`.
    before: Vec<Vec<Lit>>,
    /// Per transition, per term: (used, pos[x], neg[x]).
    terms: Vec<Vec<Term>>,
}

/// `OR_x` of the literals that make a term false on input vector `x` (term excludes `x`).
fn excluding(pos: &[Lit], neg: &[Lit], x: &[bool]) -> Vec<Lit> {
    x.iter()
        .enumerate()
        .map(|(i, &b)| if b { neg[i] } else { pos[i] })
        .collect()
}

fn encode(f: &mut impl ExtendFormula, p: &GuardProblem, max_terms: &[usize]) -> GuardVars {
    let k = p.targets.len();
    let before: Vec<Vec<Lit>> = (0..k)
        .map(|_| (0..k).map(|_| f.new_lit()).collect())
        .collect();
    // Priority is a strict total order: antisymmetric, total, transitive.
    for i in 0..k {
        f.add_clause(&[!before[i][i]]);
        for j in 0..k {
            if i != j {
                f.add_clause(&[before[i][j], before[j][i]]);
                f.add_clause(&[!before[i][j], !before[j][i]]);
                for l in 0..k {
                    if l != i && l != j {
                        f.add_clause(&[!before[i][j], !before[j][l], before[i][l]]);
                    }
                }
            }
        }
    }
    let mut terms = Vec::new();
    for i in 0..k {
        let ts: Vec<Term> = (0..max_terms[i])
            .map(|_| {
                let used = f.new_lit();
                let pos: Vec<Lit> = (0..p.inputs).map(|_| f.new_lit()).collect();
                let neg: Vec<Lit> = (0..p.inputs).map(|_| f.new_lit()).collect();
                for x in 0..p.inputs {
                    // A literal and its negation in one term: the term is empty. Forbid.
                    f.add_clause(&[!pos[x], !neg[x]]);
                    f.add_clause(&[!pos[x], used]);
                    f.add_clause(&[!neg[x], used]);
                }
                (used, pos, neg)
            })
            .collect();
        // Guard i covers each of its positive vectors with some term.
        for x in &p.positive[i] {
            let mut some = Vec::new();
            for (used, pos, neg) in &ts {
                let cov = f.new_lit();
                f.add_clause(&[!cov, *used]);
                for l in excluding(pos, neg, x) {
                    f.add_clause(&[!cov, !l]);
                }
                some.push(cov);
            }
            f.add_clause(&some);
        }
        // No term of guard i covers a negative vector, or a positive vector of a later transition.
        for (used, pos, neg) in &ts {
            for x in &p.negative {
                let mut c = excluding(pos, neg, x);
                c.push(!*used);
                f.add_clause(&c);
            }
            for (j, pj) in p.positive.iter().enumerate() {
                if j == i {
                    continue;
                }
                for x in pj {
                    let mut c = excluding(pos, neg, x);
                    c.push(!*used);
                    c.push(!before[i][j]);
                    f.add_clause(&c);
                }
            }
        }
        // Symmetry: used terms come first.
        for w in ts.windows(2) {
            f.add_clause(&[!w[1].0, w[0].0]);
        }
        terms.push(ts);
    }
    GuardVars { before, terms }
}

fn decode(model: &Model, v: &GuardVars, p: &GuardProblem) -> Vec<Transition> {
    let k = p.targets.len();
    let mut order: Vec<usize> = (0..k).collect();
    // Rank = number of transitions that come before; a total order, so ranks are distinct.
    order.sort_by_key(|&i| (0..k).filter(|&j| model.value(v.before[j][i])).count());
    order
        .into_iter()
        .map(|i| {
            let cubes: Vec<Vec<Literal>> = v.terms[i]
                .iter()
                .filter(|(used, _, _)| model.value(*used))
                .map(|(_, pos, neg)| {
                    (0..p.inputs)
                        .filter_map(|x| {
                            if model.value(pos[x]) {
                                Some((InputId(x), true))
                            } else if model.value(neg[x]) {
                                Some((InputId(x), false))
                            } else {
                                None
                            }
                        })
                        .collect()
                })
                .collect();
            Transition {
                target: StateId(p.targets[i]),
                guard: Guard::dnf(&absorbed(cubes)),
            }
        })
        .collect()
}

/// `cubes` without the ones another cube absorbs (`a | a & b` is `a`; a repeated cube counts
/// once): the same function in fewer literals. A minimization cut by its deadline can leave
/// them (`emergency | emergency` was seen on the distribution station).
fn absorbed(cubes: Vec<Vec<Literal>>) -> Vec<Vec<Literal>> {
    let within = |k: &[Literal], c: &[Literal]| k.iter().all(|l| c.contains(l));
    // The order of the rest is kept: it is how the guard reads.
    let drop: Vec<bool> = (0..cubes.len())
        .map(|i| {
            (0..cubes.len()).any(|j| {
                j != i && within(&cubes[j], &cubes[i]) && (!within(&cubes[i], &cubes[j]) || j < i)
            })
        })
        .collect();
    cubes
        .into_iter()
        .zip(drop)
        .filter_map(|(c, d)| (!d).then_some(c))
        .collect()
}

/// Guards of every state of a tree-exact structure, minimized state by state until
/// `deadline`, as [`State`]s named `s0..`; and whether every literal count is proven minimal.
pub(crate) fn all_states(
    s: &Structure,
    tree: &ScenarioTree,
    deadline: Instant,
) -> (Vec<State>, bool) {
    let mut exact = true;
    let states = (0..s.c)
        .map(|q| {
            let g = minimize_state(&GuardProblem::of_state(s, tree, q), deadline);
            exact &= g.exact;
            State {
                name: format!("s{q}"),
                algorithm: s.algorithms[q].clone(),
                transitions: g.transitions,
            }
        })
        .collect();
    (states, exact)
}

/// Minimizes the guards of one state; stops improving at `deadline` (keeps the best so far).
pub(crate) fn minimize_state(p: &GuardProblem, deadline: Instant) -> StateGuards {
    if p.targets.is_empty() {
        return StateGuards {
            transitions: Vec::new(),
            exact: true,
        };
    }
    // Few terms first: guards a person writes rarely need more than a handful, and the
    // encoding is small. One term per positive vector always suffices (minterms, in any
    // order), so the least count over that many terms is the true minimum: the few-terms
    // result is only called minimal once the full encoding has nothing smaller.
    let small: Vec<usize> = p.positive.iter().map(|ps| ps.len().min(3)).collect();
    let full: Vec<usize> = p.positive.iter().map(Vec::len).collect();
    let mut best: Option<(Vec<Transition>, usize)> = None;
    if small != full {
        if let Descent::Found(found, n, _) = descend(p, &small, None, deadline) {
            best = Some((found, n));
        }
    }
    match descend(p, &full, best.as_ref().map(|b| b.1), deadline) {
        Descent::Found(found, _, exact) => StateGuards {
            transitions: found,
            exact,
        },
        Descent::NoneBelow { proven } => {
            let (transitions, _) = best.expect("minterm guards always exist");
            StateGuards {
                transitions,
                exact: proven,
            }
        }
    }
}

/// What [`descend`] found.
enum Descent {
    /// Guards, their literal count, and whether it is proven least for the terms allowed.
    Found(Vec<Transition>, usize, bool),
    /// Nothing below the bound asked for: `proven`, or no answer before the deadline.
    NoneBelow { proven: bool },
}

/// The guards with at most `max_terms[i]` terms for transition `i` and the fewest literals
/// found before `deadline`, below `below` when given.
fn descend(
    p: &GuardProblem,
    max_terms: &[usize],
    below: Option<usize>,
    deadline: Instant,
) -> Descent {
    let mut s = Solver::new();
    s.keep_clauses();
    let vars = encode(&mut s, p, max_terms);
    let lits = literal_vars(&vars);
    let count = |ts: &[Transition]| ts.iter().map(|t| t.guard.literal_count()).sum::<usize>();
    let tot;
    let mut found;
    let mut n;
    match below {
        None => {
            let Some(m) = s.solve(&[]) else {
                return Descent::NoneBelow { proven: true };
            };
            found = decode(&m, &vars, p);
            n = count(&found);
            tot = Totalizer::new(&mut s, &lits, n);
        }
        Some(0) => return Descent::NoneBelow { proven: true },
        Some(b) => {
            tot = Totalizer::new(&mut s, &lits, b);
            let assume: Vec<Lit> = tot.at_most(b - 1).into_iter().collect();
            match s.solve_within(&assume, deadline) {
                Bounded::Sat(m) => {
                    found = decode(&m, &vars, p);
                    n = count(&found);
                }
                Bounded::Unsat => return Descent::NoneBelow { proven: true },
                Bounded::Unknown => return Descent::NoneBelow { proven: false },
            }
        }
    }
    let mut exact = n == 0;
    while n > 0 && Instant::now() < deadline {
        let assume: Vec<Lit> = tot.at_most(n - 1).into_iter().collect();
        let Some(m) = s.solve(&assume) else {
            exact = true;
            break;
        };
        found = decode(&m, &vars, p);
        n = count(&found);
        exact = n == 0;
    }
    Descent::Found(found, n, exact)
}

/// Every literal variable of the terms.
fn literal_vars(v: &GuardVars) -> Vec<Lit> {
    v.terms
        .iter()
        .flatten()
        .flat_map(|(_, pos, neg)| pos.iter().chain(neg).copied())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    fn v(s: &str) -> Vec<bool> {
        s.chars().map(|c| c == '1').collect()
    }

    fn solve(p: &GuardProblem) -> StateGuards {
        minimize_state(p, Instant::now() + Duration::from_secs(30))
    }

    fn check(p: &GuardProblem, g: &StateGuards) {
        for (i, ps) in p.positive.iter().enumerate() {
            for x in ps {
                let fired = g.transitions.iter().find(|t| t.guard.eval(x)).unwrap();
                assert_eq!(fired.target.0, p.targets[i]);
            }
        }
        for x in &p.negative {
            assert!(g.transitions.iter().all(|t| !t.guard.eval(x)));
        }
    }

    #[test]
    fn single_literal_when_one_input_decides() {
        // fire on 1x, stay on 0x
        let p = GuardProblem {
            targets: vec![1],
            positive: vec![vec![v("10"), v("11")]],
            negative: vec![v("00"), v("01")],
            inputs: 2,
        };
        let g = solve(&p);
        assert!(g.exact);
        assert_eq!(g.transitions[0].guard, Guard::Var(InputId(0)));
        check(&p, &g);
    }

    #[test]
    fn priority_lets_the_second_guard_be_true() {
        // to 1 on 11, to 2 on 10 and 01 and 00: with order (1, 2), g1 = a & b, g2 = TRUE: N = 2.
        let p = GuardProblem {
            targets: vec![2, 1],
            positive: vec![vec![v("10"), v("01"), v("00")], vec![v("11")]],
            negative: vec![],
            inputs: 2,
        };
        let g = solve(&p);
        check(&p, &g);
        assert!(g.exact);
        // Either order costs 2 (a & b then TRUE, or !a | !b then TRUE); never 3 or more.
        assert_eq!(
            g.transitions
                .iter()
                .map(|t| t.guard.literal_count())
                .sum::<usize>(),
            2
        );
        assert_eq!(g.transitions[1].guard, Guard::True);
    }

    #[test]
    fn xor_needs_two_terms() {
        let p = GuardProblem {
            targets: vec![1],
            positive: vec![vec![v("10"), v("01")]],
            negative: vec![v("00"), v("11")],
            inputs: 2,
        };
        let g = solve(&p);
        check(&p, &g);
        assert!(g.exact);
        assert_eq!(g.transitions[0].guard.literal_count(), 4);
    }

    #[test]
    fn absorbed_cubes_are_dropped() {
        let (a, b) = ((InputId(0), true), (InputId(1), false));
        assert_eq!(absorbed(vec![vec![a], vec![a]]), vec![vec![a]]);
        assert_eq!(absorbed(vec![vec![b, a], vec![a]]), vec![vec![a]]);
        assert_eq!(
            absorbed(vec![vec![b], vec![a, b], vec![a]]),
            vec![vec![b], vec![a]]
        );
        assert_eq!(absorbed(vec![vec![a], vec![b]]), vec![vec![a], vec![b]]);
    }
}
