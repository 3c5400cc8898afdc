//! The main job's `summary.json`: what the machine is, how it was found and what is proven.
//!
//! In: the result of the turn of the strategy that gave the machine. Out: a [`Summary`], one
//! shape per turn, serialized with serde (the keys in the file are sorted, as `serde_json`
//! writes a map) and described by a JSON Schema ([`schema`]). The exact loop's summary has no
//! `method` key; the others name theirs.

use super::super::cegis::Iteration;
use super::super::event::plural;
use super::super::exact::Exact;
use super::super::follow;
use crate::ecc::Size;
use crate::verify::Report;
use schemars::JsonSchema;
use serde::Serialize;

/// The main job's `summary.json`.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[serde(untagged)]
pub enum Summary {
    /// The exact loop's machine.
    Exact(ExactSummary),
    /// A machine from another turn of the strategy, named in `method`.
    Turn(Turn),
}

/// A machine from the exact loop: least C, then T and N where proven.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct ExactSummary {
    /// The machine's C, K, T and N.
    pub(crate) size: Size,
    /// Whether no machine with C states has fewer transitions (proved within the budget).
    pub(crate) transitions_proven_minimal: bool,
    /// Whether no machine with C states and T transitions has fewer guard literals.
    pub(crate) guards_proven_minimal: bool,
    /// Every candidate of the loop, the result last.
    pub(crate) iterations: Vec<Iteration>,
    /// NuSMV's verdicts on the machine (all hold).
    pub(crate) report: Report,
    /// Seconds in SAT over all candidates.
    pub(crate) sat_seconds: f64,
    /// Seconds in NuSMV over all candidates.
    pub(crate) nusmv_seconds: f64,
    /// Seconds since the run started.
    pub(crate) total_seconds: f64,
}

/// The turn of the strategy that gave a machine other than the exact loop's.
#[derive(Debug, Clone, Serialize, JsonSchema)]
#[serde(tag = "method")]
pub enum Turn {
    /// The exact loop found a machine smaller than the guide's.
    #[serde(rename = "exact loop after the game's guide")]
    BelowGuide(BelowGuideSummary),
    /// The closed-loop game's guide gave the machine.
    #[serde(rename = "game guide")]
    Guide(GuideSummary),
    /// The search gave the machine (shrunk, or replaced by the exact loop below it).
    #[serde(rename = "search")]
    Search(Box<SearchSummary>),
}

/// The exact loop's machine, smaller than the guide's.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct BelowGuideSummary {
    /// The exact loop's figures.
    #[serde(flatten)]
    pub(crate) exact: ExactSummary,
    /// The guide's machine's C, K, T and N.
    pub(crate) guide_size: Size,
    /// The guide's stages, one line each.
    pub(crate) guide: Vec<String>,
}

/// The guide's machine.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct GuideSummary {
    /// What the exact loop's turn below the guide's machine found.
    pub(crate) exact_loop_below_it: String,
    /// The machine's C, K, T and N.
    pub(crate) size: Size,
    /// Proven: no machine that reproduces the recordings is smaller in (C, T, N), verified or
    /// not, in the asked form. The machine meets the lower bounds of the recordings alone
    /// (least C, least T at it, least N at both).
    pub(crate) proven_least: bool,
    /// Whether the guide's machine is least for the recordings and the guide's closed-loop
    /// runs (else it is the repaired machine, not minimal); `made_smaller` says whether the
    /// result is a smaller machine made from it.
    pub(crate) least_for_recordings_and_runs: bool,
    /// The guide's machine has the fewest states for the recordings and the runs, its `T`
    /// and `N` not proven least for them (within the guide's budget). In `summary.json` the
    /// `guide` line that says so stands for it.
    #[serde(skip)]
    pub(crate) for_runs_unproven: bool,
    /// Proven: no machine in the asked form with fewer states reproduces the recordings
    /// (`None`: not proven, with binary algorithms).
    pub(crate) states_at_least: Option<usize>,
    /// Whether the guide's machine was made smaller by merging states and dropping
    /// transitions and literals while the in-process checker found every property kept (then
    /// verified by NuSMV; not proven least). In `summary.json` the `guide` line that says
    /// so stands for it.
    #[serde(skip)]
    pub(crate) made_smaller: bool,
    /// The form it was asked in, as in "binary algorithms" (empty: the defaults); in
    /// `summary.json` the `guide` lines say it.
    #[serde(skip)]
    pub(crate) conventions: String,
    /// The guide's stages, one line each.
    pub(crate) guide: Vec<String>,
    /// NuSMV's verdicts on the machine (all hold).
    pub(crate) report: Report,
    /// Seconds in SAT.
    pub(crate) sat_seconds: f64,
    /// NuSMV checks made.
    pub(crate) nusmv_calls: usize,
    /// Seconds in NuSMV.
    pub(crate) nusmv_seconds: f64,
    /// Seconds since the run started.
    pub(crate) total_seconds: f64,
}

/// The search's machine, made small along the closed loop.
#[derive(Debug, Clone, Serialize, JsonSchema)]
pub struct SearchSummary {
    /// The search's seed.
    pub(crate) seed: u64,
    /// Where the colonies started: `sat` or `random`.
    pub(crate) start: String,
    /// The result's C, K, T and N.
    pub(crate) size: Size,
    /// The search's machine's.
    pub(crate) searched_size: Size,
    /// The shrunk machine's (`None`: not shrunk, the exact loop below the search's machine
    /// found a smaller one or the time limit came first).
    pub(crate) shrunk_size: Option<Size>,
    /// Whether the exact loop below the search's machine found the result.
    pub(crate) replaced_by_exact_loop: bool,
    /// The rounds that shrank the search's machine.
    pub(crate) shrink_rounds: Vec<follow::Round>,
    /// The search's best fitness.
    pub(crate) fitness: f64,
    /// The search's figures.
    pub(crate) search: crate::search::algorithm::Stats,
    /// Candidates NuSMV judged during the search.
    pub(crate) nusmv_runs: u64,
    /// Candidates the in-process checker judged.
    pub(crate) in_process_checks: u64,
    /// Verdicts taken from the cache.
    pub(crate) cache_hits: u64,
    /// NuSMV's final check of the search's machine.
    pub(crate) report: Report,
    /// Seconds since the run started.
    pub(crate) total_seconds: f64,
}

impl ExactSummary {
    /// The summary of the exact loop's result `r` (checked: it has a certificate), `total`
    /// seconds into the run.
    pub(crate) fn of(r: &Exact, report: &Report, total_seconds: f64) -> ExactSummary {
        ExactSummary {
            size: r.synthesis.size,
            transitions_proven_minimal: r.synthesis.transitions_exact,
            guards_proven_minimal: r.synthesis.guards_exact,
            iterations: r.iterations.clone(),
            report: report.clone(),
            sat_seconds: r.iterations.iter().map(|i| i.sat_seconds).sum(),
            nusmv_seconds: r.iterations.iter().map(|i| i.nusmv_seconds).sum(),
            total_seconds,
        }
    }
}

impl Summary {
    /// The machine's C, K, T and N.
    pub(crate) fn size(&self) -> Size {
        match self {
            Summary::Exact(e)
            | Summary::Turn(Turn::BelowGuide(BelowGuideSummary { exact: e, .. })) => e.size,
            Summary::Turn(Turn::Guide(g)) => g.size,
            Summary::Turn(Turn::Search(s)) => s.size,
        }
    }

    /// The summary as JSON (the keys sorted).
    pub(crate) fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("a summary is JSON")
    }
}

/// The JSON Schema of [`Summary`].
pub(crate) fn schema() -> schemars::Schema {
    schemars::schema_for!(Summary)
}

/// The closing lines of the main job: how the machine was found and what is proven.
impl std::fmt::Display for Summary {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Summary::Exact(e) => exact_lines(f, e),
            Summary::Turn(Turn::BelowGuide(b)) => write!(
                f,
                "{}\n(the exact loop found it below the game's guide's {})",
                Summary::Exact(b.exact.clone()),
                b.guide_size
            ),
            Summary::Turn(Turn::Guide(g)) => guide_lines(f, g),
            Summary::Turn(Turn::Search(s)) => search_line(f, s),
        }
    }
}

/// The exact loop's figures, and which of T and N the proof budget left unproven.
fn exact_lines(f: &mut std::fmt::Formatter<'_>, e: &ExactSummary) -> std::fmt::Result {
    write!(
        f,
        "{}, {:.2} s total (SAT {:.2} s, NuSMV {:.2} s)",
        plural(e.iterations.len(), "candidate"),
        e.total_seconds,
        e.sat_seconds,
        e.nusmv_seconds
    )?;
    // C is always proven least; T and N only when the proof fit in the budget.
    let unproven: Vec<&str> = [
        (!e.transitions_proven_minimal).then_some("T"),
        (!e.guards_proven_minimal).then_some("N"),
    ]
    .into_iter()
    .flatten()
    .collect();
    if !unproven.is_empty() {
        let unproven = unproven.join(" and ");
        write!(
            f,
            "\n{unproven} not proven minimal within the proof budget (--proof-budget SECONDS to \
             try longer)"
        )?;
    }
    Ok(())
}

/// The guide's figures and what is proven about its machine.
fn guide_lines(f: &mut std::fmt::Formatter<'_>, g: &GuideSummary) -> std::fmt::Result {
    write!(
        f,
        "closed-loop game as the guide: {:.2} s total (SAT {:.2} s, NuSMV {:.2} s in {})\n{}",
        g.total_seconds,
        g.sat_seconds,
        g.nusmv_seconds,
        plural(g.nusmv_calls, "check"),
        guide_claim(g)
    )?;
    match g.states_at_least {
        _ if g.proven_least => {}
        Some(c) if c == g.size.c => write!(
            f,
            "\nproven: C = {c} is least (no machine with fewer states reproduces the recordings)"
        )?,
        Some(c) => write!(
            f,
            "\nproven: C >= {c} (no machine with fewer states reproduces the recordings); T and \
             N are not bounded"
        )?,
        None => {}
    }
    if g.conventions.is_empty() {
        return Ok(());
    }
    write!(f, "\nthe machine has {}, as asked", g.conventions)?;
    match g.proven_least || !g.made_smaller && g.least_for_recordings_and_runs {
        true => write!(f, "; it is least among the machines that have them"),
        false => Ok(()),
    }
}

/// What the guide's machine is least among, in words.
fn guide_claim(g: &GuideSummary) -> &'static str {
    match (
        g.made_smaller,
        g.least_for_recordings_and_runs,
        g.for_runs_unproven,
    ) {
        _ if g.proven_least => {
            "C, T and N are least: the machine meets the lower bounds of the recordings alone, so \
             no machine that reproduces the recordings is smaller"
        }
        (true, _, _) => {
            "the guide's machine made smaller by merging states and dropping transitions and \
             literals while every property holds (see the guide's lines); it is not proven least"
        }
        (false, true, _) => {
            "C, T and N are least for the recordings and the closed-loop runs of the guide; a \
             smaller machine that answers differently where nothing was recorded is not ruled out"
        }
        (false, false, true) => {
            "C is least for the recordings and the closed-loop runs of the guide, T and N are not \
             proven least for them; a smaller machine that answers differently where nothing was \
             recorded is not ruled out"
        }
        (false, false, false) => {
            "the repaired machine itself (the least machine for the runs failed NuSMV); it is not \
             minimal"
        }
    }
}

/// The search's figures and what became of its machine.
fn search_line(f: &mut std::fmt::Formatter<'_>, s: &SearchSummary) -> std::fmt::Result {
    let became = match (s.replaced_by_exact_loop, s.shrunk_size) {
        (true, _) => "bounded the exact loop, which found this smaller one".to_string(),
        (false, Some(size)) => format!(
            "made small along the closed loop in {} ({size})",
            plural(s.shrink_rounds.len(), "round")
        ),
        (false, None) => "stands: the time limit came before it was made small".into(),
    };
    write!(
        f,
        "search, seed {}: {:.2} s total, {} evaluations, {} in-process checks, {} NuSMV runs; its \
         machine ({}) {became}",
        s.seed,
        s.total_seconds,
        s.search.evaluations,
        s.in_process_checks,
        s.nusmv_runs,
        s.searched_size,
    )
}
