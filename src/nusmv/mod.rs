//! Running the NuSMV model checker and reading what it prints.
//!
//! In: an SMV file on disk (written by the `smv` layer or by hand) and, for a [`Dialogue`], the
//! names of its properties ([`Query`]). Out: one [`PropertyResult`] per property asked, in the
//! order asked (a batch run: in the order of the `LTLSPEC`s in the file), each
//! [`Verdict::Violated`] carrying the counterexample [`Trace`] when NuSMV printed one.
//!
//! What NuSMV prints is read with a bound ([`driver::MAX_ANSWER_BYTES`] per answer): a NuSMV
//! printing without end is killed, not followed into the memory of this program.
//!
//! - [`locate()`] finds the binary (`--nusmv`, `$NUSMV`, `PATH`, the install script's cache);
//! - [`driver`] runs it: one process per model ([`Nusmv::check_file`]) or one long-lived
//!   `NuSMV -int` process fed many models ([`Dialogue`]), with timeouts and a Ctrl-C handler
//!   that kills every child;
//! - [`output`] parses stdout (verdicts and traces) and stderr (errors with file and line).
//!
//! This module knows nothing about SAT synthesis: the CEGIS loop that joins both lives
//! elsewhere.

pub(crate) mod driver;
pub(crate) mod locate;
pub(crate) mod output;

pub(crate) use driver::{kill_all_children, Dialogue, Query};
pub use driver::{CheckMode, Nusmv};
pub use locate::locate;
pub use output::{parse_errors, parse_output, Verdict};
pub use output::{ModelError, OutputParseError, PropertyResult, Trace};

use std::path::PathBuf;

/// Everything that can go wrong between asking NuSMV for verdicts and getting them.
#[derive(Debug, thiserror::Error)]
pub enum NusmvError {
    /// No NuSMV binary anywhere we look; `hint` says how to get one.
    #[error("NuSMV not found: {hint}")]
    NotFound {
        /// Where we looked and how to install NuSMV or point to it.
        hint: String,
    },
    /// The binary named by `--nusmv` or `$NUSMV` does not exist.
    #[error("NuSMV binary `{}` (from --nusmv or NUSMV) does not exist", .0.display())]
    ExplicitPathMissing(PathBuf),
    /// NuSMV ran longer than the configured timeout on `model`; the process was killed.
    #[error("NuSMV ran longer than {seconds} s on `{}` and was killed", model.display())]
    Timeout {
        /// The timeout that was exceeded, in seconds.
        seconds: f64,
        /// The SMV file being checked.
        model: PathBuf,
    },
    /// The run's deadline passed ([`crate::deadline`]): the check was killed, or not started.
    #[error("NuSMV stopped at the time limit")]
    Stopped,
    /// NuSMV rejected the model; each error carries the file and line NuSMV reported.
    #[error("NuSMV rejected the model: {}", describe_model_errors(.0))]
    Model(Vec<ModelError>),
    /// NuSMV failed without saying where: `status` tells how it ended, `stderr_tail` holds
    /// the last lines it printed on stderr.
    #[error("NuSMV failed ({status}): {stderr_tail}{}", out_of_memory(.stderr_tail))]
    Crashed {
        /// How the process ended (exit status or signal), or what was wrong with its answer.
        status: String,
        /// The last lines NuSMV printed on stderr.
        stderr_tail: String,
    },
    /// A model path NuSMV's interactive shell would mangle (`!` and `%` trigger its history
    /// expansion, `#` starts a comment, `"` ends the quoting).
    #[error("model path `{}` contains a character NuSMV's shell cannot take (one of ! % # \" \\ or a control character)", .0.display())]
    UnsafePath(PathBuf),
    /// A property a [`Dialogue`] cannot ask about: a name or formula NuSMV's command shell
    /// would not take as one argument (a name is a letter or `_`, then letters, digits and
    /// `_`; a formula holds no `"`, `\` or control character), or a name asked twice (NuSMV
    /// answers about a property once per model).
    #[error(
        "property {} cannot be asked of NuSMV: {reason}",
        crate::quote::backquote(property)
    )]
    UnsafeQuery {
        /// The property's name, as given.
        property: String,
        /// Why it cannot be asked.
        reason: &'static str,
    },
    /// NuSMV's answer to the check of one named property held not exactly one verdict.
    #[error(
        "NuSMV answered the check of property {} with {verdicts} verdicts, not one{}{}",
        crate::quote::backquote(property),
        stderr_suffix(stderr_tail),
        out_of_memory(stderr_tail)
    )]
    Answer {
        /// The name the property was asked for by.
        property: String,
        /// How many verdicts the answer held.
        verdicts: usize,
        /// The last lines NuSMV printed on stderr meanwhile.
        stderr_tail: String,
    },
    /// NuSMV printed more than `limit` bytes on `stream` in answer to one command (one
    /// property, or reading the model): it was killed, and nothing it printed is used.
    #[error("NuSMV printed more than {limit} bytes on {stream} in one answer while checking `{}` (the bound on what is read of one answer); it was killed and its output is not used", model.display())]
    OutputTooLarge {
        /// The bound, in bytes ([`driver::MAX_ANSWER_BYTES`] or [`driver::MAX_BATCH_BYTES`]).
        limit: usize,
        /// `stdout` or `stderr`.
        stream: &'static str,
        /// The SMV file being checked.
        model: PathBuf,
    },
    /// Starting NuSMV, talking to it, or reading the model file failed.
    #[error("running NuSMV: {0}")]
    Io(#[from] std::io::Error),
    /// NuSMV printed something the output parser does not understand.
    #[error("unexpected NuSMV output: {0}")]
    Output(#[from] OutputParseError),
    /// The model has no fair infinite path from an initial state (an `INIT`, `INVAR`, `TRANS`
    /// or `FAIRNESS` constraint that is never satisfied), so every LTL property would hold
    /// vacuously. `warning` is what NuSMV said about it, if anything.
    #[error("the model `{}` has no {what}: every property would hold vacuously, so nothing is verified; check the plant's INIT, INVAR, TRANS and FAIRNESS constraints{}", model.display(), warning.as_deref().map(|w| format!(" (NuSMV: {w})")).unwrap_or_default())]
    Vacuous {
        /// The SMV file being checked.
        model: PathBuf,
        /// What is missing: `initial state`, `state` or `fair infinite path`.
        what: &'static str,
        /// NuSMV's warning that a set of the finite state machine is empty, if it printed one.
        warning: Option<String>,
    },
    /// A reachable state of the model has no successor (NuSMV's `check_fsm`). NuSMV's LTL
    /// checking ignores runs that end, so a property violated only by runs through such a
    /// state would be reported as holding: no verdict on the model counts.
    #[error("the model `{}` deadlocks: the reachable state {} has no successor, and NuSMV's LTL verdicts ignore the runs that end there, so nothing is verified; the plant must accept every output the controller gives (check its INVAR and TRANS constraints)", model.display(), show_state(state))]
    Deadlock {
        /// The SMV file being checked.
        model: PathBuf,
        /// The state NuSMV printed, as `name = value` pairs.
        state: Vec<(String, String)>,
    },
}

/// `a = 1, b = TRUE`: a state as NuSMV printed it.
pub(crate) fn show_state(state: &[(String, String)]) -> String {
    let pairs: Vec<String> = state.iter().map(|(n, v)| format!("{n} = {v}")).collect();
    pairs.join(", ")
}

fn describe_model_errors(errors: &[ModelError]) -> String {
    match errors {
        [] => "no error line".to_string(),
        [one] => one.to_string(),
        [first, rest @ ..] => format!("{first} (and {} more)", rest.len()),
    }
}

/// `: ` and NuSMV's last words on stderr, if it printed any.
fn stderr_suffix(tail: &str) -> String {
    match tail.trim() {
        "" => String::new(),
        t => format!(": {t}"),
    }
}

/// The located NuSMV for the library's tests, or `None` after printing a skip note. Under
/// `CI=true` a missing NuSMV panics instead: CI installs it, so a skip there would hide a
/// broken install. (The integration tests have their own, in `tests/integration/common.rs`.)
#[cfg(test)]
pub(crate) fn nusmv_for_tests() -> Option<Nusmv> {
    match locate(None) {
        Ok(path) => Some(Nusmv::new(path)),
        Err(e) if std::env::var("CI").as_deref() == Ok("true") => {
            panic!("NuSMV is required when CI=true, but: {e}")
        }
        Err(e) => {
            eprintln!("skipping NuSMV test: {e}");
            None
        }
    }
}

/// What to do when NuSMV said it ran out of memory: it runs under a cap
/// ([`driver::memory_cap`]).
fn out_of_memory(stderr: &str) -> String {
    if !stderr.contains("Out of memory") {
        return String::new();
    }
    format!(
        "\n(NuSMV may take {} MB; the model is too large for that: narrow the plant's ranges, or raise the cap with FBSYNTH_NUSMV_MEMORY_MB)",
        driver::memory_cap() / (1 << 20)
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn model_error_message_names_the_first_position_and_counts_the_rest() {
        let err = |line| ModelError {
            file: "m.smv".into(),
            line,
            message: "syntax error".into(),
        };
        let e = NusmvError::Model(vec![err(3), err(9)]);
        assert_eq!(
            e.to_string(),
            "NuSMV rejected the model: m.smv:3: syntax error (and 1 more)"
        );
    }
}
