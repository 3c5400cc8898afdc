//! Negative scenarios in SAT: the machine must leave every counterexample lasso.
//!
//! The machine is deterministic, so on a lasso with prefix length `p` and loop length `l` the
//! pair (lasso position, machine state) repeats within `l * C` steps after the prefix. Hence
//! "follows forever" equals "follows for `H = p + l * C_max` steps", and the encoding unrolls
//! that far:
//! - `g[0,0]`: at time 0 the machine is in state 0 (and follows, outputs = initial outputs);
//! - `ok[i,q'] <- AND_z (a_{before_i[z]}[q',z] <-> after_i[z])`: entering `q'` at position `i`
//!   produces the recorded outputs;
//! - `g[t,q] & y[q,u_i,q'] & ok[i,q'] -> g[t+1,q']`, and if the step keeps the outputs,
//!   `g[t,q] & y[q,u_i,⊥] -> g[t+1,q]` (position `i` of time `t`);
//! - `!g[H,q]` for every `q`: the machine never follows the whole unrolling.
//!
//! A finite negative scenario (no loop) is the same with `H = n`, the number of its steps.
//!
//! `g` and `ok` are only forced *up*; the solver can always set the rest false, so the
//! constraint is exact.

use super::vars::Vars;
use crate::scenario::negative::NegativeScenario;
use crate::scenario::tree::InputVec;
use varisat::{ExtendFormula, Lit};

/// Encodes one negative scenario; `ids[i]` is the alphabet index of step `i`'s inputs.
pub(crate) fn leave_lasso(
    f: &mut impl ExtendFormula,
    v: &Vars,
    neg: &NegativeScenario,
    ids: &[InputVec],
) {
    let n = neg.steps.len();
    let c = v.c_max;
    let (p, l, horizon) = match neg.loop_start {
        Some(p) if p < n => (p, n - p, p + (n - p) * c),
        Some(_) => return,
        None => (n, 1, n),
    };
    if n == 0 {
        return;
    }
    let ok: Vec<Vec<Lit>> = neg
        .steps
        .iter()
        .map(|s| {
            (0..c)
                .map(|q2| {
                    let ok = f.new_lit();
                    let mut clause = vec![ok];
                    for (z, (&was, &now)) in s.before.iter().zip(&s.after).enumerate() {
                        let a = v.a(q2, z, was);
                        clause.push(if now { !a } else { a });
                    }
                    f.add_clause(&clause);
                    ok
                })
                .collect()
        })
        .collect();
    let g: Vec<Vec<Lit>> = (0..=horizon)
        .map(|_| (0..c).map(|_| f.new_lit()).collect())
        .collect();
    f.add_clause(&[g[0][0]]);
    for t in 0..horizon {
        let i = if t < n { t } else { p + (t - p) % l };
        let (u, step) = (ids[i], &neg.steps[i]);
        for q in 0..c {
            for q2 in 0..c {
                f.add_clause(&[!g[t][q], !v.y(q, u, q2), !ok[i][q2], g[t + 1][q2]]);
            }
            if step.before == step.after {
                f.add_clause(&[!g[t][q], !v.y(q, u, v.none()), g[t + 1][q]]);
            }
        }
    }
    for &last in &g[horizon] {
        f.add_clause(&[!last]);
    }
}
