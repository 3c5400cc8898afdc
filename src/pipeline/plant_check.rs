//! The plant put to the test before synthesis, by NuSMV: it must accept every output the
//! controller can give at every reachable state (it is *receptive*), and it must be able to
//! produce every recorded step's inputs under the recorded outputs.
//!
//! In: the recordings and a [`Check`]. Out: nothing, or a [`PlantCheckError`] naming the
//! plant state and the outputs it refuses, or the first recorded step it cannot produce.
//!
//! Why: NuSMV's LTL checking ignores runs that end, so a plant that blocks the controller
//! (an `INVAR` or `TRANS` that reads its outputs) can discard exactly the runs that violate a
//! property and make "verified" vacuous; a physical plant never refuses a command. And a plant
//! that cannot produce what was recorded verifies a closed loop the real plant is not in: the
//! recordings' verdicts ([`super::explain`]) and NuSMV's would speak of different plants.
//!
//! A plant that allows no behaviour at all (an `INIT`, `INVAR`, `TRANS` or `FAIRNESS`
//! constraint no run satisfies) is refused as vacuous, as the closed-loop check would. A plant
//! NuSMV rejects passes on to the closed-loop check, which names the line. The models are
//! built by [`crate::smv::plant_checks`].

use super::{Check, Error};
use crate::nusmv::{show_state, Dialogue, NusmvError};
use crate::scenario::ScenarioSet;
use crate::smv::plant_checks::{self, Replayed};
use crate::verify::VerifyError;
use std::path::{Path, PathBuf};

/// The plant fails a check before synthesis.
#[derive(Debug, thiserror::Error)]
pub enum PlantCheckError {
    /// A reachable plant state has no successor for some outputs of the controller.
    #[error("{}: the plant is not receptive: in the reachable state {state} (controller outputs {now}), it has no successor for the controller outputs {refused}; a plant must accept every output the controller can give at every reachable state (a physical plant does not block a command, and NuSMV's verdicts would ignore the runs it blocks); check its INVAR and TRANS constraints that read the controller's outputs", plant.display())]
    NotReceptive {
        /// The plant file.
        plant: PathBuf,
        /// The plant's variables in that state.
        state: String,
        /// The controller outputs the state was reached with.
        now: String,
        /// The outputs it has no successor for.
        refused: String,
    },
    /// The plant cannot produce a recorded step's inputs under the recorded outputs.
    #[error("{place}: the plant {} cannot produce this recorded step: its inputs {inputs} under the outputs {outputs}, after the steps before it; a machine verified with this plant would be verified for a plant the recordings do not come from (the inputs are declared at {declared})", plant.display())]
    Unproducible {
        /// The plant file.
        plant: PathBuf,
        /// The scenario's file, line and the step (1-based).
        place: String,
        /// The recorded inputs, `name = value`.
        inputs: String,
        /// The outputs in force, `name = value`.
        outputs: String,
        /// Where the plant declares the inputs, `name (file:line)`.
        declared: String,
    },
}

/// Both checks of the module header, with one NuSMV dialogue.
pub(crate) fn check_plant(set: &ScenarioSet, check: &Check) -> Result<(), Error> {
    let dir = tempfile::tempdir()?;
    let mut dialogue = check.nusmv.dialogue();
    receptive(check, &mut dialogue, dir.path())?;
    replays(set, check, &mut dialogue, dir.path())
}

/// Refuses a plant that is not receptive (see the module header).
fn receptive(check: &Check, dialogue: &mut Dialogue, dir: &Path) -> Result<(), Error> {
    let p = &check.problem;
    let path = dir.join("receptiveness.smv");
    std::fs::write(&path, plant_checks::receptiveness(&p.plant, &p.coupling))?;
    let state = match dialogue.deadlock_of(&path) {
        Ok(None) => return Ok(()),
        Ok(Some(state)) => state,
        Err(e) => return nusmv_failed(e, check),
    };
    let part = |prefix: &str| -> String {
        let named: Vec<(String, String)> = (state.iter())
            .filter_map(|(n, v)| Some((n.strip_prefix(prefix)?.to_string(), v.clone())))
            .collect();
        match named.is_empty() {
            true => "(none)".into(),
            false => show_state(&named),
        }
    };
    Err(PlantCheckError::NotReceptive {
        plant: p.plant.file.clone(),
        state: part("plant."),
        now: part("_o_"),
        refused: part("_p_"),
    }
    .into())
}

/// What a NuSMV failure of a check model means: no behaviour is vacuous, as in the closed
/// loop; a plant NuSMV rejects is left to the closed-loop check, which names its line.
fn nusmv_failed(e: NusmvError, check: &Check) -> Result<(), Error> {
    let plant = &check.problem.plant;
    match e {
        NusmvError::Vacuous { what, warning, .. } => Err(VerifyError::Vacuous {
            plant: plant.file.clone(),
            what,
            warning,
        }
        .into()),
        NusmvError::Model(errors) => {
            let lines = plant.text.lines().count();
            match errors.iter().all(|e| e.line <= lines + 1) {
                true => Ok(()),
                false => Err(Error::Bug(format!(
                    "NuSMV rejected a generated check model of the plant: {}",
                    NusmvError::Model(errors)
                ))),
            }
        }
        e => Err(e.into()),
    }
}

/// The recorded runs as states of the closed loop (see [`crate::smv::plant_checks`]).
fn recorded_runs(set: &ScenarioSet) -> Replayed {
    let runs = (set.scenarios.iter())
        .map(|s| {
            let mut outputs = set.initial_outputs.clone();
            let mut states = Vec::new();
            for step in &s.steps {
                states.push((outputs.clone(), Some(step.inputs.clone())));
                if let Some(o) = &step.outputs {
                    outputs.clone_from(o);
                }
            }
            states.push((outputs, None));
            states
        })
        .collect();
    Replayed { runs }
}

/// Refuses a plant that cannot produce a recorded run, naming its first step it cannot.
fn replays(
    set: &ScenarioSet,
    check: &Check,
    dialogue: &mut Dialogue,
    dir: &Path,
) -> Result<(), Error> {
    let p = &check.problem;
    let runs = recorded_runs(set);
    let path = dir.join("replay.smv");
    std::fs::write(&path, plant_checks::replay(&p.plant, &p.coupling, &runs))?;
    let lasts = runs.last_states();
    let unreachable = |dialogue: &mut Dialogue, gs: &[usize]| -> Result<Vec<bool>, NusmvError> {
        let formulas: Vec<String> = gs.iter().map(|g| format!("_g != {g}")).collect();
        dialogue.invariants(&path, &formulas)
    };
    let holds = match unreachable(dialogue, &lasts) {
        Ok(h) => h,
        Err(e) => return nusmv_failed(e, check),
    };
    let Some(j) = holds.iter().position(|&h| h) else {
        return Ok(());
    };
    // The last reachable state of run `j`: its transitions are the step it cannot take.
    let first = lasts[j] + 1 - runs.runs[j].len();
    let (mut lo, mut hi) = (first, lasts[j]);
    while lo + 1 < hi {
        let mid = (lo + hi) / 2;
        match unreachable(dialogue, &[mid])?[0] {
            true => hi = mid,
            false => lo = mid,
        }
    }
    let reached = match unreachable(dialogue, &[lo])?[0] {
        true => None,
        false => Some(lo),
    };
    let state = reached.map_or(0, |g| g - first);
    Err(unproducible(set, check, &runs, j, state).into())
}

/// The error for state `state` (0-based) of run `j`: its step `state + 1`.
fn unproducible(
    set: &ScenarioSet,
    check: &Check,
    runs: &Replayed,
    j: usize,
    state: usize,
) -> PlantCheckError {
    let plant = &check.problem.plant;
    let (outputs, inputs) = &runs.runs[j][state];
    let pairs = |names: &[String], values: &[bool]| {
        let all: Vec<String> = (names.iter().zip(values))
            .map(|(n, v)| format!("{n} = {}", crate::smv::bool_literal(*v)))
            .collect();
        all.join(", ")
    };
    let declared: Vec<String> = (set.inputs.iter())
        .filter_map(|x| {
            let d = plant.names.iter().find(|d| &d.name == x)?;
            Some(format!("{x} ({}:{})", plant.file.display(), d.line))
        })
        .collect();
    PlantCheckError::Unproducible {
        plant: plant.file.clone(),
        place: set.scenarios[j].origin.step(state + 1),
        inputs: pairs(&set.inputs, inputs.as_deref().unwrap_or_default()),
        outputs: pairs(&set.outputs, outputs),
        declared: declared.join(", "),
    }
}
