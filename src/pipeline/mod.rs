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
//! [`crate::nusmv`] and [`crate::verify`]; the command line only parses, calls one function
//! here and prints.
//!
//! Letters, the same in every method's output, the README and `summary.json`:
//! C states, K largest out-degree, T transitions, N guard literals, ε corrected errors,
//! M modules.

pub mod active;
pub mod ambiguity;
pub mod batch;
pub mod cegis;
pub mod closed_loop;
pub mod distributed;
pub mod exact;
pub mod explain;
pub mod follow;
pub mod guide;
pub mod lazy;
pub mod lazy_noisy;
pub mod limit;
pub mod main_job;
pub mod modular;
pub mod noisy;
pub mod output;
pub mod recordings;
pub mod refine;
pub mod search;
pub mod table1;

pub use crate::nusmv::Nusmv;
pub use crate::verify::{Problem, Report};
pub use recordings::Recordings;
use std::sync::Arc;

/// What a verified result is checked against: the problem and the NuSMV that certifies it.
#[derive(Debug, Clone)]
pub struct Check {
    /// Plant, coupling and properties, shared by every verifier of a run.
    pub problem: Arc<Problem>,
    /// The model checker; every "verified" comes from it.
    pub nusmv: Nusmv,
}

impl Check {
    /// A check of `problem` by `nusmv`.
    pub fn new(problem: Problem, nusmv: Nusmv) -> Check {
        Check {
            problem: Arc::new(problem),
            nusmv,
        }
    }

    /// A fresh verifier (own NuSMV session and work folder).
    pub fn verifier(&self) -> Result<crate::verify::Verifier, Error> {
        Ok(crate::verify::Verifier::new(
            self.problem.clone(),
            &self.nusmv,
        )?)
    }

    /// The same check with NuSMV stopped at `deadline`; the pipelines that take a check stop
    /// their other work there too ([`Check::deadline`]).
    pub fn until(&self, deadline: crate::deadline::Deadline) -> Check {
        let mut check = self.clone();
        check.nusmv.deadline = deadline;
        check
    }

    /// The deadline of the run this check belongs to ([`Check::until`]).
    pub fn deadline(&self) -> crate::deadline::Deadline {
        self.nusmv.deadline
    }
}

/// Progress of a pipeline, for the caller to show (or not).
#[derive(Debug)]
pub enum Event<'a> {
    /// A step inside a SAT minimization (solver-level detail, for verbose output).
    Solver(crate::sat::Step),
    /// The exact loop's lower bounds, from the recorded inputs alone.
    LowerBounds {
        /// Lower bound on the number of states C.
        c: usize,
        /// Lower bound on the number of transitions T.
        t: usize,
        /// Wall-clock seconds since the loop started, when the bounds were proven.
        seconds: f64,
    },
    /// One candidate of the exact loop, verified by NuSMV.
    Candidate(&'a cegis::Iteration),
    /// The in-process checker stopped at one of its bounds ([`crate::check::Limits`]): NuSMV
    /// alone judges the exact loop's candidates from here.
    InProcessStopped {
        /// The bound, and how far the closed loop goes past it.
        why: String,
    },
    /// The search's start machine, found by SAT for the scenarios alone.
    SatStart {
        /// The start machine's figures (C, K, T, N).
        size: crate::ecc::Size,
        /// Wall-clock seconds the SAT synthesis took.
        seconds: f64,
    },
    /// The search begins.
    SearchStarted {
        /// The random seed (`--seed`) that makes the run reproducible.
        seed: u64,
        /// Number of states of every machine in the search.
        states: usize,
        /// Number of colonies searching side by side.
        colonies: usize,
        /// Worker threads.
        threads: usize,
        /// The search's time limit in seconds (`--time-limit`).
        time_limit: f64,
    },
    /// A round of the search (emitted by the search at its own pace).
    SearchRound(&'a crate::search::Progress),
    /// The search ended.
    SearchEnded {
        /// Wall-clock seconds the search ran.
        seconds: f64,
        /// Scenario fitness evaluations.
        evaluations: u64,
        /// Candidates verified by running NuSMV.
        nusmv_runs: u64,
        /// Candidates judged by the in-process model checker ([`crate::check`]) without NuSMV.
        in_process_checks: u64,
        /// Verdicts answered from the cache of machines already verified.
        cache_hits: u64,
    },
    /// NuSMV's verdict on a candidate of the noisy enumeration.
    CandidateVerdict {
        /// Names of the properties the candidate violates (empty: all hold).
        failing: &'a [String],
    },
    /// A noisy candidate's corrected traces go into the closed loop.
    ClosedLoopOf {
        /// The candidate's number, 1-based, in the order of [`noisy::Noisy`]'s candidates.
        candidate: usize,
        /// Number of recording errors ε the candidate corrects.
        errors: usize,
    },
    /// One controller checked in [`follow`] (a composite following a verified machine).
    Followed(&'a follow::Round),
    /// A round of noisy synthesis in parts ([`lazy_noisy`]) ended.
    NoisyPart(lazy_noisy::PartRound),
    /// The least ε of a noisy log in parts: lower bounds summed over disjoint parts.
    NoisyBound(lazy_noisy::Bounds),
    /// A stage of the closed-loop game's guide ([`guide`]).
    Guide(guide::Stage),
    /// A turn of the main job's strategy ([`main_job`]).
    MainJob(main_job::Step),
    /// A round of [`lazy`] synthesis over long recordings ended.
    Lazy {
        /// The round, 1-based.
        round: usize,
        /// Recorded steps encoded in this round.
        encoded: usize,
        /// Recorded steps in all.
        total: usize,
        /// Scenarios the round's machine departs from (0: the last round).
        diverging: usize,
    },
}

/// A sink for [`Event`]s.
pub type Events<'a> = &'a mut dyn FnMut(Event<'_>);

/// What kind of failure an [`Error`] is; the command line maps each to one exit code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// Bad input (file, line, step named) or a failed tool.
    Input,
    /// The check came out negative without a verdict to show: the plant allows no behaviour,
    /// so every property would hold vacuously and nothing is verified.
    Vacuous,
    /// An option out of its range or a combination the method does not take.
    Usage,
    /// No machine within the limits given.
    NoMachine,
    /// An internal invariant broke: a bug.
    Bug,
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
    /// Bad input described in words (the place is in the text).
    #[error("{0}")]
    Input(String),
    /// An option the method cannot take.
    #[error("{0}")]
    Usage(String),
    /// No machine within the limits given.
    #[error("{0}")]
    NoMachine(String),
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
    pub fn in_generated_code(&self) -> bool {
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

    /// The kind of failure, for the exit code.
    pub fn class(&self) -> Class {
        use crate::sat::modular::ModularError;
        use crate::sat::SatError;
        use crate::search::algorithm::SearchError;
        use crate::search::oracle::OracleError;
        use crate::verify::VerifyError::Vacuous;
        match self {
            Error::Noted { error, .. } => error.class(),
            Error::Verify(Vacuous { .. })
            | Error::Cegis(cegis::CegisError::Verify(Vacuous { .. }))
            | Error::Search(SearchError::Verify(OracleError::Nusmv(Vacuous { .. })))
            | Error::Search(SearchError::Verify(OracleError::InProcess(
                crate::check::CheckError::NoBehaviour { .. },
            ))) => Class::Vacuous,
            Error::Sat(
                SatError::TooManyStates { .. }
                | SatError::TooFewErrors { .. }
                | SatError::OutOfBounds { .. }
                | SatError::Stopped,
            )
            | Error::Modular(ModularError::Stopped)
            | Error::Cegis(cegis::CegisError::Sat(
                SatError::TooManyStates { .. } | SatError::Stopped,
            ))
            | Error::Cegis(cegis::CegisError::Iterations { .. })
            | Error::Cegis(cegis::CegisError::Exhausted { .. })
            | Error::Modular(ModularError::NoController { .. })
            | Error::NoMachine(_)
            | Error::TimeLimit { .. }
            | Error::Interrupted { .. } => Class::NoMachine,
            Error::Sat(SatError::Bug(_))
            | Error::Cegis(cegis::CegisError::Sat(SatError::Bug(_)))
            | Error::Cegis(cegis::CegisError::Disagreement { .. })
            | Error::Modular(ModularError::Bug(_))
            | Error::Bug(_) => Class::Bug,
            Error::Modular(ModularError::NoModules | ModularError::PinsInChain)
            | Error::Pin(_)
            | Error::Usage(_) => Class::Usage,
            _ => Class::Input,
        }
    }
}

/// The longest time any option may name: a year. Longer (or infinite) values are refused
/// rather than turned into a timer that panics or never fires.
pub const MAX_SECONDS: f64 = 365.0 * 24.0 * 3600.0;

/// A number of seconds given as option `option`: finite, not negative (positive when
/// `positive`), at most [`MAX_SECONDS`].
pub fn seconds(option: &str, value: f64, positive: bool) -> Result<std::time::Duration, Error> {
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
pub fn verify(ecc: &crate::ecc::Ecc, check: &Check) -> Result<crate::verify::Verification, Error> {
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
