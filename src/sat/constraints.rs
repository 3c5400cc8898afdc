//! The constraint families of the basic ECC encoding, one function each.
//!
//! Together they say: the nodes of the scenario tree are coloured with states so that merging
//! nodes of one colour gives a deterministic ECC (seed 000, section IV.B; seed 004's basic
//! model) that reproduces every scenario. Each function writes into any clause sink
//! ([`ExtendFormula`]), so tests can inspect a [`varisat::CnfFormula`] while production writes
//! straight into the solver. Notation: `c[v,q]` colour, `y[q,u,q']` transition, `⊥` none,
//! `a0/a1[q,z]` algorithm, `t[q,q']` edge, `p[j,i]` BFS parent.

use super::vars::Vars;
use crate::ecc::AlgorithmKind;
use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};
use varisat::{ExtendFormula, Lit};

/// Pairwise at-most-one.
pub(crate) fn at_most_one(f: &mut impl ExtendFormula, lits: &[Lit]) {
    for (i, &a) in lits.iter().enumerate() {
        for &b in &lits[i + 1..] {
            f.add_clause(&[!a, !b]);
        }
    }
}

/// States in use form a prefix: `used[q+1] -> used[q]`; the initial state is used.
pub fn used_prefix(f: &mut impl ExtendFormula, v: &Vars) {
    f.add_clause(&[v.used(0)]);
    for q in 1..v.c_max {
        f.add_clause(&[!v.used(q), v.used(q - 1)]);
    }
}

/// Every node has exactly one colour, a used one; the root has colour 0:
/// `ALO_q c[v,q]`, `AMO_q c[v,q]`, `c[v,q] -> used[q]`, `c[root,0]`.
pub fn coloring(f: &mut impl ExtendFormula, v: &Vars, tree: &ScenarioTree) {
    for n in 0..tree.nodes.len() {
        let node = NodeId(n);
        let lits: Vec<Lit> = (0..v.c_max).map(|q| v.color(node, q)).collect();
        f.add_clause(&lits);
        at_most_one(f, &lits);
        for q in 0..v.c_max {
            f.add_clause(&[!v.color(node, q), v.used(q)]);
        }
    }
    f.add_clause(&[v.color(tree.root(), 0)]);
}

/// Every `(q, u)` has exactly one target in `0..C_max ∪ {⊥}`; targets are used states.
pub fn transition_function(f: &mut impl ExtendFormula, v: &Vars, u: InputVec) {
    for q in 0..v.c_max {
        let lits: Vec<Lit> = (0..=v.c_max).map(|t| v.y(q, u, t)).collect();
        f.add_clause(&lits);
        at_most_one(f, &lits);
        for t in 0..v.c_max {
            f.add_clause(&[!v.y(q, u, t), v.used(t)]);
        }
    }
}

/// Active edge `p -u-> w`: `c[p,q] & c[w,q'] -> y[q,u,q']` and, for propagation,
/// `c[p,q] & y[q,u,q'] -> c[w,q']`.
pub fn active_edges(f: &mut impl ExtendFormula, v: &Vars, tree: &ScenarioTree) {
    for (w, node) in tree.nodes.iter().enumerate() {
        let Some((p, u)) = node.parent else { continue };
        let w = NodeId(w);
        for q in 0..v.c_max {
            for q2 in 0..v.c_max {
                f.add_clause(&[!v.color(p, q), !v.color(w, q2), v.y(q, u, q2)]);
                f.add_clause(&[!v.color(p, q), !v.y(q, u, q2), v.color(w, q2)]);
            }
        }
    }
}

/// Passive mark `(p, u)`: nothing fires, `c[p,q] -> y[q,u,⊥]`. (The passive step's target node
/// is merged with `p` in the tree, so "same colour" holds by construction.)
pub fn passive_marks(f: &mut impl ExtendFormula, v: &Vars, tree: &ScenarioTree) {
    for (p, node) in tree.nodes.iter().enumerate() {
        for &u in &node.passive {
            for q in 0..v.c_max {
                f.add_clause(&[!v.color(NodeId(p), q), v.y(q, u, v.none())]);
            }
        }
    }
}

/// Transitions never exercised by a scenario do not exist:
/// `!sel[u] | y[q,u,⊥] | OR_{p has an active child on u} c[p,q]`.
///
/// `sel[u]` is assumed true while `u` is an input of the scenarios only. Once a counterexample
/// uses `u`, the assumption is dropped: to leave a bad lasso the machine may need a transition
/// on an input where the scenarios saw it do nothing.
pub fn no_unexercised_transitions(
    f: &mut impl ExtendFormula,
    v: &Vars,
    tree: &ScenarioTree,
    sel: &[Lit],
) {
    let mut parents_on: Vec<Vec<NodeId>> = vec![Vec::new(); tree.input_vectors.len()];
    for node in &tree.nodes {
        if let Some((p, u)) = node.parent {
            if !parents_on[u.0].contains(&p) {
                parents_on[u.0].push(p);
            }
        }
    }
    for q in 0..v.c_max {
        for (u, parents) in parents_on.iter().enumerate() {
            let mut clause = vec![!sel[u], v.y(q, InputVec(u), v.none())];
            clause.extend(parents.iter().map(|&p| v.color(p, q)));
            f.add_clause(&clause);
        }
    }
}

/// Outputs: entering `q'` over active edge `p -u-> w` turns the outputs of `p` into those of `w`:
/// `c[w,q'] -> (a_{z_p}[q',z] <-> z_w)`, where `a_{z_p}` is `a1` if output `z` was 1 at `p`,
/// else `a0`. Tri algorithms also forbid "flip": `a0[q,z] -> a1[q,z]`.
pub fn algorithms(f: &mut impl ExtendFormula, v: &Vars, tree: &ScenarioTree, kind: AlgorithmKind) {
    for (w, node) in tree.nodes.iter().enumerate() {
        let Some((p, _)) = node.parent else { continue };
        let old = &tree.nodes[p.0].outputs;
        for q in 0..v.c_max {
            for (z, (&was, &now)) in old.iter().zip(&node.outputs).enumerate() {
                let a = v.a(q, z, was);
                let lit = if now { a } else { !a };
                f.add_clause(&[!v.color(NodeId(w), q), lit]);
            }
        }
    }
    if kind == AlgorithmKind::Tri {
        for q in 0..v.c_max {
            for z in 0..v.outputs {
                f.add_clause(&[!v.a0(q, z), v.a1(q, z)]);
            }
        }
    }
}

/// Edge variables, part 1: `y[q,u,q'] -> t[q,q']` for one input.
pub fn edge_of_input(f: &mut impl ExtendFormula, v: &Vars, u: InputVec) {
    for q in 0..v.c_max {
        for q2 in 0..v.c_max {
            f.add_clause(&[!v.y(q, u, q2), v.t(q, q2)]);
        }
    }
}

/// Edge variables, part 2: `t[q,q'] -> OR_u y[q,u,q'] | tail[q,q']`, with `!tail` assumed.
/// The tail keeps the disjunction open for inputs added later ([`extend_edges`]).
pub fn edge_definition(f: &mut impl ExtendFormula, v: &Vars, tails: &[Lit]) {
    for q in 0..v.c_max {
        for q2 in 0..v.c_max {
            let mut clause = vec![!v.t(q, q2), tails[q * v.c_max + q2]];
            clause.extend((0..v.inputs).map(|u| v.y(q, InputVec(u), q2)));
            f.add_clause(&clause);
        }
    }
}

/// Extends every edge disjunction by input `u`: `tail_old -> y[q,u,q'] | tail_new`.
pub fn extend_edges(f: &mut impl ExtendFormula, v: &Vars, u: InputVec, tails: &mut [Lit]) {
    for q in 0..v.c_max {
        for q2 in 0..v.c_max {
            let new = f.new_lit();
            let old = std::mem::replace(&mut tails[q * v.c_max + q2], new);
            f.add_clause(&[!old, v.y(q, u, q2), new]);
        }
    }
}

/// BFS symmetry breaking (Ulyantsev, Zakirzyanov, Shalyto 2015), the part independent of
/// inputs: states are numbered in the order a breadth-first search from state 0 visits them.
/// - `p[j,i] <-> t[i,j] & AND_{k<i} !t[k,j]` (the parent is the smallest predecessor);
/// - `used[j] -> OR_{i<j} p[j,i]` for `j >= 1`;
/// - `p[j,i] -> !p[j+1,k]` for `k < i` (parents are non-decreasing).
///
/// Sound because every used state is reachable from state 0: each colour labels a tree node,
/// and the tree path to it consists of transitions. (Spurious `t` could only weaken it.)
pub fn bfs_parents(f: &mut impl ExtendFormula, v: &Vars) {
    let c = v.c_max;
    for j in 1..c {
        let mut alo = vec![!v.used(j)];
        for i in 0..j {
            let p = v.p(j, i);
            alo.push(p);
            f.add_clause(&[!p, v.t(i, j)]);
            let mut back = vec![p, !v.t(i, j)];
            for k in 0..i {
                f.add_clause(&[!p, !v.t(k, j)]);
                back.push(v.t(k, j));
            }
            f.add_clause(&back);
        }
        f.add_clause(&alo);
        for i in j..c {
            f.add_clause(&[!v.p(j, i)]);
        }
    }
    for j in 1..c.saturating_sub(1) {
        for i in 0..j {
            for k in 0..i {
                f.add_clause(&[!v.p(j, i), !v.p(j + 1, k)]);
            }
        }
    }
    for i in 0..c {
        for j in 0..c {
            f.add_clause(&[v.nm(i, 0, j)]);
        }
    }
}

/// BFS symmetry breaking, the part of one input `u`: siblings are ordered by the smallest
/// input leading to them.
/// - `nm[i,u+1,j] <-> nm[i,u,j] & !y[i,u,j]`, `m[i,u,j] <-> y[i,u,j] & nm[i,u,j]`;
/// - `p[j,i] & p[j+1,i] & m[i,u,j] -> nm[i,u,j+1]`.
pub fn bfs_input(f: &mut impl ExtendFormula, v: &Vars, u: InputVec) {
    let c = v.c_max;
    for i in 0..c {
        for j in 0..c {
            let (y, nm, nm1, m) = (
                v.y(i, u, j),
                v.nm(i, u.0, j),
                v.nm(i, u.0 + 1, j),
                v.m(i, u, j),
            );
            f.add_clause(&[!nm1, nm]);
            f.add_clause(&[!nm1, !y]);
            f.add_clause(&[nm1, !nm, y]);
            f.add_clause(&[!m, y]);
            f.add_clause(&[!m, nm]);
            f.add_clause(&[m, !y, !nm]);
        }
    }
    for j in 1..c.saturating_sub(1) {
        for i in 0..j {
            f.add_clause(&[
                !v.p(j, i),
                !v.p(j + 1, i),
                !v.m(i, u, j),
                v.nm(i, u.0, j + 1),
            ]);
        }
    }
}

/// fbSAT's convention (optional): state 0 is a start state that no transition enters,
/// `!y[q,u,0]`. The published fbSAT minima are counted under it, so it costs one state there.
pub fn start_state_never_entered(f: &mut impl ExtendFormula, v: &Vars, u: InputVec) {
    for q in 0..v.c_max {
        f.add_clause(&[!v.y(q, u, 0)]);
    }
}

/// The families of one input vector (`bits`: its values).
pub fn per_input(
    f: &mut impl ExtendFormula,
    v: &Vars,
    u: InputVec,
    bits: &[bool],
    start_state: bool,
) {
    transition_function(f, v, u);
    if v.cubes.is_some() {
        super::cubes::input(f, v, u, bits);
    }
    edge_of_input(f, v, u);
    bfs_input(f, v, u);
    if start_state {
        start_state_never_entered(f, v, u);
    }
}

/// Every family of the basic encoding. `sel` and `tails` are the assumption literals of
/// [`no_unexercised_transitions`] and [`edge_definition`].
pub fn basic(
    f: &mut impl ExtendFormula,
    v: &Vars,
    tree: &ScenarioTree,
    kind: AlgorithmKind,
    start_state: bool,
    sel: &[Lit],
    tails: &[Lit],
) {
    used_prefix(f, v);
    coloring(f, v, tree);
    if v.cubes.is_some() {
        super::cubes::slots(f, v);
    }
    for u in 0..v.inputs {
        per_input(f, v, InputVec(u), &tree.input_vectors[u], start_state);
    }
    active_edges(f, v, tree);
    passive_marks(f, v, tree);
    // With guards in the encoding, transitions on unrecorded inputs follow from the guards.
    if v.cubes.is_none() {
        no_unexercised_transitions(f, v, tree, sel);
    }
    algorithms(f, v, tree, kind);
    edge_definition(f, v, tails);
    bfs_parents(f, v);
}
