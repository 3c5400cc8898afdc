//! Running the NuSMV model checker and reading what it prints.
//!
//! In: an SMV file on disk (written by the `smv` layer or by hand). Out: one
//! [`PropertyResult`] per LTL property, in the order NuSMV checked them (the order of the
//! `LTLSPEC`s in the file), each [`Verdict::Violated`] carrying the counterexample
//! [`Trace`] when NuSMV printed one.
//!
//! - [`locate`] finds the binary (`--nusmv`, `$NUSMV`, `PATH`, the install script's cache);
//! - [`driver`] runs it: one process per model ([`Nusmv::check_file`]) or one long-lived
//!   `NuSMV -int` process fed many models ([`Session`]), with timeouts and a Ctrl-C handler
//!   that kills every child;
//! - [`output`] parses stdout (verdicts and traces) and stderr (errors with file and line).
//!
//! This module knows nothing about SAT synthesis: the CEGIS loop that joins both lives
//! elsewhere.

pub mod output;

pub use output::{
    parse_errors, parse_output, ModelError, OutputParseError, PropertyResult, Trace, Verdict,
};
