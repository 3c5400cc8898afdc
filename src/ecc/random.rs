//! Random ECCs, for property tests and differential tests (seeded, so reproducible).

use super::modular::{Modular, Module, Topology};
use super::network::Network;
use super::{Algorithm, Ecc, Guard, InputId, OutputId, State, StateId, Transition, Tri};
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

/// A random network of two controllers that read each other: `C1` (`c1` states) reads `a`
/// and `q`, writes `p`; `C2` (`c2` states) reads `b` and `p`, writes `q` and `r`.
pub fn random_network(seed: u64, c1: usize, c2: usize) -> Network {
    let mut e1 = random_ecc(seed, c1, 2, 1);
    let mut e2 = random_ecc(seed + 100, c2, 2, 2);
    e1.inputs = vec!["a".into(), "q".into()];
    e1.outputs = vec!["p".into()];
    e2.inputs = vec!["b".into(), "p".into()];
    e2.outputs = vec!["q".into(), "r".into()];
    Network {
        names: vec!["C1".into(), "C2".into()],
        external: 2,
        modular: Modular {
            inputs: ["a", "b", "p", "q", "r"].map(String::from).to_vec(),
            outputs: ["p", "q", "r"].map(String::from).to_vec(),
            initial_outputs: vec![false; 3],
            modules: vec![
                Module {
                    inputs: vec![InputId(0), InputId(3)],
                    outputs: vec![OutputId(0)],
                    ecc: e1,
                },
                Module {
                    inputs: vec![InputId(1), InputId(2)],
                    outputs: vec![OutputId(1), OutputId(2)],
                    ecc: e2,
                },
            ],
            topology: Topology::Parallel,
        },
    }
}
