//! What kind of failure each error is ([`Class`]), for the exit code of the command line.
//!
//! In: an [`Error`] of a pipeline, or any error it wraps. Out: its [`Class`]. Every error type
//! is classed by a `match` over all its variants with no wildcard arm, so a new variant does
//! not compile until it is given a class: no failure becomes "bad input" by default. The
//! command line maps each class to one exit code, in one function.

use super::Error;
use crate::export::ExportError;
use crate::files::ReadError;
use crate::nusmv::NusmvError;
use crate::pipeline::{cegis::CegisError, distributed::DescriptionError};
use crate::sat::modular::ModularError;
use crate::sat::SatError;
use crate::scenario::ScenarioError;
use crate::search::algorithm::SearchError;
use crate::search::fitness::DataError;
use crate::search::oracle::OracleError;
use crate::verify::{ProblemError, VerifyError};

/// What kind of failure an [`Error`] is; the command line maps each to one exit code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Class {
    /// Bad input (file, line, step named) or a failed tool.
    Input,
    /// The check came out negative without a verdict to show: the plant allows no behaviour,
    /// or the closed loop deadlocks, so properties would hold vacuously and nothing is
    /// verified.
    Vacuous,
    /// The check asked for came out negative: a violated property, a difference between two
    /// machines, a step a machine does not reproduce.
    Negative,
    /// An option out of its range or a combination the method does not take.
    Usage,
    /// No machine within the limits given.
    NoMachine,
    /// An internal invariant broke: a bug.
    Bug,
}

/// An error that knows its [`Class`].
pub(crate) trait Classed {
    /// The kind of failure.
    fn class(&self) -> Class;
}

impl Error {
    /// The kind of failure, for the exit code.
    pub fn class(&self) -> Class {
        match self {
            Error::Scenario(e) => e.class(),
            Error::Problem(e) => e.class(),
            Error::Verify(e) => e.class(),
            Error::Nusmv(e) => e.class(),
            Error::Sat(e) => e.class(),
            Error::Modular(e) => e.class(),
            Error::Network(e) => e.class(),
            Error::Search(e) => e.class(),
            Error::SearchData(e) => e.class(),
            Error::Cegis(e) => e.class(),
            Error::Export(e) => e.class(),
            Error::Json(e) => e.class(),
            Error::Read(e) => e.class(),
            Error::Ingest(e) => e.class(),
            Error::Events(e) => e.class(),
            Error::Diff(e) => e.class(),
            Error::Folder(e) => e.class(),
            Error::PlantCheck(e) => e.class(),
            Error::RecordingsViolate(_)
            | Error::NegativeRecorded(_)
            | Error::Name(_)
            | Error::Smv(_)
            | Error::Io(_)
            | Error::Write(_)
            | Error::Live(_)
            | Error::Input(_) => Class::Input,
            Error::Pin(_) | Error::Usage(_) => Class::Usage,
            Error::NoMachine(_) | Error::TimeLimit { .. } | Error::Interrupted { .. } => {
                Class::NoMachine
            }
            Error::Negative(_) => Class::Negative,
            Error::Bug(_) => Class::Bug,
            Error::Noted { error, .. } => error.class(),
        }
    }
}

impl Classed for super::plant_check::PlantCheckError {
    fn class(&self) -> Class {
        use super::plant_check::PlantCheckError;
        match self {
            PlantCheckError::NotReceptive { .. }
            | PlantCheckError::Unfair { .. }
            | PlantCheckError::Unproducible { .. } => Class::Input,
        }
    }
}

impl Classed for ScenarioError {
    fn class(&self) -> Class {
        match self {
            ScenarioError::Io { .. }
            | ScenarioError::Gzip { .. }
            | ScenarioError::Read(_)
            | ScenarioError::Syntax { .. }
            | ScenarioError::Step { .. }
            | ScenarioError::Names { .. }
            | ScenarioError::Contradiction(_)
            | ScenarioError::Other(_) => Class::Input,
        }
    }
}

impl Classed for ProblemError {
    fn class(&self) -> Class {
        match self {
            ProblemError::Spec(_)
            | ProblemError::Plant(_)
            | ProblemError::Coupling(_)
            | ProblemError::UnknownProperty { .. } => Class::Input,
        }
    }
}

impl Classed for VerifyError {
    fn class(&self) -> Class {
        match self {
            VerifyError::Vacuous { .. } => Class::Vacuous,
            VerifyError::Nusmv(e) => e.class(),
            VerifyError::Model(_)
            | VerifyError::Smv(_)
            | VerifyError::Io(_)
            | VerifyError::Timeout { .. }
            | VerifyError::Count { .. }
            | VerifyError::Incomplete { .. } => Class::Input,
        }
    }
}

impl Classed for NusmvError {
    fn class(&self) -> Class {
        match self {
            NusmvError::Vacuous { .. } | NusmvError::Deadlock { .. } => Class::Vacuous,
            // Only after the deadline passed, where the pipelines report the time limit.
            NusmvError::Stopped => Class::NoMachine,
            NusmvError::NotFound { .. }
            | NusmvError::ExplicitPathMissing(_)
            | NusmvError::Timeout { .. }
            | NusmvError::Model(_)
            | NusmvError::Crashed { .. }
            | NusmvError::UnsafePath(_)
            | NusmvError::Io(_)
            | NusmvError::Output(_)
            | NusmvError::UnsafeQuery { .. }
            | NusmvError::Answer { .. }
            | NusmvError::OutputTooLarge { .. } => Class::Input,
        }
    }
}

impl Classed for SatError {
    fn class(&self) -> Class {
        match self {
            SatError::TooManyStates { .. }
            | SatError::TooFewErrors { .. }
            | SatError::OutOfBounds { .. }
            | SatError::Stopped => Class::NoMachine,
            SatError::Bug(_) => Class::Bug,
        }
    }
}

impl Classed for ModularError {
    fn class(&self) -> Class {
        match self {
            ModularError::NoController { .. } | ModularError::Stopped => Class::NoMachine,
            ModularError::PinsInChain | ModularError::NoModules => Class::Usage,
            ModularError::Bug(_) => Class::Bug,
        }
    }
}

impl Classed for DescriptionError {
    fn class(&self) -> Class {
        match self {
            DescriptionError::Read { .. }
            | DescriptionError::Syntax { .. }
            | DescriptionError::Controller { .. }
            | DescriptionError::Network { .. } => Class::Input,
        }
    }
}

impl Classed for SearchError {
    fn class(&self) -> Class {
        match self {
            SearchError::Verify(OracleError::Nusmv(e)) => e.class(),
            SearchError::Verify(OracleError::InProcess(e)) => e.class(),
            SearchError::Config | SearchError::Threads(_) | SearchError::Checkers(..) => {
                Class::Input
            }
        }
    }
}

impl Classed for crate::check::CheckError {
    fn class(&self) -> Class {
        use crate::check::CheckError;
        match self {
            CheckError::NoBehaviour { .. } => Class::Vacuous,
            CheckError::Bug(_) => Class::Bug,
            CheckError::Coupling { .. }
            | CheckError::Ecc(_)
            | CheckError::Eval(_)
            | CheckError::TooManyStates { .. }
            | CheckError::TooManyTransitions { .. }
            | CheckError::TooMuchMemory { .. }
            | CheckError::Property { .. } => Class::Input,
        }
    }
}

impl Classed for DataError {
    fn class(&self) -> Class {
        match self {
            DataError::TooManyInputs { .. }
            | DataError::TooManyOutputs { .. }
            | DataError::Empty => Class::Input,
        }
    }
}

impl Classed for CegisError {
    fn class(&self) -> Class {
        match self {
            CegisError::Sat(e) => e.class(),
            CegisError::Verify(e) => e.class(),
            CegisError::Iterations { .. }
            | CegisError::Exhausted { .. }
            | CegisError::Stalled { .. } => Class::NoMachine,
            CegisError::Disagreement { .. } => Class::Bug,
            CegisError::NoCounterexample { .. } => Class::Input,
        }
    }
}

impl Classed for ExportError {
    fn class(&self) -> Class {
        match self {
            ExportError::InvalidEcc(_)
            | ExportError::Name { .. }
            | ExportError::Smv(_)
            | ExportError::Write { .. }
            | ExportError::Render { .. } => Class::Input,
        }
    }
}

impl Classed for crate::export::json::JsonError {
    fn class(&self) -> Class {
        use crate::export::json::JsonError;
        match self {
            JsonError::Syntax { .. } | JsonError::Content { .. } => Class::Input,
        }
    }
}

impl Classed for ReadError {
    fn class(&self) -> Class {
        match self {
            ReadError::Io(_)
            | ReadError::LineTooLong { .. }
            | ReadError::RecordTooLong { .. }
            | ReadError::TooLarge { .. }
            | ReadError::Gzip { .. }
            | ReadError::NotUtf8 { .. } => Class::Input,
        }
    }
}

impl Classed for crate::ingest::IngestError {
    fn class(&self) -> Class {
        use crate::ingest::IngestError;
        match self {
            IngestError::Parquet(e) => e.class(),
            IngestError::Io { .. }
            | IngestError::Mapping { .. }
            | IngestError::Header { .. }
            | IngestError::Row { .. }
            | IngestError::Read(_)
            | IngestError::Write(_)
            | IngestError::NoData { .. } => Class::Input,
        }
    }
}

impl Classed for crate::events::EventsError {
    fn class(&self) -> Class {
        use crate::events::EventsError;
        match self {
            EventsError::Log(e) => e.class(),
            EventsError::Reset { .. } | EventsError::Write(_) | EventsError::Sink { .. } => {
                Class::Input
            }
        }
    }
}

impl Classed for crate::ecc::diff::DiffError {
    fn class(&self) -> Class {
        use crate::ecc::diff::DiffError;
        match self {
            DiffError::Inputs(..) | DiffError::Outputs(..) | DiffError::TooManyInputs(_) => {
                Class::Input
            }
        }
    }
}

impl Classed for crate::files::ResultSetError {
    fn class(&self) -> Class {
        use crate::files::ResultSetError;
        match self {
            ResultSetError::Busy { .. } | ResultSetError::Write(_) | ResultSetError::Rule(_) => {
                Class::Input
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    /// A failure keeps its class through every wrapper that forwards it: the exit code of a
    /// plant without behaviour, of no machine within the limits and of a bug is the same
    /// whichever pipeline met it.
    #[test]
    fn wrapped_failures_keep_their_class() {
        let vacuous = || VerifyError::Vacuous {
            plant: PathBuf::from("plant.smv"),
            what: "initial state",
            warning: None,
        };
        let too_many = || SatError::TooManyStates { max_states: 3 };
        let cases = [
            (Error::Verify(vacuous()), Class::Vacuous),
            (Error::Cegis(CegisError::Verify(vacuous())), Class::Vacuous),
            (
                Error::Search(SearchError::Verify(OracleError::Nusmv(vacuous()))),
                Class::Vacuous,
            ),
            (Error::Sat(too_many()), Class::NoMachine),
            (Error::Cegis(CegisError::Sat(too_many())), Class::NoMachine),
            (
                Error::Cegis(CegisError::Sat(SatError::Bug("x".into()))),
                Class::Bug,
            ),
            (Error::Modular(ModularError::NoModules), Class::Usage),
            (
                Error::Negative("the machines differ".into()),
                Class::Negative,
            ),
            (Error::Input("bad".into()), Class::Input),
            (
                Error::Noted {
                    error: Box::new(Error::Sat(too_many())),
                    notes: vec!["a note".into()],
                },
                Class::NoMachine,
            ),
        ];
        for (error, class) in cases {
            assert_eq!(error.class(), class, "{error}");
        }
    }
}
