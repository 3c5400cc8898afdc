//! Progress on stderr: the library's [`Event`]s as lines prefixed with the elapsed time.

use crate::pipeline::lazy_noisy::{Bounds, PartRound};
use crate::pipeline::main_job::Step;
use crate::pipeline::Event;
use std::time::Instant;

/// Progress lines on stderr, prefixed with the elapsed time.
pub struct Progress {
    start: Instant,
    quiet: bool,
}

impl Progress {
    /// Progress lines unless `quiet` or `-q`.
    pub fn new(quiet: bool) -> Progress {
        Progress {
            start: Instant::now(),
            quiet: quiet || super::quiet(),
        }
    }

    /// One progress line on stderr, with the seconds since the start.
    pub fn line(&self, msg: &str) {
        if !self.quiet {
            eprintln!("[{:7.2}s] {msg}", self.start.elapsed().as_secs_f64());
        }
    }

    /// Seconds since the start.
    pub fn elapsed(&self) -> f64 {
        self.start.elapsed().as_secs_f64()
    }

    /// When the run started (the clock of every line, and of `--time-limit`).
    pub fn started(&self) -> Instant {
        self.start
    }

    /// Shows one event of a pipeline.
    pub fn event(&self, e: Event<'_>) {
        self.line(&describe(&e));
    }
}

/// One line for an event.
pub fn describe(e: &Event<'_>) -> String {
    match e {
        Event::Solver(step) => step.to_string(),
        Event::LowerBounds { c, t, seconds } => format!(
            "lower bounds from the recorded inputs alone: C >= {c}, T >= {t} ({seconds:.2} s)"
        ),
        Event::Candidate(it) if it.checked_by == crate::pipeline::cegis::UNCHANGED => format!(
            "iteration {}: C = {} T = {}; no smaller machine, the verified candidate is the result; SAT {:.2} s",
            it.number, it.c, it.t, it.sat_seconds
        ),
        Event::Candidate(it) => format!(
            "iteration {}: C = {} T = {}; {}; SAT {:.2} s, {} {:.3} s",
            it.number,
            it.c,
            it.t,
            if it.failing.is_empty() {
                "every property holds".to_string()
            } else {
                format!(
                    "failing: {} (counterexample of {} steps)",
                    it.failing.join(", "),
                    it.counterexample_length.unwrap_or(0)
                )
            },
            it.sat_seconds,
            it.checked_by,
            it.check_seconds
        ),
        Event::SatStart { size, seconds } => {
            format!("SAT start: {size} for the scenarios alone in {seconds:.2} s")
        }
        Event::SearchStarted {
            seed,
            states,
            colonies,
            threads,
            time_limit,
        } => format!(
            "search: seed {seed}, {states} states, {colonies} colonies on {threads} threads, limit {time_limit} s"
        ),
        Event::SearchRound(p) => {
            let props = p
                .properties
                .map(|(s, t)| format!(", properties {s}/{t}"))
                .unwrap_or_default();
            format!(
                "round {}: best fitness {:.5} ({}/{} scenarios{props}), {} evaluations, {:.0}/s",
                p.round,
                p.best_fitness,
                p.best_score.reproduced,
                p.best_score.scenarios,
                p.evaluations,
                p.evaluations as f64 / p.seconds.max(1e-9)
            )
        }
        Event::SearchEnded {
            seconds,
            evaluations,
            nusmv_runs,
            in_process_checks,
            cache_hits,
        } => format!(
            "search ended after {seconds:.2} s: {evaluations} evaluations; candidates judged: {in_process_checks} in process, {nusmv_runs} by NuSMV, {cache_hits} from the cache"
        ),
        Event::CandidateVerdict { failing } => format!(
            "  NuSMV: {}",
            if failing.is_empty() {
                "every property holds".to_string()
            } else {
                format!("violated: {}", failing.join(", "))
            }
        ),
        Event::ClosedLoopOf { candidate, errors } => format!(
            "candidate {candidate} (ε = {errors}): the closed loop on its corrected traces"
        ),
        Event::NoisyPart(PartRound {
            round,
            traces,
            total,
            unexplained,
            corrections,
        }) => format!(
            "part {round}: {traces} of {total} distinct traces encoded; {}",
            match unexplained {
                0 => format!("the machine explains every trace with {corrections} corrections"),
                n => format!("the machine cannot explain {n} traces: some join the part"),
            }
        ),
        Event::NoisyBound(Bounds {
            parts,
            lower,
            upper,
        }) => format!(
            "least ε: at least {lower} (summed over {parts} parts), the machine needs {upper}{}",
            if lower == upper { ": proven" } else { "" }
        ),
        Event::Guide(stage) => stage.to_string(),
        Event::InProcessStopped { why } => format!(
            "the in-process checker stops: {why}; NuSMV alone judges the candidates from here"
        ),
        Event::MainJob(step) => main_job_step(step),
        Event::Lazy {
            round,
            encoded,
            total,
            diverging,
        } => format!(
            "part {round}: {encoded} of {total} recorded steps encoded; {}",
            match diverging {
                0 => "the machine reproduces every step".to_string(),
                1 => "1 scenario departs from the machine: its prefix grows".to_string(),
                n => format!("{n} scenarios depart from the machine: their prefixes grow"),
            }
        ),
        Event::Followed(r) => format!(
            "controller {}: largest part {} states, {} states in all; {}; SAT {:.2} s, NuSMV {:.3} s",
            r.number,
            r.largest_states,
            r.states,
            if r.failing.is_empty() {
                "every property holds".to_string()
            } else {
                format!(
                    "failing: {} ({} steps recorded from the verified machine along the counterexamples)",
                    r.failing.join(", "),
                    r.added_steps
                )
            },
            r.sat_seconds,
            r.nusmv_seconds
        ),
    }
}

/// One line for a turn of the main job's strategy.
fn main_job_step(step: &Step) -> String {
    match step {
        Step::GuideStarted => {
            "solving the closed-loop game to guide the synthesis where nothing was recorded".into()
        }
        Step::GuideDeclined { why } => format!("guide: no machine ({why}); the exact loop goes on"),
        Step::BelowGuide { states, seconds } => format!(
            "the exact loop looks for a smaller verified machine with at most {states} states, for up to {seconds:.1} s:"
        ),
        Step::GuideStands { after } => {
            format!("the exact loop: {after}; the guide's machine stands")
        }
        Step::Realizability => "no verified machine within the limits; solving the closed-loop game to tell whether any controller exists".into(),
        Step::Searched { size } => {
            format!("the search's machine: {size}; made small along the closed loop:")
        }
        Step::Shrunk { size } => format!(
            "shrunk to {size}; the exact loop looks for a smaller verified machine with at most {} states:",
            size.c
        ),
        Step::ShrunkStands => {
            "the exact loop ran out of --time-limit; the shrunk machine stands".into()
        }
    }
}
