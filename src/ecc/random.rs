//! Random ECCs, for property tests and differential tests (seeded, so reproducible).

use super::{Algorithm, Ecc, Guard, InputId, State, StateId, Transition, Tri};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A random ECC: `c` states with random tri algorithms, 1..=3 transitions per state with random
/// cube guards over `inputs` inputs, named `x1..` and `z1..`.
pub fn random_ecc(seed: u64, c: usize, inputs: usize, outputs: usize) -> Ecc {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let states = (0..c)
        .map(|q| {
            let algorithm = Algorithm::Tri(
                (0..outputs)
                    .map(|_| match rng.gen_range(0..3) {
                        0 => Tri::Zero,
                        1 => Tri::One,
                        _ => Tri::Keep,
                    })
                    .collect(),
            );
            let transitions = (0..rng.gen_range(1..=3))
                .map(|_| {
                    let mut lits: Vec<(InputId, bool)> = Vec::new();
                    for i in 0..inputs {
                        if rng.gen_bool(0.5) {
                            lits.push((InputId(i), rng.gen_bool(0.5)));
                        }
                    }
                    Transition {
                        target: StateId(rng.gen_range(0..c)),
                        guard: Guard::cube(&lits),
                    }
                })
                .collect();
            State {
                name: format!("s{q}"),
                algorithm,
                transitions,
            }
        })
        .collect();
    Ecc {
        inputs: (1..=inputs).map(|i| format!("x{i}")).collect(),
        outputs: (1..=outputs).map(|i| format!("z{i}")).collect(),
        initial_outputs: vec![false; outputs],
        states,
    }
}
