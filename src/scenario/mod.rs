//! Execution scenarios: what a black-box controller was seen to do.
//!
//! In: scenario files in the fbSAT text format ([`fbsat`]) or sampled PLC I/O logs in CSV
//! ([`csvlog`]), plus names of the interface variables ([`names`]).
//! Out: a [`ScenarioSet`] (interface + scenarios) and, from it, the [`tree::ScenarioTree`]
//! that SAT synthesis colours.
//!
//! A scenario is a sequence of [`Step`]s, one per `REQ`: the input vector and, if the controller
//! answered with `CNF`, the output values it emitted (an *active* step); otherwise `None`
//! (a *passive* step: outputs unchanged, no `CNF`).

pub mod csvlog;
pub mod fbsat;
pub mod names;
pub mod negative;
pub mod parquet;
pub mod steps;
pub mod trace_graph;
pub mod tree;

use crate::ecc::{bits_to_string, replay, Controller};
use std::fmt;
use std::path::{Path, PathBuf};

/// One `REQ` of a scenario.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Step {
    pub inputs: Vec<bool>,
    /// Outputs emitted with `CNF`, or `None` for a passive step.
    pub outputs: Option<Vec<bool>>,
}

/// Where a scenario came from, for error messages.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Origin {
    pub file: PathBuf,
    /// 1-based line of the file where the scenario starts.
    pub line: usize,
    /// The line of each step, when steps are rows of a CSV log (one row may hold a step the
    /// conversion kept, others are merged or dropped); `None` when a scenario is one line.
    pub rows: Option<std::sync::Arc<[usize]>>,
}

impl Origin {
    /// Where step `step` (1-based) of the scenario is: `FILE:ROW (step K of the scenario
    /// from line L)` for a CSV log, `FILE:LINE step K` otherwise.
    pub fn step(&self, step: usize) -> String {
        let row = (self.rows.as_ref()).and_then(|r| r.get(step.checked_sub(1)?));
        match row {
            Some(row) => format!(
                "{}:{row} (step {step} of the scenario from line {})",
                self.file.display(),
                self.line
            ),
            None => format!("{self} step {step}"),
        }
    }
}

impl fmt::Display for Origin {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.file.display(), self.line)
    }
}

/// One recorded run of the controller from its initial state.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Scenario {
    pub origin: Origin,
    pub steps: Vec<Step>,
}

/// Scenarios over one interface.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScenarioSet {
    pub inputs: Vec<String>,
    pub outputs: Vec<String>,
    /// Output values before the first step of every scenario.
    pub initial_outputs: Vec<bool>,
    pub scenarios: Vec<Scenario>,
}

/// An error in scenario input, always with its place.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    #[error("{file}: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{file}: not a valid gzip stream: {message}")]
    Gzip { file: PathBuf, message: String },
    /// A line over the limit, or a file too large to read.
    #[error(transparent)]
    Read(#[from] crate::files::FileReadError),
    #[error("{file}:{line}: {message}")]
    Syntax {
        file: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{file}:{line}: step {step}: {message}")]
    Step {
        file: PathBuf,
        line: usize,
        /// 1-based number of the `REQ` within the scenario.
        step: usize,
        message: String,
    },
    #[error("{file}:{line}: {message}")]
    Names {
        file: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{0}")]
    Contradiction(Box<Contradiction>),
    #[error("{0}")]
    Other(String),
}

/// Two scenarios that answer the same input history differently.
#[derive(Debug, thiserror::Error)]
#[error("contradictory scenarios: {} {first_says}, but {} {second_says} after the same input history", first.step(*first_step), second.step(*second_step))]
pub struct Contradiction {
    pub first: Origin,
    pub first_step: usize,
    pub first_says: String,
    pub second: Origin,
    pub second_step: usize,
    pub second_says: String,
}

impl Step {
    /// Human-readable description of what the step records.
    pub fn describe(&self) -> String {
        match &self.outputs {
            Some(o) => format!(
                "answers inputs {} with CNF[{}]",
                bits_to_string(&self.inputs),
                bits_to_string(o)
            ),
            None => format!("ignores inputs {}", bits_to_string(&self.inputs)),
        }
    }
}

impl ScenarioSet {
    /// Total number of steps over all scenarios.
    pub fn step_count(&self) -> usize {
        self.scenarios.iter().map(|s| s.steps.len()).sum()
    }

    /// Number of active steps over all scenarios.
    pub fn active_count(&self) -> usize {
        self.scenarios
            .iter()
            .flat_map(|s| &s.steps)
            .filter(|s| s.outputs.is_some())
            .count()
    }

    /// Appends the scenarios of another set over the same interface.
    pub fn merge(&mut self, other: ScenarioSet) -> Result<(), ScenarioError> {
        if other.inputs != self.inputs || other.outputs != self.outputs {
            let file = other
                .scenarios
                .first()
                .map(|s| s.origin.to_string())
                .unwrap_or_default();
            return Err(ScenarioError::Other(format!(
                "{file}: the scenarios use a different interface than the files before them"
            )));
        }
        self.scenarios.extend(other.scenarios);
        Ok(())
    }

    /// Replays every scenario on `ecc` (an ECC or a modular composite) and returns, per
    /// scenario that departs from it, the first step where it does (conformance monitoring).
    pub fn divergences(&self, ecc: &impl Controller) -> Vec<Divergence> {
        self.scenarios
            .iter()
            .enumerate()
            .filter_map(|(k, sc)| {
                let steps = sc
                    .steps
                    .iter()
                    .map(|s| (s.inputs.as_slice(), s.outputs.as_deref()));
                replay(ecc, steps).err().map(|m| Divergence {
                    scenario: k,
                    step: m.step,
                    inputs: sc.steps[m.step].inputs.clone(),
                    recorded: m.expected,
                    machine: m.actual,
                })
            })
            .collect()
    }

    /// Replays every scenario on `ecc` (an ECC or a modular composite); the first disagreement
    /// is described with its place.
    pub fn check(&self, ecc: &impl Controller) -> Result<(), String> {
        match self.divergences(ecc).first() {
            None => Ok(()),
            Some(d) => Err(d.describe(self)),
        }
    }
}

/// The first step where a machine departs from a recorded scenario.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Divergence {
    /// Index of the scenario in its set.
    pub scenario: usize,
    /// 0-based step.
    pub step: usize,
    pub inputs: Vec<bool>,
    /// Outputs recorded with `CNF`, or `None` if no `CNF` was recorded.
    pub recorded: Option<Vec<bool>>,
    /// Outputs the machine emits with `CNF`, or `None` if it emits nothing.
    pub machine: Option<Vec<bool>>,
}

impl Divergence {
    /// `scenario FILE:LINE step K: inputs ... recorded ..., the machine gives ...` (1-based step).
    pub fn describe(&self, set: &ScenarioSet) -> String {
        format!(
            "scenario {} {}",
            set.scenarios[self.scenario].origin,
            self.describe_step()
        )
    }

    /// `step K: inputs ... recorded ..., the machine gives ...` (1-based step).
    pub fn describe_step(&self) -> String {
        let show = |o: &Option<Vec<bool>>| match o {
            Some(v) => format!("CNF[{}]", bits_to_string(v)),
            None => "no CNF".to_string(),
        };
        format!(
            "step {}: inputs {} recorded {}, the machine gives {}",
            self.step + 1,
            bits_to_string(&self.inputs),
            show(&self.recorded),
            show(&self.machine)
        )
    }
}

/// Reads a whole file with [`crate::files::read_text`] (gunzipped when it is gzip): at most
/// [`MAX_FILE_BYTES`](crate::files::MAX_FILE_BYTES), and lines of at most `max_line` bytes
/// when given.
pub fn read_text(path: &Path, max_line: Option<usize>) -> Result<String, ScenarioError> {
    use crate::files::ReadError;
    crate::files::read_text(path, max_line).map_err(|e| match e.error {
        ReadError::Io(source) => ScenarioError::Io {
            file: path.to_path_buf(),
            source,
        },
        ReadError::Gzip { message } => ScenarioError::Gzip {
            file: path.to_path_buf(),
            message,
        },
        _ => ScenarioError::Read(e),
    })
}
