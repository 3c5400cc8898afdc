//! Helpers shared by the integration tests.

use fbsynth::ecc::{Algorithm, Ecc, Guard, InputId, Run, State, StateId, Transition, Tri};
use fbsynth::scenario::{Origin, Scenario, ScenarioSet, Step};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::PathBuf;

/// A random ECC: `c` states, random tri algorithms, 1..=3 transitions per state with random
/// cube guards over `inputs` inputs.
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

/// Records `runs` random runs of `len` steps of `ecc` as scenarios.
pub fn record(ecc: &Ecc, seed: u64, runs: usize, len: usize) -> ScenarioSet {
    let mut rng = ChaCha8Rng::seed_from_u64(seed ^ 0x5eed);
    let scenarios = (0..runs)
        .map(|r| {
            let mut run = Run::new(ecc);
            let steps = (0..len)
                .map(|_| {
                    let x: Vec<bool> = (0..ecc.inputs.len())
                        .map(|_| rng.gen_bool(0.5))
                        .collect::<Vec<bool>>();
                    let fired = run.step(&x).is_some();
                    Step {
                        inputs: x,
                        outputs: fired.then(|| run.outputs.clone()),
                    }
                })
                .collect();
            Scenario {
                origin: Origin {
                    file: PathBuf::from("random"),
                    line: r + 2,
                },
                steps,
            }
        })
        .collect();
    ScenarioSet {
        inputs: ecc.inputs.clone(),
        outputs: ecc.outputs.clone(),
        initial_outputs: ecc.initial_outputs.clone(),
        scenarios,
    }
}
