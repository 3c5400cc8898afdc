//! Whether the recordings determine the machine: a *rival*, a second machine with the same
//! number of states that reproduces every recording but answers some input sequence
//! differently, found by SAT.
//!
//! In: the scenario tree, the number of states `C`, the input vectors sequences may use (the
//! alphabet: the tree's own first, then any others), a depth `L`, and the machines the rival
//! must differ from (the minimal machine, then the rivals already found). Out: a rival, or the
//! proof that none differs within `L` steps of a recorded point, or "unknown" at the deadline.
//!
//! # The encoding
//! The rival is the basic encoding's colouring of the tree with `C` states in the cube guard
//! model ([`super::cubes`]): guards are conjunctions inside the encoding, so the transition
//! function `y` is the rival's on every alphabet vector, recorded in its state or not. Its
//! states and transitions per state are bounded like the minimal machine's (`C`, `K`); its
//! transitions and guard literals are not, since a machine in service need not be minimal in
//! them (bounding them as well made the search several times slower on Pick-and-Place). A
//! rival found is then made smaller for a short while, so that it reads like the machine it
//! rivals.
//!
//! For every known machine `F` one *distinguishing path* is added: a start node `v` of the
//! tree (both machines are in the configurations they reach there, with the recorded output
//! values), then up to `L` input vectors of the alphabet. Per step, `F`'s move is a fixed
//! table and the rival's is read from `y` and its algorithms; the two agree (same `CNF` or
//! none, same output values) until the step marked as the difference, where they do not.
//! Since `F` is fixed, one path per known machine is linear in the tree, the alphabet and `L`.
//!
//! Differences are over alphabet sequences only: for recorded logs the alphabet is the input
//! combinations the plant was seen to produce, so every sequence reported can occur.

use super::card::Totalizer;
use super::constraints;
use super::decode;
use super::solver::{Bounded, Model, Solver};
use super::vars::{GuardModel, Vars};
use crate::ecc::{AlgorithmKind, Ecc, Guard, InputId, State, StateId};
use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};
use std::time::Instant;
use varisat::{ExtendFormula, Lit};

/// What a rival must be and do.
#[derive(Debug, Clone)]
pub(crate) struct Query<'a> {
    /// The scenario tree the rival must reproduce (every recorded point is a possible start of a
    /// distinguishing path).
    pub(crate) tree: &'a ScenarioTree,
    /// The algorithm form of the rival's states, as for the minimal machine.
    pub(crate) kind: AlgorithmKind,
    /// The rival's size, at most: states and transitions per state (the cube model's slots).
    pub(crate) states: usize,
    /// The largest out-degree `K` of the rival: transition slots per state in the cube model.
    pub(crate) max_out_degree: usize,
    /// Time to make a rival found smaller (fewer transitions, then fewer guard literals).
    pub(crate) polish: std::time::Duration,
    /// The input vectors distinguishing sequences may use; the tree's vectors come first, in
    /// the tree's order. Ignored with `every_vector`.
    pub(crate) alphabet: Vec<Vec<bool>>,
    /// Sequences over every input vector: each step's input is a vector of free bits and both
    /// machines' guards are evaluated on it, instead of a choice among the alphabet.
    pub(crate) every_vector: bool,
    /// The longest distinguishing sequence looked for.
    pub(crate) depth: usize,
    /// Names for the decoded rival.
    pub(crate) inputs: Vec<String>,
    /// Output names of the decoded rival, in scenario order.
    pub(crate) outputs: Vec<String>,
}

/// The answer of [`rival`].
#[derive(Debug, Clone)]
pub(crate) enum Outcome {
    /// A machine that reproduces the recordings and differs from every known machine.
    Rival(Ecc),
    /// None exists within the bounds.
    None,
    /// The deadline came first.
    Unknown,
}

/// Looks for a rival of every machine in `known` (each must replay the tree); once one is
/// found, looks for smaller ones (fewer transitions, then fewer guard literals) for
/// [`Query::polish`].
pub(crate) fn rival(q: &Query, known: &[&Ecc], deadline: Instant) -> Outcome {
    let mut s = Solver::new();
    s.keep_clauses();
    let (v, counters) = encode_rival(&mut s, q);
    for f in known {
        distinguishing_path(&mut s, q, &v, f);
    }
    let mut model = match s.solve_within(&[], deadline) {
        Bounded::Sat(model) => model,
        Bounded::Unsat => return Outcome::None,
        Bounded::Unknown => return Outcome::Unknown,
    };
    let polish = Instant::now() + q.polish;
    let mut fixed: Vec<Lit> = Vec::new();
    for Counter { lits, total } in &counters {
        while let Some(b) = model.count(lits).checked_sub(1) {
            let Some(bound) = total.at_most(b) else { break };
            let assume: Vec<Lit> = fixed.iter().copied().chain([bound]).collect();
            match s.solve_within(&assume, polish) {
                Bounded::Sat(m) => model = m,
                _ => break,
            }
        }
        fixed.extend(total.at_most(model.count(lits)));
    }
    Outcome::Rival(decode_rival(&model, q, &v))
}

/// The rival's colouring of the tree in the cube guard model, over the whole alphabet, with
/// counters of its transitions and guard literals.
fn encode_rival(f: &mut impl ExtendFormula, q: &Query) -> (Vars, [Counter; 2]) {
    let mut v = Vars::new(f, q.tree, q.states, Some(q.max_out_degree));
    let sel: Vec<Lit> = (0..v.inputs).map(|_| f.new_lit()).collect();
    let mut tails: Vec<Lit> = (0..q.states * q.states).map(|_| f.new_lit()).collect();
    constraints::basic(f, &v, q.tree, q.kind, false, &sel, &tails);
    let extra = match q.every_vector {
        true => &[][..],
        false => &q.alphabet[q.tree.input_vectors.len()..],
    };
    for bits in extra {
        let u = v.add_input(f);
        constraints::per_input(f, &v, u, bits, false);
        constraints::extend_edges(f, &v, u, &mut tails);
    }
    for &t in &tails {
        f.add_clause(&[!t]);
    }
    let GuardModel::Cubes(cv) = &v.guards else {
        unreachable!("built in the cube model")
    };
    let counters = [cv.all_en().to_vec(), cv.all_literals()].map(|lits| Counter {
        total: Totalizer::new(f, &lits, lits.len()),
        lits,
    });
    (v, counters)
}

/// Literals and their totalizer.
struct Counter {
    lits: Vec<Lit>,
    total: Totalizer,
}

/// The state `ecc` is in at every tree node (it replays the tree).
pub(crate) fn node_states(ecc: &Ecc, tree: &ScenarioTree) -> Vec<StateId> {
    let mut states = vec![StateId(0); tree.nodes.len()];
    let mut stack = vec![NodeId(0)];
    while let Some(p) = stack.pop() {
        for &(u, w) in &tree.nodes[p.0].children {
            let mut run = crate::ecc::sim::Run::new(ecc);
            run.state = states[p.0];
            run.outputs.clone_from(&tree.nodes[p.0].outputs);
            run.step(&tree.input_vectors[u.0]);
            states[w.0] = run.state;
            stack.push(w);
        }
    }
    states
}

/// One-hot literals of the rival's state (`m`), the fixed machine's state (`f`), the output
/// values before the step (`z`), and per step the input (`x`).
struct Config {
    m: Vec<Lit>,
    f: Vec<Lit>,
    z: Vec<Lit>,
}

fn config(s: &mut impl ExtendFormula, c: usize, cf: usize, outputs: usize) -> Config {
    let mut new = |n: usize| (0..n).map(|_| s.new_lit()).collect::<Vec<_>>();
    Config {
        m: new(c),
        f: new(cf),
        z: new(outputs),
    }
}

/// A path from a tree node on which `fixed` and the rival answer differently at some step.
fn distinguishing_path(s: &mut impl ExtendFormula, q: &Query, v: &Vars, fixed: &Ecc) {
    let (c, cf, nz) = (q.states, fixed.states.len(), v.outputs);
    let at = node_states(fixed, q.tree);
    // `fixed`'s move on every (state, alphabet vector): target, or None.
    let moves: Vec<Vec<Option<usize>>> = match q.every_vector {
        true => Vec::new(),
        false => (0..cf)
            .map(|p| {
                q.alphabet
                    .iter()
                    .map(|x| fixed.states[p].fired(x).map(|t| t.target.0))
                    .collect()
            })
            .collect(),
    };
    let start = config(s, c, cf, nz);
    start_at_some_node(s, q, v, &at, &start);
    let depth = q.depth.max(1);
    let stop: Vec<Lit> = (0..depth).map(|_| s.new_lit()).collect();
    s.add_clause(&stop);
    let live: Vec<Lit> = (0..depth).map(|_| s.new_lit()).collect();
    for t in 0..depth {
        s.add_clause(&[!stop[t], live[t]]);
        if t + 1 < depth {
            s.add_clause(&[!live[t + 1], live[t]]);
        }
    }
    let bits = q.inputs.len();
    let mut before = start;
    for t in 0..depth {
        let x: Vec<Lit> = match q.every_vector {
            true => (0..bits).map(|_| s.new_lit()).collect(),
            false => {
                let x: Vec<Lit> = (0..q.alphabet.len()).map(|_| s.new_lit()).collect();
                let mut clause = vec![!live[t]];
                clause.extend(&x);
                s.add_clause(&clause);
                x
            }
        };
        let after = config(s, c, cf, nz);
        let step = Step {
            live: live[t],
            stop: stop[t],
            fires_f: s.new_lit(),
            fires_m: s.new_lit(),
        };
        if q.every_vector {
            fixed_moves_on_bits(s, fixed, &step, &x, &before, &after);
            rival_moves_on_bits(s, v, &step, &x, &before, &after);
        } else {
            fixed_moves_on_alphabet(s, &moves, &step, &x, &before, &after);
            rival_moves_on_alphabet(s, v, &step, &x, &before, &after);
        }
        outputs_and_difference(s, v, fixed, &step, &before, &after);
        before = after;
    }
}

/// The start: some tree node `v`, the fixed machine in its state there, the rival in the
/// colour of `v`, the outputs as recorded at `v`.
fn start_at_some_node(
    s: &mut impl ExtendFormula,
    q: &Query,
    v: &Vars,
    at: &[StateId],
    start: &Config,
) {
    let nodes: Vec<Lit> = (0..q.tree.nodes.len()).map(|_| s.new_lit()).collect();
    s.add_clause(&nodes);
    for (n, &sv) in nodes.iter().enumerate() {
        s.add_clause(&[!sv, start.f[at[n].0]]);
        for (z, &value) in q.tree.nodes[n].outputs.iter().enumerate() {
            s.add_clause(&[!sv, if value { start.z[z] } else { !start.z[z] }]);
        }
        for st in 0..q.states {
            s.add_clause(&[!sv, !v.color(NodeId(n), st), start.m[st]]);
        }
    }
}

/// The literals of one step: whether the path still runs, whether this is the step of the
/// difference, and whether each machine answers (`CNF`).
struct Step {
    live: Lit,
    stop: Lit,
    fires_f: Lit,
    fires_m: Lit,
}

/// The fixed machine's move on the alphabet vector chosen (one of `x`): a table.
fn fixed_moves_on_alphabet(
    s: &mut impl ExtendFormula,
    moves: &[Vec<Option<usize>>],
    step: &Step,
    x: &[Lit],
    before: &Config,
    after: &Config,
) {
    for (p, row) in moves.iter().enumerate() {
        for (u, mv) in row.iter().enumerate() {
            let pre = [!step.live, !before.f[p], !x[u]];
            let (fires, target) = match *mv {
                Some(target) => (step.fires_f, target),
                None => (!step.fires_f, p),
            };
            s.add_clause(&[pre[0], pre[1], pre[2], fires]);
            s.add_clause(&[pre[0], pre[1], pre[2], after.f[target]]);
        }
    }
}

/// The rival's move on the alphabet vector chosen: its transition function `y`.
fn rival_moves_on_alphabet(
    s: &mut impl ExtendFormula,
    v: &Vars,
    step: &Step,
    x: &[Lit],
    before: &Config,
    after: &Config,
) {
    for m in 0..v.c_max {
        for (u, &xu) in x.iter().enumerate() {
            let pre = [!step.live, !before.m[m], !xu];
            for target in 0..v.c_max {
                let y = v.y(m, InputVec(u), target);
                s.add_clause(&[pre[0], pre[1], pre[2], !y, step.fires_m]);
                s.add_clause(&[pre[0], pre[1], pre[2], !y, after.m[target]]);
            }
            let none = v.y(m, InputVec(u), v.none());
            s.add_clause(&[pre[0], pre[1], pre[2], !none, !step.fires_m]);
            s.add_clause(&[pre[0], pre[1], pre[2], !none, after.m[m]]);
        }
    }
}

/// A literal equivalent to `g` on the input bits `x` (Tseitin).
fn guard_lit(s: &mut impl ExtendFormula, g: &Guard, x: &[Lit]) -> Lit {
    match g {
        Guard::Var(i) => x[i.0],
        Guard::Not(h) => !guard_lit(s, h, x),
        Guard::True | Guard::False => {
            let l = s.new_lit();
            s.add_clause(&[if matches!(g, Guard::True) { l } else { !l }]);
            l
        }
        Guard::And(gs) | Guard::Or(gs) => {
            let parts: Vec<Lit> = gs.iter().map(|h| guard_lit(s, h, x)).collect();
            let l = s.new_lit();
            // An Or is the negation of the And of the negations.
            let (out, sign) = match g {
                Guard::And(_) => (l, true),
                _ => (!l, false),
            };
            let parts: Vec<Lit> = parts.iter().map(|&p| if sign { p } else { !p }).collect();
            for &p in &parts {
                s.add_clause(&[!out, p]);
            }
            let mut clause: Vec<Lit> = parts.iter().map(|&p| !p).collect();
            clause.push(out);
            s.add_clause(&clause);
            l
        }
    }
}

/// `(clause of earlier) | !when[0] | ... -> each conclusion`: one clause per conclusion, the
/// negated premises in `earlier` (already negated) and `when` (negated here).
fn implies(s: &mut impl ExtendFormula, earlier: &[Lit], when: &[Lit], conclusions: &[Lit]) {
    for &concl in conclusions {
        let mut clause = earlier.to_vec();
        clause.extend(when.iter().map(|&w| !w));
        clause.push(concl);
        s.add_clause(&clause);
    }
}

/// The fixed machine's move on free input bits: its guards evaluated on them, first fires.
fn fixed_moves_on_bits(
    s: &mut impl ExtendFormula,
    fixed: &Ecc,
    step: &Step,
    x: &[Lit],
    before: &Config,
    after: &Config,
) {
    for (p, state) in fixed.states.iter().enumerate() {
        let holds: Vec<Lit> = state
            .transitions
            .iter()
            .map(|t| guard_lit(s, &t.guard, x))
            .collect();
        // `live & in p & none of the earlier guards & this one -> target, CNF`.
        let mut earlier = vec![!step.live, !before.f[p]];
        for (t, &h) in state.transitions.iter().zip(&holds) {
            implies(s, &earlier, &[h], &[step.fires_f, after.f[t.target.0]]);
            earlier.push(h);
        }
        implies(s, &earlier, &[], &[!step.fires_f, after.f[p]]);
    }
}

/// The rival's move on free input bits: its cube guards (slots) evaluated on them, first fires.
fn rival_moves_on_bits(
    s: &mut impl ExtendFormula,
    v: &Vars,
    step: &Step,
    x: &[Lit],
    before: &Config,
    after: &Config,
) {
    let GuardModel::Cubes(cv) = &v.guards else {
        unreachable!("the rival is encoded in the cube model")
    };
    for m in 0..v.c_max {
        let mut earlier = vec![!step.live, !before.m[m]];
        for k in 0..cv.max_out_degree {
            // fire <-> en & no literal of the cube is false on x.
            let fire = s.new_lit();
            let en = cv.en(0, m, k);
            s.add_clause(&[!fire, en]);
            let mut converse = vec![fire, !en];
            for (b, &xb) in x.iter().enumerate() {
                let (pos, neg) = (cv.pos(0, m, k, b), cv.neg(0, m, k, b));
                s.add_clause(&[!fire, !pos, xb]);
                s.add_clause(&[!fire, !neg, !xb]);
                // bad: this literal is false on x.
                let bad = s.new_lit();
                s.add_clause(&[!bad, pos, neg]);
                s.add_clause(&[!bad, pos, xb]);
                s.add_clause(&[!bad, neg, !xb]);
                converse.push(bad);
            }
            s.add_clause(&converse);
            for target in 0..v.c_max {
                let when = [fire, cv.tgt(0, m, k, target)];
                implies(s, &earlier, &when, &[step.fires_m, after.m[target]]);
            }
            earlier.push(fire);
        }
        implies(s, &earlier, &[], &[!step.fires_m, after.m[m]]);
    }
}

/// Both machines' outputs after the step, their agreement before the difference and their
/// disagreement at it. `after.z` holds the common outputs after a step that agrees.
fn outputs_and_difference(
    s: &mut impl ExtendFormula,
    v: &Vars,
    fixed: &Ecc,
    step: &Step,
    before: &Config,
    after: &Config,
) {
    let (c, nz) = (v.c_max, v.outputs);
    let (fires_f, fires_m, live) = (step.fires_f, step.fires_m, step.live);
    let zf: Vec<Lit> = (0..nz).map(|_| s.new_lit()).collect();
    let zm: Vec<Lit> = (0..nz).map(|_| s.new_lit()).collect();
    for (p, state) in fixed.states.iter().enumerate() {
        for (z, (&zb, &zn)) in before.z.iter().zip(&zf).enumerate() {
            for old in [false, true] {
                let new = state.algorithm.apply_one(z, old);
                let old_lit = if old { !zb } else { zb };
                let new_lit = if new { zn } else { !zn };
                s.add_clause(&[!live, !fires_f, !after.f[p], old_lit, new_lit]);
            }
        }
    }
    // The rival's algorithms.
    for m in 0..c {
        for (z, (&zb, &zn)) in before.z.iter().zip(&zm).enumerate() {
            for old in [false, true] {
                let a = v.a(m, z, old);
                let old_lit = if old { !zb } else { zb };
                s.add_clause(&[!live, !fires_m, !after.m[m], old_lit, !a, zn]);
                s.add_clause(&[!live, !fires_m, !after.m[m], old_lit, a, !zn]);
            }
        }
    }
    // Silent machines keep their outputs.
    for z in 0..nz {
        for (fires, zz) in [(fires_f, &zf), (fires_m, &zm)] {
            s.add_clause(&[!live, fires, !before.z[z], zz[z]]);
            s.add_clause(&[!live, fires, before.z[z], !zz[z]]);
        }
    }
    // Before the difference: the same answer, and the common outputs carried on.
    let agree = [!live, step.stop];
    s.add_clause(&[agree[0], agree[1], !fires_f, fires_m]);
    s.add_clause(&[agree[0], agree[1], fires_f, !fires_m]);
    for z in 0..nz {
        s.add_clause(&[agree[0], agree[1], !zf[z], zm[z]]);
        s.add_clause(&[agree[0], agree[1], zf[z], !zm[z]]);
        s.add_clause(&[agree[0], agree[1], !zf[z], after.z[z]]);
        s.add_clause(&[agree[0], agree[1], zf[z], !after.z[z]]);
    }
    // At the difference: one answers and the other does not, or the values differ.
    let mut differs = vec![!step.stop];
    let silent_one = s.new_lit();
    s.add_clause(&[!silent_one, fires_f, fires_m]);
    s.add_clause(&[!silent_one, !fires_f, !fires_m]);
    differs.push(silent_one);
    for z in 0..nz {
        let e = s.new_lit();
        s.add_clause(&[!e, zf[z], zm[z]]);
        s.add_clause(&[!e, !zf[z], !zm[z]]);
        differs.push(e);
    }
    s.add_clause(&differs);
}

/// The rival as an ECC: its cube transitions in priority order.
fn decode_rival(model: &Model, q: &Query, v: &Vars) -> Ecc {
    let c = (0..q.states)
        .take_while(|&s| model.value(v.used(s)))
        .count();
    let GuardModel::Cubes(cv) = &v.guards else {
        unreachable!("the rival is encoded in the cube model")
    };
    let states = (0..c)
        .map(|m| {
            let a0 = (0..v.outputs)
                .map(|z| model.value(v.a(m, z, false)))
                .collect();
            let a1 = (0..v.outputs)
                .map(|z| model.value(v.a(m, z, true)))
                .collect();
            State {
                name: format!("s{m}"),
                algorithm: decode::algorithm(q.kind, a0, a1),
                transitions: (0..cv.max_out_degree)
                    .filter(|&k| model.value(cv.en(0, m, k)))
                    .map(|k| decode::cube_transition(model, cv, 0, m, k, InputId))
                    .collect(),
            }
        })
        .collect();
    Ecc {
        inputs: q.inputs.clone(),
        outputs: q.outputs.clone(),
        initial_outputs: q.tree.nodes[0].outputs.clone(),
        states,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The Tseitin literal of a guard is forced to the guard's value on every input vector.
    #[test]
    fn guard_literals_agree_with_evaluation() {
        let var = |i| Guard::Var(InputId(i));
        let not = |g| Guard::Not(Box::new(g));
        let g = Guard::Or(vec![
            Guard::And(vec![var(0), not(var(1))]),
            var(2),
            Guard::False,
        ]);
        for guard in [
            g.clone(),
            not(g),
            Guard::True,
            Guard::And(vec![var(1), var(2)]),
        ] {
            for v in 0..8u32 {
                let bits: Vec<bool> = (0..3).map(|i| v >> i & 1 == 1).collect();
                let mut s = Solver::new();
                let x: Vec<Lit> = (0..3).map(|_| s.new_lit()).collect();
                let l = guard_lit(&mut s, &guard, &x);
                let assume: Vec<Lit> = x
                    .iter()
                    .zip(&bits)
                    .map(|(&l, &b)| if b { l } else { !l })
                    .collect();
                let m = s.solve(&assume).unwrap();
                assert_eq!(m.value(l), guard.eval(&bits), "{guard:?} on {bits:?}");
                // And the other value is impossible.
                let mut other = assume.clone();
                other.push(if guard.eval(&bits) { !l } else { l });
                assert!(s.solve(&other).is_none(), "{guard:?} on {bits:?}");
            }
        }
    }
}
