//! The learned plant read back and put to the recordings: every recorded run must be a run
//! of it, step by step.
//!
//! In: the [`Learned`] text and the [`Runs`]. Out: nothing, or [`LearnError::NotAdmitted`]
//! naming the first recorded step no state the plant can be in produces (or
//! [`LearnError::Unreadable`] when the text, observers included, is outside the subset).

use super::{LearnError, Learned, Observers, Runs, Scan};
use crate::plant::explicit::{Semantics, State};
use crate::plant::{Model, Name, Value, VarId};
use std::collections::BTreeSet;
use std::path::Path;

/// Reads `text` as a plant model (named `learned plant` in messages).
pub(crate) fn read(text: &str, observers: Option<&Observers>) -> Result<Model, LearnError> {
    crate::plant::parse::parse_str(text, Path::new("learned plant"))
        .map_err(|e| unreadable(observers, e.to_string()))
}

/// The learned text, with `observers` if any, does not read back as a plant: `message`.
fn unreadable(observers: Option<&Observers>, message: String) -> LearnError {
    LearnError::Unreadable {
        observers: observers
            .map(|o| format!(" (check the observers in {})", o.file.display()))
            .unwrap_or_default(),
        message,
    }
}

/// The names of `model` that hold the sensors `names`, in order (a sensor it lacks is an
/// error naming it).
pub(crate) fn sensor_names(model: &Model, names: &[String]) -> Result<Vec<Name>, String> {
    (names.iter())
        .map(|n| match model.lookup(n) {
            Some(x @ (Name::Var(_) | Name::Define(_))) => Ok(x),
            _ => Err(format!(
                "{} has no VAR or DEFINE {n} (a controller input)",
                model.file.display()
            )),
        })
        .collect()
}

/// Per formal parameter of `model`: the index of the controller output of that name.
pub(crate) fn param_map(model: &Model, outputs: &[String]) -> Result<Vec<usize>, String> {
    (model.params.iter())
        .map(|p| {
            outputs.iter().position(|o| o == p).ok_or_else(|| {
                format!(
                    "{} reads {p}, which is not a controller output",
                    model.file.display()
                )
            })
        })
        .collect()
}

/// A model with what replaying runs on it needs.
pub(crate) struct Replayer<'m> {
    /// The semantics.
    pub(crate) sem: Semantics<'m>,
    /// The sensors, as names of the model.
    pub(crate) sensors: Vec<Name>,
    /// Per parameter, the controller output it reads.
    pub(crate) params: Vec<usize>,
}

impl<'m> Replayer<'m> {
    /// The replayer of `model` over the interface `inputs`, `outputs`.
    pub(crate) fn new(
        model: &'m Model,
        inputs: &[String],
        outputs: &[String],
    ) -> Result<Replayer<'m>, String> {
        Ok(Replayer {
            sem: Semantics::new(model),
            sensors: sensor_names(model, inputs)?,
            params: param_map(model, outputs)?,
        })
    }

    /// The parameters of the model for the controller outputs `outputs`.
    pub(crate) fn params(&self, outputs: &[bool]) -> Vec<bool> {
        self.params.iter().map(|&z| outputs[z]).collect()
    }

    /// The sensor values of state `s` under the outputs `outputs`.
    pub(crate) fn sensors(&self, s: &[Value], outputs: &[bool]) -> Result<Vec<bool>, String> {
        let params = self.params(outputs);
        (self.sensors.iter())
            .map(|&n| match self.sem.read(n, s, &params) {
                Ok(Value::Bool(b)) => Ok(b),
                Ok(v) => Err(format!(
                    "the sensor {} is not Boolean ({v})",
                    self.sem.model().name_of(n)
                )),
                Err(e) => Err(e.to_string()),
            })
            .collect()
    }

    /// The sensors that are variables of the model, with the values `inputs` gives them:
    /// what a successor must show (sensors that are `DEFINE`s are checked on each successor).
    fn known(&self, inputs: &[bool]) -> Vec<(VarId, Value)> {
        (self.sensors.iter().zip(inputs))
            .filter_map(|(n, &b)| match n {
                Name::Var(v) => Some((*v, Value::Bool(b))),
                _ => None,
            })
            .collect()
    }

    /// The index of the first scan of `scans` the model cannot produce, if any.
    pub(crate) fn first_refused(&self, scans: &[Scan]) -> Result<Option<usize>, String> {
        let Some(first) = scans.first() else {
            return Ok(None);
        };
        let mut now = BTreeSet::new();
        for s in
            (self.sem.initial_states(&self.params(&first.outputs))).map_err(|e| e.to_string())?
        {
            if self.sensors(&s, &first.outputs)? == first.inputs {
                now.insert(s);
            }
        }
        if now.is_empty() {
            return Ok(Some(0));
        }
        for (k, w) in scans.windows(2).enumerate() {
            let (p, q) = (self.params(&w[0].outputs), self.params(&w[1].outputs));
            let known = self.known(&w[1].inputs);
            let mut next: BTreeSet<State> = BTreeSet::new();
            for s in &now {
                let succ = self.sem.successors_where(s, &p, &q, &known);
                for t in succ.map_err(|e| e.to_string())? {
                    if self.sensors(&t, &w[1].outputs)? == w[1].inputs {
                        next.insert(t);
                    }
                }
            }
            if next.is_empty() {
                return Ok(Some(k + 1));
            }
            now = next;
        }
        Ok(None)
    }
}

/// Checks that `learned` admits every run of `runs`.
pub(crate) fn check(
    learned: &Learned,
    runs: &Runs,
    observers: Option<&Observers>,
) -> Result<(), LearnError> {
    let model = read(&learned.text, observers)?;
    let unreadable = |message: String| unreadable(observers, message);
    let replayer = Replayer::new(&model, &runs.inputs, &runs.outputs).map_err(unreadable)?;
    for (origin, scans) in &runs.runs {
        if let Some(k) = replayer.first_refused(scans).map_err(unreadable)? {
            let before = match k {
                0 => "none: the first step".to_string(),
                _ => show(&runs.outputs, &scans[k - 1].outputs),
            };
            return Err(LearnError::NotAdmitted {
                place: origin.step(k + 1),
                why: format!(
                    "no state it can be in shows the sensors ({}) under the outputs in force before ({before})",
                    show(&runs.inputs, &scans[k].inputs),
                ),
            });
        }
    }
    Ok(())
}

/// `name = value` pairs, comma-separated, of the signals that are on.
fn show(names: &[String], values: &[bool]) -> String {
    let on: Vec<&str> = (names.iter().zip(values))
        .filter(|(_, &v)| v)
        .map(|(n, _)| n.as_str())
        .collect();
    match on.is_empty() {
        true => "all off".into(),
        false => format!("on: {}", on.join(", ")),
    }
}
