//! The cube-guard model: guards inside the encoding, for one ECC (the basic encoding with
//! `Options::max_out_degree`) or for every module of a modular controller (the SAT reconstruction paper, section V).
//!
//! In the tree-exact model the solver decides transitions only on recorded input vectors and
//! guards are minimized afterwards, so behaviour on unrecorded inputs is outside the solver.
//! Closed-loop verification exercises exactly those inputs. Here, as in the SAT reconstruction paper's modular
//! synthesis, every state has `K` ordered transition slots, each a target and a guard that is a
//! conjunction of literals over the inputs; the first slot whose guard holds fires. In the basic
//! encoding the transition function `y` on every input vector of the alphabet is *derived* from
//! the guards, so the solver's machine is the machine, on all inputs, and a counterexample rules
//! out every machine with the same guards along it.
//!
//! - [`slots`]: `en[q,k+1] -> en[q,k]`, `en[q,k] -> used[q]`, `en[q,k] <-> exactly one
//!   tgt[q,k,·]`, `tgt[q,k,q'] -> used[q']`, `!(pos[q,k,x] & neg[q,k,x])`, `pos|neg -> en`
//!   (a module's slots also say which inputs it reads:
//!   [`crate::sat::modular::constraints::slots`]);
//! - [`slot_fires`]: `fire[u,q,k] <-> en[q,k] & AND_{x: u_x=0} !pos[q,k,x] & AND_{x: u_x=1}
//!   !neg[q,k,x]` and `nf[u,q,k+1] <-> nf[u,q,k] & !fire[u,q,k]` (first-fire order, with
//!   `nf[u,q,0]` true);
//! - [`input`] (basic encoding): `nf[u,q,K] <-> y[q,u,⊥]`, and
//!   `nf[u,q,k] & fire[u,q,k] & tgt[q,k,q'] -> y[q,u,q']`.

use super::vars::{Coloring, CubeVars, Vars};
use crate::scenario::tree::InputVec;
use varisat::{ExtendFormula, Lit};

/// The slots of the single ECC of the basic encoding: targets and literal exclusivity.
pub(crate) fn slots(f: &mut impl ExtendFormula, cv: &CubeVars, machine: &Coloring) {
    let c = cv.c_max;
    for q in 0..c {
        for k in 0..cv.max_out_degree {
            let en = cv.en(0, q, k);
            if k + 1 < cv.max_out_degree {
                f.add_clause(&[!cv.en(0, q, k + 1), en]);
            }
            f.add_clause(&[!en, machine.used(q)]);
            let tg: Vec<Lit> = (0..c).map(|t| cv.tgt(0, q, k, t)).collect();
            let mut alo = vec![!en];
            alo.extend(&tg);
            f.add_clause(&alo);
            for (i, &a) in tg.iter().enumerate() {
                f.add_clause(&[!a, en]);
                f.add_clause(&[!a, machine.used(i)]);
                for &b in &tg[i + 1..] {
                    f.add_clause(&[!a, !b]);
                }
            }
            for x in 0..cv.bits {
                let (p, n) = (cv.pos(0, q, k, x), cv.neg(0, q, k, x));
                f.add_clause(&[!p, !n]);
                f.add_clause(&[!p, en]);
                f.add_clause(&[!n, en]);
            }
        }
    }
}

/// One slot on one input vector: `fire <-> en & AND ¬killers` (no literal of the guard is false
/// on the input) and `nf1 <-> nf & ¬fire` (no slot up to this one fires).
pub(crate) fn first_fire(
    f: &mut impl ExtendFormula,
    [fire, en, nf, nf1]: [Lit; 4],
    killers: &[Lit],
) {
    f.add_clause(&[!fire, en]);
    for &l in killers {
        f.add_clause(&[!fire, !l]);
    }
    let mut back = vec![fire, !en];
    back.extend(killers);
    f.add_clause(&back);
    f.add_clause(&[!nf1, nf]);
    f.add_clause(&[!nf1, !fire]);
    f.add_clause(&[nf1, !nf, fire]);
}

/// Slot `k` of state `q` of machine `m` on input vector `u` with bits `bits`: whether it fires,
/// and whether any slot up to it does (the first-fire gadget above).
pub(crate) fn slot_fires(
    f: &mut impl ExtendFormula,
    cv: &CubeVars,
    (m, u, q, k): (usize, InputVec, usize, usize),
    bits: &[bool],
) {
    // The literals that make the guard false on u.
    let killers: Vec<Lit> = bits
        .iter()
        .enumerate()
        .map(|(x, &b)| {
            if b {
                cv.neg(m, q, k, x)
            } else {
                cv.pos(m, q, k, x)
            }
        })
        .collect();
    let lits = [
        cv.fire(m, u, q, k),
        cv.en(m, q, k),
        cv.nf(m, u, q, k),
        cv.nf(m, u, q, k + 1),
    ];
    first_fire(f, lits, &killers);
}

/// The basic encoding's part of input vector `u` with bits `bits`: which slot fires, hence
/// `y[·,u,·]`.
pub(crate) fn input(
    f: &mut impl ExtendFormula,
    v: &Vars,
    cv: &CubeVars,
    u: InputVec,
    bits: &[bool],
) {
    let c = v.c_max;
    for q in 0..c {
        for k in 0..cv.max_out_degree {
            slot_fires(f, cv, (0, u, q, k), bits);
            let (nf, fire) = (cv.nf(0, u, q, k), cv.fire(0, u, q, k));
            for t in 0..c {
                f.add_clause(&[!nf, !fire, !cv.tgt(0, q, k, t), v.y(q, u, t)]);
            }
        }
        f.add_clause(&[cv.nf(0, u, q, 0)]);
        let last = cv.nf(0, u, q, cv.max_out_degree);
        f.add_clause(&[!last, v.y(q, u, v.none())]);
        f.add_clause(&[last, !v.y(q, u, v.none())]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use varisat::CnfFormula;

    /// The first-fire gadget, exhaustively: for every value of `en`, `nf` and two killer literals,
    /// `fire` and `nf1` are forced to `en & no killer` and `nf & !fire`.
    #[test]
    fn first_fire_gadget_is_exact() {
        let mut f = CnfFormula::new();
        let [fire, en, nf, nf1, k1, k2] = [(); 6].map(|_| f.new_lit());
        first_fire(&mut f, [fire, en, nf, nf1], &[k1, k2]);
        for mask in 0u32..16 {
            let bit = |i: u32| mask >> i & 1 == 1;
            let given = [(en, bit(0)), (nf, bit(1)), (k1, bit(2)), (k2, bit(3))];
            let want_fire = bit(0) && !bit(2) && !bit(3);
            let want_nf1 = bit(1) && !want_fire;
            for (fv, nv) in [(false, false), (false, true), (true, false), (true, true)] {
                let mut s = varisat::Solver::new();
                s.add_formula(&f);
                let mut assume: Vec<Lit> =
                    given.iter().map(|&(l, v)| if v { l } else { !l }).collect();
                assume.push(if fv { fire } else { !fire });
                assume.push(if nv { nf1 } else { !nf1 });
                s.assume(&assume);
                let expect = fv == want_fire && nv == want_nf1;
                assert_eq!(
                    s.solve().unwrap(),
                    expect,
                    "mask {mask:04b} fire {fv} nf1 {nv}"
                );
            }
        }
    }
}
