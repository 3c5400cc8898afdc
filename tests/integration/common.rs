//! Helpers shared by the integration tests.

use fbsynth::ecc::{Ecc, Run};
use fbsynth::scenario::{Origin, Scenario, ScenarioSet, Step};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::path::PathBuf;

pub use fbsynth::ecc::random::random_ecc;

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
                    rows: None,
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
