//! Benchmark cases owned by the project: a plant simulation, a hand-made reference controller
//! (the "legacy PLC" whose logic is to be recovered) and the generator of the recorded data.
//!
//! In: nothing but the case's own constants (and, for [`pnp`], a work-piece order; for
//! [`tank`], a seed of the noisy plant).
//! Out: [`ScenarioSet`](fbsynth::scenario::ScenarioSet)s and the data files under `specs/` that
//! are committed beside the code and checked against the generator by a test.

pub mod distribution;
pub mod pnp;
pub mod tank;

use fbsynth::ecc::{Algorithm, Ecc, State, StateId, Transition, Tri};
use fbsynth::export::guard_text::parse_guard;

/// A reference controller written as tables: states `(name, algorithm)` with the algorithm as
/// `0/1/x` symbols per output, and transitions `(from, to, guard text)` in priority order.
/// State 0 is initial, every output starts 0. The tables are constants of a case module, so a
/// bad name or guard there is a bug and panics.
pub(crate) fn table_ecc(
    inputs: &[&str],
    outputs: &[&str],
    states: &[(&str, &str)],
    transitions: &[(&str, &str, &str)],
) -> Ecc {
    let id = |name: &str| {
        StateId(
            states
                .iter()
                .position(|(n, _)| *n == name)
                .unwrap_or_else(|| panic!("unknown state '{name}'")),
        )
    };
    let inputs: Vec<String> = inputs.iter().map(|s| s.to_string()).collect();
    let states = states
        .iter()
        .map(|(name, algorithm)| State {
            name: name.to_string(),
            algorithm: Algorithm::Tri(
                algorithm
                    .chars()
                    .map(|c| Tri::from_symbol(c).expect("algorithm symbol"))
                    .collect(),
            ),
            transitions: transitions
                .iter()
                .filter(|(from, _, _)| from == name)
                .map(|(_, to, guard)| Transition {
                    target: id(to),
                    guard: parse_guard(guard, &inputs)
                        .unwrap_or_else(|e| panic!("guard '{guard}': {e}")),
                })
                .collect(),
        })
        .collect();
    Ecc {
        inputs,
        outputs: outputs.iter().map(|s| s.to_string()).collect(),
        initial_outputs: vec![false; outputs.len()],
        states,
    }
}
