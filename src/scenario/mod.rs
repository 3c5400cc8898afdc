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
pub(crate) mod parquet;
pub(crate) mod steps;
pub(crate) mod trace_graph;
pub mod tree;

use crate::ecc::{bits_to_string, replay, Controller};
use std::fmt;
use std::path::{Path, PathBuf};

/// One `REQ` of a scenario.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Step {
    /// Input variable values sampled with this `REQ`, in interface order.
    pub inputs: Vec<bool>,
    /// Outputs emitted with `CNF`, or `None` for a passive step.
    pub outputs: Option<Vec<bool>>,
}

/// Where a scenario came from, for error messages.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Origin {
    /// The file the scenario was read from.
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
    pub(crate) fn step(&self, step: usize) -> String {
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
    /// Where the scenario was read from.
    pub origin: Origin,
    /// The `REQ`s of the run, in order.
    pub steps: Vec<Step>,
}

/// Scenarios over one interface.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ScenarioSet {
    /// Names of the input variables, in the order of [`Step::inputs`].
    pub inputs: Vec<String>,
    /// Names of the output variables, in the order of [`Step::outputs`].
    pub outputs: Vec<String>,
    /// Output values before the first step of every scenario.
    pub initial_outputs: Vec<bool>,
    /// The scenarios, in file order.
    pub scenarios: Vec<Scenario>,
}

/// An error in scenario input, always with its place.
#[derive(Debug, thiserror::Error)]
pub enum ScenarioError {
    /// A file could not be opened, read or written.
    #[error("{file}: {source}")]
    Io {
        /// The file concerned.
        file: PathBuf,
        /// The underlying I/O error.
        #[source]
        source: std::io::Error,
    },
    /// A `.gz` file whose compressed stream is corrupt.
    #[error("{file}: not a valid gzip stream: {message}")]
    Gzip {
        /// The compressed file.
        file: PathBuf,
        /// The decoder's complaint.
        message: String,
    },
    /// A line over the limit, or a file too large to read.
    #[error(transparent)]
    Read(#[from] crate::files::FileReadError),
    /// A malformed scenario file (fbSAT text, CSV log or Parquet) at a line or row.
    #[error("{file}:{line}: {message}")]
    Syntax {
        /// The scenario file.
        file: PathBuf,
        /// 1-based line (or row) of the problem.
        line: usize,
        /// What is wrong there.
        message: String,
    },
    /// A bad step of a scenario (e.g. a vector of the wrong width).
    #[error("{file}:{line}: step {step}: {message}")]
    Step {
        /// The scenario file.
        file: PathBuf,
        /// 1-based line where the scenario starts.
        line: usize,
        /// 1-based number of the `REQ` within the scenario.
        step: usize,
        /// What is wrong with the step.
        message: String,
    },
    /// A bad interface names file: an invalid or duplicate name, or a wrong count.
    #[error("{file}:{line}: {message}")]
    Names {
        /// The names file.
        file: PathBuf,
        /// 1-based line of the problem.
        line: usize,
        /// What is wrong there.
        message: String,
    },
    /// Two scenarios answer the same input history differently (found building the tree).
    #[error("{0}")]
    Contradiction(Box<Contradiction>),
    /// Any other problem, e.g. merging scenario sets over different interfaces.
    #[error("{0}")]
    Other(String),
}

/// Two scenarios that answer the same input history differently.
#[derive(Debug, thiserror::Error)]
#[error("contradictory scenarios: {} {first_says}, but {} {second_says} after the same input history", first.step(*first_step), second.step(*second_step))]
pub struct Contradiction {
    /// Where the scenario seen first comes from.
    pub first: Origin,
    /// 1-based step of the first scenario where it answers.
    pub(crate) first_step: usize,
    /// What the first scenario does there ([`Step::describe`]).
    pub(crate) first_says: String,
    /// Where the contradicting scenario comes from.
    pub second: Origin,
    /// 1-based step of the second scenario where it answers differently.
    pub(crate) second_step: usize,
    /// What the second scenario does there ([`Step::describe`]).
    pub(crate) second_says: String,
}

impl Step {
    /// Human-readable description of what the step records.
    pub(crate) fn describe(&self) -> String {
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
    /// The answers of `controller` (from its initial state each time) to every input sequence
    /// of `runs`, as scenarios named `recorded:<k>`, over the given interface.
    pub fn recorded<C: Controller>(
        controller: &C,
        inputs: Vec<String>,
        outputs: Vec<String>,
        initial_outputs: Vec<bool>,
        runs: &[Vec<Vec<bool>>],
    ) -> ScenarioSet {
        use crate::ecc::Reactive;
        let scenarios = (runs.iter().enumerate())
            .map(|(i, xs)| {
                let mut run = controller.start();
                Scenario {
                    origin: Origin {
                        file: "recorded".into(),
                        line: i + 1,
                        rows: None,
                    },
                    steps: (xs.iter())
                        .map(|x| Step {
                            inputs: x.clone(),
                            outputs: run.react(x).map(<[bool]>::to_vec),
                        })
                        .collect(),
                }
            })
            .collect();
        ScenarioSet {
            inputs,
            outputs,
            initial_outputs,
            scenarios,
        }
    }

    /// Total number of steps over all scenarios.
    pub fn step_count(&self) -> usize {
        self.scenarios.iter().map(|s| s.steps.len()).sum()
    }

    /// Number of active steps over all scenarios.
    pub(crate) fn active_count(&self) -> usize {
        self.scenarios
            .iter()
            .flat_map(|s| &s.steps)
            .filter(|s| s.outputs.is_some())
            .count()
    }

    /// Appends the scenarios of another set over the same interface.
    pub(crate) fn merge(&mut self, other: ScenarioSet) -> Result<(), ScenarioError> {
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
    pub(crate) scenario: usize,
    /// 0-based step.
    pub(crate) step: usize,
    /// The step's input values.
    pub(crate) inputs: Vec<bool>,
    /// Outputs recorded with `CNF`, or `None` if no `CNF` was recorded.
    pub(crate) recorded: Option<Vec<bool>>,
    /// Outputs the machine emits with `CNF`, or `None` if it emits nothing.
    pub(crate) machine: Option<Vec<bool>>,
}

impl Divergence {
    /// `scenario FILE:LINE step K: inputs ... recorded ..., the machine gives ...` (1-based step).
    pub(crate) fn describe(&self, set: &ScenarioSet) -> String {
        format!(
            "scenario {} {}",
            set.scenarios[self.scenario].origin,
            self.describe_step()
        )
    }

    /// `step K: inputs ... recorded ..., the machine gives ...` (1-based step).
    pub(crate) fn describe_step(&self) -> String {
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
pub(crate) fn read_text(path: &Path, max_line: Option<usize>) -> Result<String, ScenarioError> {
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
