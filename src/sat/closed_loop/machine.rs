//! The machine's step in CNF, on inputs that are literals (the plant's sensors), with the cube
//! guard model's variables ([`CubeVars`]): the same ECC the scenario tree colours.
//!
//! With `st[t]` the one-hot state and `o[t]` the outputs at step `t`, and `x` the inputs read
//! at `t`:
//! - `fire[q,k] <-> en[q,k] & AND_x (pos[q,k,x] -> x) & (neg[q,k,x] -> !x)`;
//! - `nf[q,0]`, `nf[q,k+1] <-> nf[q,k] & !fire[q,k]` (first-fire order);
//! - `taken[q,k] <-> st[t][q] & nf[q,k] & fire[q,k]`, and
//!   `taken[q,k] & tgt[q,k,q'] -> st[t+1][q']`, `st[t][q] & nf[q,K] -> st[t+1][q]`, at most
//!   one `st[t+1][·]`;
//! - `fired <-> OR taken`; `fired & st[t+1][q'] & !o[t][z] -> (o[t+1][z] <-> a0[q'][z])`,
//!   likewise `a1` when `o[t][z]`, and `!fired -> (o[t+1][z] <-> o[t][z])`.

use super::gates::{Gates, B};
use crate::sat::vars::{CubeVars, Vars};
use varisat::ExtendFormula;

/// The machine at one step.
#[derive(Debug, Clone)]
pub(crate) struct MachineState {
    /// One-hot over `0..C_max`.
    pub(crate) state: Vec<B>,
    /// Output values, one per machine output (scenario order).
    pub(crate) outputs: Vec<B>,
}

impl MachineState {
    /// State 0 with the initial outputs.
    pub(crate) fn initial(c_max: usize, outputs: &[bool]) -> MachineState {
        MachineState {
            state: (0..c_max).map(|q| B::C(q == 0)).collect(),
            outputs: outputs.iter().map(|&o| B::C(o)).collect(),
        }
    }
}

/// One reaction of the machine to `inputs`.
pub(crate) fn step<F: ExtendFormula>(
    g: &mut Gates<'_, F>,
    vars: &Vars,
    cv: &CubeVars,
    cur: &MachineState,
    inputs: &[B],
) -> MachineState {
    let c = vars.c_max;
    let next: Vec<B> = (0..c).map(|_| B::L(g.fresh())).collect();
    for (i, &a) in next.iter().enumerate() {
        for &b in &next[i + 1..] {
            g.clause(&[!a, !b]);
        }
    }
    let mut taken_all = Vec::new();
    for q in 0..c {
        let here = cur.state[q];
        if here == B::C(false) {
            continue;
        }
        let mut nf = B::C(true);
        for k in 0..cv.max_out_degree {
            let mut conj = vec![B::L(cv.en(0, q, k))];
            for (x, &input) in inputs.iter().enumerate() {
                conj.push(g.or2(!B::L(cv.pos(0, q, k, x)), input));
                conj.push(g.or2(!B::L(cv.neg(0, q, k, x)), !input));
            }
            let fire = g.and(&conj);
            let taken = g.and(&[here, nf, fire]);
            for (t, &n) in next.iter().enumerate() {
                g.clause(&[!taken, !B::L(cv.tgt(0, q, k, t)), n]);
            }
            taken_all.push(taken);
            nf = g.and2(nf, !fire);
        }
        g.clause(&[!here, !nf, next[q]]);
    }
    let fired = g.or(&taken_all);
    let outputs = cur
        .outputs
        .iter()
        .enumerate()
        .map(|(z, &old)| {
            let new = B::L(g.fresh());
            for (q, &n) in next.iter().enumerate() {
                for (was, a) in [(false, vars.a(q, z, false)), (true, vars.a(q, z, true))] {
                    let old_is = if was { old } else { !old };
                    g.clause(&[!fired, !n, !old_is, !new, B::L(a)]);
                    g.clause(&[!fired, !n, !old_is, new, !B::L(a)]);
                }
            }
            g.clause(&[fired, !old, new]);
            g.clause(&[fired, old, !new]);
            new
        })
        .collect();
    MachineState {
        state: next,
        outputs,
    }
}
