//! Progress of a pipeline as typed [`Event`]s, and the line each reads as.
//!
//! In: what a pipeline reports while it runs. Out: the event's line of progress
//! ([`std::fmt::Display`]; an event of two lines has a newline between them). The caller
//! decides whether and where to show them; the command line prefixes each line with the
//! seconds since the start.

use super::explain::Explanation;
use super::lazy_noisy::{Bounds, PartRound};
use super::main_job::Step;
use super::{cegis, follow, guide, lazy_noisy, main_job};
use crate::scenario::ScenarioSet;
use std::fmt;
use std::path::Path;

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
        /// Lower bound on the guard literals N at C states and T transitions, when proven
        /// (every machine with those C and T that reproduces the recordings needs as many).
        n: Option<usize>,
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
    /// The in-process engines (checker, SAT encoding of the properties) do not read this
    /// closed loop: NuSMV alone judges every candidate of the exact loop.
    InProcessRefused {
        /// The construct and where it is (file, line), or what else stands in the way.
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
    /// A try of the search from random machines made no progress on the properties for
    /// `rounds` rounds: the scenarios are reconstructed anew with `seed`.
    SearchTriesAgain {
        /// Rounds without progress.
        rounds: usize,
        /// The next try's seed.
        seed: u64,
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
        /// The candidate's number, 1-based, in the order of [`super::noisy::Noisy`]'s candidates.
        candidate: usize,
        /// Number of recording errors ε the candidate corrects.
        errors: usize,
    },
    /// One controller checked in [`super::follow`] (a composite following a verified machine).
    Followed(&'a follow::Round),
    /// A round of noisy synthesis in parts ([`super::lazy_noisy`]) ended.
    NoisyPart(lazy_noisy::PartRound),
    /// The least ε of a noisy log in parts: lower bounds summed over disjoint parts.
    NoisyBound(lazy_noisy::Bounds),
    /// A stage of the closed-loop game's guide ([`super::guide`]).
    Guide(guide::Stage),
    /// A turn of the main job's strategy ([`super::main_job`]).
    MainJob(main_job::Step),
    /// A round of [`super::lazy`] synthesis over long recordings ended.
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
    /// A round of active learning ([`super::active::learn`]) ended.
    LearnRound {
        /// The round, 1-based.
        number: usize,
        /// What it found and recorded.
        round: &'a super::active::Round,
    },
    /// What a command reads, checks and decides around its pipelines.
    Note(Note<'a>),
}

/// What a command reads, checks and decides around its pipelines, for progress.
#[derive(Debug)]
pub enum Note<'a> {
    /// The recordings were read (the main job's line).
    Recordings {
        /// Scenarios read.
        scenarios: usize,
        /// Steps in all.
        steps: usize,
        /// The files, as [`Recordings::show`](super::Recordings::show) names them.
        from: &'a str,
    },
    /// The recordings were read, with their interface.
    Loaded(&'a ScenarioSet),
    /// A plant was learned from the recordings (the main job's `--learn-plant`); every
    /// recorded scan is a step of it.
    LearnedPlant {
        /// Recorded scans.
        scans: usize,
        /// Recorded runs.
        runs: usize,
        /// Sensors.
        sensors: usize,
        /// Sensors a command moves over several scans.
        delayed: usize,
    },
    /// The verification problem was read.
    Problem {
        /// Properties read.
        properties: usize,
        /// The specification file.
        spec: &'a Path,
        /// The plant model file.
        plant: &'a Path,
    },
    /// Properties no controller can affect (they read only plant signals no controller
    /// output influences), each with the reason; before any candidate.
    Unaffected(&'a [(String, String)]),
    /// The recordings were checked against the properties before any synthesis.
    Explained {
        /// What they say about the properties.
        explanation: &'a Explanation,
        /// Number of properties.
        properties: usize,
    },
    /// A file of negative scenarios was read.
    Negatives {
        /// Negative scenarios in it.
        count: usize,
        /// The file.
        file: &'a Path,
    },
    /// The ambiguity check was asked for but is not run: it does not take negative scenarios.
    AmbiguitySkipped,
    /// Exact synthesis climbs to as many states as scan-cycle glitches in a log cost: the
    /// noisy reading may be what the recordings need.
    GlitchHint,
    /// The ambiguity check starts.
    AmbiguityStarted {
        /// Rivals looked for at most.
        rivals: usize,
        /// States of the machine (and of its rivals).
        states: usize,
    },
    /// A batch starts.
    BatchStarted {
        /// PLCs found.
        plcs: usize,
        /// The folder of logs.
        logs: &'a Path,
        /// PLCs reconstructed at once.
        threads: usize,
        /// Whether NuSMV verifies each machine.
        verified: bool,
    },
}

/// A sink for [`Event`]s.
pub type Events<'a> = &'a mut dyn FnMut(Event<'_>);

/// Said when exact synthesis fails on a contradiction, or climbs as high as glitches in a log
/// make it ([`Note::GlitchHint`]).
pub(crate) const NOISY_HINT: &str = "hint: if the recording has scan-cycle glitches (outputs logged a scan early or late), `synth infer --noisy --max-errors N` corrects up to N samples";

/// `1 candidate` or `n candidates` (of anything).
pub(crate) fn plural(n: usize, what: &str) -> String {
    format!("{n} {what}{}", if n == 1 { "" } else { "s" })
}

/// `every property holds`, or `{violated}: a, b{after}`.
fn verdict(failing: &[String], violated: &str, after: &str) -> String {
    match failing.is_empty() {
        true => "every property holds".to_string(),
        false => format!("{violated}: {}{after}", failing.join(", ")),
    }
}

impl fmt::Display for Event<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Event::Solver(step) => write!(f, "{step}"),
            Event::LowerBounds { c, t, n, seconds } => lower_bounds(f, *c, *t, *n, *seconds),
            Event::Candidate(it) => candidate(f, it),
            Event::InProcessStopped { why } => write!(
                f,
                "the in-process checker stops: {why}; NuSMV alone judges the candidates from here"
            ),
            Event::InProcessRefused { why } => write!(
                f,
                "the in-process checker does not read this closed loop: {why}; NuSMV judges every candidate"
            ),
            Event::SatStart { size, seconds } => {
                write!(f, "SAT start: {size} for the scenarios alone in {seconds:.2} s")
            }
            Event::SearchStarted {
                seed,
                states,
                colonies,
                threads,
                time_limit,
            } => write!(
                f,
                "search: seed {seed}, {states} states, {colonies} colonies on {threads} threads, limit {time_limit} s"
            ),
            Event::SearchTriesAgain { rounds, seed } => write!(
                f,
                "search: no progress on the properties in {rounds} rounds; the scenarios reconstructed anew (seed {seed})"
            ),
            Event::SearchRound(p) => search_round(f, p),
            Event::SearchEnded {
                seconds,
                evaluations,
                nusmv_runs,
                in_process_checks,
                cache_hits,
            } => write!(
                f,
                "search ended after {seconds:.2} s: {evaluations} evaluations; candidates judged: {in_process_checks} in process, {nusmv_runs} by NuSMV, {cache_hits} from the cache"
            ),
            Event::CandidateVerdict { failing } => {
                write!(f, "  NuSMV: {}", verdict(failing, "violated", ""))
            }
            Event::ClosedLoopOf { candidate, errors } => write!(
                f,
                "candidate {candidate} (ε = {errors}): the closed loop on its corrected traces"
            ),
            Event::Followed(r) => followed(f, r),
            Event::NoisyPart(p) => noisy_part(f, p),
            Event::NoisyBound(Bounds {
                parts,
                lower,
                upper,
            }) => write!(
                f,
                "least ε: at least {lower} (summed over {parts} parts), the machine needs {upper}{}",
                if lower == upper { ": proven" } else { "" }
            ),
            Event::Guide(stage) => write!(f, "{stage}"),
            Event::MainJob(step) => write!(f, "{step}"),
            Event::Lazy {
                round,
                encoded,
                total,
                diverging,
            } => lazy_part(f, *round, *encoded, *total, *diverging),
            Event::LearnRound { number, round } => learn_round(f, *number, round),
            Event::Note(note) => write!(f, "{note}"),
        }
    }
}

/// The line of the lower bounds the recordings alone give.
fn lower_bounds(
    f: &mut fmt::Formatter<'_>,
    c: usize,
    t: usize,
    n: Option<usize>,
    seconds: f64,
) -> fmt::Result {
    write!(
        f,
        "lower bounds from the recorded inputs alone: C >= {c}, T >= {t}"
    )?;
    if let Some(n) = n {
        write!(f, ", N >= {n} at C = {c} and T = {t}")?;
    }
    write!(f, " ({seconds:.2} s)")
}

/// The line of a round of the search.
fn search_round(f: &mut fmt::Formatter<'_>, p: &crate::search::Progress) -> fmt::Result {
    let props = (p.properties)
        .map(|(s, t)| format!(", properties {s}/{t}"))
        .unwrap_or_default();
    write!(
        f,
        "round {}: best fitness {:.5} ({}/{} scenarios{props}), {} evaluations, {:.0}/s",
        p.round,
        p.best_fitness,
        p.best_score.reproduced,
        p.best_score.scenarios,
        p.evaluations,
        p.evaluations as f64 / p.seconds.max(1e-9)
    )
}

/// The line of a part of the lazy encoding of long recordings.
fn lazy_part(
    f: &mut fmt::Formatter<'_>,
    round: usize,
    encoded: usize,
    total: usize,
    diverging: usize,
) -> fmt::Result {
    let departing = match diverging {
        0 => "the machine reproduces every step".to_string(),
        1 => "1 scenario departs from the machine: its prefix grows".to_string(),
        n => format!("{n} scenarios depart from the machine: their prefixes grow"),
    };
    write!(
        f,
        "part {round}: {encoded} of {total} recorded steps encoded; {departing}"
    )
}

/// The line of a candidate of the exact loop.
fn candidate(f: &mut fmt::Formatter<'_>, it: &cegis::Iteration) -> fmt::Result {
    if it.checked_by == cegis::UNCHANGED {
        return write!(
            f,
            "iteration {}: C = {} T = {}; no smaller machine, the verified candidate is the result; SAT {:.2} s",
            it.number, it.c, it.t, it.sat_seconds
        );
    }
    let after = format!(
        " (counterexample of {} steps)",
        it.counterexample_length.unwrap_or(0)
    );
    write!(
        f,
        "iteration {}: C = {} T = {}; {}; SAT {:.2} s, {} {:.3} s",
        it.number,
        it.c,
        it.t,
        verdict(&it.failing, "failing", &after),
        it.sat_seconds,
        it.checked_by,
        it.check_seconds
    )
}

/// The line of a controller checked in [`follow`].
fn followed(f: &mut fmt::Formatter<'_>, r: &follow::Round) -> fmt::Result {
    let after = format!(
        " ({} steps recorded from the verified machine along the counterexamples)",
        r.added_steps
    );
    write!(
        f,
        "controller {}: largest part {} states, {} states in all; {}; SAT {:.2} s, NuSMV {:.3} s",
        r.number,
        r.largest_states,
        r.states,
        verdict(&r.failing, "failing", &after),
        r.sat_seconds,
        r.nusmv_seconds
    )
}

/// The line of a part of noisy synthesis.
fn noisy_part(f: &mut fmt::Formatter<'_>, p: &PartRound) -> fmt::Result {
    let PartRound {
        round,
        traces,
        total,
        unexplained,
        corrections,
    } = p;
    write!(
        f,
        "part {round}: {traces} of {total} distinct traces encoded; {}",
        match unexplained {
            0 => format!("the machine explains every trace with {corrections} corrections"),
            n => format!("the machine cannot explain {n} traces: some join the part"),
        }
    )
}

impl fmt::Display for Note<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
        Note::Recordings {
            scenarios,
            steps,
            from,
        } => write!(f, "read {scenarios} scenarios ({steps} steps) from {from}"),
        Note::Loaded(set) => write!(
            f,
            "read {} scenarios, {} steps ({} active) over {} inputs and {} outputs",
            set.scenarios.len(),
            set.step_count(),
            set.active_count(),
            set.inputs.len(),
            set.outputs.len()
        ),
        Note::LearnedPlant {
            scans,
            runs,
            sensors,
            delayed,
        } => write!(
            f,
            "learned a plant from {scans} recorded scans in {}: {}, {delayed} delayed; every recorded step is a step of it",
            plural(*runs, "run"),
            plural(*sensors, "sensor")
        ),
        Note::Problem {
            properties,
            spec,
            plant,
        } => write!(
            f,
            "read {properties} properties from {} and plant {}",
            spec.display(),
            plant.display()
        ),
        Note::Explained {
            explanation,
            properties,
        } => match explanation.unrecorded_line() {
            Some(line) => write!(f, "{}\n{line}", explanation.checked_line(*properties)),
            None => write!(f, "{}", explanation.checked_line(*properties)),
        },
        Note::Unaffected(found) => {
            let lines: Vec<String> = (found.iter())
                .map(|(name, why)| {
                    format!("warning: no controller can affect property {name}: {why}; its verdict is the plant's alone")
                })
                .collect();
            write!(f, "{}", lines.join("\n"))
        }
        Note::Negatives { count, file } => write!(
            f,
            "read {} from {}",
            plural(*count, "negative scenario"),
            file.display()
        ),
        Note::AmbiguitySkipped => {
            write!(f, "ambiguity check skipped: it does not take negative scenarios")
        }
        Note::GlitchHint => write!(f, "{NOISY_HINT}"),
        Note::AmbiguityStarted { rivals, states } => write!(
            f,
            "ambiguity: looking for up to {rivals} other machines with {states} states that fit the recordings"
        ),
        Note::BatchStarted {
            plcs,
            logs,
            threads,
            verified,
        } => write!(
            f,
            "{plcs} PLCs in {}, {} at a time{}",
            logs.display(),
            threads.min(plcs),
            if *verified {
                ", each verified by NuSMV"
            } else {
                ""
            }
        ),
    }
    }
}

/// The line of round `number` of active learning.
fn learn_round(f: &mut fmt::Formatter<'_>, number: usize, r: &super::active::Round) -> fmt::Result {
    use super::ambiguity::Uniqueness;
    let verdict = match r.verdict {
        Some(Uniqueness::Unique) => "unique",
        Some(Uniqueness::Ambiguous) => "ambiguous",
        Some(Uniqueness::Unknown) => "unknown",
        None => r.asked.name(),
    };
    let widened = if r.widened {
        " over the recorded combinations; now over every input vector"
    } else {
        ""
    };
    write!(
        f,
        "round {number}: C = {}, {verdict}{widened}; {} steps recorded",
        r.states, r.recorded_steps
    )
}

impl fmt::Display for Step {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Step::GuideStarted => write!(
                f,
                "solving the closed-loop game to guide the synthesis where nothing was recorded"
            ),
            Step::Stalled { why } => {
                write!(f, "the exact loop: {why}; the closed-loop game's guide takes over")
            }
            Step::GuideDeclined { why } => {
                write!(f, "guide: no machine ({why}); the exact loop goes on")
            }
            Step::BelowGuide { states, seconds } => write!(
                f,
                "the exact loop looks for a smaller verified machine with at most {states} states, for up to {seconds:.1} s:"
            ),
            Step::GuideLeast { floor } => write!(
                f,
                "the guide's machine meets {floor}: it is least, no turn of the exact loop below it"
            ),
            Step::GuideStands { after } => {
                write!(f, "the exact loop: {after}; the guide's machine stands")
            }
            Step::Polishing {
                size,
                judged,
                seconds,
            } => write!(
                f,
                "guide: making its machine smaller in process: {size} so far ({judged} moves judged, {seconds:.1} s)"
            ),
            Step::Polished { line } => write!(f, "{line}"),
            Step::Realizability => write!(
                f,
                "no verified machine within the limits; solving the closed-loop game to tell whether any controller exists"
            ),
            Step::Searched { size } => write!(f, "the search's machine: {size}, verified"),
            Step::BelowSearched { states, seconds } => write!(
                f,
                "the exact loop looks for a smaller verified machine with at most {states} states (at most {seconds:.1} s):"
            ),
            Step::BelowSearchedStopped { why } => {
                write!(f, "below the search's machine: {why}; making it small along the closed loop:")
            }
            Step::Shrunk {
                size,
                finished: true,
            } => write!(f, "the search's machine made small along the closed loop: {size}"),
            Step::Shrunk {
                size,
                finished: false,
            } => write!(
                f,
                "--time-limit reached while making the search's machine small: it stands ({size})"
            ),
        }
    }
}

/// The progress line of one PLC of a batch done.
impl fmt::Display for super::batch::Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.result {
            Ok(r) => write!(
                f,
                "{}: {}{} ({:.2} s)",
                self.plc.name,
                r.synthesis.size,
                if r.certificate.is_some() {
                    ", verified"
                } else {
                    ""
                },
                self.seconds
            ),
            Err(e) => write!(f, "{}: failed: {e}", self.plc.name),
        }
    }
}
