//! The plant put to the test before synthesis, by NuSMV: it must accept every output the
//! controller can give at every reachable state (it is *receptive*), no fairness constraint
//! of it may read a controller output, and some reachable state of it must show each
//! recorded step's inputs under the outputs in force then.
//!
//! In: the recordings and a [`Check`]. Out: nothing, or a [`PlantCheckError`] naming the
//! plant state and the outputs it refuses, or the first recorded step it cannot produce.
//! Where the recordings violate a property, [`refuse_violations`] also asks whether the
//! plant produces the recorded runs step by step as recorded (its reactions at the recorded
//! steps): only then does "no controller that reproduces them can satisfy it" follow.
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

use super::explain::{self, Explanation};
use super::{Check, Error};
use crate::nusmv::{show_state, Dialogue, NusmvError};
use crate::scenario::ScenarioSet;
use crate::smv::composition::PLANT_INSTANCE;
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
    /// A fairness constraint reads a controller output.
    #[error("{}:{line}: this {keyword} constraint reads the controller output {}: NuSMV's LTL verdicts ignore the runs it calls unfair, so it could discard exactly the runs where the controller violates a property, and \"verified\" would be vacuous; fairness may read the plant's own variables only", plant.display(), crate::quote::quote(output))]
    Unfair {
        /// The plant file.
        plant: PathBuf,
        /// 1-based line of the constraint.
        line: usize,
        /// `FAIRNESS`, `JUSTICE` or `COMPASSION`.
        keyword: &'static str,
        /// The controller output it reads.
        output: String,
    },
    /// The plant cannot produce a recorded step's inputs under the recorded outputs.
    #[error("{place}: the plant {} cannot produce this recorded step: no reachable state of it shows the inputs {inputs} under the outputs {outputs}; a machine verified with this plant would be verified for a plant the recordings do not come from; {forbidding}", plant.display())]
    Unproducible {
        /// The plant file.
        plant: PathBuf,
        /// The scenario's file, line and the step (1-based).
        place: String,
        /// The recorded inputs, `name = value`.
        inputs: String,
        /// The outputs in force, `name = value`.
        outputs: String,
        /// The inputs the plant refuses and the plant lines that decide them,
        /// `name (file:line: text)`.
        forbidding: String,
    },
}

/// Refuses a fairness constraint of the plant that reads a controller output: it could make
/// NuSMV's verdicts vacuous by calling unfair exactly the runs where a property fails. Also
/// checked by `verify`, which checks a given machine with no synthesis before.
pub(crate) fn refuse_unfair(check: &Check) -> Result<(), Error> {
    let p = &check.problem;
    match p.plant.fairness_reading_outputs().into_iter().next() {
        Some(u) => Err(PlantCheckError::Unfair {
            plant: p.plant.file.clone(),
            line: u.line,
            keyword: u.keyword,
            output: u.output,
        }
        .into()),
        None => Ok(()),
    }
}

/// The checks of the module header before synthesis, with one NuSMV dialogue.
pub(crate) fn check_plant(set: &ScenarioSet, check: &Check) -> Result<(), Error> {
    let p = &check.problem;
    refuse_unfair(check)?;
    let dir = crate::files::WorkDir::new()?;
    let mut dialogue = check.nusmv.dialogue();
    let path = dir.path().join("receptiveness.smv");
    std::fs::write(&path, plant_checks::receptiveness(&p.plant, &p.coupling))?;
    receptive(check, &mut dialogue, &path)?;
    recorded_steps(set, check, &mut dialogue, &path)
}

/// The recordings' verdicts on the properties (`recorded`, from
/// [`explain::refuse_violations`]); where they violate one, whether the plant produces the
/// recorded runs as recorded, which the claim that no controller reproducing them satisfies
/// the property rests on.
pub(crate) fn refuse_violations(
    recorded: Result<Explanation, explain::RecordingsViolate>,
    set: &ScenarioSet,
    check: &Check,
) -> Result<Explanation, Error> {
    match recorded {
        Ok(found) => Ok(found),
        Err(mut violate) => {
            let dir = crate::files::WorkDir::new()?;
            let mut dialogue = check.nusmv.dialogue();
            // Without NuSMV's answer the claim about controllers is not made either.
            violate.unreplayed = first_unreplayed(set, check, &mut dialogue, dir.path())
                .unwrap_or_else(|e| Some(format!("a step NuSMV could not check: {e}")));
            Err(violate.into())
        }
    }
}

/// Refuses a plant that is not receptive (see the module header); `path` holds the model of
/// [`plant_checks::receptiveness`].
fn receptive(check: &Check, dialogue: &mut Dialogue, path: &Path) -> Result<(), Error> {
    let p = &check.problem;
    let state = match dialogue.deadlock_of(path) {
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
/// loop; a plant NuSMV rejects, and NuSMV out of time or memory, are left to the closed-loop
/// check, which meets the same plant first and says so in its words (with the plant's line).
fn nusmv_failed(e: NusmvError, check: &Check) -> Result<(), Error> {
    let plant = &check.problem.plant;
    match e {
        NusmvError::Vacuous { what, warning, .. } => Err(VerifyError::Vacuous {
            plant: plant.file.clone(),
            what,
            warning,
        }
        .into()),
        NusmvError::Stopped => Err(e.into()),
        _ => Ok(()),
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

/// Refuses a plant none of whose reachable states shows a recorded step's inputs under the
/// outputs in force, naming the first such step; `path` holds the model of
/// [`plant_checks::receptiveness`], where every reachable plant state comes with every value
/// of the outputs it reads.
fn recorded_steps(
    set: &ScenarioSet,
    check: &Check,
    dialogue: &mut Dialogue,
    path: &Path,
) -> Result<(), Error> {
    let runs = recorded_runs(set);
    // Each valuation once, at its first step.
    let mut firsts: Vec<Valuation> = Vec::new();
    let mut seen = std::collections::HashSet::new();
    for (j, run) in runs.runs.iter().enumerate() {
        for (i, (outputs, inputs)) in run.iter().enumerate() {
            let Some(inputs) = inputs else { continue };
            let v = valuation(check, j, i, outputs, inputs);
            if seen.insert((v.inputs.clone(), v.outputs.clone())) {
                firsts.push(v);
            }
        }
    }
    let formulas: Vec<String> = firsts.iter().map(|f| f.formula(None)).collect();
    let holds = match dialogue.invariants(path, &formulas) {
        Ok(h) => h,
        Err(e) => return nusmv_failed(e, check),
    };
    let Some(k) = holds.iter().position(|&h| h) else {
        return Ok(());
    };
    let v = &firsts[k];
    // The inputs no reachable state shows alone under these outputs; when each alone is
    // shown, it is their combination the plant forbids.
    let singles: Vec<String> = (0..v.inputs.len()).map(|x| v.formula(Some(x))).collect();
    let alone = dialogue.invariants(path, &singles).unwrap_or_default();
    let refused: Vec<usize> = (0..v.inputs.len())
        .filter(|&x| alone.get(x) == Some(&true))
        .collect();
    Err(unproducible(set, check, &runs, (v.run, v.state), &refused).into())
}

/// A recorded state as NuSMV literals: the controller inputs the plant shows and the outputs
/// in force that it reads.
struct Valuation {
    run: usize,
    state: usize,
    inputs: Vec<String>,
    outputs: Vec<String>,
}

impl Valuation {
    /// The invariant that no reachable state shows the valuation (or, with `Some(x)`, input
    /// `x` alone under the outputs).
    fn formula(&self, only: Option<usize>) -> String {
        let inputs = match only {
            Some(x) => &self.inputs[x..=x],
            None => &self.inputs[..],
        };
        let all: Vec<&str> = (inputs.iter().chain(&self.outputs))
            .map(String::as_str)
            .collect();
        format!("!({})", all.join(" & "))
    }
}

/// State `i` of run `j` with these outputs and inputs, as a [`Valuation`].
fn valuation(check: &Check, j: usize, i: usize, outputs: &[bool], inputs: &[bool]) -> Valuation {
    let c = &check.problem.coupling;
    let literal = |name: String, v: bool| match v {
        true => name,
        false => format!("!{name}"),
    };
    Valuation {
        run: j,
        state: i,
        inputs: (c.sensors.iter().zip(inputs))
            .map(|(x, &v)| literal(format!("{PLANT_INSTANCE}.{x}"), v))
            .collect(),
        outputs: (c.params.iter())
            .map(|&z| literal(format!("_o_{}", c.outputs[z]), outputs[z]))
            .collect(),
    }
}

/// The first recorded step (its place) the plant cannot take after the steps before it as
/// recorded, or `None` when it produces every recorded run (see [`plant_checks::replay`]).
fn first_unreplayed(
    set: &ScenarioSet,
    check: &Check,
    dialogue: &mut Dialogue,
    dir: &Path,
) -> Result<Option<String>, Error> {
    let p = &check.problem;
    let runs = recorded_runs(set);
    let path = dir.join("replay.smv");
    std::fs::write(&path, plant_checks::replay(&p.plant, &p.coupling, &runs))?;
    let lasts = runs.last_states();
    let unreachable = |dialogue: &mut Dialogue, gs: &[usize]| -> Result<Vec<bool>, NusmvError> {
        let formulas: Vec<String> = gs.iter().map(|g| format!("_g != {g}")).collect();
        dialogue.invariants(&path, &formulas)
    };
    let holds = unreachable(dialogue, &lasts)?;
    let Some(j) = holds.iter().position(|&h| h) else {
        return Ok(None);
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
    Ok(Some(set.scenarios[j].origin.step(state + 1)))
}

/// The error for state `state` (0-based) of run `j` (its step `state + 1`), naming the
/// inputs the plant refuses (indices into the recorded inputs; none when only their
/// combination is refused) and the plant lines deciding them.
fn unproducible(
    set: &ScenarioSet,
    check: &Check,
    runs: &Replayed,
    (j, state): (usize, usize),
    refused: &[usize],
) -> PlantCheckError {
    let plant = &check.problem.plant;
    let (outputs, inputs) = &runs.runs[j][state];
    let inputs = inputs.as_deref().unwrap_or_default();
    let pairs = |names: &[String], values: &[bool]| {
        let all: Vec<String> = (names.iter().zip(values))
            .map(|(n, v)| format!("{n} = {}", crate::smv::bool_literal(*v)))
            .collect();
        all.join(", ")
    };
    let text: Vec<&str> = plant.text.lines().collect();
    let at = |x: &str, line: usize| {
        let shown = text.get(line - 1).map_or("", |t| t.trim());
        format!("{x} ({}:{line}: `{shown}`)", plant.file.display())
    };
    let combination = refused.is_empty();
    let all: Vec<usize> = (0..inputs.len()).collect();
    let refused = if combination { &all[..] } else { refused };
    // The plant's own names for the inputs (they differ where `--couple` maps them).
    let names = &check.problem.coupling.sensors;
    let lines: Vec<String> = (refused.iter().map(|&x| &names[x]))
        .flat_map(|x| {
            let mut lines = plant.lines_constraining(x);
            if lines.is_empty() {
                lines.extend(plant.names.iter().filter(|d| &d.name == x).map(|d| d.line));
            }
            lines.into_iter().map(move |l| at(x, l))
        })
        .collect();
    let named: Vec<String> = refused
        .iter()
        .map(|&x| pairs(&set.inputs[x..=x], &inputs[x..=x]))
        .collect();
    let forbidding = match combination {
        true => format!(
            "no input alone is refused, their combination is; the plant lines that decide them: {}",
            lines.join(", ")
        ),
        false => format!(
            "no reachable state shows {} under these outputs; the plant lines that decide it: {}",
            named.join(", "),
            lines.join(", ")
        ),
    };
    PlantCheckError::Unproducible {
        plant: plant.file.clone(),
        place: set.scenarios[j].origin.step(state + 1),
        inputs: pairs(&set.inputs, inputs),
        outputs: pairs(&set.outputs, outputs),
        forbidding,
    }
}
