//! The constraint families of the modular encoding (the SAT reconstruction paper, section V), one function each.
//!
//! Together they say: every tree node gets one colour per module, so that each module's
//! colouring is the run of a deterministic ECC with conjunctive guards over the module's inputs
//! (first-fire order), each output belongs to one module whose transitions produce its values,
//! and the composite fires exactly on the active steps ([`crate::ecc::modular`] semantics).
//! Notation as in [`super::vars`]; `⊥` never appears, "nothing fires" is `nf[m,g,q,K]`.
//!
//! The families a module shares with a single ECC (used states, colouring, passive marks,
//! algorithms, BFS) and the cube guards ([`crate::sat::cubes`]) are the shared ones, applied to
//! every module's [`crate::sat::vars::Coloring`]; only what ties the modules together is here.

use super::vars::ModVars;
use crate::ecc::modular::Topology;
use crate::ecc::{AlgorithmKind, InputId, OutputId};
use crate::sat::constraints::{self as shared, at_most_one, tree_edges};
use crate::sat::cubes;
use crate::scenario::tree::{InputVec, ScenarioTree};
use varisat::{ExtendFormula, Lit};

/// θ: every output belongs to exactly one module; pinned outputs to their module
/// (`pins[m]` lists the outputs pinned to module `m`).
pub(crate) fn output_owner(f: &mut impl ExtendFormula, v: &ModVars, pins: &[Vec<OutputId>]) {
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
pub(crate) fn module_order(f: &mut impl ExtendFormula, v: &ModVars) {
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
pub(crate) fn slots(f: &mut impl ExtendFormula, v: &ModVars) {
    let (d, cv) = (v.d, &v.cubes);
    for m in 0..d.modules {
        for q in 0..d.c_max {
            for k in 0..d.max_out_degree {
                let en = cv.en(m, q, k);
                if k + 1 < d.max_out_degree {
                    f.add_clause(&[!cv.en(m, q, k + 1), en]);
                }
                f.add_clause(&[!en, v.used(m, q)]);
                let tg: Vec<Lit> = (0..d.c_max).map(|t| cv.tgt(m, q, k, t)).collect();
                let mut alo = vec![!en];
                alo.extend(&tg);
                f.add_clause(&alo);
                at_most_one(f, &tg);
                for (t, &l) in tg.iter().enumerate() {
                    f.add_clause(&[!l, en]);
                    f.add_clause(&[!l, v.used(m, t)]);
                }
                for x in 0..d.bits {
                    let (p, n) = (cv.pos(m, q, k, x), cv.neg(m, q, k, x));
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

/// Firing on input vector `g` with bits `bits` (the paper's `f` and `nf`), per module:
/// `nf[m,g,q,0]` and [`cubes::slot_fires`] for every slot. The first slot that fires is the one
/// with `nf[k] & f[k]` (the paper's `ff`); nothing fires iff `nf[K]`.
pub(crate) fn firing(f: &mut impl ExtendFormula, v: &ModVars, g: InputVec, bits: &[bool]) {
    let cv = &v.cubes;
    for m in 0..v.d.modules {
        for q in 0..v.d.c_max {
            f.add_clause(&[cv.nf(m, g, q, 0)]);
            for k in 0..v.d.max_out_degree {
                cubes::slot_fires(f, cv, (m, g, q, k), bits);
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
pub(crate) fn active_edges(f: &mut impl ExtendFormula, v: &ModVars, tree: &ScenarioTree) {
    let (d, cv) = (v.d, &v.cubes);
    for (p, g, w) in tree_edges(tree) {
        for m in 0..d.modules {
            let fired = v.fired(m, w);
            for q in 0..d.c_max {
                let (cp, none) = (v.color(m, p, q), cv.nf(m, g, q, d.max_out_degree));
                f.add_clause(&[!cp, !none, !fired]);
                f.add_clause(&[!cp, none, fired]);
                f.add_clause(&[!cp, !none, v.color(m, w, q)]);
                for k in 0..d.max_out_degree {
                    let (nf, fire) = (cv.nf(m, g, q, k), cv.fire(m, g, q, k));
                    for t in 0..d.c_max {
                        f.add_clause(&[!cp, !nf, !fire, !cv.tgt(m, q, k, t), v.color(m, w, t)]);
                    }
                }
            }
            let old = &tree.nodes[p.0].outputs;
            for (z, (a, b)) in old.iter().zip(&tree.nodes[w.0].outputs).enumerate() {
                if a != b {
                    f.add_clause(&[!v.theta(m, z), fired]);
                }
            }
        }
        let any: Vec<Lit> = (0..d.modules).map(|m| v.fired(m, w)).collect();
        f.add_clause(&any);
    }
}

/// Consecutive: every module owns every output (`θ[m,z]`), and every module fires on every
/// active edge, since each module's `CNF` is the next one's `REQ` and the composite's `CNF` is
/// the last module's (`fired[m,w]`).
pub(crate) fn chain_fires(f: &mut impl ExtendFormula, v: &ModVars, tree: &ScenarioTree) {
    for m in 0..v.d.modules {
        for z in 0..v.d.outputs {
            f.add_clause(&[v.theta(m, z)]);
        }
        for (_, _, w) in tree_edges(tree) {
            f.add_clause(&[v.fired(m, w)]);
        }
    }
}

/// Consecutive outputs on active edge `p -> w`, through `val[m,w,z]`:
/// - module 1 rewrites the outputs of `p`: `c[0,w,q] -> (val[0,w,z] <-> a_{z_p}[0,q,z])`;
/// - module `m > 1` rewrites module `m-1`'s values:
///   `c[m,w,q] & val[m-1,w,z] -> (val[m,w,z] <-> a1[m,q,z])`, and with `¬val[m-1,w,z]` `a0`;
/// - the last module's values are the recorded ones: `val[M-1,w,z] = z_w`.
///
/// Per state: tri algorithms forbid "flip", `a0 -> a1`; unused states' entries are 0.
pub(crate) fn chain_values(
    f: &mut impl ExtendFormula,
    v: &ModVars,
    tree: &ScenarioTree,
    kind: AlgorithmKind,
) {
    let d = v.d;
    let iff_under = |f: &mut dyn FnMut(&[Lit]), given: &[Lit], a: Lit, b: Lit| {
        let mut one: Vec<Lit> = given.iter().map(|&l| !l).collect();
        let mut two = one.clone();
        one.extend([!a, b]);
        two.extend([a, !b]);
        f(&one);
        f(&two);
    };
    let mut add = |c: &[Lit]| f.add_clause(c);
    for (p, _, w) in tree_edges(tree) {
        let old = &tree.nodes[p.0].outputs;
        for q in 0..d.c_max {
            for (z, &was) in old.iter().enumerate() {
                let a = if was { v.a1(0, q, z) } else { v.a0(0, q, z) };
                iff_under(&mut add, &[v.color(0, w, q)], v.value(0, w, z), a);
            }
        }
        for m in 1..d.modules {
            for q in 0..d.c_max {
                for z in 0..d.outputs {
                    let (c, prev, now) = (v.color(m, w, q), v.value(m - 1, w, z), v.value(m, w, z));
                    iff_under(&mut add, &[c, prev], now, v.a1(m, q, z));
                    iff_under(&mut add, &[c, !prev], now, v.a0(m, q, z));
                }
            }
        }
        for (z, &now) in tree.nodes[w.0].outputs.iter().enumerate() {
            let last = v.value(d.modules - 1, w, z);
            add(&[if now { last } else { !last }]);
        }
    }
    for m in 0..d.modules {
        for q in 0..d.c_max {
            for z in 0..d.outputs {
                let (a0, a1) = (v.a0(m, q, z), v.a1(m, q, z));
                if kind == AlgorithmKind::Tri {
                    add(&[!a0, a1]);
                }
                add(&[v.used(m, q), !a0]);
                add(&[v.used(m, q), !a1]);
            }
        }
    }
}

/// A fixed interface: module `m` reads no input outside `reads[m]`, `¬α[m,x]`.
pub(crate) fn allowed_reads(f: &mut impl ExtendFormula, v: &ModVars, reads: &[Vec<InputId>]) {
    for (m, allowed) in reads.iter().enumerate() {
        for x in 0..v.d.bits {
            if !allowed.contains(&InputId(x)) {
                f.add_clause(&[!v.alpha(m, x)]);
            }
        }
    }
}

/// A network's module never reads its own output: with the outputs before the step as inputs
/// `external..`, `¬α[m,external+z] ∨ ¬θ[m,z]`.
pub(crate) fn no_self_reads(f: &mut impl ExtendFormula, v: &ModVars, external: usize) {
    for m in 0..v.d.modules {
        for z in 0..v.d.outputs.min(v.d.bits.saturating_sub(external)) {
            f.add_clause(&[!v.alpha(m, external + z), !v.theta(m, z)]);
        }
    }
}

/// The transition relation of each module: `tr[m,q,q'] <-> OR_k tgt[m,q,k,q']`.
pub(crate) fn transition_relation(f: &mut impl ExtendFormula, v: &ModVars) {
    let d = v.d;
    for m in 0..d.modules {
        for q in 0..d.c_max {
            for t in 0..d.c_max {
                let tr = v.tr(m, q, t);
                let mut clause = vec![!tr];
                for k in 0..d.max_out_degree {
                    let y = v.cubes.tgt(m, q, k, t);
                    f.add_clause(&[!y, tr]);
                    clause.push(y);
                }
                f.add_clause(&clause);
            }
        }
    }
}

/// Every family. `pins[m]`: outputs pinned to module `m` (parallel modules are ordered by
/// [`module_order`] only when nothing is pinned; a chain's modules are not interchangeable and
/// own every output).
pub(crate) fn all(
    f: &mut impl ExtendFormula,
    v: &ModVars,
    tree: &ScenarioTree,
    kind: AlgorithmKind,
    pins: &[Vec<OutputId>],
    topology: Topology,
) {
    let modules = v.modules();
    for c in &modules {
        shared::used_prefix(f, c);
    }
    for c in &modules {
        shared::coloring(f, c);
    }
    let chain = topology == Topology::Consecutive;
    if chain {
        chain_fires(f, v, tree);
    } else {
        output_owner(f, v, pins);
        if pins.iter().all(Vec::is_empty) {
            module_order(f, v);
        }
    }
    slots(f, v);
    for (g, bits) in tree.input_vectors.iter().enumerate() {
        firing(f, v, InputVec(g), bits);
    }
    active_edges(f, v, tree);
    let none = |m: usize, q: usize, g: InputVec| v.cubes.nf(m, g, q, v.d.max_out_degree);
    if chain {
        // Only module 1 gets the passive step's REQ.
        shared::passive_marks(f, tree, &modules[..1], none);
        chain_values(f, v, tree, kind);
    } else {
        shared::passive_marks(f, tree, &modules, none);
        shared::algorithms(f, tree, &modules, kind);
    }
    transition_relation(f, v);
    for c in &modules {
        shared::bfs_parents(f, c);
    }
}
