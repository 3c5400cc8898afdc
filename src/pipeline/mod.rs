//! Every synthesize-then-verify pipeline of the tool, one function each, over one
//! verification problem.
//!
//! In: a [`ScenarioSet`](crate::scenario::ScenarioSet) (read with [`Recordings::load`]), the
//! options of the method and, where the result must be correct in closed loop, a [`Check`]:
//! the [`Problem`] (plant, coupling, properties) and the NuSMV binary that certifies it.
//! Out: the machine, its figures and, when checked, NuSMV's [`Report`]
//! with the closed-loop model it verified. Progress is reported as typed [`Event`]s; the caller
//! decides how to show them.
//!
//! | method | function | result |
//! |---|---|---|
//! | the main job: the game's guide, the exact loop, the search, whichever the problem needs, under one time limit | [`main_job::run`] | [`main_job::VerifiedMachine`] |
//! | exact SAT, optionally with counterexample-guided refinement against NuSMV | [`exact::run`] (with a time limit: [`limit::Limit::exact`]) | [`exact::Exact`] |
//! | metaheuristic search with verification-aware fitness | [`search::run`] | [`search::Searched`] |
//! | noisy logs (scan-cycle error model), candidates by number of errors | [`noisy::run`] | [`noisy::Noisy`] |
//! | modular: M function blocks and their composite | [`modular::run`] | [`crate::sat::modular::ModularSynthesis`] |
//! | distributed: several controllers with interfaces of their own | [`distributed::run`] | [`distributed::Distributed`] |
//! | monitoring and refinement of a machine in service | [`refine::run`] | [`refine::Refined`] |
//! | how far the recordings determine the machine: rivals and distinguishing sequences | [`ambiguity::check`] | [`ambiguity::Ambiguity`] |
//! | recordings that already violate a property, before any synthesis | [`explain::explain`] | [`explain::Explanation`] |
//!
//! A time limit is a deadline inside the pipeline ([`limit`], [`crate::deadline`]): SAT calls,
//! NuSMV checks and the game stop there, and no thread is left running.
//!
//! Long recordings (days of one run) are taken a part at a time by [`lazy`], for exact
//! synthesis without NuSMV and for the ambiguity check, with the answer of the whole.
//!
//! [`output`] writes results to folders (every file atomically, mode 0644 under the usual
//! umask). This module is the only one that joins [`crate::sat`] or [`crate::search`] with
//! [`crate::nusmv`] and [`crate::verify`]. Above it, one function per command of `synth` reads
//! the command's files, calls a pipeline here and writes its result folder; the command line
//! only parses, calls that function and prints. Every [`Error`] has a [`Class`], which the
//! command line turns into the exit code. `summary` holds the typed `summary.json` and
//! `--json` of every command, with their JSON Schema.
//!
//! Letters, the same in every method's output, the README and `summary.json`:
//! C states, K largest out-degree, T transitions, N guard literals, ε corrected errors,
//! M modules.

pub(crate) mod active;
pub mod ambiguity;
pub(crate) mod batch;
pub(crate) mod cegis;
mod class;
pub(crate) mod distributed;
pub mod event;
pub mod exact;
pub mod explain;
pub(crate) mod follow;
pub(crate) mod guide;
pub(crate) mod lazy;
pub(crate) mod lazy_noisy;
pub(crate) mod limit;
pub(crate) mod loop_encoding;
pub mod main_job;
pub mod modular;
pub mod noisy;
pub(crate) mod output;
pub(crate) mod plant_check;
pub(crate) mod polish;
pub(crate) mod recordings;
pub mod refine;
pub mod search;
pub(crate) mod summary;
pub mod table1;

pub use crate::check::CheckError;
pub use crate::deadline::Deadline;
pub use crate::ecc::diff::DiffError;
pub use crate::files::{ResultSetError, RuleError};
pub(crate) use crate::nusmv::Nusmv;
pub use crate::verify::{
    Counterexample, LocatedError, Problem, ProblemError, PropertyReport, Report,
    VerificationResult, Verifier, VerifyError,
};
pub use active::Round as LearnRound;
pub use cegis::{CegisError, Learned, Stall};
pub use class::Class;
pub use distributed::DescriptionError;
pub use event::{Event, Events, Note};
pub use follow::{Followed, Round};
pub use guide::Stage;
pub use lazy_noisy::{Bounds, PartRound};
pub use limit::{Limit, SoFar};
pub use recordings::Recordings;
use std::sync::Arc;

/// What a verified result is checked against: the problem and the NuSMV that certifies it.
#[derive(Debug, Clone)]
pub struct Check {
    /// Plant, coupling and properties, shared by every verifier of a run.
    pub problem: Arc<Problem>,
    /// The model checker; every "verified" comes from it.
    pub(crate) nusmv: Nusmv,
}

impl Check {
    /// A check of `problem` by `nusmv`.
    pub fn new(problem: Problem, nusmv: Nusmv) -> Check {
        Check {
            problem: Arc::new(problem),
            nusmv,
        }
    }

    /// A fresh verifier (own NuSMV dialogue and work folder).
    pub fn verifier(&self) -> Result<crate::verify::Verifier, Error> {
        Ok(crate::verify::Verifier::new(
            self.problem.clone(),
            &self.nusmv,
        )?)
    }

    /// The same check with NuSMV stopped at `deadline`; the pipelines that take a check stop
    /// their other work there too ([`Check::deadline`]).
    pub(crate) fn until(&self, deadline: crate::deadline::Deadline) -> Check {
        let mut check = self.clone();
        check.nusmv.deadline = deadline;
        check
    }

    /// The deadline of the run this check belongs to ([`Check::until`]).
    pub(crate) fn deadline(&self) -> crate::deadline::Deadline {
        self.nusmv.deadline
    }
}

/// Why a pipeline produced no result.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad scenario input: unreadable, malformed or contradictory (the place is named).
    #[error(transparent)]
    Scenario(#[from] crate::scenario::ScenarioError),
    /// The verification problem (plant, coupling, properties) could not be read.
    #[error(transparent)]
    Problem(#[from] crate::verify::ProblemError),
    /// A closed-loop verification gave no verdicts.
    #[error(transparent)]
    Verify(#[from] crate::verify::VerifyError),
    /// NuSMV could not be found, run, or its output understood.
    #[error(transparent)]
    Nusmv(#[from] crate::nusmv::NusmvError),
    /// Exact SAT synthesis found no machine (limits too low) or failed.
    #[error(transparent)]
    Sat(#[from] crate::sat::SatError),
    /// Modular synthesis found no controller of M modules, or was given none.
    #[error(transparent)]
    Modular(#[from] crate::sat::modular::ModularError),
    /// A network description that does not fit the recordings.
    #[error(transparent)]
    Network(#[from] distributed::DescriptionError),
    /// A bad `--pin` argument of modular synthesis.
    #[error(transparent)]
    Pin(#[from] crate::sat::modular::PinError),
    /// The metaheuristic search stopped without an outcome.
    #[error(transparent)]
    Search(#[from] crate::search::SearchError),
    /// The scenarios are out of the search's reach (too many inputs or outputs, no step).
    #[error(transparent)]
    SearchData(#[from] crate::search::fitness::DataError),
    /// The counterexample-guided loop ended without a verified controller.
    #[error(transparent)]
    Cegis(#[from] cegis::CegisError),
    /// The plant blocks some output of the controller, or cannot produce the recordings.
    #[error(transparent)]
    PlantCheck(#[from] plant_check::PlantCheckError),
    /// The recordings themselves violate properties, so no machine can satisfy them.
    #[error(transparent)]
    RecordingsViolate(#[from] explain::RecordingsViolate),
    /// A negative scenario is forced by the recordings, so no machine can avoid it.
    #[error(transparent)]
    NegativeRecorded(#[from] crate::scenario::negative::Recorded),
    /// Writing a result in one of the export formats failed.
    #[error(transparent)]
    Export(#[from] crate::export::ExportError),
    /// A JSON file does not describe a usable ECC.
    #[error(transparent)]
    Json(#[from] crate::export::json::JsonError),
    /// A name cannot be used in an output language (SMV, ST, `.fbt`, ...).
    #[error(transparent)]
    Name(#[from] crate::export::NameError),
    /// An ECC could not be emitted as SMV.
    #[error(transparent)]
    Smv(#[from] crate::smv::SmvError),
    /// An I/O error outside reading or writing a named user file.
    #[error(transparent)]
    Io(#[from] std::io::Error),
    /// An output file could not be written (its path is named).
    #[error(transparent)]
    Write(#[from] crate::files::WriteError),
    /// A user's file could not be read.
    #[error(transparent)]
    Read(#[from] crate::files::ReadError),
    /// A raw PLC log or its address mapping could not be read.
    #[error(transparent)]
    Ingest(#[from] crate::ingest::IngestError),
    /// A live run over OPC UA failed (connection, node, interface).
    #[error(transparent)]
    Live(#[from] crate::live::LiveError),
    /// An event log could not be made from a raw log.
    #[error(transparent)]
    Events(#[from] crate::events::EventsError),
    /// Two machines cannot be compared.
    #[error(transparent)]
    Diff(#[from] crate::ecc::diff::DiffError),
    /// The output folder cannot be taken for this run.
    #[error(transparent)]
    Folder(#[from] crate::files::ResultSetError),
    /// Bad input described in words (the place is in the text).
    #[error("{0}")]
    Input(String),
    /// An option the method cannot take.
    #[error("{0}")]
    Usage(String),
    /// No machine within the limits given.
    #[error("{0}")]
    NoMachine(String),
    /// The check asked for came out negative (a violated property, a difference, a step not
    /// reproduced), said in words.
    #[error("{0}")]
    Negative(String),
    /// The time limit passed before a machine was verified.
    #[error("time limit of {seconds} s reached before a verified machine (raise --time-limit SECONDS): {so_far}")]
    TimeLimit {
        /// The limit that passed, in seconds.
        seconds: f64,
        /// Lower bounds and candidates found before the limit passed.
        so_far: limit::SoFar,
    },
    /// The time limit passed before a job ended ([`limit::Limit::run`]).
    #[error("time limit of {seconds} s reached before a result (raise --time-limit SECONDS); the last step was: {last}")]
    Interrupted {
        /// The limit that passed, in seconds.
        seconds: f64,
        /// The last solver step the job reported, or "none yet".
        last: String,
    },
    /// A broken invariant.
    #[error("{0}")]
    Bug(String),
    /// An error with what the pipeline knows about it, one note a line after it (what the
    /// recordings never show, what the closed-loop game says, where a model was kept).
    #[error("{error}{}", notes.iter().map(|n| format!("\n({n})")).collect::<String>())]
    Noted {
        /// The error.
        error: Box<Error>,
        /// The notes, in order.
        notes: Vec<String>,
    },
}

impl Error {
    /// Whether NuSMV rejected code synth generated (not the user's plant or spec): the
    /// closed-loop model is then worth keeping for the bug report.
    pub(crate) fn in_generated_code(&self) -> bool {
        use crate::verify::VerifyError::Model;
        match self {
            Error::Noted { error, .. } => error.in_generated_code(),
            Error::Verify(Model(errors))
            | Error::Cegis(cegis::CegisError::Verify(Model(errors))) => {
                errors.iter().any(|e| e.generated)
            }
            _ => false,
        }
    }
}

/// The longest time any option may name: a year. Longer (or infinite) values are refused
/// rather than turned into a timer that panics or never fires.
pub(crate) const MAX_SECONDS: f64 = 365.0 * 24.0 * 3600.0;

/// A number of seconds given as option `option`: finite, not negative (positive when
/// `positive`), at most [`MAX_SECONDS`].
pub(crate) fn seconds(
    option: &str,
    value: f64,
    positive: bool,
) -> Result<std::time::Duration, Error> {
    let low_ok = if positive { value > 0.0 } else { value >= 0.0 };
    if !(value.is_finite() && low_ok && value <= MAX_SECONDS) {
        return Err(Error::Usage(format!(
            "{option} takes a {} number of seconds up to {MAX_SECONDS} (a year), not {value}",
            if positive { "positive" } else { "non-negative" }
        )));
    }
    Ok(std::time::Duration::from_secs_f64(value))
}

/// Locates NuSMV (`path`, else `$NUSMV`, `PATH`, the install script's cache) with a timeout
/// per closed-loop model; fails early with the install hint.
pub fn nusmv(path: Option<&std::path::Path>, timeout_seconds: f64) -> Result<Nusmv, Error> {
    let timeout = seconds("--timeout", timeout_seconds, true)?;
    let mut n = Nusmv::new(crate::nusmv::locate(path)?);
    n.timeout = timeout;
    Ok(n)
}

/// Verifies an existing machine in closed loop (no synthesis).
pub fn verify(
    ecc: &crate::ecc::Ecc,
    check: &Check,
) -> Result<crate::verify::VerificationResult, Error> {
    Ok(check.verifier()?.verify(ecc)?)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::verify::{LocatedError, VerifyError};

    fn rejected(generated: bool) -> VerifyError {
        VerifyError::Model(vec![LocatedError {
            file: "closed_loop.smv".into(),
            line: 3,
            message: "syntax error".into(),
            generated,
        }])
    }

    /// A noted error reads as the error with one note a line, and is of the error's class.
    #[test]
    fn notes_follow_the_error_and_keep_its_class() {
        let noted = Error::Noted {
            error: Box::new(Error::NoMachine("no machine".into())),
            notes: vec!["first".into(), "second".into()],
        };
        assert_eq!(noted.to_string(), "no machine\n(first)\n(second)");
        assert_eq!(noted.class(), Class::NoMachine);
        let generated = Error::Noted {
            error: Box::new(Error::Verify(rejected(true))),
            notes: Vec::new(),
        };
        assert!(generated.in_generated_code());
        assert_eq!(generated.class(), Error::Verify(rejected(true)).class());
    }

    /// The main job keeps the model NuSMV rejected only when the fault is in synth's code.
    #[test]
    fn only_errors_in_generated_code_count_as_such() {
        assert!(Error::Verify(rejected(true)).in_generated_code());
        assert!(Error::Cegis(cegis::CegisError::Verify(rejected(true))).in_generated_code());
        assert!(!Error::Verify(rejected(false)).in_generated_code());
        assert!(!Error::NoMachine("none".into()).in_generated_code());
    }
}
