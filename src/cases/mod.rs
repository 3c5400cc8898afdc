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

use fbsynth::ecc::{Algorithm, Ecc, Fired, Run, State, StateId, Transition, Tri};
use fbsynth::export::guard_text::parse_guard;

/// A plant simulation, scanned like a PLC in closed loop with a controller.
pub trait Simulated: Clone {
    /// The sensor values the controller reads at the start of a scan.
    fn read(&self) -> Vec<bool>;
    /// Moves the plant through one scan under the controller's commands `z`.
    fn scan(&mut self, z: &[bool]);
}

/// One scan of a closed-loop run.
#[derive(Debug, Clone, PartialEq)]
pub struct Scanned<P> {
    /// The plant as the controller saw it (before it moved for this scan).
    pub plant: P,
    /// Sensor values read.
    pub inputs: Vec<bool>,
    /// The transition that fired, if any.
    pub fired: Option<Fired>,
    /// Commands after the scan (unchanged when nothing fired).
    pub outputs: Vec<bool>,
}

/// What the driver of a run decides before a scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drive {
    Scan,
    Stop,
}

/// The one simulate loop of every case: `ecc` against `plant`, scan by scan. Before scan `k`
/// `drive(k, plant, scans so far)` may act on the plant (pieces arriving, buttons pressed)
/// or stop the run; it is called once more with `k == max_scans` (to see the last scan's
/// effect), after which the run ends in any case. Returns the scans and the plant at the end.
pub fn closed_loop<P: Simulated>(
    ecc: &Ecc,
    mut plant: P,
    max_scans: usize,
    mut drive: impl FnMut(usize, &mut P, &[Scanned<P>]) -> Drive,
) -> (Vec<Scanned<P>>, P) {
    let mut run = Run::new(ecc);
    let mut scans = Vec::new();
    for k in 0..=max_scans {
        if drive(k, &mut plant, &scans) == Drive::Stop || k == max_scans {
            break;
        }
        let inputs = plant.read();
        let seen = plant.clone();
        let fired = run.step(&inputs);
        plant.scan(&run.outputs);
        scans.push(Scanned {
            plant: seen,
            inputs,
            fired,
            outputs: run.outputs.clone(),
        });
    }
    (scans, plant)
}

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
