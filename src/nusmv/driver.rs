//! Running NuSMV processes.
//!
//! In: the path of a NuSMV binary, SMV model files and, for a [`Dialogue`], the properties to
//! ask about by name ([`Query`]). Out: parsed [`PropertyResult`]s, or a [`NusmvError`] saying
//! why there are none.
//!
//! Two ways to run it:
//! - [`Nusmv::check_file`]: one batch process per model (`NuSMV -dynamic model.smv`); simple,
//!   and what a user would run by hand.
//! - [`Dialogue`]: one `NuSMV -int` process fed model after model on stdin; it saves the
//!   process start and, with the `EL_fwd` emptiness algorithm, most of the checking time.
//!
//! Output is read with a bound ([`MAX_ANSWER_BYTES`] per answer, [`MAX_BATCH_BYTES`] per
//! batch run, whatever the length of its lines): past it NuSMV is killed and the check fails.
//!
//! Every child is kept in a process-wide registry until it has been reaped, so that Ctrl-C
//! (or [`kill_all_children`]) can kill them all: NuSMV in `-int` mode catches SIGINT itself
//! and would otherwise outlive us.

use super::output::{parse_errors, parse_output, PropertyResult, Verdict};
use super::NusmvError;
use crate::deadline::Deadline;
use std::collections::BTreeMap;
use std::io::{self, BufRead, BufReader, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

/// A NuSMV binary and how long one model may take.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Nusmv {
    /// The NuSMV executable (as found by [`locate`](super::locate())).
    pub path: PathBuf,
    /// Wall-clock limit per model; the process is killed when it is exceeded.
    pub(crate) timeout: Duration,
    /// The run's deadline: a check still running then is killed ([`NusmvError::Stopped`]),
    /// and none starts after it.
    pub(crate) deadline: Deadline,
}

impl Nusmv {
    /// The timeout [`Nusmv::new`] sets.
    pub(crate) const DEFAULT_TIMEOUT: Duration = Duration::from_secs(60);

    /// The binary at `path` with [`Nusmv::DEFAULT_TIMEOUT`].
    pub fn new(path: PathBuf) -> Nusmv {
        Nusmv {
            path,
            timeout: Self::DEFAULT_TIMEOUT,
            deadline: Deadline::NONE,
        }
    }

    /// Checks every LTL property of `model` in a fresh batch process, with traces for every
    /// violated one.
    pub fn check_file(&self, model: &Path) -> Result<Vec<PropertyResult>, NusmvError> {
        model_exists(model)?;
        if self.deadline.passed() {
            return Err(NusmvError::Stopped);
        }
        let deadline = self.deadline.cap(Instant::now() + self.timeout);
        let mut command = Command::new(&self.path);
        // -dynamic (dynamic BDD variable reordering) took ~40% off a plant + controller check.
        command.arg("-dynamic").arg(model);
        let mut child = Tracked::spawn(command)?;
        // Batch NuSMV reads no commands: give it end-of-file at once.
        child.stdin.take();
        let (tx, rx) = mpsc::channel();
        let stdout = child.stdout.take().expect("stdout is piped");
        let stderr = child.stderr.take().expect("stderr is piped");
        read_all_on_thread(Stream::Out, stdout, tx.clone(), MAX_BATCH_BYTES);
        read_all_on_thread(Stream::Err, stderr, tx, MAX_BATCH_BYTES);
        let mut out = None;
        let mut err = None;
        while out.is_none() || err.is_none() {
            match rx.recv_timeout(deadline.saturating_duration_since(Instant::now())) {
                Ok((Stream::Out, Some(text))) => out = Some(text),
                Ok((Stream::Err, Some(text))) => err = Some(text),
                Ok((stream, None)) => {
                    let _ = child.kill_and_reap();
                    return Err(NusmvError::OutputTooLarge {
                        limit: MAX_BATCH_BYTES,
                        stream: stream.name(),
                        model: model.to_path_buf(),
                    });
                }
                Err(RecvTimeoutError::Timeout) => {
                    let _ = child.kill_and_reap();
                    return Err(self.timed_out(model));
                }
                Err(RecvTimeoutError::Disconnected) => {
                    unreachable!("both reader threads send before they end")
                }
            }
        }
        let (out, err) = (out.unwrap_or_default(), err.unwrap_or_default());
        let status = child.reap()?;
        if !status.success() {
            let errors = parse_errors(&err);
            if !errors.is_empty() {
                return Err(NusmvError::Model(errors));
            }
            return Err(NusmvError::Crashed {
                status: status.to_string(),
                stderr_tail: tail(&err),
            });
        }
        Ok(parse_output(&out)?)
    }

    /// A [`Dialogue`] running this binary with this timeout.
    pub(crate) fn dialogue(&self) -> Dialogue {
        Dialogue::new(self.clone())
    }

    /// Why a check that ran out of time ended: the run's deadline or the model's timeout.
    fn timed_out(&self, model: &Path) -> NusmvError {
        match self.deadline.passed() {
            true => NusmvError::Stopped,
            false => timeout(self.timeout, model),
        }
    }
}

/// Bytes NuSMV may print on one stream in answer to one command of a [`Dialogue`] (one
/// property's verdict and counterexample, or reading a model). Past it the process is killed
/// and the check fails with [`NusmvError::OutputTooLarge`]: a NuSMV printing without end must
/// not take the memory of this program with it.
pub const MAX_ANSWER_BYTES: usize = 16 << 20;

/// Bytes a batch run ([`Nusmv::check_file`]) may print on one stream, for all its properties.
pub const MAX_BATCH_BYTES: usize = 64 << 20;

/// A property of a model, as a [`Dialogue`] asks NuSMV about it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Query {
    /// The property's name in the model (`LTLSPEC NAME name := ...`): a letter or `_`, then
    /// letters, digits and `_`. Its verdict is asked for with `check_ltlspec -P name`.
    pub name: String,
    /// The formula as SMV text over the names of module `main`, for the re-check that prints
    /// a violated property's counterexample (`check_ltlspec -p "..."`).
    pub formula: String,
}

impl Query {
    /// Refuses a name or formula NuSMV's command shell would not read as one argument.
    fn check(&self) -> Result<(), NusmvError> {
        let mut chars = self.name.chars();
        let name_ok = chars
            .next()
            .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
            && chars.all(|c| c.is_ascii_alphanumeric() || c == '_');
        let formula_ok = !self.formula.trim().is_empty()
            && !(self.formula.chars()).any(|c| matches!(c, '"' | '\\') || c.is_control());
        let reason = match (name_ok, formula_ok) {
            (true, true) => return Ok(()),
            (false, _) => "its name is not a letter or `_` followed by letters, digits and `_`",
            (true, false) => {
                "its formula is empty or holds a quote, a backslash or a control character"
            }
        };
        Err(self.refused(reason))
    }

    fn refused(&self, reason: &'static str) -> NusmvError {
        NusmvError::UnsafeQuery {
            property: self.name.clone(),
            reason,
        }
    }
}

/// What NuSMV printed between two markers of a [`Dialogue`]: its answer to one command.
struct Answer {
    out: String,
    err: String,
}

/// The verdict on `query`: the one verdict its answer holds, under the query's name.
fn one_verdict(query: &Query, answer: &Answer) -> Result<PropertyResult, NusmvError> {
    let mut verdicts = parse_output(&answer.out)?;
    if verdicts.len() != 1 {
        return Err(NusmvError::Answer {
            property: query.name.clone(),
            verdicts: verdicts.len(),
            stderr_tail: tail(&answer.err),
        });
    }
    let mut result = verdicts.remove(0);
    result.name = Some(query.name.clone());
    Ok(result)
}

/// What a [`Dialogue`] computes for each model.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CheckMode {
    /// Verdicts of every property asked, no traces (fast `EL_fwd` emptiness check).
    VerdictsOnly,
    /// Verdicts as with `VerdictsOnly`, plus the trace of the first violated property
    /// (re-checked with `EL_bwd`, the algorithm that can print traces).
    FirstCounterexample,
    /// Verdicts, plus a trace for every violated property (one `EL_bwd` re-check each).
    AllCounterexamples,
}

/// A long-lived `NuSMV -int` process checking one model after another.
///
/// Per model it sends `reset`, `read_model -i F`, `go`, then `check_ltlspec -P name` for each
/// property asked, every command followed by an `echo` marker on stdout and on stderr, and
/// cuts both streams at the markers: what comes between two markers is the answer to one
/// command, and what is kept of it is bounded ([`MAX_ANSWER_BYTES`]). Errors in one model
/// leave the dialogue usable for the next; a timeout or crash kills the process and the next
/// [`Dialogue::check`] starts a new one. The process is also restarted every
/// [`Dialogue::DEFAULT_RESTART_EVERY`] models, because NuSMV's memory grows with each model.
pub(crate) struct Dialogue {
    nusmv: Nusmv,
    process: Option<DialogueProcess>,
    models_in_process: usize,
    restart_every: usize,
    next_marker: u64,
    /// See [`Dialogue::warnings`].
    warnings: Vec<String>,
}

/// NuSMV's answer to `check_fsm` (see [`Dialogue::deadlock_of`]): `Some(None)` when no
/// reachable state lacks a successor, `Some(Some(state))` for the deadlock state it printed,
/// `None` for an answer that says neither.
fn parse_check_fsm(out: &str) -> Option<Option<Vec<(String, String)>>> {
    if let Some(k) = out.find("A deadlock state is:") {
        let state = out[k..]
            .lines()
            .skip(1)
            .take_while(|l| !l.starts_with("####"))
            .filter_map(|l| l.split_once(" = "))
            .map(|(n, v)| (n.trim().to_string(), v.trim().to_string()))
            .collect();
        return Some(Some(state));
    }
    let free = out.contains("The transition relation is total")
        || out.contains("so the machine is deadlock-free");
    free.then_some(None)
}

/// Text NuSMV echoes after each command; a number follows, then `==`.
const MARKER: &str = "==fbsynth-end-";

impl Dialogue {
    /// Models checked by one process before it is replaced by a fresh one.
    pub(crate) const DEFAULT_RESTART_EVERY: usize = 2000;

    /// A dialogue; the process starts with the first [`Dialogue::check`].
    pub(crate) fn new(nusmv: Nusmv) -> Dialogue {
        Dialogue {
            nusmv,
            process: None,
            models_in_process: 0,
            restart_every: Self::DEFAULT_RESTART_EVERY,
            next_marker: 0,
            warnings: Vec::new(),
        }
    }

    /// What NuSMV printed on stderr while checking the last model that no verdict or error
    /// accounts for (a warning of a newer or patched NuSMV, say): reports show it, since it
    /// may change what a verdict means.
    pub(crate) fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Replaces the process after `models` models (at least 1).
    pub(crate) fn set_restart_every(&mut self, models: usize) {
        self.restart_every = models.max(1);
    }

    /// The process id of the running NuSMV, if one is running.
    pub(crate) fn pid(&self) -> Option<u32> {
        self.process.as_ref().map(|p| p.child.id)
    }

    /// Checks the properties `queries` of `model`, each asked for by its name: one result per
    /// query, in the order of `queries`; see [`CheckMode`] for which carry traces.
    ///
    /// NuSMV's verdict line prints its own reprint of the formula, never the name, so no
    /// verdict is matched by its text: each `check_ltlspec -P name` is followed by an `echo`
    /// marker, and the answer between two markers is the verdict on the property asked.
    pub(crate) fn check(
        &mut self,
        model: &Path,
        queries: &[Query],
        mode: CheckMode,
    ) -> Result<Vec<PropertyResult>, NusmvError> {
        model_exists(model)?;
        let quoted = shell_quoted(model)?;
        for (k, q) in queries.iter().enumerate() {
            q.check()?;
            if queries[..k].iter().any(|earlier| earlier.name == q.name) {
                return Err(q.refused("it is asked twice, and NuSMV answers once per model"));
            }
        }
        if self.nusmv.deadline.passed() {
            return Err(NusmvError::Stopped);
        }
        // Restart between models only: the trace pass needs the model the verdict pass read.
        if self.models_in_process >= self.restart_every {
            self.process = None;
        }
        self.ensure_process()?;
        self.models_in_process += 1;
        self.warnings.clear();
        let deadline = self.nusmv.deadline.cap(Instant::now() + self.nusmv.timeout);
        let mut commands = vec![format!(
            "reset\nread_model -i {quoted}\ngo\nset oreg_justice_emptiness_bdd_algorithm EL_fwd\n"
        )];
        commands.extend((queries.iter()).map(|q| format!("check_ltlspec -P {}\n", q.name)));
        let answers = self.run(&commands, deadline, model)?;
        let out: String = answers.iter().map(|a| a.out.as_str()).collect();
        let err: String = answers.iter().map(|a| a.err.as_str()).collect();
        let errors = parse_errors(&err);
        if !errors.is_empty() {
            return Err(NusmvError::Model(errors));
        }
        let mut results = (queries.iter().zip(&answers[1..]))
            .map(|(q, answer)| one_verdict(q, answer))
            .collect::<Result<Vec<_>, _>>()?;
        self.check_not_vacuous(&format!("{out}\n{err}"), deadline, model)?;
        if let Some(state) = self.deadlock(deadline, model)? {
            return Err(NusmvError::Deadlock {
                model: model.to_path_buf(),
                state,
            });
        }
        self.warnings = unexplained(&err);
        match mode {
            CheckMode::VerdictsOnly => {}
            CheckMode::FirstCounterexample => {
                self.add_traces(&mut results, queries, deadline, model, false)?
            }
            CheckMode::AllCounterexamples => {
                self.add_traces(&mut results, queries, deadline, model, true)?
            }
        }
        Ok(results)
    }

    /// A reachable state of `model` without successor (NuSMV's `check_fsm`), as `name =
    /// value` pairs, or `None` when every reachable state has one. Fails as
    /// [`Dialogue::check`] does on a model NuSMV rejects or that has no fair infinite path.
    pub(crate) fn deadlock_of(
        &mut self,
        model: &Path,
    ) -> Result<Option<Vec<(String, String)>>, NusmvError> {
        model_exists(model)?;
        let quoted = shell_quoted(model)?;
        if self.nusmv.deadline.passed() {
            return Err(NusmvError::Stopped);
        }
        // A fresh process: the check is asked once per run, beside the dialogue's models.
        self.process = None;
        self.ensure_process()?;
        self.models_in_process += 1;
        let deadline = self.nusmv.deadline.cap(Instant::now() + self.nusmv.timeout);
        let command = format!("reset\nread_model -i {quoted}\ngo\n");
        let answer = self.run(&[command], deadline, model)?.remove(0);
        let errors = parse_errors(&answer.err);
        if !errors.is_empty() {
            return Err(NusmvError::Model(errors));
        }
        let printed = format!("{}\n{}", answer.out, answer.err);
        self.check_not_vacuous(&printed, deadline, model)?;
        self.deadlock(deadline, model)
    }

    /// Whether each invariant of `formulas` holds in `model` (NuSMV's `check_invar`, without
    /// counterexamples), in order. The formulas are generated, never a user's text.
    pub(crate) fn invariants(
        &mut self,
        model: &Path,
        formulas: &[String],
    ) -> Result<Vec<bool>, NusmvError> {
        model_exists(model)?;
        let quoted = shell_quoted(model)?;
        if self.nusmv.deadline.passed() {
            return Err(NusmvError::Stopped);
        }
        self.ensure_process()?;
        self.models_in_process += 1;
        let deadline = self.nusmv.deadline.cap(Instant::now() + self.nusmv.timeout);
        let mut commands = vec![format!(
            "reset\nset counter_examples 0\nread_model -i {quoted}\ngo\ncompute_reachable\n"
        )];
        commands.extend(formulas.iter().map(|f| format!("check_invar -p \"{f}\"\n")));
        let answers = self.run(&commands, deadline, model)?;
        // The next model gets a process that prints counterexamples again.
        self.process = None;
        let err: String = answers.iter().map(|a| a.err.as_str()).collect();
        let errors = parse_errors(&err);
        if !errors.is_empty() {
            return Err(NusmvError::Model(errors));
        }
        (answers[1..=formulas.len()].iter())
            .map(|a| {
                let verdict = a.out.lines().find(|l| l.contains("-- invariant "));
                match verdict.map(str::trim_end) {
                    Some(l) if l.ends_with("is true") => Ok(true),
                    Some(l) if l.ends_with("is false") => Ok(false),
                    _ => Err(NusmvError::Crashed {
                        status: "an answer to check_invar without a verdict".into(),
                        stderr_tail: tail(&format!("{}\n{}", a.out, a.err)),
                    }),
                }
            })
            .collect()
    }

    /// Asks `check_fsm` of the model read last: a reachable state without successor, or
    /// `None`. NuSMV prints "The transition relation is total" or, when only unreachable
    /// states lack a successor, "... so the machine is deadlock-free"; otherwise "A deadlock
    /// state is:" and the state, one `name = value` a line.
    fn deadlock(
        &mut self,
        deadline: Instant,
        model: &Path,
    ) -> Result<Option<Vec<(String, String)>>, NusmvError> {
        let answer = self
            .run(&["check_fsm\n".to_string()], deadline, model)?
            .remove(0);
        parse_check_fsm(&answer.out).ok_or_else(|| NusmvError::Crashed {
            status: "an answer to check_fsm that says neither total nor deadlock".into(),
            stderr_tail: tail(&format!("{}\n{}", answer.out, answer.err)),
        })
    }

    /// Fails when the model has no fair infinite path from an initial state. Then every LTL
    /// property holds and NuSMV says so, at most with a warning; the question `FALSE` tells:
    /// it is violated exactly when such a path exists.
    fn check_not_vacuous(
        &mut self,
        printed: &str,
        deadline: Instant,
        model: &Path,
    ) -> Result<(), NusmvError> {
        let command = "check_ltlspec -p \"FALSE\"\n".to_string();
        let answer = self.run(&[command], deadline, model)?.remove(0);
        let verdicts = parse_output(&answer.out)?;
        let holds = match &verdicts[..] {
            [one] => one.verdict == Verdict::Holds,
            _ => {
                return Err(NusmvError::Crashed {
                    status: format!("{} verdicts on the emptiness check", verdicts.len()),
                    stderr_tail: tail(&answer.err),
                })
            }
        };
        if !holds {
            return Ok(());
        }
        // NuSMV's own words, where it printed any ("The initial states set ... is empty.").
        let warning = printed
            .lines()
            .find(|l| l.contains("set of the finite state machine is empty"))
            .map(|l| l.trim().trim_end_matches('.').to_string());
        let what = match &warning {
            Some(w) if w.contains("initial states") => "initial state",
            Some(_) => "state",
            None => "fair infinite path",
        };
        Err(NusmvError::Vacuous {
            model: model.to_path_buf(),
            what,
            warning,
        })
    }

    /// Re-checks violated properties in order with `EL_bwd` until one yields a trace (or, with
    /// `all`, every one of them).
    ///
    /// NuSMV skips a named property whose status it knows already, so the property is checked
    /// again as a new one, given by its formula (`check_ltlspec -p`); the answer is the one
    /// between this command's markers, whatever NuSMV reprints in it.
    fn add_traces(
        &mut self,
        results: &mut [PropertyResult],
        queries: &[Query],
        deadline: Instant,
        model: &Path,
        all: bool,
    ) -> Result<(), NusmvError> {
        for (result, query) in results.iter_mut().zip(queries) {
            if result.verdict != Verdict::Violated(None) {
                continue;
            }
            let command = format!(
                "set oreg_justice_emptiness_bdd_algorithm EL_bwd\n\
                 check_ltlspec -p \"{}\"\n",
                query.formula
            );
            let answer = self.run(&[command], deadline, model)?.remove(0);
            let errors = parse_errors(&answer.err);
            if !errors.is_empty() {
                return Err(NusmvError::Model(errors));
            }
            let recheck = one_verdict(query, &answer)?;
            // EL_bwd is NuSMV's reference algorithm: its verdict replaces EL_fwd's.
            result.verdict = recheck.verdict;
            if !all && matches!(result.verdict, Verdict::Violated(Some(_))) {
                break;
            }
        }
        Ok(())
    }

    /// Sends each command followed by its markers and returns, per command, the stdout and
    /// stderr text printed between the markers before it and its own.
    fn run(
        &mut self,
        commands: &[String],
        deadline: Instant,
        model: &Path,
    ) -> Result<Vec<Answer>, NusmvError> {
        self.ensure_process()?;
        let first = self.next_marker + 1;
        self.next_marker += commands.len() as u64;
        let mut script = String::new();
        for (k, command) in commands.iter().enumerate() {
            let marker = first + k as u64;
            script.push_str(command);
            script.push_str(&format!(
                "echo {MARKER}{marker}==\necho -2 {MARKER}{marker}==\n"
            ));
        }
        let process = self.process.as_mut().expect("started above");
        let sent = process
            .stdin
            .write_all(script.as_bytes())
            .and_then(|()| process.stdin.flush());
        if sent.is_err() {
            return Err(self.crashed());
        }
        let mut out: Vec<Option<String>> = vec![None; commands.len()];
        let mut err: Vec<Option<String>> = vec![None; commands.len()];
        let mut missing = 2 * commands.len();
        while missing > 0 {
            let process = self.process.as_mut().expect("set until a failure returns");
            match process
                .events
                .recv_timeout(deadline.saturating_duration_since(Instant::now()))
            {
                Ok(Event::Chunk {
                    stream,
                    marker,
                    text,
                }) if marker >= first && marker - first < commands.len() as u64 => {
                    let slots = match stream {
                        Stream::Out => &mut out,
                        Stream::Err => &mut err,
                    };
                    let slot = &mut slots[(marker - first) as usize];
                    missing -= usize::from(slot.is_none());
                    *slot = Some(text);
                }
                // A leftover of an earlier model cannot happen (each failure replaces the
                // process), but it would be harmless to skip.
                Ok(Event::Chunk { .. }) => {}
                Ok(Event::Overflow { stream }) => {
                    // Dropping the process kills it: nothing more of its output is read.
                    self.process = None;
                    return Err(NusmvError::OutputTooLarge {
                        limit: MAX_ANSWER_BYTES,
                        stream: stream.name(),
                        model: model.to_path_buf(),
                    });
                }
                Ok(Event::Closed { stream, rest }) => {
                    process.closed(stream, rest);
                    return Err(self.crashed());
                }
                Err(RecvTimeoutError::Timeout) => {
                    // Dropping the process kills and reaps it.
                    self.process = None;
                    return Err(self.nusmv.timed_out(model));
                }
                Err(RecvTimeoutError::Disconnected) => return Err(self.crashed()),
            }
        }
        Ok((out.into_iter().zip(err))
            .map(|(out, err)| Answer {
                out: out.unwrap_or_default(),
                err: err.unwrap_or_default(),
            })
            .collect())
    }

    fn ensure_process(&mut self) -> Result<(), NusmvError> {
        if self.process.is_none() {
            self.process = Some(DialogueProcess::start(&self.nusmv.path)?);
            self.models_in_process = 0;
        }
        Ok(())
    }

    /// The process died: reap it and report how, with what it last said on stderr.
    fn crashed(&mut self) -> NusmvError {
        let Some(mut process) = self.process.take() else {
            return NusmvError::Crashed {
                status: "no process".to_string(),
                stderr_tail: String::new(),
            };
        };
        // Give the stderr reader a moment to deliver the last words.
        let grace = Instant::now() + Duration::from_secs(1);
        while !process.stderr_closed {
            match process
                .events
                .recv_timeout(grace.saturating_duration_since(Instant::now()))
            {
                Ok(Event::Chunk {
                    stream: Stream::Err,
                    text,
                    ..
                }) => process.keep_stderr(&text),
                Ok(Event::Closed { stream, rest }) => process.closed(stream, rest),
                Ok(_) => {}
                Err(_) => break,
            }
        }
        // Killing first: a process that closed its stdout but lingers must not hang us.
        let status = match process.child.kill_and_reap() {
            Ok(status) => status.to_string(),
            Err(e) => format!("could not be reaped: {e}"),
        };
        let stderr_tail = match tail(&process.stderr_text) {
            t if t.trim().is_empty() => "it printed nothing on stderr".to_string(),
            t => t,
        };
        NusmvError::Crashed {
            status,
            stderr_tail,
        }
    }
}

/// The running `NuSMV -int` of a [`Dialogue`]. Dropping it kills and reaps the process.
struct DialogueProcess {
    child: Tracked,
    stdin: ChildStdin,
    events: Receiver<Event>,
    /// stderr text that came after the last marker, kept for crash reports.
    stderr_text: String,
    stderr_closed: bool,
}

impl DialogueProcess {
    fn start(binary: &Path) -> Result<DialogueProcess, NusmvError> {
        let mut command = Command::new(binary);
        command.arg("-int");
        let mut child = Tracked::spawn(command)?;
        let stdin = child.stdin.take().expect("stdin is piped");
        let (tx, events) = mpsc::channel();
        let (out, err) = (child.stdout.take(), child.stderr.take());
        read_chunks_on_thread(
            Stream::Out,
            out.expect("piped"),
            tx.clone(),
            MAX_ANSWER_BYTES,
        );
        read_chunks_on_thread(Stream::Err, err.expect("piped"), tx, MAX_ANSWER_BYTES);
        Ok(DialogueProcess {
            child,
            stdin,
            events,
            stderr_text: String::new(),
            stderr_closed: false,
        })
    }

    /// Adds `text` to the stderr kept for a crash report, of which only the end is shown: at
    /// most [`MAX_ANSWER_BYTES`] of the end are kept.
    fn keep_stderr(&mut self, text: &str) {
        self.stderr_text.push_str(text);
        let excess = self.stderr_text.len().saturating_sub(MAX_ANSWER_BYTES);
        if excess > 0 {
            let cut = (excess..=self.stderr_text.len())
                .find(|&i| self.stderr_text.is_char_boundary(i))
                .unwrap_or(self.stderr_text.len());
            self.stderr_text.drain(..cut);
        }
    }

    fn closed(&mut self, stream: Stream, rest: String) {
        if stream == Stream::Err {
            self.keep_stderr(&rest);
            self.stderr_closed = true;
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Stream {
    Out,
    Err,
}

impl Stream {
    fn name(self) -> &'static str {
        match self {
            Stream::Out => "stdout",
            Stream::Err => "stderr",
        }
    }
}

/// What a dialogue's reader thread reports.
enum Event {
    /// The text before the marker numbered `marker` (since the previous marker).
    Chunk {
        stream: Stream,
        marker: u64,
        text: String,
    },
    /// The text since the last marker passed [`MAX_ANSWER_BYTES`]; the reader keeps nothing
    /// more, and the process is to be killed.
    Overflow { stream: Stream },
    /// End of the stream; `rest` is what came after the last marker.
    Closed { stream: Stream, rest: String },
}

/// Reads a whole stream on a thread and sends it once, at its end; `None` as soon as it
/// passes `limit` bytes (the rest is not read: the caller kills the process).
fn read_all_on_thread(
    stream: Stream,
    pipe: impl Read + Send + 'static,
    tx: Sender<(Stream, Option<String>)>,
    limit: usize,
) {
    thread::spawn(move || {
        let mut bytes = Vec::new();
        // A read error ends the output early; the caller then sees a truncated text and
        // the exit status, which says more than the read error would.
        let _ = pipe.take(limit as u64 + 1).read_to_end(&mut bytes);
        let text = (bytes.len() <= limit).then(|| String::from_utf8_lossy(&bytes).into_owned());
        let _ = tx.send((stream, text));
    });
}

/// Reads a dialogue stream line by line on a thread, sending the text between markers; at
/// most `limit` bytes of it are kept (see [`Event::Overflow`]).
fn read_chunks_on_thread(
    stream: Stream,
    pipe: impl Read + Send + 'static,
    tx: Sender<Event>,
    limit: usize,
) {
    thread::spawn(move || {
        let mut reader = BufReader::new(pipe);
        let mut text = String::new();
        let mut line = Vec::new();
        loop {
            line.clear();
            match read_line_within(&mut reader, &mut line, limit - text.len()) {
                Ok(Line::End) | Err(_) => break,
                Ok(Line::Whole) => {}
                Ok(Line::TooLong) => {
                    if tx.send(Event::Overflow { stream }).is_err() {
                        return;
                    }
                    // Drained, not kept, until the process is killed: a full pipe would
                    // block it before it sees the signal, and nothing here waits for it.
                    let _ = io::copy(&mut reader, &mut io::sink());
                    return;
                }
            }
            let line = String::from_utf8_lossy(&line);
            match marker_in(&line) {
                Some((before, marker)) => {
                    text.push_str(before);
                    let chunk = std::mem::take(&mut text);
                    if tx
                        .send(Event::Chunk {
                            stream,
                            marker,
                            text: chunk,
                        })
                        .is_err()
                    {
                        return;
                    }
                }
                None => text.push_str(&line),
            }
        }
        let _ = tx.send(Event::Closed { stream, rest: text });
    });
}

/// How [`read_line_within`] ended.
#[derive(Debug, PartialEq, Eq)]
enum Line {
    /// A line, with its line break unless the stream ended after it.
    Whole,
    /// The stream ended before any byte.
    End,
    /// The line is longer than the room left; what was read of it is dropped.
    TooLong,
}

/// Reads one line into `line` (empty on entry), keeping at most `room` bytes: a line without
/// end must not grow without bound.
fn read_line_within(
    reader: &mut impl BufRead,
    line: &mut Vec<u8>,
    room: usize,
) -> io::Result<Line> {
    loop {
        let buf = match reader.fill_buf() {
            Ok(buf) => buf,
            Err(e) if e.kind() == io::ErrorKind::Interrupted => continue,
            Err(e) => return Err(e),
        };
        if buf.is_empty() {
            return Ok(if line.is_empty() {
                Line::End
            } else {
                Line::Whole
            });
        }
        let (take, ends) = match buf.iter().position(|&b| b == b'\n') {
            Some(i) => (i + 1, true),
            None => (buf.len(), false),
        };
        if line.len() + take > room {
            line.clear();
            return Ok(Line::TooLong);
        }
        line.extend_from_slice(&buf[..take]);
        reader.consume(take);
        if ends {
            return Ok(Line::Whole);
        }
    }
}

/// Finds `==fbsynth-end-N==` in a line: the text before it (prompts) and `N`.
fn marker_in(line: &str) -> Option<(&str, u64)> {
    let at = line.find(MARKER)?;
    let digits = &line[at + MARKER.len()..];
    let end = digits.find("==")?;
    let marker = digits[..end].parse().ok()?;
    Some((&line[..at], marker))
}

/// NuSMV reports a missing model with a misleading line number; say it plainly instead.
fn model_exists(model: &Path) -> io::Result<()> {
    std::fs::metadata(model)
        .map(drop)
        .map_err(|e| io::Error::new(e.kind(), format!("model `{}`: {e}", model.display())))
}

/// `model` in double quotes for NuSMV's command shell, or an error for paths it would mangle.
fn shell_quoted(model: &Path) -> Result<String, NusmvError> {
    let unsafe_path = || NusmvError::UnsafePath(model.to_path_buf());
    let text = model.to_str().ok_or_else(unsafe_path)?;
    if text
        .chars()
        .any(|c| matches!(c, '!' | '%' | '#' | '"' | '\\') || c.is_control())
    {
        return Err(unsafe_path());
    }
    Ok(format!("\"{text}\""))
}

fn timeout(limit: Duration, model: &Path) -> NusmvError {
    NusmvError::Timeout {
        seconds: limit.as_secs_f64(),
        model: model.to_path_buf(),
    }
}

/// The lines of NuSMV's stderr that nothing here understands, each cut to a line of a
/// terminal, at most [`TAIL_LINES`] of them. The empty-state-set warning is understood: the
/// emptiness check turns it into an error whenever it matters.
fn unexplained(stderr: &str) -> Vec<String> {
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| !l.trim().is_empty())
        .filter(|l| !l.contains("set of the finite state machine is empty"))
        .collect();
    let mut shown: Vec<String> = lines
        .iter()
        .take(TAIL_LINES)
        .map(|l| crate::quote::message(l.trim()).to_string())
        .collect();
    if lines.len() > TAIL_LINES {
        shown.push(format!("({} more lines)", lines.len() - TAIL_LINES));
    }
    shown
}

/// Lines of another program's stderr shown at most.
const TAIL_LINES: usize = 12;

/// The last lines of a stderr text, enough to see why a process failed.
fn tail(text: &str) -> String {
    let lines: Vec<&str> = text.lines().filter(|l| !l.trim().is_empty()).collect();
    // NuSMV echoes the tokens of the model, which a plant file can make megabytes long.
    let last: Vec<String> = lines[lines.len().saturating_sub(TAIL_LINES)..]
        .iter()
        .map(|l| crate::quote::message(l).to_string())
        .collect();
    last.join("\n")
}

// ---------------------------------------------------------------------------------------
// The registry of running children.

/// Every child not yet reaped, by registration number. Signals go through `Child`, which
/// remembers that it was reaped and then sends none, so a reused process id is never hit.
static CHILDREN: Mutex<BTreeMap<u64, Arc<Mutex<Child>>>> = Mutex::new(BTreeMap::new());
static NEXT_CHILD: AtomicU64 = AtomicU64::new(0);

/// Kills every NuSMV process this program started and has not reaped yet.
///
/// Registered with [`crate::signals`] when the first child starts: SIGINT, SIGTERM and SIGHUP
/// call it before the program exits with status 130.
pub(crate) fn kill_all_children() {
    let children = CHILDREN.lock().unwrap_or_else(|e| e.into_inner());
    for child in children.values() {
        let mut child = child.lock().unwrap_or_else(|e| e.into_inner());
        kill_group(&child);
        let _ = child.kill();
        let _ = child.wait();
    }
}

/// Kills the process group that `child` leads (see [`Tracked::spawn`]): a wrapper script's
/// NuSMV, or anything else it started, goes with it instead of holding the pipes open.
///
/// Only while the child is not reaped (running, or a zombie) is the group id surely its own,
/// so that is checked first, without reaping; the caller holds the child's lock, under which
/// alone children are reaped.
fn kill_group(child: &Child) {
    let Ok(pid) = libc::pid_t::try_from(child.id()) else {
        return;
    };
    // SAFETY: waitid only writes into `info`, which lives for the call.
    let unreaped = unsafe {
        let mut info: libc::siginfo_t = std::mem::zeroed();
        libc::waitid(
            libc::P_PID,
            pid as libc::id_t,
            &mut info,
            libc::WEXITED | libc::WNOHANG | libc::WNOWAIT,
        ) == 0
    };
    if unreaped {
        // SAFETY: a plain kill(2) of the group this program created for the child.
        unsafe {
            libc::kill(-pid, libc::SIGKILL);
        }
    }
}

/// The address space a NuSMV process may take: `FBSYNTH_NUSMV_MEMORY_MB` megabytes, by default
/// half of the machine's memory. A plant with a huge range can make NuSMV grow past 10 GB
/// before the timeout ends it; with the cap it fails early and says it ran out of memory.
pub(crate) fn memory_cap() -> libc::rlim_t {
    let from_env = std::env::var("FBSYNTH_NUSMV_MEMORY_MB")
        .ok()
        .and_then(|v| v.trim().parse::<u64>().ok())
        .filter(|&mb| mb > 0);
    let bytes = match from_env {
        Some(mb) => mb.saturating_mul(1 << 20),
        None => {
            // SAFETY: sysconf only reads system constants.
            let (pages, size) = unsafe {
                (
                    libc::sysconf(libc::_SC_PHYS_PAGES),
                    libc::sysconf(libc::_SC_PAGESIZE),
                )
            };
            if pages <= 0 || size <= 0 {
                return libc::RLIM_INFINITY;
            }
            (pages as u64).saturating_mul(size as u64) / 2
        }
    };
    bytes as libc::rlim_t
}

fn install_ctrl_c_handler() {
    crate::signals::on_termination(kill_all_children);
}

/// A registered child process: killed and reaped when dropped.
struct Tracked {
    key: u64,
    id: u32,
    child: Arc<Mutex<Child>>,
    stdin: Option<ChildStdin>,
    stdout: Option<std::process::ChildStdout>,
    stderr: Option<std::process::ChildStderr>,
}

impl Tracked {
    /// Spawns `command` with all three streams piped and registers it.
    fn spawn(mut command: Command) -> io::Result<Tracked> {
        use std::os::unix::process::CommandExt;
        install_ctrl_c_handler();
        command
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            // Its own process group, killed as one: see `kill_group`. (A Ctrl-C at the
            // terminal then reaches synth alone, whose handler kills the group.)
            .process_group(0);
        let cap = memory_cap();
        // SAFETY: setrlimit is async-signal-safe and touches only the child's own limits.
        unsafe {
            command.pre_exec(move || {
                let limit = libc::rlimit {
                    rlim_cur: cap,
                    rlim_max: cap,
                };
                // Best effort: a hard limit the parent already has below `cap` stays.
                let _ = libc::setrlimit(libc::RLIMIT_AS, &limit);
                Ok(())
            });
        }
        let mut registry = CHILDREN.lock().unwrap_or_else(|e| e.into_inner());
        // Spawning under the lock: a Ctrl-C in between cannot miss the new child.
        let mut child = command.spawn()?;
        let key = NEXT_CHILD.fetch_add(1, Ordering::Relaxed);
        let (stdin, stdout, stderr) =
            (child.stdin.take(), child.stdout.take(), child.stderr.take());
        let id = child.id();
        let child = Arc::new(Mutex::new(child));
        registry.insert(key, Arc::clone(&child));
        Ok(Tracked {
            key,
            id,
            child,
            stdin,
            stdout,
            stderr,
        })
    }

    /// Waits for the child to exit. Polls, so that the child's lock is never held while
    /// blocking and the Ctrl-C handler can always get it.
    fn reap(&mut self) -> io::Result<ExitStatus> {
        let mut pause = Duration::from_micros(100);
        loop {
            if let Some(status) = self.lock().try_wait()? {
                self.unregister();
                return Ok(status);
            }
            thread::sleep(pause);
            pause = (pause * 2).min(Duration::from_millis(10));
        }
    }

    /// Kills the child unless it has exited already, and reaps it; the status tells which.
    fn kill_and_reap(&mut self) -> io::Result<ExitStatus> {
        let mut child = self.lock();
        kill_group(&child);
        let _ = child.kill();
        let status = child.wait();
        drop(child);
        self.unregister();
        status
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, Child> {
        self.child.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn unregister(&self) {
        CHILDREN
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .remove(&self.key);
    }
}

impl Drop for Tracked {
    fn drop(&mut self) {
        // Closing stdin first lets a well-behaved process end on its own; it is killed
        // anyway, and reaped, so no zombie is left behind.
        self.stdin.take();
        let _ = self.kill_and_reap();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `check_fsm`'s three answers: total, states without successor that are unreachable
    /// (deadlock-free), and a reachable deadlock state, read as its `name = value` pairs.
    #[test]
    fn check_fsm_answers_are_read() {
        let total = "####\nThe transition relation is total: No deadlock state exists\n####\n";
        assert_eq!(parse_check_fsm(total), Some(None));
        let unreachable = "The transition relation is not total. A state without\nsuccessors is:\nx = 3\n\
                           However, all the states without successors are\nnon-reachable, so the machine is deadlock-free.\n";
        assert_eq!(parse_check_fsm(unreachable), Some(None));
        let dead = "The transition relation is not total. A state without\nsuccessors is:\nx = 3\n\
                    The transition relation is not deadlock-free.\nA deadlock state is:\n\
                    _o_lamp = FALSE\nplant.dead = TRUE\n####\n";
        let state = vec![
            ("_o_lamp".to_string(), "FALSE".to_string()),
            ("plant.dead".to_string(), "TRUE".to_string()),
        ];
        assert_eq!(parse_check_fsm(dead), Some(Some(state)));
        assert_eq!(parse_check_fsm("NuSMV > "), None);
    }
    use crate::nusmv::nusmv_for_tests;

    fn data(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/nusmv")
            .join(name)
    }

    /// One query per `LTLSPEC NAME name := formula` of the model file (none if it cannot be
    /// read).
    fn queries(model: &Path) -> Vec<Query> {
        let text = std::fs::read_to_string(model).unwrap_or_default();
        (text.lines())
            .filter_map(|l| l.strip_prefix("LTLSPEC NAME ")?.split_once(" := "))
            .map(|(name, formula)| Query {
                name: name.to_string(),
                formula: formula.to_string(),
            })
            .collect()
    }

    /// A copy of the fixture `model` in `dir` in which every unnamed property is named
    /// `unnamed_<k>` (`k` its 0-based position): a dialogue asks for properties by name.
    fn named_copy(model: &str, dir: &Path) -> PathBuf {
        let text = std::fs::read_to_string(data(model)).unwrap();
        let mut named = String::new();
        let mut k = 0;
        for line in text.lines() {
            match line.strip_prefix("LTLSPEC ") {
                Some(rest) if !rest.starts_with("NAME ") => {
                    named.push_str(&format!("LTLSPEC NAME unnamed_{k} := {rest}\n"));
                    k += 1;
                }
                Some(_) => {
                    named.push_str(line);
                    named.push('\n');
                    k += 1;
                }
                None => {
                    named.push_str(line);
                    named.push('\n');
                }
            }
        }
        let copy = dir.join(model);
        std::fs::write(&copy, named).unwrap();
        copy
    }

    /// Checks every named property of `model` in `dialogue`.
    fn ask(
        dialogue: &mut Dialogue,
        model: &Path,
        mode: CheckMode,
    ) -> Result<Vec<PropertyResult>, NusmvError> {
        dialogue.check(model, &queries(model), mode)
    }

    fn holds(results: &[PropertyResult]) -> Vec<(String, bool)> {
        results
            .iter()
            .map(|r| (r.formula.clone(), r.verdict == Verdict::Holds))
            .collect()
    }

    #[test]
    fn marker_lines_are_recognised_after_prompts() {
        assert_eq!(
            marker_in("NuSMV > NuSMV > ==fbsynth-end-42== \n"),
            Some(("NuSMV > NuSMV > ", 42))
        );
        assert_eq!(marker_in("-- specification  G x  is true\n"), None);
    }

    #[test]
    fn unsafe_paths_are_refused() {
        assert!(shell_quoted(Path::new("/tmp/a b;c.smv")).is_ok());
        for bad in [
            "/tmp/a!b.smv",
            "/tmp/50%.smv",
            "/tmp/#1.smv",
            "/tmp/\"q\".smv",
        ] {
            assert!(
                matches!(shell_quoted(Path::new(bad)), Err(NusmvError::UnsafePath(_))),
                "{bad}"
            );
        }
    }

    #[test]
    fn unexplained_stderr_lines_are_kept_for_the_report() {
        let err = "\n*** WARNING: something new\n\nWARNING *** The initial states set of the finite state machine is empty. ***\n";
        assert_eq!(unexplained(err), ["*** WARNING: something new"]);
        let many: String = (1..=20).map(|i| format!("w{i}\n")).collect();
        let shown = unexplained(&many);
        assert_eq!(shown.len(), TAIL_LINES + 1);
        assert_eq!(shown.last().unwrap(), "(8 more lines)");
    }

    #[test]
    fn tail_keeps_the_last_nonblank_lines() {
        let text: String = (1..=20).map(|i| format!("l{i}\n\n")).collect();
        assert_eq!(tail(&text).lines().count(), 12);
        assert!(tail(&text).ends_with("l20"));
    }

    #[test]
    fn batch_and_dialogue_verdicts_agree() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let mut dialogue = nusmv.dialogue();
        let dir = tempfile::tempdir().unwrap();
        for model in ["cylinder.smv", "light.smv"] {
            let batch = nusmv.check_file(&data(model)).unwrap();
            let named = named_copy(model, dir.path());
            let fast = ask(&mut dialogue, &named, CheckMode::VerdictsOnly).unwrap();
            let traced = ask(&mut dialogue, &named, CheckMode::FirstCounterexample).unwrap();
            assert_eq!(holds(&batch), holds(&fast), "{model}");
            assert_eq!(holds(&batch), holds(&traced), "{model}");
            assert!(fast
                .iter()
                .all(|r| matches!(r.verdict, Verdict::Holds | Verdict::Violated(None))));
            assert!(batch
                .iter()
                .all(|r| matches!(r.verdict, Verdict::Holds | Verdict::Violated(Some(_)))));
            // The first violated property, and only it, has its trace.
            let first = traced
                .iter()
                .position(|r| r.verdict != Verdict::Holds)
                .unwrap();
            for (i, r) in traced.iter().enumerate() {
                let has_trace =
                    matches!(&r.verdict, Verdict::Violated(Some(t)) if !t.loop_starts.is_empty());
                assert_eq!(has_trace, i == first, "{model} property {i}");
            }
        }
    }

    /// Each answer is the verdict on the property asked, in the order asked: here the reverse
    /// of the file's, with properties whose verdicts differ.
    #[test]
    fn verdicts_come_in_the_order_asked() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let model = data("light.smv");
        let mut asked = queries(&model);
        asked.reverse();
        let mut dialogue = nusmv.dialogue();
        let results = dialogue
            .check(&model, &asked, CheckMode::AllCounterexamples)
            .unwrap();
        let got: Vec<(&str, bool)> = (results.iter())
            .map(|r| (r.name.as_deref().unwrap(), r.verdict == Verdict::Holds))
            .collect();
        assert_eq!(
            got,
            [
                ("green_again", false),
                ("req_served", false),
                ("always_red", false),
                ("red_not_to_yellow", true),
            ]
        );
        assert_eq!(results[2].formula, "G light = red");
        let two = [asked[3].clone(), asked[2].clone()];
        let results = dialogue
            .check(&model, &two, CheckMode::VerdictsOnly)
            .unwrap();
        let holds: Vec<bool> = results
            .iter()
            .map(|r| r.verdict == Verdict::Holds)
            .collect();
        assert_eq!(holds, [true, false]);
        // NuSMV prints nothing when asked about a property a second time: refused.
        let twice = [asked[3].clone(), asked[2].clone(), asked[3].clone()];
        let result = dialogue.check(&model, &twice, CheckMode::VerdictsOnly);
        assert!(
            matches!(&result, Err(NusmvError::UnsafeQuery { property, .. }) if property == "red_not_to_yellow"),
            "{result:?}"
        );
    }

    #[test]
    fn a_property_nusmv_does_not_know_is_an_error_naming_it() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let unknown = Query {
            name: "no_such_property".into(),
            formula: "TRUE".into(),
        };
        let result =
            nusmv
                .dialogue()
                .check(&data("light.smv"), &[unknown], CheckMode::VerdictsOnly);
        let Err(e) = result else { panic!("{result:?}") };
        assert!(e.to_string().contains("no_such_property"), "{e}");
    }

    #[test]
    fn queries_the_shell_would_misread_are_refused() {
        let query = |name: &str, formula: &str| Query {
            name: name.into(),
            formula: formula.into(),
        };
        assert!(query("_p1", "G !(a & b$c#-d) -> F x.y = 3").check().is_ok());
        for (name, formula) in [
            ("p 1", "TRUE"),
            ("1p", "TRUE"),
            ("p-1", "TRUE"),
            ("", "TRUE"),
            ("p", ""),
            ("p", "G \"a\""),
            ("p", "G a\\"),
            ("p", "G a\ncheck_ltlspec"),
        ] {
            assert!(
                matches!(
                    query(name, formula).check(),
                    Err(NusmvError::UnsafeQuery { .. })
                ),
                "{name:?} {formula:?}"
            );
        }
    }

    /// A fake NuSMV at `dir/NuSMV` running the shell `script`.
    #[cfg(unix)]
    fn fake_nusmv(dir: &Path, script: &str) -> Nusmv {
        use std::os::unix::fs::PermissionsExt;
        let path = dir.join("NuSMV");
        std::fs::write(&path, format!("#!/bin/sh\n{script}\n")).unwrap();
        std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
        Nusmv::new(path)
    }

    /// A NuSMV that prints without end, in lines or in one line, is killed once one answer
    /// passes the bound, and the error names the bound; the batch run likewise.
    #[cfg(unix)]
    #[test]
    fn output_without_end_is_cut_at_the_bound() {
        let dir = tempfile::tempdir().unwrap();
        let model = data("light.smv");
        for script in [
            "exec yes 'NuSMV > -- specification  G x  is true'",
            "yes | tr -d '\\n'",
        ] {
            let nusmv = fake_nusmv(dir.path(), script);
            let result = nusmv
                .dialogue()
                .check(&model, &queries(&model), CheckMode::VerdictsOnly);
            match result {
                Err(NusmvError::OutputTooLarge { limit, stream, .. }) => {
                    assert_eq!((limit, stream), (MAX_ANSWER_BYTES, "stdout"), "{script}")
                }
                other => panic!("{script}: {other:?}"),
            }
            match nusmv.check_file(&model) {
                Err(e @ NusmvError::OutputTooLarge { .. }) => assert!(
                    e.to_string()
                        .contains(&format!("more than {MAX_BATCH_BYTES} bytes on stdout")),
                    "{e}"
                ),
                other => panic!("{script}: {other:?}"),
            }
        }
    }

    #[test]
    fn lines_are_read_within_the_room_left() {
        let mut reader = BufReader::with_capacity(4, &b"abc\ndefghij\nk"[..]);
        let mut line = Vec::new();
        assert_eq!(
            read_line_within(&mut reader, &mut line, 10).unwrap(),
            Line::Whole
        );
        assert_eq!(line, b"abc\n");
        line.clear();
        assert_eq!(
            read_line_within(&mut reader, &mut line, 5).unwrap(),
            Line::TooLong
        );
        assert!(line.is_empty());
        let mut reader = BufReader::with_capacity(4, &b"defghij\nk"[..]);
        assert_eq!(
            read_line_within(&mut reader, &mut line, 8).unwrap(),
            Line::Whole
        );
        assert_eq!(line, b"defghij\n");
        line.clear();
        assert_eq!(
            read_line_within(&mut reader, &mut line, 8).unwrap(),
            Line::Whole
        );
        assert_eq!(line, b"k");
        line.clear();
        assert_eq!(
            read_line_within(&mut reader, &mut line, 8).unwrap(),
            Line::End
        );
    }

    #[test]
    fn batch_reports_model_errors_with_their_line() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let Err(NusmvError::Model(errors)) = nusmv.check_file(&data("err_case.smv")) else {
            panic!("err_case.smv must be rejected");
        };
        assert_eq!(errors.len(), 1);
        assert!(errors[0].file.ends_with("err_case.smv"));
        assert_eq!(errors[0].line, 10);
        assert_eq!(errors[0].message, "case conditions are not exhaustive");
    }

    #[test]
    fn dialogue_survives_a_model_error() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let mut dialogue = nusmv.dialogue();
        let first = ask(&mut dialogue, &data("light.smv"), CheckMode::VerdictsOnly).unwrap();
        let pid = dialogue.pid();
        for (model, line) in [
            ("err_syntax.smv", 5),
            ("err_undefined.smv", 8),
            ("err_assign.smv", 7),
        ] {
            match ask(&mut dialogue, &data(model), CheckMode::FirstCounterexample) {
                Err(NusmvError::Model(errors)) => {
                    assert!(errors[0].file.ends_with(model), "{errors:?}");
                    assert_eq!(errors[0].line, line, "{model}");
                }
                other => panic!("{model}: expected a model error, got {other:?}"),
            }
        }
        let again = ask(&mut dialogue, &data("light.smv"), CheckMode::VerdictsOnly).unwrap();
        assert_eq!(holds(&first), holds(&again));
        assert_eq!(dialogue.pid(), pid, "errors must not restart the process");
    }

    #[test]
    fn dialogue_restarts_after_the_configured_number_of_models() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let mut dialogue = nusmv.dialogue();
        dialogue.set_restart_every(2);
        let mut pids = Vec::new();
        for _ in 0..3 {
            // Each model takes two rounds with the process; it must not be replaced between.
            let results = ask(
                &mut dialogue,
                &data("light.smv"),
                CheckMode::FirstCounterexample,
            )
            .unwrap();
            assert!(matches!(results[1].verdict, Verdict::Violated(Some(_))));
            pids.push(dialogue.pid().unwrap());
        }
        assert_eq!(pids[0], pids[1]);
        assert_ne!(pids[1], pids[2]);
    }

    #[test]
    fn missing_model_file_is_an_io_error() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let missing = data("no_such_model.smv");
        assert!(matches!(nusmv.check_file(&missing), Err(NusmvError::Io(_))));
        let mut dialogue = nusmv.dialogue();
        assert!(matches!(
            dialogue.check(&missing, &[], CheckMode::VerdictsOnly),
            Err(NusmvError::Io(_))
        ));
    }

    /// Run in a child test process by `ctrl_c_kills_nusmv_and_exits_130`: starts a dialogue,
    /// prints its NuSMV's pid and keeps it checking a long model until the signal comes.
    /// Does nothing in a normal test run.
    #[test]
    fn ctrl_c_helper() {
        if std::env::var_os(CTRL_C_HELPER).is_none() {
            return;
        }
        let nusmv = nusmv_for_tests().expect("the parent test found NuSMV");
        let mut dialogue = nusmv.dialogue();
        ask(&mut dialogue, &data("light.smv"), CheckMode::VerdictsOnly).unwrap();
        println!("nusmv-pid {}", dialogue.pid().unwrap());
        // Keep NuSMV busy: were it left alive, it would go on for minutes instead of
        // stopping at the end of its stdin.
        let result = ask(
            &mut dialogue,
            &data("long_counter.smv"),
            CheckMode::VerdictsOnly,
        );
        panic!("no Ctrl-C came: {result:?}");
    }

    const CTRL_C_HELPER: &str = "FBSYNTH_CTRL_C_HELPER";

    #[cfg(target_os = "linux")]
    #[test]
    fn ctrl_c_kills_nusmv_and_exits_130() {
        if nusmv_for_tests().is_none() {
            return;
        }
        let mut helper = Command::new(std::env::current_exe().unwrap())
            .args([
                "--exact",
                "nusmv::driver::tests::ctrl_c_helper",
                "--nocapture",
            ])
            .args(["--test-threads", "1"])
            .env(CTRL_C_HELPER, "1")
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let mut lines = BufReader::new(helper.stdout.take().unwrap()).lines();
        let nusmv_pid: u32 = lines
            // libtest prints `test ... ... ` before the helper's own text on the same line.
            .find_map(|line| line.ok()?.split("nusmv-pid ").nth(1)?.trim().parse().ok())
            .expect("the helper prints its NuSMV pid");
        assert!(process_exists(nusmv_pid));
        let sent = Command::new("sh")
            .arg("-c")
            .arg(format!("kill -INT {}", helper.id()))
            .status()
            .unwrap();
        assert!(sent.success());
        let status = helper.wait().unwrap();
        assert_eq!(status.code(), Some(130));
        assert!(
            !process_exists(nusmv_pid),
            "NuSMV {nusmv_pid} outlived the Ctrl-C"
        );
    }

    /// A process that is gone from the process table was reaped: a zombie would still be
    /// listed.
    #[cfg(target_os = "linux")]
    fn process_exists(pid: u32) -> bool {
        Path::new(&format!("/proc/{pid}")).exists()
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn dialogue_timeout_kills_the_process_and_recovers() {
        let Some(mut nusmv) = nusmv_for_tests() else {
            return;
        };
        nusmv.timeout = Duration::from_millis(500);
        let mut dialogue = nusmv.dialogue();
        ask(&mut dialogue, &data("light.smv"), CheckMode::VerdictsOnly).unwrap();
        let pid = dialogue.pid().unwrap();
        let result = ask(
            &mut dialogue,
            &data("long_counter.smv"),
            CheckMode::VerdictsOnly,
        );
        assert!(
            matches!(result, Err(NusmvError::Timeout { .. })),
            "{result:?}"
        );
        assert_eq!(dialogue.pid(), None);
        assert!(
            !process_exists(pid),
            "NuSMV {pid} is still in the process table"
        );
        let after = ask(&mut dialogue, &data("light.smv"), CheckMode::VerdictsOnly).unwrap();
        assert_eq!(after.len(), 4);
    }

    /// The run's deadline kills a check under way and refuses the next: no NuSMV outlives it.
    #[cfg(target_os = "linux")]
    #[test]
    fn the_deadline_kills_a_dialogue_and_starts_no_other() {
        let Some(mut nusmv) = nusmv_for_tests() else {
            return;
        };
        nusmv.deadline = Deadline::after(Duration::from_secs(2));
        let mut dialogue = nusmv.dialogue();
        ask(&mut dialogue, &data("light.smv"), CheckMode::VerdictsOnly).unwrap();
        let pid = dialogue.pid().unwrap();
        let result = ask(
            &mut dialogue,
            &data("long_counter.smv"),
            CheckMode::VerdictsOnly,
        );
        assert!(matches!(result, Err(NusmvError::Stopped)), "{result:?}");
        assert_eq!(dialogue.pid(), None);
        assert!(
            !process_exists(pid),
            "NuSMV {pid} is still in the process table"
        );
        let after = ask(&mut dialogue, &data("light.smv"), CheckMode::VerdictsOnly);
        assert!(matches!(after, Err(NusmvError::Stopped)), "{after:?}");
        assert_eq!(dialogue.pid(), None);
        let batch = nusmv.check_file(&data("light.smv"));
        assert!(matches!(batch, Err(NusmvError::Stopped)), "{batch:?}");
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn batch_timeout_kills_the_process() {
        let Some(mut nusmv) = nusmv_for_tests() else {
            return;
        };
        nusmv.timeout = Duration::from_millis(1000);
        // A copy under a unique name, to find this test's process among parallel tests'.
        let dir = tempfile::tempdir().unwrap();
        let model = dir.path().join("long_counter.smv");
        std::fs::copy(data("long_counter.smv"), &model).unwrap();
        let checker = {
            let (nusmv, model) = (nusmv.clone(), model.clone());
            thread::spawn(move || nusmv.check_file(&model))
        };
        let mut pid = None;
        while pid.is_none() && !checker.is_finished() {
            pid = pid_running(&model);
            thread::sleep(Duration::from_millis(5));
        }
        let result = checker.join().unwrap();
        assert!(
            matches!(result, Err(NusmvError::Timeout { .. })),
            "{result:?}"
        );
        let pid = pid.expect("the NuSMV process was seen while it ran");
        assert!(
            !process_exists(pid),
            "NuSMV {pid} is still in the process table"
        );
    }

    /// The process whose command line mentions `model`.
    #[cfg(target_os = "linux")]
    fn pid_running(model: &Path) -> Option<u32> {
        let needle = model.to_str()?.as_bytes();
        std::fs::read_dir("/proc")
            .ok()?
            .flatten()
            .find_map(|entry| {
                let pid: u32 = entry.file_name().to_str()?.parse().ok()?;
                let cmdline = std::fs::read(entry.path().join("cmdline")).ok()?;
                cmdline
                    .windows(needle.len())
                    .any(|w| w == needle)
                    .then_some(pid)
            })
    }

    /// Median time per model of each way of running NuSMV; prints, asserts nothing.
    /// Run with `cargo test speed_per_model -- --ignored --nocapture`.
    #[test]
    #[ignore = "measurement, not a test"]
    fn speed_per_model() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        const RUNS: usize = 41;
        let model = data("cylinder.smv");
        let dir = tempfile::tempdir().unwrap();
        let named = named_copy("cylinder.smv", dir.path());
        let median = |mut ms: Vec<f64>| {
            ms.sort_by(f64::total_cmp);
            ms[ms.len() / 2]
        };
        let time = |f: &mut dyn FnMut()| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1000.0
        };
        let batch: Vec<f64> = (0..RUNS)
            .map(|_| time(&mut || drop(nusmv.check_file(&model).unwrap())))
            .collect();
        let mut dialogue = nusmv.dialogue();
        ask(&mut dialogue, &named, CheckMode::VerdictsOnly).unwrap();
        let mut per_mode = |mode| -> Vec<f64> {
            (0..RUNS)
                .map(|_| time(&mut || drop(ask(&mut dialogue, &named, mode).unwrap())))
                .collect()
        };
        let fast = per_mode(CheckMode::VerdictsOnly);
        let traced = per_mode(CheckMode::FirstCounterexample);
        println!("cylinder.smv, median of {RUNS} runs:");
        println!("  batch (-dynamic), all traces:   {:.1} ms", median(batch));
        println!("  dialogue, VerdictsOnly:          {:.1} ms", median(fast));
        println!(
            "  dialogue, FirstCounterexample:   {:.1} ms",
            median(traced)
        );
    }
}
