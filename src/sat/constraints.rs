//! The constraint families, one function each: first those every encoding shares (written
//! against one machine's [`Coloring`], so the basic, noisy and modular encodings use the same
//! code), then those of the basic ECC encoding.
//!
//! Together the basic families say: the nodes of the scenario tree are coloured with states so
//! that merging nodes of one colour gives a deterministic ECC (the SAT reconstruction paper, section IV.B; seed
//! 004's basic model) that reproduces every scenario. Each function writes into any clause sink
//! ([`ExtendFormula`]), so tests can inspect a [`varisat::CnfFormula`] while production writes
//! straight into the solver. Notation: `c[v,q]` colour, `y[q,u,q']` transition, `⊥` none,
//! `a0/a1[q,z]` algorithm, `t[q,q']` edge, `p[j,i]` BFS parent; for a module (the SAT reconstruction paper,
//! section V) `θ[z]` "owns output `z`" and `fired[w]` "fires on the tree edge into `w`".

use super::cubes;
use super::vars::{Coloring, GuardModel, Scope, Vars};
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

/// The active edges `p -u-> w` of the tree (every node but the root, with its parent).
pub(crate) fn tree_edges(
    tree: &ScenarioTree,
) -> impl Iterator<Item = (NodeId, InputVec, NodeId)> + '_ {
    tree.nodes
        .iter()
        .enumerate()
        .filter_map(|(w, node)| node.parent.map(|(p, u)| (p, u, NodeId(w))))
}

/// States in use form a prefix containing the initial state: `used[0]`, `used[q+1] -> used[q]`.
pub(crate) fn used_prefix(f: &mut impl ExtendFormula, c: &Coloring) {
    f.add_clause(&[c.used(0)]);
    for q in 1..c.c_max {
        f.add_clause(&[!c.used(q), c.used(q - 1)]);
    }
}

/// Every node has exactly one colour, a used one; the root has colour 0:
/// `ALO_q c[v,q]`, `AMO_q c[v,q]`, `c[v,q] -> used[q]`, `c[root,0]`.
pub(crate) fn coloring(f: &mut impl ExtendFormula, c: &Coloring) {
    for n in 0..c.nodes() {
        let lits: Vec<Lit> = (0..c.c_max).map(|q| c.color(NodeId(n), q)).collect();
        f.add_clause(&lits);
        at_most_one(f, &lits);
        for (q, &l) in lits.iter().enumerate() {
            f.add_clause(&[!l, c.used(q)]);
        }
    }
    f.add_clause(&[c.color(NodeId(0), 0)]);
}

/// Passive mark `(p, u)`: nothing fires in any machine, `c[p,q] -> idle[q,u]`, where
/// `idle(m, q, u)` is machine `m`'s literal "in state `q` nothing fires on `u`" (`y[q,u,⊥]` in
/// the basic encoding). (The passive step's target node is merged with `p` in the tree, so
/// "same colour" holds by construction.)
pub(crate) fn passive_marks(
    f: &mut impl ExtendFormula,
    tree: &ScenarioTree,
    machines: &[Coloring],
    idle: impl Fn(usize, usize, InputVec) -> Lit,
) {
    for (p, node) in tree.nodes.iter().enumerate() {
        for &u in &node.passive {
            for (m, c) in machines.iter().enumerate() {
                for q in 0..c.c_max {
                    f.add_clause(&[!c.color(NodeId(p), q), idle(m, q, u)]);
                }
            }
        }
    }
}

/// Outputs: entering `q'` over active edge `p -u-> w` turns the outputs of `p` into those of `w`:
/// `c[w,q'] -> (a_{z_p}[q',z] <-> z_w)`, where `a_{z_p}` is `a1` if output `z` was 1 at `p`,
/// else `a0`. A module does so only where it fires and only for the outputs it owns:
/// `fired[w] & c[w,q'] & θ[z] -> ...`.
///
/// Per state: tri algorithms forbid "flip", `a0[q,z] -> a1[q,z]`; a module's entries it never
/// reads (of unused states, of outputs it does not own) are 0 (symmetry breaking).
pub(crate) fn algorithms(
    f: &mut impl ExtendFormula,
    tree: &ScenarioTree,
    machines: &[Coloring],
    kind: AlgorithmKind,
) {
    for (p, _, w) in tree_edges(tree) {
        let old = &tree.nodes[p.0].outputs;
        let now = &tree.nodes[w.0].outputs;
        for c in machines {
            for q in 0..c.c_max {
                for (z, (&was, &now)) in old.iter().zip(now).enumerate() {
                    let a = c.a(q, z, was);
                    let mut clause = vec![!c.color(w, q), if now { a } else { !a }];
                    if let Scope::Module { owns, fires, .. } = c.scope {
                        clause.extend([!fires[w.0], !owns[z]]);
                    }
                    f.add_clause(&clause);
                }
            }
        }
    }
    for c in machines {
        for q in 0..c.c_max {
            for z in 0..c.outputs {
                let (a0, a1) = (c.a0(q, z), c.a1(q, z));
                if kind == AlgorithmKind::Tri {
                    f.add_clause(&[!a0, a1]);
                }
                if let Scope::Module { owns, .. } = c.scope {
                    for a in [a0, a1] {
                        f.add_clause(&[c.used(q), !a]);
                        f.add_clause(&[owns[z], !a]);
                    }
                }
            }
        }
    }
}

/// BFS symmetry breaking (Ulyantsev, Zakirzyanov, Shalyto 2015), the part independent of
/// inputs: states are numbered in the order a breadth-first search from state 0 visits them.
/// - `p[j,i] <-> t[i,j] & AND_{k<i} !t[k,j]` (the parent is the smallest predecessor), and
///   `!p[j,i]` for `i >= j`;
/// - `used[j] -> OR_{i<j} p[j,i]` for `j >= 1`;
/// - `p[j,i] -> !p[j+1,k]` for `k < i` (parents are non-decreasing).
///
/// A module may leave states unused (the SAT reconstruction paper, section V.D): `p[j,i] -> used[j]`, and state 0
/// has no parent.
///
/// Sound because every used state is reachable from state 0: each colour labels a tree node,
/// and the tree path to it consists of transitions. (Spurious `t` could only weaken it.)
pub(crate) fn bfs_parents(f: &mut impl ExtendFormula, c: &Coloring) {
    let n = c.c_max;
    let module = matches!(c.scope, Scope::Module { .. });
    // `!p[j,i]` for `i >= j`.
    let no_later_parent = |f: &mut _, j: usize| {
        for i in j..n {
            ExtendFormula::add_clause(f, &[!c.parent(j, i)]);
        }
    };
    for j in 1..n {
        let mut alo = vec![!c.used(j)];
        for i in 0..j {
            let p = c.parent(j, i);
            alo.push(p);
            f.add_clause(&[!p, c.edge(i, j)]);
            if module {
                f.add_clause(&[!p, c.used(j)]);
            }
            let mut back = vec![p, !c.edge(i, j)];
            for k in 0..i {
                f.add_clause(&[!p, !c.edge(k, j)]);
                back.push(c.edge(k, j));
            }
            f.add_clause(&back);
        }
        f.add_clause(&alo);
        if !module {
            no_later_parent(f, j);
        }
    }
    // A module's units come after the loop, state 0's included: the clause order the modular
    // encoding always had (the order steers the solver, hence which minimal controller it finds).
    if module {
        for j in 0..n {
            no_later_parent(f, j);
        }
    }
    for j in 1..n.saturating_sub(1) {
        for i in 0..j {
            for k in 0..i {
                f.add_clause(&[!c.parent(j, i), !c.parent(j + 1, k)]);
            }
        }
    }
}

/// Every `(q, u)` has exactly one target in `0..C_max ∪ {⊥}`; targets are used states.
pub(crate) fn transition_function(f: &mut impl ExtendFormula, v: &Vars, u: InputVec) {
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
///
/// (A module of the modular encoding may stay put on an active edge, so its edges have their
/// own family, [`super::modular::constraints::active_edges`].)
pub(crate) fn active_edges(f: &mut impl ExtendFormula, v: &Vars, tree: &ScenarioTree) {
    for (p, u, w) in tree_edges(tree) {
        for q in 0..v.c_max {
            for q2 in 0..v.c_max {
                f.add_clause(&[!v.color(p, q), !v.color(w, q2), v.y(q, u, q2)]);
                f.add_clause(&[!v.color(p, q), !v.y(q, u, q2), v.color(w, q2)]);
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
pub(crate) fn no_unexercised_transitions(
    f: &mut impl ExtendFormula,
    v: &Vars,
    tree: &ScenarioTree,
    sel: &[Lit],
) {
    let mut parents_on: Vec<Vec<NodeId>> = vec![Vec::new(); tree.input_vectors.len()];
    for (p, u, _) in tree_edges(tree) {
        if !parents_on[u.0].contains(&p) {
            parents_on[u.0].push(p);
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

/// Edge variables, part 1: `y[q,u,q'] -> t[q,q']` for one input.
pub(crate) fn edge_of_input(f: &mut impl ExtendFormula, v: &Vars, u: InputVec) {
    for q in 0..v.c_max {
        for q2 in 0..v.c_max {
            f.add_clause(&[!v.y(q, u, q2), v.t(q, q2)]);
        }
    }
}

/// Edge variables, part 2: `t[q,q'] -> OR_u y[q,u,q'] | tail[q,q']`, with `!tail` assumed.
/// The tail keeps the disjunction open for inputs added later ([`extend_edges`]).
pub(crate) fn edge_definition(f: &mut impl ExtendFormula, v: &Vars, tails: &[Lit]) {
    for q in 0..v.c_max {
        for q2 in 0..v.c_max {
            let mut clause = vec![!v.t(q, q2), tails[q * v.c_max + q2]];
            clause.extend((0..v.inputs).map(|u| v.y(q, InputVec(u), q2)));
            f.add_clause(&clause);
        }
    }
}

/// Extends every edge disjunction by input `u`: `tail_old -> y[q,u,q'] | tail_new`.
pub(crate) fn extend_edges(f: &mut impl ExtendFormula, v: &Vars, u: InputVec, tails: &mut [Lit]) {
    for q in 0..v.c_max {
        for q2 in 0..v.c_max {
            let new = f.new_lit();
            let old = std::mem::replace(&mut tails[q * v.c_max + q2], new);
            f.add_clause(&[!old, v.y(q, u, q2), new]);
        }
    }
}

/// BFS symmetry breaking, the part of one input `u`: siblings are ordered by the smallest
/// input leading to them.
/// - `nm[i,u+1,j] <-> nm[i,u,j] & !y[i,u,j]`, `m[i,u,j] <-> y[i,u,j] & nm[i,u,j]`;
/// - `p[j,i] & p[j+1,i] & m[i,u,j] -> nm[i,u,j+1]`.
pub(crate) fn bfs_input(f: &mut impl ExtendFormula, v: &Vars, u: InputVec) {
    let c = v.c_max;
    let col = v.coloring();
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
                !col.parent(j, i),
                !col.parent(j + 1, i),
                !v.m(i, u, j),
                v.nm(i, u.0, j + 1),
            ]);
        }
    }
}

/// The start of the chain of [`bfs_input`]: before the first input nothing leads anywhere,
/// `nm[i,0,j]`.
pub(crate) fn bfs_inputs_start(f: &mut impl ExtendFormula, v: &Vars) {
    for i in 0..v.c_max {
        for j in 0..v.c_max {
            f.add_clause(&[v.nm(i, 0, j)]);
        }
    }
}

/// fbSAT's convention (optional): state 0 is a start state that no transition enters,
/// `!y[q,u,0]`. The published fbSAT minima are counted under it, so it costs one state there.
pub(crate) fn start_state_never_entered(f: &mut impl ExtendFormula, v: &Vars, u: InputVec) {
    for q in 0..v.c_max {
        f.add_clause(&[!v.y(q, u, 0)]);
    }
}

/// The families of one input vector (`bits`: its values).
pub(crate) fn per_input(
    f: &mut impl ExtendFormula,
    v: &Vars,
    u: InputVec,
    bits: &[bool],
    start_state: bool,
) {
    transition_function(f, v, u);
    if let GuardModel::Cubes(cv) = &v.guards {
        cubes::input(f, v, cv, u, bits);
    }
    edge_of_input(f, v, u);
    bfs_input(f, v, u);
    if start_state {
        start_state_never_entered(f, v, u);
    }
}

/// The families every colouring of the tree by one ECC has, whatever labels its edges:
/// states, colours, the families of every input, passive marks and algorithms. Active edges
/// are the caller's (the basic and the noisy encodings differ there).
pub(crate) fn ecc_coloring(
    f: &mut impl ExtendFormula,
    v: &Vars,
    tree: &ScenarioTree,
    start_state: bool,
) {
    let c = v.coloring();
    used_prefix(f, &c);
    coloring(f, &c);
    if let GuardModel::Cubes(cv) = &v.guards {
        cubes::slots(f, cv, &c);
    }
    for u in 0..v.inputs {
        per_input(f, v, InputVec(u), &tree.input_vectors[u], start_state);
    }
}

/// The edge variables' definition and BFS symmetry breaking, last in every ECC encoding.
pub(crate) fn ecc_edges_and_bfs(f: &mut impl ExtendFormula, v: &Vars, tails: &[Lit]) {
    edge_definition(f, v, tails);
    bfs_parents(f, &v.coloring());
    bfs_inputs_start(f, v);
}

/// `y[q,u,⊥]`: the basic encoding's "nothing fires", for [`passive_marks`].
pub(crate) fn idle(v: &Vars) -> impl Fn(usize, usize, InputVec) -> Lit + '_ {
    move |_, q, u| v.y(q, u, v.none())
}

/// Every family of the basic encoding. `sel` and `tails` are the assumption literals of
/// [`no_unexercised_transitions`] and [`edge_definition`].
pub(crate) fn basic(
    f: &mut impl ExtendFormula,
    v: &Vars,
    tree: &ScenarioTree,
    kind: AlgorithmKind,
    start_state: bool,
    sel: &[Lit],
    tails: &[Lit],
) {
    ecc_coloring(f, v, tree, start_state);
    active_edges(f, v, tree);
    passive_marks(f, tree, &[v.coloring()], idle(v));
    // With guards in the encoding, transitions on unrecorded inputs follow from the guards.
    if let GuardModel::TreeExact = v.guards {
        no_unexercised_transitions(f, v, tree, sel);
    }
    algorithms(f, tree, &[v.coloring()], kind);
    ecc_edges_and_bfs(f, v, tails);
}
