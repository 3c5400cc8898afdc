//! Two plants compared on the runs of one controller: bounded language inclusion, measured by
//! random closed-loop runs of one plant replayed on the other.
//!
//! In: a machine ([`Ecc`]), the plant that makes the runs and the plant that must admit them
//! (both [`Model`]s over the machine's interface), how many runs of how many scans, a seed.
//! Out: an [`Inclusion`]: how many of the runs the second plant admits, and the first it
//! refuses. A run is the machine scanned against the first plant as a PLC scans: it reads the
//! sensors, answers, and the plant moves under the answer, each nondeterministic choice of
//! the plant drawn uniformly among its successors.

use super::admit::Replayer;
use super::Scan;
use crate::ecc::{Ecc, Run};
use crate::plant::explicit::State;
use crate::plant::Model;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// How many random runs of one plant the other admits.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Inclusion {
    /// Runs made.
    pub(crate) runs: usize,
    /// Runs the other plant admits.
    pub(crate) admitted: usize,
    /// The first refused: (run, 1-based scan).
    pub(crate) first_refused: Option<(usize, usize)>,
}

/// `runs` random runs of `scans` scans of `ecc` against `from`, replayed on `into`.
pub(crate) fn inclusion(
    ecc: &Ecc,
    from: &Model,
    into: &Model,
    runs: usize,
    scans: usize,
    seed: u64,
) -> Result<Inclusion, String> {
    let maker = Replayer::new(from, &ecc.inputs, &ecc.outputs)?;
    let judge = Replayer::new(into, &ecc.inputs, &ecc.outputs)?;
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Inclusion {
        runs,
        admitted: 0,
        first_refused: None,
    };
    for r in 0..runs {
        let run = random_run(ecc, &maker, scans, &mut rng)?;
        match judge.first_refused(&run)? {
            None => out.admitted += 1,
            Some(k) => {
                out.first_refused.get_or_insert((r, k + 1));
            }
        }
    }
    Ok(out)
}

/// One random run of `ecc` against the plant of `maker`.
fn random_run(
    ecc: &Ecc,
    maker: &Replayer<'_>,
    scans: usize,
    rng: &mut ChaCha8Rng,
) -> Result<Vec<Scan>, String> {
    let mut machine = Run::new(ecc);
    let starts =
        (maker.sem.initial_states(&maker.params(&machine.outputs))).map_err(|e| e.to_string())?;
    let mut state: State = pick(starts, rng).ok_or("the plant has no initial state")?;
    let mut out = Vec::with_capacity(scans);
    for _ in 0..scans {
        let inputs = maker.sensors(&state, &machine.outputs)?;
        machine.step(&inputs);
        let p = maker.params(&machine.outputs);
        out.push(Scan {
            inputs,
            outputs: machine.outputs.clone(),
        });
        let succ = maker
            .sem
            .successors(&state, &p, &p)
            .map_err(|e| e.to_string())?;
        match pick(succ, rng) {
            Some(s) => state = s,
            None => break,
        }
    }
    Ok(out)
}

fn pick(mut states: Vec<State>, rng: &mut ChaCha8Rng) -> Option<State> {
    match states.len() {
        0 => None,
        n => Some(states.swap_remove(rng.gen_range(0..n))),
    }
}
