//! The constraint families of the modular encoding (seed 000, section V), one function each.
//!
//! Together they say: every tree node gets one colour per module, so that each module's
//! colouring is the run of a deterministic ECC with conjunctive guards over the module's inputs
//! (first-fire order), each output belongs to one module whose transitions produce its values,
//! and the composite fires exactly on the active steps ([`crate::ecc::modular`] semantics).
//! Notation as in [`super::vars`]; `⊥` never appears, "nothing fires" is `nf[m,g,q,K]`.

use super::vars::ModVars;
use crate::ecc::{AlgorithmKind, OutputId};
use crate::sat::constraints::at_most_one;
use crate::sat::cubes::first_fire;
use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};
use varisat::{ExtendFormula, Lit};

/// Used states of every module form a prefix containing state 0:
/// `uc[m,0]`, `uc[m,q+1] -> uc[m,q]` (the paper's `¬uc[m,n] -> ¬uc[m,n+1]`).
pub fn used_prefix(f: &mut impl ExtendFormula, v: &ModVars) {
    for m in 0..v.d.modules {
        f.add_clause(&[v.used(m, 0)]);
        for q in 1..v.d.c_max {
            f.add_clause(&[!v.used(m, q), v.used(m, q - 1)]);
        }
    }
}

/// Exactly one colour per node and module, a used one; the root has colour 0 everywhere.
pub fn coloring(f: &mut impl ExtendFormula, v: &ModVars) {
    for m in 0..v.d.modules {
        for n in 0..v.d.nodes {
            let lits: Vec<Lit> = (0..v.d.c_max).map(|q| v.color(m, NodeId(n), q)).collect();
            f.add_clause(&lits);
            at_most_one(f, &lits);
            for (q, &c) in lits.iter().enumerate() {
                f.add_clause(&[!c, v.used(m, q)]);
            }
        }
        f.add_clause(&[v.color(m, NodeId(0), 0)]);
    }
}

/// θ: every output belongs to exactly one module; pinned outputs to their module
/// (`pins[m]` lists the outputs pinned to module `m`).
pub fn output_owner(f: &mut impl ExtendFormula, v: &ModVars, pins: &[Vec<OutputId>]) {
    for z in 0..v.d.outputs {
        let lits: Vec<Lit> = (0..v.d.modules).map(|m| v.theta(m, z)).collect();
        f.add_clause(&lits);
        at_most_one(f, &lits);
    }
    for (m, zs) in pins.iter().enumerate() {
        for z in zs {
            f.add_clause(&[v.theta(m, z.0)]);
        }
    }
}

/// Interchangeable modules are ordered by their smallest output: module `m >= 1` owns `z` only
/// if module `m - 1` owns a smaller output, `θ[m,z] -> OR_{z'<z} θ[m-1,z']`. Sound because any
/// decomposition can be renumbered so; used only when nothing is pinned.
pub fn module_order(f: &mut impl ExtendFormula, v: &ModVars) {
    for m in 1..v.d.modules {
        for z in 0..v.d.outputs {
            let mut clause = vec![!v.theta(m, z)];
            clause.extend((0..z).map(|z2| v.theta(m - 1, z2)));
            f.add_clause(&clause);
        }
    }
}

/// Transition slots: `en[k+1] -> en[k]`, `en -> uc[q]`, `en <-> exactly one tgt[·]`,
/// `tgt[q'] -> uc[q']`, guards are consistent cubes over the module's inputs:
/// `¬(pos & neg)`, `pos|neg -> en`, `pos|neg -> α[m,x]`.
pub fn slots(f: &mut impl ExtendFormula, v: &ModVars) {
    let d = v.d;
    for m in 0..d.modules {
        for q in 0..d.c_max {
            for k in 0..d.slots {
                let en = v.en(m, q, k);
                if k + 1 < d.slots {
                    f.add_clause(&[!v.en(m, q, k + 1), en]);
                }
                f.add_clause(&[!en, v.used(m, q)]);
                let tg: Vec<Lit> = (0..d.c_max).map(|t| v.tgt(m, q, k, t)).collect();
                let mut alo = vec![!en];
                alo.extend(&tg);
                f.add_clause(&alo);
                at_most_one(f, &tg);
                for (t, &l) in tg.iter().enumerate() {
                    f.add_clause(&[!l, en]);
                    f.add_clause(&[!l, v.used(m, t)]);
                }
                for x in 0..d.bits {
                    let (p, n) = (v.pos(m, q, k, x), v.neg(m, q, k, x));
                    f.add_clause(&[!p, !n]);
                    for l in [p, n] {
                        f.add_clause(&[!l, en]);
                        f.add_clause(&[!l, v.alpha(m, x)]);
                    }
                }
            }
        }
    }
}

/// Firing on input vector `g` with bits `bits` (the paper's `f` and `nf`):
/// `f[m,g,q,k] <-> en & AND_{x: g_x=1} ¬neg[x] & AND_{x: g_x=0} ¬pos[x]`;
/// `nf[·,0]`, `nf[·,k+1] <-> nf[·,k] & ¬f[·,k]`. The first slot that fires is the one with
/// `nf[k] & f[k]` (the paper's `ff`); nothing fires iff `nf[K]`.
pub fn firing(f: &mut impl ExtendFormula, v: &ModVars, g: InputVec, bits: &[bool]) {
    let d = v.d;
    for m in 0..d.modules {
        for q in 0..d.c_max {
            f.add_clause(&[v.nf(m, g, q, 0)]);
            for k in 0..d.slots {
                let (fire, en) = (v.fire(m, g, q, k), v.en(m, q, k));
                // The literals that make the guard false on g.
                let killers: Vec<Lit> = bits
                    .iter()
                    .enumerate()
                    .map(|(x, &b)| {
                        if b {
                            v.neg(m, q, k, x)
                        } else {
                            v.pos(m, q, k, x)
                        }
                    })
                    .collect();
                let (nf, nf1) = (v.nf(m, g, q, k), v.nf(m, g, q, k + 1));
                first_fire(f, [fire, en, nf, nf1], &killers);
            }
        }
    }
}

/// Active tree edge `p -g-> w`, per module `m`:
/// - `fired[m,w] <-> OR_q c[m,p,q] & ¬nf[m,g,q,K]` (the module makes a transition);
/// - `c[m,p,q] & nf[m,g,q,k] & f[m,g,q,k] & tgt[m,q,k,q'] -> c[m,w,q']` (first fire decides);
/// - `c[m,p,q] & nf[m,g,q,K] -> c[m,w,q]` (no transition: the colour is kept);
/// - `θ[m,z] -> fired[m,w]` for every output `z` that changes on the edge;
/// - `OR_m fired[m,w]`: some module fires, so the composite emits `CNF`.
pub fn active_edges(f: &mut impl ExtendFormula, v: &ModVars, tree: &ScenarioTree) {
    let d = v.d;
    for (w, node) in tree.nodes.iter().enumerate() {
        let Some((p, g)) = node.parent else { continue };
        let w = NodeId(w);
        for m in 0..d.modules {
            let fired = v.fired(m, w);
            for q in 0..d.c_max {
                let (cp, none) = (v.color(m, p, q), v.nf(m, g, q, d.slots));
                f.add_clause(&[!cp, !none, !fired]);
                f.add_clause(&[!cp, none, fired]);
                f.add_clause(&[!cp, !none, v.color(m, w, q)]);
                for k in 0..d.slots {
                    let (nf, fire) = (v.nf(m, g, q, k), v.fire(m, g, q, k));
                    for t in 0..d.c_max {
                        f.add_clause(&[!cp, !nf, !fire, !v.tgt(m, q, k, t), v.color(m, w, t)]);
                    }
                }
            }
            let old = &tree.nodes[p.0].outputs;
            for (z, (a, b)) in old.iter().zip(&node.outputs).enumerate() {
                if a != b {
                    f.add_clause(&[!v.theta(m, z), fired]);
                }
            }
        }
        let any: Vec<Lit> = (0..d.modules).map(|m| v.fired(m, w)).collect();
        f.add_clause(&any);
    }
}

/// Passive mark `(p, g)`: no module fires, `c[m,p,q] -> nf[m,g,q,K]`.
pub fn passive_marks(f: &mut impl ExtendFormula, v: &ModVars, tree: &ScenarioTree) {
    for (p, node) in tree.nodes.iter().enumerate() {
        for &g in &node.passive {
            for m in 0..v.d.modules {
                for q in 0..v.d.c_max {
                    f.add_clause(&[!v.color(m, NodeId(p), q), v.nf(m, g, q, v.d.slots)]);
                }
            }
        }
    }
}

/// Output algorithms: a module that fires on edge `p -> w` into state `q'` produces its outputs'
/// values at `w`: `fired[m,w] & c[m,w,q'] & θ[m,z] -> (d_{z_p}[m,q',z] <-> z_w)`.
/// Tri algorithms forbid "flip" (`d0 -> d1`). Algorithms of unused states and entries of outputs
/// the module does not own are fixed to 0 (symmetry: they are never read).
pub fn algorithms(
    f: &mut impl ExtendFormula,
    v: &ModVars,
    tree: &ScenarioTree,
    kind: AlgorithmKind,
) {
    let d = v.d;
    for (w, node) in tree.nodes.iter().enumerate() {
        let Some((p, _)) = node.parent else { continue };
        let old = &tree.nodes[p.0].outputs;
        for m in 0..d.modules {
            for q in 0..d.c_max {
                for (z, (&was, &now)) in old.iter().zip(&node.outputs).enumerate() {
                    let a = v.a(m, q, z, was);
                    f.add_clause(&[
                        !v.fired(m, NodeId(w)),
                        !v.color(m, NodeId(w), q),
                        !v.theta(m, z),
                        if now { a } else { !a },
                    ]);
                }
            }
        }
    }
    for m in 0..d.modules {
        for q in 0..d.c_max {
            for z in 0..d.outputs {
                let (a0, a1) = (v.a0(m, q, z), v.a1(m, q, z));
                if kind == AlgorithmKind::Tri {
                    f.add_clause(&[!a0, a1]);
                }
                for a in [a0, a1] {
                    f.add_clause(&[v.used(m, q), !a]);
                    f.add_clause(&[v.theta(m, z), !a]);
                }
            }
        }
    }
}

/// The transition relation of each module: `tr[m,q,q'] <-> OR_k tgt[m,q,k,q']`.
pub fn transition_relation(f: &mut impl ExtendFormula, v: &ModVars) {
    let d = v.d;
    for m in 0..d.modules {
        for q in 0..d.c_max {
            for t in 0..d.c_max {
                let tr = v.tr(m, q, t);
                let mut clause = vec![!tr];
                for k in 0..d.slots {
                    let y = v.tgt(m, q, k, t);
                    f.add_clause(&[!y, tr]);
                    clause.push(y);
                }
                f.add_clause(&clause);
            }
        }
    }
}

/// BFS symmetry breaking adapted to unused states (seed 000, section V.D), per module:
/// - `p[m,j,i] <-> tr[m,i,j] & AND_{k<i} ¬tr[m,k,j]` for `i < j`, `¬p[m,j,i]` for `i >= j`;
/// - `uc[m,j] -> OR_{i<j} p[m,j,i]` for `j >= 1` (only used states need a parent);
/// - `¬uc[m,j] -> ¬p[m,j,i]` (unused states have none);
/// - `p[m,j,i] -> ¬p[m,j+1,k]` for `k < i` (parents are non-decreasing).
///
/// Sound because every used state of a module labels a tree node, hence is reachable from
/// state 0 over transitions, and renumbering a module's states in BFS order changes nothing.
pub fn bfs(f: &mut impl ExtendFormula, v: &ModVars) {
    let c = v.d.c_max;
    for m in 0..v.d.modules {
        for j in 1..c {
            let mut alo = vec![!v.used(m, j)];
            for i in 0..j {
                let p = v.parent(m, j, i);
                alo.push(p);
                f.add_clause(&[!p, v.tr(m, i, j)]);
                f.add_clause(&[!p, v.used(m, j)]);
                let mut back = vec![p, !v.tr(m, i, j)];
                for k in 0..i {
                    f.add_clause(&[!p, !v.tr(m, k, j)]);
                    back.push(v.tr(m, k, j));
                }
                f.add_clause(&back);
            }
            f.add_clause(&alo);
        }
        for j in 0..c {
            for i in j..c {
                f.add_clause(&[!v.parent(m, j, i)]);
            }
        }
        for j in 1..c.saturating_sub(1) {
            for i in 0..j {
                for k in 0..i {
                    f.add_clause(&[!v.parent(m, j, i), !v.parent(m, j + 1, k)]);
                }
            }
        }
    }
}

/// Every family. `pins[m]`: outputs pinned to module `m` (modules are ordered by
/// [`module_order`] only when nothing is pinned).
pub fn all(
    f: &mut impl ExtendFormula,
    v: &ModVars,
    tree: &ScenarioTree,
    kind: AlgorithmKind,
    pins: &[Vec<OutputId>],
) {
    used_prefix(f, v);
    coloring(f, v);
    output_owner(f, v, pins);
    if pins.iter().all(Vec::is_empty) {
        module_order(f, v);
    }
    slots(f, v);
    for (g, bits) in tree.input_vectors.iter().enumerate() {
        firing(f, v, InputVec(g), bits);
    }
    active_edges(f, v, tree);
    passive_marks(f, v, tree);
    algorithms(f, v, tree, kind);
    transition_relation(f, v);
    bfs(f, v);
}
