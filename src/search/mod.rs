//! Search-based synthesis (the metaheuristic and verification-in-the-loop papers): a metaheuristic that evolves ECCs against the
//! scenarios and, with properties, against NuSMV's verdicts.
//!
//! In: a [`ScenarioSet`](crate::scenario::ScenarioSet) (precomputed into
//! [`data::ScenarioData`]), a [`algorithm::Config`], and for verification-aware search one
//! [`oracle::Checker`] per colony. Out: an [`algorithm::Outcome`] whose [`Ecc`](crate::ecc::Ecc)
//! goes through the same exporters, simulator and verifier as a SAT result.
//!
//! Layers, each importing only those before it:
//! - [`machine`]: states with transition groups (significance mask + table), conversion to
//!   and from [`Ecc`](crate::ecc::Ecc);
//! - [`data`]: the scenarios precomputed into flat bit-mask arrays;
//! - [`labeling`]: the `{0,1,x}` state algorithms from the scenarios;
//! - [`fitness`]: the fitness terms and the allocation-free evaluator (labels with `labeling`);
//! - [`operators`]: the four mutations of the metaheuristic paper and the verification-in-the-loop paper's counterexample-weighted one;
//! - [`oracle`]: verdicts from NuSMV through [`crate::verify::verify`], cached by machine;
//! - [`algorithm`]: the parallel `(1+λ)` colonies sharing their best, seeded and repeatable.
//!
//! This module does not use [`crate::sat`]; the CLI joins the two paths.

pub(crate) mod algorithm;
pub(crate) mod data;
pub(crate) mod fitness;
pub(crate) mod labeling;
pub(crate) mod machine;
pub mod operators;
pub(crate) mod oracle;

pub(crate) use algorithm::{run, Config, Restart};
pub use algorithm::{Outcome, Progress, SearchError};
pub use data::DataError;
pub use data::ScenarioData;
pub use fitness::Evaluator;
pub use fitness::{ScenarioScore, Weights};
pub use machine::Machine;
pub use oracle::OracleError;
