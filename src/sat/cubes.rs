//! The cube-guard model: guards inside the encoding.
//!
//! In the tree-exact model the solver decides transitions only on recorded input vectors and
//! guards are minimized afterwards, so behaviour on unrecorded inputs is outside the solver.
//! Closed-loop verification exercises exactly those inputs. Here, as in seed 000's modular
//! synthesis, every state has `K` ordered transition slots, each a target and a guard that is a
//! conjunction of literals over the inputs; the first slot whose guard holds fires. The
//! transition function `y` on every input vector of the alphabet is *derived* from the guards,
//! so the solver's machine is the machine, on all inputs, and a counterexample rules out every
//! machine with the same guards along it.
//!
//! - `en[q,k+1] -> en[q,k]`, `en[q,k] -> used[q]`, `en[q,k] <-> exactly one tgt[q,k,·]`,
//!   `tgt[q,k,q'] -> used[q']`, `!(pos[q,k,x] & neg[q,k,x])`, `pos|neg -> en`;
//! - `fire[u,q,k] <-> en[q,k] & AND_{x: u_x=0} !pos[q,k,x] & AND_{x: u_x=1} !neg[q,k,x]`;
//! - `nf[u,q,0]`, `nf[u,q,k+1] <-> nf[u,q,k] & !fire[u,q,k]` (first-fire order);
//! - `nf[u,q,K] <-> y[q,u,⊥]`, and `nf[u,q,k] & fire[u,q,k] & tgt[q,k,q'] -> y[q,u,q']`.

use super::vars::Vars;
use crate::scenario::tree::InputVec;
use varisat::{ExtendFormula, Lit};

/// The per-state part: slots, targets, literal exclusivity.
pub fn slots(f: &mut impl ExtendFormula, v: &Vars) {
    let cv = v.cubes.as_ref().expect("cube model");
    let c = v.c_max;
    for q in 0..c {
        for k in 0..cv.slots {
            let en = cv.en(q, k);
            if k + 1 < cv.slots {
                f.add_clause(&[!cv.en(q, k + 1), en]);
            }
            f.add_clause(&[!en, v.used(q)]);
            let tg: Vec<Lit> = (0..c).map(|t| cv.tgt(q, k, c, t)).collect();
            let mut alo = vec![!en];
            alo.extend(&tg);
            f.add_clause(&alo);
            for (i, &a) in tg.iter().enumerate() {
                f.add_clause(&[!a, en]);
                f.add_clause(&[!a, v.used(i)]);
                for &b in &tg[i + 1..] {
                    f.add_clause(&[!a, !b]);
                }
            }
            for x in 0..cv.bits {
                let (p, n) = (cv.pos(q, k, x), cv.neg(q, k, x));
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

/// The part of one input vector `u` with bits `bits`: which slot fires, hence `y[·,u,·]`.
pub fn input(f: &mut impl ExtendFormula, v: &Vars, u: InputVec, bits: &[bool]) {
    let cv = v.cubes.as_ref().expect("cube model");
    let c = v.c_max;
    for q in 0..c {
        for k in 0..cv.slots {
            let (fire, en) = (cv.fire(u, q, k), cv.en(q, k));
            // The literals that make the guard false on u.
            let killers: Vec<Lit> = bits
                .iter()
                .enumerate()
                .map(|(x, &b)| if b { cv.neg(q, k, x) } else { cv.pos(q, k, x) })
                .collect();
            let (nf, nf1) = (cv.nf(u, q, k), cv.nf(u, q, k + 1));
            first_fire(f, [fire, en, nf, nf1], &killers);
            for t in 0..c {
                f.add_clause(&[!nf, !fire, !cv.tgt(q, k, c, t), v.y(q, u, t)]);
            }
        }
        f.add_clause(&[cv.nf(u, q, 0)]);
        let last = cv.nf(u, q, cv.slots);
        f.add_clause(&[!last, v.y(q, u, v.none())]);
        f.add_clause(&[last, !v.y(q, u, v.none())]);
    }
}
