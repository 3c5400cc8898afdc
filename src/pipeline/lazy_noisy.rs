//! Noisy synthesis in parts: Algorithm 1 on a few traces, the error model replayed on the
//! rest, and the least ε proven part by part.
//!
//! In: a noisy [`ScenarioSet`] whose trace graph is too large to encode whole (at least
//! [`LAZY_FROM_NODES`] nodes), and the [`Options`]. Out: a [`NoisySynthesis`] with one
//! candidate, the least-ε machine of the least size, its corrected traces covering the whole
//! log; the same `C`, `K`, `T` and `ε` as [`synthesize_noisy`] on the whole log.
//!
//! # Why
//! The whole-log encoding spends its time in UNSAT proofs over every trace (no machine with
//! `C-1` states, `K-1`, `T-1`, `ε-1` errors), and they grow much faster than the log: on 10^5
//! samples of the distribution station the sizes alone do not end within minutes. Most traces
//! repeat what a few already show.
//!
//! # How
//! 1. The part starts as a few traces that show every kind of step the log shows, up to
//!    [`FIRST_PART_NODES`] active steps (`first_part`).
//!    Algorithm 1 on the part gives the least `C, K, T` of the part and its least-ε machine.
//! 2. The machine is replayed under the error model on every distinct trace
//!    ([`least_corrections`]: a dynamic programme over its states, linear in the trace). Traces
//!    it cannot explain join the part (a few per round), and so do traces with corrections when
//!    their sum exceeds `--max-errors`; then back to 1.
//! 3. When it explains every trace within the bound, its sizes are the whole log's least:
//!    a machine for the whole, with its unused transitions removed, explains the part with no
//!    more states, successors or transitions, so the part's least sizes bound the whole's from
//!    below, and this machine attains them on the whole.
//! 4. The least ε. Let `E` be the corrections the machine needs in all. The traces it explains
//!    without correction need none from any machine. The others are cut into *segments*, one
//!    per correction the machine makes, at steps that carry no alternative edge (so a segment
//!    keeps every alternative its trace has there). A segment is a trace of its own: it starts
//!    with the outputs recorded before it, in a state that numbering the states from it makes
//!    state 0. For each, the least corrections of *any* machine within the sizes is computed
//!    ([`least_errors_within`](crate::sat::noisy::least_errors_within), in parallel; one
//!    UNSAT call when it is the machine's count), first on windows of a few steps around its
//!    correction, which are parts of it too.
//!    The corrections of every minimal machine for the whole log are a sum over the segments
//!    and the part, each at least its least, and the part's least is its Algorithm 1 ε: when
//!    the bounds sum to `E`, `E` is the least ε.
//! 5. A segment whose bound falls short has its correction forced by what the rest of the log
//!    shows of the machine, not by its own steps. First it takes the steps its neighbours'
//!    windows leave (`widen_short_segments`); those still short are given two things in
//!    the next proof:
//!    - *context*: traces the machine explains as recorded count for nothing in the sum, yet
//!      pin the machine down. Each group that falls short takes some (the longest first, about
//!      one trace each, each used once, so the groups stay disjoint); a segment that falls
//!      short becomes the prefix of its trace up to its end, so that it starts in the initial
//!      state, like the context.
//!      Once those traces are used up, a trace whose segments are all proven lends the steps
//!      before the window that proved its first one: they are rooted and need no correction
//!      either, and the bound of that segment holds on its window alone;
//!    - *known bounds*: the windows and segments already proven inside the group
//!      ([`least_errors_knowing`]). They are implied constraints; when they add up to one
//!      less than the group's corrections, every other step is taken as recorded, and the
//!      proof is an exact-consistency check per choice of a few corrections.
//!
//!    Once no context is left, a short segment is joined with its neighbour, and short groups
//!    of whole traces pairwise, the last one with the part. If even that falls short, another
//!    machine needs fewer corrections, and the whole log is encoded after all.
//!
//! Times, and the commands that reproduce them, are in `BENCHMARKS.md`.
//!
//! The machine is replayed on its corrected traces before it is returned, as every candidate.

use super::{Error, Event, Events};
use crate::ecc::Ecc;
use crate::sat::noisy::{
    least_errors_knowing, synthesize_noisy, Candidate, Flow, NoisyOptions as Options, NoisyStats,
    NoisySynthesis, Stretch,
};
use crate::sat::step::{Bound, Step as Solver};
use crate::sat::SatError;
use crate::scenario::trace_graph::{alternative_input, least_corrections, Corrections};
use crate::scenario::{ScenarioSet, Step};
use rayon::prelude::*;
use std::collections::{HashMap, HashSet};
use std::sync::Mutex;
use std::time::Instant;

/// Logs whose trace graph has at least this many nodes are synthesized in parts.
pub(crate) const LAZY_FROM_NODES: usize = 2_048;

/// Active steps (graph nodes) the first part holds at most (`first_part`).
pub(crate) const FIRST_PART_NODES: usize = 512;

/// Steps of recorded traces without correction that a short group takes as context in one
/// round, at least (see [`EpsilonProof`]).
const CONTEXT_STEPS: usize = 100;

/// Traces that join the part in one round.
const JOIN_PER_ROUND: usize = 4;

/// What a round of [`synthesize`] in parts found ([`Event::NoisyPart`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PartRound {
    /// The round, 1-based.
    pub(crate) round: usize,
    /// Distinct traces encoded in this round.
    pub(crate) traces: usize,
    /// Distinct traces in all.
    pub(crate) total: usize,
    /// Traces the round's machine cannot explain, even with corrections (0: the last round,
    /// unless the corrections exceed the bound).
    pub(crate) unexplained: usize,
    /// Corrections the machine needs over every trace it explains.
    pub(crate) corrections: usize,
}

/// The least ε so far ([`Event::NoisyBound`]): lower bounds summed over disjoint parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bounds {
    /// Parts whose least corrections were computed.
    pub(crate) parts: usize,
    /// The sum of the parts' least corrections.
    pub(crate) lower: usize,
    /// The corrections the machine needs (the least ε when equal to `lower`).
    pub(crate) upper: usize,
}

/// Where the parts start; [`Default`] is what
/// `synth infer --noisy` uses.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Parts {
    /// Logs with fewer graph nodes are encoded whole.
    pub(crate) from_nodes: usize,
    /// Active steps of the first part.
    pub(crate) first_nodes: usize,
}

impl Default for Parts {
    fn default() -> Self {
        Parts {
            from_nodes: LAZY_FROM_NODES,
            first_nodes: FIRST_PART_NODES,
        }
    }
}

/// Algorithm 1 on `set`, in parts when its trace graph has at least `parts.from_nodes` nodes
/// (then one candidate, whatever `opts.enumerate` says), else whole.
pub(crate) fn synthesize(
    set: &ScenarioSet,
    opts: &Options,
    parts: Parts,
    events: Events<'_>,
) -> Result<NoisySynthesis, Error> {
    let distinct = distinct_traces(set);
    let nodes = 1 + distinct
        .iter()
        .map(|&i| active(&set.scenarios[i].steps))
        .sum::<usize>();
    if nodes < parts.from_nodes || distinct.len() < 2 {
        return whole(set, opts, events);
    }
    in_parts(set, &distinct, nodes, opts, parts, events)
}

fn whole(set: &ScenarioSet, opts: &Options, events: Events<'_>) -> Result<NoisySynthesis, Error> {
    Ok(synthesize_noisy(
        set,
        opts,
        &mut |m| events(Event::Solver(m)),
        &mut |_| Flow::Continue,
    )?)
}

/// Indices of the first scenario of every distinct trace, in order.
fn distinct_traces(set: &ScenarioSet) -> Vec<usize> {
    let mut seen: HashSet<&[Step]> = HashSet::new();
    (0..set.scenarios.len())
        .filter(|&i| seen.insert(set.scenarios[i].steps.as_slice()))
        .collect()
}

fn active(steps: &[Step]) -> usize {
    steps.iter().filter(|s| s.outputs.is_some()).count()
}

/// The scenarios `which` of `set`, in that order.
fn subset(set: &ScenarioSet, which: &[usize]) -> ScenarioSet {
    ScenarioSet {
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        scenarios: which.iter().map(|&i| set.scenarios[i].clone()).collect(),
    }
}

/// What one step shows of a machine: the outputs before it, its inputs, the outputs after it
/// (`None`: nothing fired).
type Seen<'a> = (&'a [bool], &'a [bool], Option<&'a [bool]>);

/// The first part (positions in `distinct`): traces picked one by one, each the one whose steps
/// show the most [`Seen`] not yet in the part (the earliest of equals), until none shows two
/// new ones or the part holds `max_nodes` active steps.
///
/// Why: the first distinct traces of a log need not show its rarer behaviour, and a machine
/// made for them then fails on the traces that do, which costs a second part round. On 10^5
/// samples of the distribution station the first 128 active steps (3 traces) left 28 traces
/// unexplained; four traces picked so show 46 of the log's 47 step kinds, their machine
/// explains every trace, and the sizes take half the time or less. A fifth trace for the
/// last kind would more than double it again: a kind one trace adds alone is often one skewed
/// step.
fn first_part(set: &ScenarioSet, distinct: &[usize], max_nodes: usize) -> Vec<usize> {
    let seen: Vec<HashSet<Seen<'_>>> = distinct
        .iter()
        .map(|&i| {
            let mut before = set.initial_outputs.as_slice();
            let mut out = HashSet::new();
            for step in &set.scenarios[i].steps {
                out.insert((before, step.inputs.as_slice(), step.outputs.as_deref()));
                before = step.outputs.as_deref().unwrap_or(before);
            }
            out
        })
        .collect();
    let mut part: Vec<usize> = Vec::new();
    let mut shown: HashSet<Seen<'_>> = HashSet::new();
    let mut nodes = 0;
    while nodes < max_nodes {
        let new = |d: usize| seen[d].iter().filter(|s| !shown.contains(*s)).count();
        let Some((d, n)) = (0..distinct.len())
            .filter(|d| !part.contains(d))
            .map(|d| (d, new(d)))
            .max_by_key(|&(d, n)| (n, std::cmp::Reverse(d)))
        else {
            break;
        };
        if n < 2 {
            break;
        }
        part.push(d);
        shown.extend(seen[d].iter().copied());
        nodes += active(&set.scenarios[distinct[d]].steps);
    }
    part
}

/// The corrections `ecc` needs on each distinct trace (`None`: it cannot explain it).
fn replay(set: &ScenarioSet, distinct: &[usize], ecc: &Ecc) -> Vec<Option<Corrections>> {
    distinct
        .par_iter()
        .map(|&i| least_corrections(ecc, &set.initial_outputs, &set.scenarios[i].steps))
        .collect()
}

/// Steps 1-5 of the module doc: the sizes on a growing part, the least ε proven over
/// segments, and the machine's corrected log; the whole log's encoding when the proof falls
/// short.
fn in_parts(
    set: &ScenarioSet,
    distinct: &[usize],
    nodes: usize,
    opts: &Options,
    parts: Parts,
    events: Events<'_>,
) -> Result<NoisySynthesis, Error> {
    let t0 = Instant::now();
    let PartMachine {
        part,
        synthesis: s,
        fixes,
        rounds,
        mut stats,
    } = part_machine(set, distinct, opts, parts, events)?;
    let candidate = s
        .candidates
        .into_iter()
        .next()
        .expect("checked in the loop");
    stats.minimize_seconds = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let upper: usize = fixes.iter().map(|f| f.steps.len()).sum();
    let sizes = (s.n, s.k, s.r);
    let proof = EpsilonProof::new(set, distinct, &fixes, &part, candidate.errors, sizes, opts)?;
    if !proof.run(events)? {
        // Another machine of these sizes needs fewer corrections: only the whole log says which.
        return whole(set, opts, events);
    }
    let corrected = corrected_log(set, distinct, &fixes);
    let ecc = candidate.ecc;
    corrected.check(&ecc).map_err(|m| {
        SatError::Bug(format!(
            "the machine found in parts does not replay its corrected traces: {m}"
        ))
    })?;
    events(Event::Solver(Solver::Minimal {
        bound: Bound::Errors,
        value: upper,
    }));
    events(Event::Solver(Solver::Candidate {
        number: 1,
        errors: upper,
        size: ecc.size(),
    }));
    let used: Vec<bool> = fixes.iter().flat_map(|f| f.used.iter().copied()).collect();
    let inputs: HashSet<&[bool]> = distinct
        .iter()
        .flat_map(|&i| set.scenarios[i].steps.iter().map(|s| s.inputs.as_slice()))
        .collect();
    stats.graph_nodes = nodes;
    stats.distinct_traces = distinct.len();
    stats.alternatives = used.len();
    stats.distinct_inputs = inputs.len();
    stats.rounds = rounds;
    stats.encoded_nodes = 1 + part
        .iter()
        .map(|&d| active(&set.scenarios[distinct[d]].steps))
        .sum::<usize>();
    stats.enumerate_seconds = t1.elapsed().as_secs_f64();
    Ok(NoisySynthesis {
        n: s.n,
        k: s.k,
        r: s.r,
        candidates: vec![Candidate {
            size: ecc.size(),
            ecc,
            errors: upper,
            used,
            corrected,
            guards_exact: candidate.guards_exact,
        }],
        exhausted: false,
        stats,
    })
}

/// Steps 1-3 of the module doc: a part of the log whose machine explains every trace within
/// the bound, so that the part's least sizes are the whole log's.
struct PartMachine {
    /// Positions in `distinct` of the part's traces.
    part: Vec<usize>,
    /// Algorithm 1 on the part, with one candidate.
    synthesis: NoisySynthesis,
    /// The candidate's corrections on every distinct trace.
    fixes: Vec<Corrections>,
    /// Part rounds made.
    rounds: usize,
    /// Encoding figures summed over the rounds.
    stats: NoisyStats,
}

/// Algorithm 1 on a part of the log that starts as [`first_part`] and takes, each round, up
/// to [`JOIN_PER_ROUND`] traces its machine cannot explain (or, when the corrections exceed
/// `--max-errors`, traces with corrections), until the machine explains every trace within
/// the bound (steps 1-3 of the module doc). Each part holds the one before, so its least
/// sizes are proven for every later part too.
fn part_machine(
    set: &ScenarioSet,
    distinct: &[usize],
    opts: &Options,
    parts: Parts,
    events: Events<'_>,
) -> Result<PartMachine, Error> {
    let mut part = first_part(set, distinct, parts.first_nodes);
    let mut in_part = vec![false; distinct.len()];
    for &d in &part {
        in_part[d] = true;
    }
    let mut one = Options {
        enumerate: 1,
        ..opts.clone()
    };
    let mut stats = NoisyStats::default();
    let mut round = 0;
    loop {
        round += 1;
        let (s, fixes) = part_round(set, distinct, &part, &one, events)?;
        stats.variables += s.stats.variables;
        stats.clauses += s.stats.clauses;
        stats.solver_calls += s.stats.solver_calls;
        // Every later part holds this one: its least sizes are proven for them too.
        one.at_least = Some((s.n, s.k, s.r));
        let unexplained: Vec<usize> = (0..distinct.len())
            .filter(|&d| fixes[d].is_none())
            .collect();
        if let Some(&d) = unexplained.iter().find(|&&d| in_part[d]) {
            return Err(SatError::Bug(format!(
                "the machine made for a part of the log cannot explain trace {} of that part",
                set.scenarios[distinct[d]].origin
            ))
            .into());
        }
        let corrections: usize = fixes.iter().flatten().map(|f| f.steps.len()).sum();
        events(Event::NoisyPart(PartRound {
            round,
            traces: part.len(),
            total: distinct.len(),
            unexplained: unexplained.len(),
            corrections,
        }));
        let over = opts.max_errors.is_some_and(|m| corrections > m);
        let join: Vec<usize> = if !unexplained.is_empty() {
            unexplained
        } else if over {
            (0..distinct.len())
                .filter(|&d| !in_part[d] && fixes[d].as_ref().is_some_and(|f| !f.steps.is_empty()))
                .collect()
        } else {
            return Ok(PartMachine {
                part,
                synthesis: s,
                fixes: (fixes.into_iter())
                    .map(|f| f.expect("every trace explained"))
                    .collect(),
                rounds: round,
                stats,
            });
        };
        if join.is_empty() {
            return Err(SatError::Bug(
                "the corrections exceed the bound, yet the part holds every corrected trace".into(),
            )
            .into());
        }
        for d in join.into_iter().take(JOIN_PER_ROUND) {
            part.push(d);
            in_part[d] = true;
        }
    }
}

/// One part round: Algorithm 1 on the traces `part` (positions in `distinct`) with options
/// `one`, and the corrections its candidate needs on every distinct trace (`None`: it cannot
/// explain it).
fn part_round(
    set: &ScenarioSet,
    distinct: &[usize],
    part: &[usize],
    one: &Options,
    events: Events<'_>,
) -> Result<(NoisySynthesis, Vec<Option<Corrections>>), Error> {
    let traces: Vec<usize> = part.iter().map(|&d| distinct[d]).collect();
    // The part's own ε and candidate are not the log's: their lines are left out.
    let s = synthesize_noisy(
        &subset(set, &traces),
        one,
        &mut |m| match m {
            Solver::Candidate { .. }
            | Solver::Minimal {
                bound: Bound::Errors,
                ..
            } => {}
            m => events(Event::Solver(m)),
        },
        &mut |_| Flow::Continue,
    )?;
    let candidate = s
        .candidates
        .first()
        .ok_or_else(|| SatError::Bug("Algorithm 1 ended without a candidate".into()))?;
    let fixes = replay(set, distinct, &candidate.ecc);
    Ok((s, fixes))
}

/// The log with every distinct trace's corrections `fixes` applied (each corrected step
/// takes the inputs of the step after it), on every scenario that records it.
fn corrected_log(set: &ScenarioSet, distinct: &[usize], fixes: &[Corrections]) -> ScenarioSet {
    let mut corrected = set.clone();
    let at: HashMap<&[Step], usize> = distinct
        .iter()
        .enumerate()
        .map(|(d, &i)| (set.scenarios[i].steps.as_slice(), d))
        .collect();
    let mut fixed_steps: Vec<Vec<Step>> = Vec::with_capacity(distinct.len());
    for (d, &i) in distinct.iter().enumerate() {
        let steps = &set.scenarios[i].steps;
        let mut out = steps.clone();
        for &k in &fixes[d].steps {
            out[k].inputs = steps[k + 1].inputs.clone();
        }
        fixed_steps.push(out);
    }
    for sc in &mut corrected.scenarios {
        sc.steps = fixed_steps[at[sc.steps.as_slice()]].clone();
    }
    corrected
}

/// Steps `from..to` of distinct trace `d`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Piece {
    d: usize,
    from: usize,
    to: usize,
}

/// Pieces of the log bounded together, with the corrections the machine needs on them and,
/// once computed, the least any machine of the sizes needs. Either one segment of a trace or
/// whole traces.
#[derive(Debug, Clone)]
struct Group {
    pieces: Vec<Piece>,
    upper: usize,
    lower: Option<usize>,
    /// Bounds proven on disjoint stretches of it (pieces, least corrections): told to the
    /// solver when the group is bounded ([`least_errors_knowing`]).
    known: Vec<(Vec<Piece>, usize)>,
}

impl Group {
    fn new(pieces: Vec<Piece>, upper: usize) -> Group {
        Group {
            pieces,
            upper,
            lower: None,
            known: Vec::new(),
        }
    }

    fn short(&self) -> bool {
        self.lower != Some(self.upper)
    }

    /// Keeps the bound just computed as a known one (on `window`, the stretch that proved it,
    /// or on the whole group), unless the known ones already say more.
    fn remember(&mut self, window: Option<Piece>) {
        let lower = self.lower.unwrap_or(0);
        if lower > self.known.iter().map(|(_, n)| n).sum::<usize>() {
            let stretch = window.map_or_else(|| self.pieces.clone(), |p| vec![p]);
            self.known = vec![(stretch, lower)];
        }
    }

    /// Two groups as one, covering `pieces`, with what is known of each.
    fn join(a: Group, b: Group, pieces: Vec<Piece>) -> Group {
        Group {
            known: [a.known, b.known].concat(),
            ..Group::new(pieces, a.upper + b.upper)
        }
    }

    /// Two groups of whole traces or prefixes as one: the pieces of both.
    fn merge(mut a: Group, mut b: Group) -> Group {
        let pieces = [std::mem::take(&mut a.pieces), std::mem::take(&mut b.pieces)].concat();
        Group::join(a, b, pieces)
    }
}

/// Where trace `steps` may be cut: before step `l` when step `l - 1` has no alternative edge
/// (a passive step, or one that changed nothing), so each side keeps every alternative the
/// trace has. `cut[l]` for `l` in `0..=len`.
fn cuts(steps: &[Step], initial_outputs: &[bool]) -> Vec<bool> {
    let mut cut = vec![true; steps.len() + 1];
    let mut outputs = initial_outputs;
    for (k, step) in steps.iter().enumerate() {
        if let Some(out) = &step.outputs {
            cut[k + 1] = alternative_input(steps, k, *out != outputs).is_none();
            outputs = out;
        }
    }
    cut
}

/// The segments of a trace, one per correction the machine makes in it (`corrections`,
/// sorted): each boundary is the allowed cut nearest the middle between two corrections,
/// past the step after the first (its alternative reads that step's inputs). Corrections
/// with no cut between them share a segment. Returns `(from, to, corrections in it)`.
fn segments(cut: &[bool], corrections: &[usize]) -> Vec<(usize, usize, usize)> {
    let len = cut.len() - 1;
    let mut out = Vec::new();
    let (mut from, mut count) = (0, 0);
    for (i, &c) in corrections.iter().enumerate() {
        count += 1;
        let Some(&next) = corrections.get(i + 1) else {
            break;
        };
        let mid = (c + next).div_ceil(2);
        let best = (c + 2..=next)
            .filter(|&l| cut[l])
            .min_by_key(|&l| l.abs_diff(mid));
        if let Some(l) = best {
            out.push((from, l, count));
            from = l;
            count = 0;
        }
    }
    out.push((from, len, count));
    out
}

/// The known bounds of `g` ([`Group::known`]) in the steps of its [`group_set`].
fn stretches(g: &Group) -> Vec<(Vec<Stretch>, usize)> {
    let at = |p: &Piece| -> Option<Stretch> {
        let (s, whole) = g.pieces.iter().enumerate().find(|(_, w)| w.d == p.d)?;
        Some((s, p.from - whole.from..p.to - whole.from))
    };
    g.known
        .iter()
        .map(|(pieces, n)| (pieces.iter().filter_map(at).collect(), *n))
        .collect()
}

/// The recordings of a group: whole traces as they are, or one segment as a trace of its own
/// that starts with the outputs recorded before it. The segment's first state is unknown, but
/// numbering the states of any machine from it makes it state 0, so the segment's least
/// corrections bound those of every machine on that stretch of the trace.
fn group_set(set: &ScenarioSet, distinct: &[usize], g: &Group) -> ScenarioSet {
    let len = |p: &Piece| set.scenarios[distinct[p.d]].steps.len();
    match g.pieces.as_slice() {
        [p] if p.from > 0 || p.to < len(p) => {
            let sc = &set.scenarios[distinct[p.d]];
            let before = sc.steps[..p.from]
                .iter()
                .rev()
                .find_map(|s| s.outputs.clone())
                .unwrap_or_else(|| set.initial_outputs.clone());
            ScenarioSet {
                inputs: set.inputs.clone(),
                outputs: set.outputs.clone(),
                initial_outputs: before,
                scenarios: vec![crate::scenario::Scenario {
                    origin: sc.origin.clone(),
                    steps: sc.steps[p.from..p.to].to_vec(),
                }],
            }
        }
        pieces => {
            // Pieces bounded together all start with their trace (whole traces, prefixes).
            let traces: Vec<usize> = pieces.iter().map(|p| distinct[p.d]).collect();
            let mut out = subset(set, &traces);
            for (sc, p) in out.scenarios.iter_mut().zip(pieces) {
                debug_assert_eq!(
                    p.from, 0,
                    "only a group's one piece may start inside a trace"
                );
                sc.steps.truncate(p.to);
            }
            out
        }
    }
}

/// Steps on either side of a segment's corrections in its first [`windows`]; each next one
/// doubles them.
const WINDOW_STEPS: usize = 8;

/// Windows of a one-segment group `g`, narrowest first, each strictly inside it: the steps from
/// `w` before its first correction to `w` after its last, widened to the nearest [`cuts`], for
/// `w` = [`WINDOW_STEPS`], twice that, and so on. A window is a segment of its own, so any
/// machine's corrections on `g` are at least its least within the sizes: a window that needs
/// `g.upper` proves `g`'s bound.
///
/// Why: a skewed input contradicts what the few steps around it show. On 10^4 samples of the
/// distribution station, 8 steps on either side proved half the segments' bounds in about 20 ms
/// each, where the whole segment (40-120 active steps) took 0.2-1.2 s: the SAT proof grows with
/// the steps that do not matter.
fn windows(set: &ScenarioSet, distinct: &[usize], fixes: &[Corrections], g: &Group) -> Vec<Group> {
    // Joined groups need two corrections or more, forced by steps far apart: their windows
    // cover almost all of them, and each that falls short is a SAT call on a long piece.
    let ([p], 1) = (g.pieces.as_slice(), g.upper) else {
        return Vec::new();
    };
    let steps = &set.scenarios[distinct[p.d]].steps;
    let inside: Vec<usize> = (fixes[p.d].steps.iter())
        .copied()
        .filter(|k| (p.from..p.to).contains(k))
        .collect();
    let (Some(&first), Some(&last)) = (inside.first(), inside.last()) else {
        return Vec::new();
    };
    let cut = cuts(steps, &set.initial_outputs);
    let mut out = Vec::new();
    let mut w = WINDOW_STEPS;
    loop {
        // The correction at `last` reads the inputs of step `last + 1`: the window keeps it.
        let from = (p.from..=first.saturating_sub(w).max(p.from))
            .rev()
            .find(|&l| cut[l])
            .unwrap_or(p.from);
        let to = ((last + 2 + w).min(p.to)..=p.to)
            .find(|&l| cut[l])
            .unwrap_or(p.to);
        if from == p.from && to == p.to {
            return out;
        }
        out.push(Group::new(vec![Piece { from, to, ..*p }], g.upper));
        w *= 2;
    }
}

/// The segments of one trace, in order, with every short one joined to its neighbour: the
/// one before it, whose steps may pin the state it starts in, or the one after it when it is
/// the first. Joined segments are bounded anew.
fn join_short_segments(segs: Vec<Group>) -> Vec<Group> {
    let mut out: Vec<Group> = Vec::new();
    let mut it = segs.into_iter();
    while let Some(g) = it.next() {
        if !g.short() {
            out.push(g);
            continue;
        }
        let p = g.pieces[0];
        if let Some(prev) = out.pop() {
            let q = prev.pieces[0];
            out.push(Group::join(prev, g, vec![Piece { from: q.from, ..p }]));
        } else if let Some(n) = it.next() {
            let q = n.pieces[0];
            out.push(Group::join(g, n, vec![Piece { to: q.to, ..p }]));
        } else {
            // A trace in one segment: bounded as it is, a whole-trace group.
            out.push(g);
        }
    }
    out
}

/// Widens every short segment of the first pass over the steps its neighbours in the trace
/// do not need: a neighbour whose bound a window proved keeps its piece only up to (or from)
/// that window, and the short segment takes the rest, with no correction more. The longer
/// stretch before its correction pins the state it starts in better. Returns whether one
/// was widened (its bound is then computed anew).
///
/// Why: on 10^5 samples of the distribution station 15 of the 59 short segments could
/// widen, 5 of them were proven so in about a second, and the round with context that
/// followed was that much shorter.
fn widen_short_segments(groups: &mut [Group]) -> bool {
    // The window that proved a one-piece group's bound, if one did.
    let window = |g: &Group| -> Option<Piece> {
        let ([p], [(w, _)], false) = (g.pieces.as_slice(), g.known.as_slice(), g.short()) else {
            return None;
        };
        match w.as_slice() {
            [w] if w.d == p.d => Some(*w),
            _ => None,
        }
    };
    let mut any = false;
    for i in 0..groups.len() {
        let (&[p], true) = (groups[i].pieces.as_slice(), groups[i].short()) else {
            continue;
        };
        let mut q = p;
        if let Some(prev) = i.checked_sub(1).map(|j| &groups[j]) {
            if let (Some(w), &[b]) = (window(prev), prev.pieces.as_slice()) {
                if b.d == p.d && b.to == p.from && w.to < p.from {
                    q.from = w.to;
                    groups[i - 1].pieces[0].to = w.to;
                }
            }
        }
        if let Some(next) = groups.get(i + 1) {
            if let (Some(w), &[b]) = (window(next), next.pieces.as_slice()) {
                if b.d == p.d && b.from == p.to && w.from > p.to {
                    q.to = w.from;
                    groups[i + 1].pieces[0].from = w.from;
                }
            }
        }
        if q != p {
            groups[i].pieces[0] = q;
            groups[i].lower = None;
            any = true;
        }
    }
    any
}

/// Steps shorter than this at the start of a trace are not worth lending as context.
const FREE_PREFIX_STEPS: usize = 16;

/// The free prefixes of traces whose segments are all proven, each trace once (`lent`): the
/// steps before the window that proved its first segment's bound. That bound holds on the
/// window alone, so the group gives up the steps before it (its piece shrinks to start there)
/// and they can join another group as context: rooted in the initial state, and explained by
/// the machine as recorded, like a trace without corrections.
fn free_prefixes(groups: &mut [Group], lent: &mut HashSet<usize>) -> Vec<Piece> {
    let mut settled: HashMap<usize, bool> = HashMap::new();
    for g in groups.iter() {
        if let [p] = g.pieces.as_slice() {
            *settled.entry(p.d).or_insert(true) &= !g.short();
        }
    }
    let mut out = Vec::new();
    for g in groups.iter_mut() {
        let (&[p], &[(ref stretch, _)]) = (g.pieces.as_slice(), g.known.as_slice()) else {
            continue;
        };
        let &[w] = stretch.as_slice() else { continue };
        if p.from != 0 || g.short() || !settled[&p.d] || lent.contains(&p.d) {
            continue;
        }
        if w.d != p.d || w.from < FREE_PREFIX_STEPS {
            continue;
        }
        out.push(Piece { to: w.from, ..p });
        g.pieces[0].from = w.from;
        lent.insert(p.d);
    }
    out
}

/// What a bound is computed on ([`least_errors_knowing`]): recordings, the machine's
/// corrections on them, and the bounds known on their stretches.
#[derive(PartialEq, Eq, Hash)]
struct Recorded {
    initial_outputs: Vec<bool>,
    steps: Vec<Vec<Step>>,
    upper: usize,
    known: Vec<(Vec<Stretch>, usize)>,
}

/// The memo of bounds; a thread that panicked while holding it left it whole (inserts only).
fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// The proof that the machine's corrections are the least ε of the whole log (steps 4-5 of
/// the module doc): lower bounds on disjoint groups of the log, summed, with the short groups
/// given context, widened or joined round after round.
struct EpsilonProof<'a> {
    set: &'a ScenarioSet,
    distinct: &'a [usize],
    /// The machine's corrections on every distinct trace.
    fixes: &'a [Corrections],
    /// The part's least sizes `(C, K, T)`, which every bound is computed within.
    sizes: (usize, usize, usize),
    opts: &'a Options,
    /// The corrections the machine needs in all.
    upper: usize,
    /// Segments and groups of traces outside the part.
    groups: Vec<Group>,
    /// The part, a group whose bound is known: its own least ε.
    part: Group,
    /// Context: traces outside the part the machine explains without a correction, longest
    /// last, then free prefixes.
    pool: Vec<Piece>,
    /// Free prefixes waiting for the pool to run out ([`free_prefixes`]).
    reserve: Vec<Piece>,
    /// Traces whose free prefix went to the reserve.
    lent: HashSet<usize>,
    /// Bounds already computed, by what they were computed on: on 10^5 samples of the
    /// distribution station 256 of the 339 first windows and 176 of the 325 second ones
    /// repeat another segment's (the same skew at the same point of the same cycle).
    proven: Mutex<HashMap<Recorded, usize>>,
    /// Whether short segments were widened once ([`widen_short_segments`]).
    widened: bool,
}

impl<'a> EpsilonProof<'a> {
    /// The first groups: the part (`part`, positions in `distinct`, bound `part_errors`, its
    /// Algorithm 1 ε) and one segment per correction the machine makes outside it
    /// ([`segments`]).
    fn new(
        set: &'a ScenarioSet,
        distinct: &'a [usize],
        fixes: &'a [Corrections],
        part: &[usize],
        part_errors: usize,
        sizes: (usize, usize, usize),
        opts: &'a Options,
    ) -> Result<Self, Error> {
        let errs = |d: usize| fixes[d].steps.len();
        let part_upper: usize = part.iter().map(|&d| errs(d)).sum();
        if part_upper != part_errors {
            return Err(SatError::Bug(format!(
                "the part's least ε is {part_errors}, its machine replays the part with {part_upper}"
            ))
            .into());
        }
        let mut proof = EpsilonProof {
            set,
            distinct,
            fixes,
            sizes,
            opts,
            upper: (0..distinct.len()).map(errs).sum(),
            groups: Vec::new(),
            part: Group::new(Vec::new(), part_errors),
            pool: Vec::new(),
            reserve: Vec::new(),
            lent: HashSet::new(),
            proven: Mutex::new(HashMap::new()),
            widened: false,
        };
        let in_part: HashSet<usize> = part.iter().copied().collect();
        let outside = || (0..distinct.len()).filter(|d| !in_part.contains(d));
        proof.pool = outside()
            .filter(|&d| errs(d) == 0)
            .map(|d| whole_trace(set, distinct, d))
            .collect();
        proof.pool.sort_by_key(|p| p.to);
        for d in outside().filter(|&d| errs(d) > 0) {
            let steps = &set.scenarios[distinct[d]].steps;
            let cut = cuts(steps, &set.initial_outputs);
            for (from, to, n) in segments(&cut, &fixes[d].steps) {
                proof
                    .groups
                    .push(Group::new(vec![Piece { d, from, to }], n));
            }
        }
        let pieces: Vec<Piece> = part.iter().map(|&d| proof.whole(d)).collect();
        proof.part = Group {
            pieces: pieces.clone(),
            upper: part_errors,
            lower: Some(part_errors),
            known: vec![(pieces, part_errors)],
        };
        Ok(proof)
    }

    /// Distinct trace `d` as a piece.
    fn whole(&self, d: usize) -> Piece {
        whole_trace(self.set, self.distinct, d)
    }

    /// Whether the bounds add up to the machine's corrections, round after round: `false`
    /// when every group is tight and the sum still falls short (another machine of these
    /// sizes needs fewer corrections).
    fn run(mut self, events: Events<'_>) -> Result<bool, Error> {
        loop {
            let lower = self.bound_groups()?;
            events(Event::NoisyBound(Bounds {
                parts: self.groups.len() + 1,
                lower,
                upper: self.upper,
            }));
            if lower == self.upper {
                return Ok(true);
            }
            if !std::mem::replace(&mut self.widened, true) && widen_short_segments(&mut self.groups)
            {
                continue;
            }
            if !self.regroup() {
                return Ok(false);
            }
        }
    }

    /// Bounds every group not yet bounded (in parallel) and returns the sum of all bounds, the
    /// part's included. A bound above a group's corrections is a bug.
    fn bound_groups(&mut self) -> Result<usize, Error> {
        let lowers: Vec<_> = (self.groups.par_iter())
            .map(|g| g.lower.is_none().then(|| self.bound(g)))
            .collect();
        for (g, l) in self.groups.iter_mut().zip(lowers) {
            if let Some(l) = l {
                let (lower, window) = l?;
                g.lower = Some(lower);
                g.remember(window);
            }
        }
        if self.part.lower.is_none() {
            self.part.lower = Some(self.bound(&self.part)?.0);
        }
        let all = || self.groups.iter().chain([&self.part]);
        if let Some(g) = all().find(|g| g.lower > Some(g.upper)) {
            return Err(SatError::Bug(format!(
                "a part of the log needs at least {} corrections, its machine replays it with {}",
                g.lower.unwrap_or(0),
                g.upper
            ))
            .into());
        }
        Ok(all().map(|g| g.lower.expect("every group bounded")).sum())
    }

    /// The bound of `g`, and the window that proved it if one did. A window that needs as
    /// many corrections as its group proves the group's bound. The group keeps its whole
    /// piece all the same: shrunk to the window, it would leave its neighbours less to be
    /// joined with, and on 10^5 samples the joins then took longer than the windows saved.
    /// Only a trace with nothing left to join gives up the steps before its first window
    /// ([`free_prefixes`]).
    fn bound(&self, g: &Group) -> Result<(usize, Option<Piece>), SatError> {
        for w in windows(self.set, self.distinct, self.fixes, g) {
            if self.within(&w)? == g.upper {
                return Ok((g.upper, Some(w.pieces[0])));
            }
        }
        Ok((self.within(g)?, None))
    }

    /// The least corrections of any machine within the sizes on `g`, with what is known on
    /// its stretches ([`least_errors_knowing`]); remembered by what it was computed on.
    fn within(&self, g: &Group) -> Result<usize, SatError> {
        let gs = group_set(self.set, self.distinct, g);
        let known = stretches(g);
        let key = Recorded {
            initial_outputs: gs.initial_outputs.clone(),
            steps: gs.scenarios.iter().map(|sc| sc.steps.clone()).collect(),
            upper: g.upper,
            known: known.clone(),
        };
        if let Some(&n) = lock(&self.proven).get(&key) {
            return Ok(n);
        }
        let (algorithms, deadline) = (self.opts.algorithms, self.opts.deadline);
        let n = least_errors_knowing(&gs, algorithms, self.sizes, g.upper, &known, deadline)?;
        lock(&self.proven).insert(key, n);
        Ok(n)
    }

    /// The groups of the next round: short segments given context or joined with their
    /// neighbours, short groups of whole traces given context or merged. `false` when
    /// nothing is left to try: every group is tight and the shortfall is the part's.
    fn regroup(&mut self) -> bool {
        // Free prefixes are context of a second kind: lent only once the traces without
        // corrections are used up (more context than needed makes every proof longer).
        self.reserve
            .extend(free_prefixes(&mut self.groups, &mut self.lent));
        if self.pool.is_empty() {
            self.pool = std::mem::take(&mut self.reserve);
            self.pool.sort_by_key(|p| p.to);
        }
        let (mut next, short) = self.resegment();
        let pending = next.iter().any(|g| g.lower.is_none());
        if short.is_empty() && !pending {
            // Every group is tight: the shortfall is the part's, merged with the last short
            // group. Another machine of these sizes needs fewer corrections.
            return false;
        }
        next.extend(self.merge_short(short, pending));
        self.groups = next;
        true
    }

    /// Splits the groups into those kept and the short ones to be given context or merged.
    /// A trace with a short segment is bounded anew: with context to give, from its start
    /// up to its last short segment, with what its segments proved (the steps before a
    /// short segment pin the state it starts in, and the context the machine); without,
    /// each short segment joined with its neighbour ([`join_short_segments`]).
    fn resegment(&mut self) -> (Vec<Group>, Vec<Group>) {
        let (set, distinct) = (self.set, self.distinct);
        let is_segment =
            |g: &Group| matches!(g.pieces.as_slice(), [p] if *p != whole_trace(set, distinct, p.d));
        let resegment: HashSet<usize> = (self.groups.iter())
            .filter(|g| g.short() && is_segment(g))
            .map(|g| g.pieces[0].d)
            .collect();
        let mut next: Vec<Group> = Vec::new();
        let mut short: Vec<Group> = Vec::new();
        let mut by_trace: HashMap<usize, Vec<Group>> = HashMap::new();
        for g in std::mem::take(&mut self.groups) {
            if is_segment(&g) && resegment.contains(&g.pieces[0].d) {
                by_trace.entry(g.pieces[0].d).or_default().push(g);
            } else if g.short() {
                short.push(g);
            } else {
                next.push(g);
            }
        }
        let mut traces: Vec<(usize, Vec<Group>)> = by_trace.into_iter().collect();
        traces.sort_unstable_by_key(|(d, _)| *d);
        for (d, mut segs) in traces {
            segs.sort_unstable_by_key(|g| g.pieces[0].from);
            if self.pool.is_empty() {
                next.extend(join_short_segments(segs));
                continue;
            }
            let j = segs
                .iter()
                .rposition(Group::short)
                .expect("a short segment");
            let rest = segs.split_off(j + 1);
            let to = segs[j].pieces[0].to;
            let upper = segs.iter().map(|g| g.upper).sum();
            let known = segs.into_iter().flat_map(|g| g.known).collect();
            short.push(Group {
                known,
                ..Group::new(vec![Piece { d, from: 0, to }], upper)
            });
            next.extend(rest);
        }
        (next, short)
    }

    /// The short groups for the next round. With context in the pool, each takes some;
    /// without, the last one joins the part when nothing else is pending, or they are merged
    /// pairwise (an odd one left over keeps its bound and is merged in the next round).
    fn merge_short(&mut self, short: Vec<Group>, pending: bool) -> Vec<Group> {
        let mut merged = Vec::new();
        if !self.pool.is_empty() {
            // Traces the machine explains as recorded count for nothing in the sum, yet they
            // pin down the machine: a short group of whole traces takes some of them and is
            // bounded again with the corrections it has, an exact-consistency proof where
            // joining two short groups needs a proof of two corrections.
            // The longest first, and only as many as CONTEXT_STEPS asks: one whole trace
            // usually. An even share of the pool (half of it over the short groups, 150 steps
            // at least) makes every proof longer and proves no more bounds: on 10^5 samples
            // the round takes a third longer.
            for a in short {
                let mut pieces = a.pieces.clone();
                let mut steps = 0;
                while steps < CONTEXT_STEPS {
                    let Some(p) = self.pool.pop() else { break };
                    pieces.push(p);
                    steps += p.to;
                }
                merged.push(Group {
                    known: a.known,
                    ..Group::new(pieces, a.upper)
                });
            }
        } else if short.len() == 1 && !pending {
            let a = short.into_iter().next().expect("one short group");
            let part = std::mem::replace(&mut self.part, Group::new(Vec::new(), 0));
            self.part = Group::merge(part, a);
        } else {
            let mut short = short.into_iter();
            while let Some(a) = short.next() {
                merged.push(match short.next() {
                    Some(b) => Group::merge(a, b),
                    None => a,
                });
            }
        }
        merged
    }
}

/// Distinct trace `d` (a position in `distinct`) as a piece.
fn whole_trace(set: &ScenarioSet, distinct: &[usize], d: usize) -> Piece {
    Piece {
        d,
        from: 0,
        to: set.scenarios[distinct[d]].steps.len(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::distribution;
    use crate::sat::noisy::least_errors_within;

    /// Distribution-station logs of `samples` samples with skew injected, and the number
    /// injected.
    fn noisy_logs(samples: usize, seed: u64) -> (ScenarioSet, usize) {
        let mut injected = 0;
        let logs: Vec<_> = distribution::random_logs(samples, seed)
            .iter()
            .enumerate()
            .map(|(k, log)| {
                let (n, i) = distribution::inject_skew(log, 0.05, seed + k as u64);
                injected += i;
                n
            })
            .collect();
        (distribution::to_scenarios(&logs, "<generated>"), injected)
    }

    /// One candidate, with at most the injected errors.
    fn one_candidate(injected: usize) -> Options {
        Options {
            enumerate: 1,
            max_errors: Some(injected),
            ..Options::default()
        }
    }

    #[test]
    fn parts_give_the_sizes_and_the_least_errors_of_the_whole_log() {
        // A log with corrected traces outside the first part (with seed 3 it holds them all).
        let (set, injected) = noisy_logs(1_500, 5);
        let opts = one_candidate(injected);
        let whole = synthesize_noisy(&set, &opts, &mut |_| {}, &mut |_| Flow::Continue).unwrap();
        let small = Parts {
            from_nodes: 0,
            first_nodes: 40,
        };
        let mut rounds = 0;
        let mut bounds = Vec::new();
        let parts = synthesize(&set, &opts, small, &mut |e| match e {
            Event::NoisyPart(r) => rounds = r.round,
            Event::NoisyBound(b) => bounds.push((b.parts, b.lower, b.upper)),
            _ => {}
        })
        .unwrap();
        assert_eq!(
            (parts.n, parts.k, parts.r, parts.candidates[0].errors),
            (whole.n, whole.k, whole.r, whole.candidates[0].errors)
        );
        // Encoded in parts, not whole, and the least ε proven by the bounds.
        assert!(
            rounds >= 1 && parts.stats.encoded_nodes < parts.stats.graph_nodes,
            "{rounds} rounds, {} of {} nodes encoded",
            parts.stats.encoded_nodes,
            parts.stats.graph_nodes
        );
        // Segments bounded beside the part, and the bounds meet the machine's count.
        let &(n, lower, upper) = bounds.last().unwrap();
        assert!(n > 1, "{bounds:?}");
        assert_eq!(lower, upper);
        let c = &parts.candidates[0];
        assert_eq!(c.corrected.check(&c.ecc), Ok(()));
        let changed: usize = set
            .scenarios
            .iter()
            .zip(&c.corrected.scenarios)
            .map(|(a, b)| a.steps.iter().zip(&b.steps).filter(|(x, y)| x != y).count())
            .sum();
        assert!(
            changed >= c.errors,
            "{changed} steps changed, ε = {}",
            c.errors
        );
        assert_eq!(c.used.iter().filter(|&&u| u).count(), c.errors);
    }

    #[test]
    fn known_bounds_leave_a_traces_least_corrections_as_they_are() {
        let (set, injected) = noisy_logs(1_500, 3);
        let opts = one_candidate(injected);
        let small = Parts {
            from_nodes: 0,
            first_nodes: 40,
        };
        let s = synthesize(&set, &opts, small, &mut |_| {}).unwrap();
        let sizes = (s.n, s.k, s.r);
        let distinct = distinct_traces(&set);
        let fixes: Vec<Corrections> = replay(&set, &distinct, &s.candidates[0].ecc)
            .into_iter()
            .map(Option::unwrap)
            .collect();
        // The shortest traces with two corrections or more: the proofs stay short.
        let mut two: Vec<usize> = (0..distinct.len())
            .filter(|&d| fixes[d].steps.len() >= 2)
            .collect();
        two.sort_by_key(|&d| set.scenarios[distinct[d]].steps.len());
        assert!(!two.is_empty(), "no trace with two corrections");
        for d in two.into_iter().take(2) {
            let steps = &set.scenarios[distinct[d]].steps;
            let cut = cuts(steps, &set.initial_outputs);
            let whole = Piece {
                d,
                from: 0,
                to: steps.len(),
            };
            let mut trace = Group::new(vec![whole], 0);
            for (from, to, n) in segments(&cut, &fixes[d].steps) {
                let mut g = Group::new(vec![Piece { d, from, to }], n);
                let alone = group_set(&set, &distinct, &g);
                g.lower = Some(least_errors_within(&alone, opts.algorithms, sizes, n).unwrap());
                g.remember(None);
                trace = Group::join(trace, g, vec![whole]);
            }
            let traced = group_set(&set, &distinct, &trace);
            let least = least_errors_within(&traced, opts.algorithms, sizes, trace.upper).unwrap();
            // With a loose upper bound too: the known bounds must not cut off the least.
            for upper in [trace.upper, trace.upper + 1] {
                let known = stretches(&trace);
                let with = least_errors_knowing(
                    &traced,
                    opts.algorithms,
                    sizes,
                    upper,
                    &known,
                    crate::deadline::Deadline::NONE,
                );
                assert_eq!(with.unwrap(), least, "trace {d}: {:?}", trace.known);
            }
        }
    }

    #[test]
    fn groups_of_several_pieces_hold_trace_prefixes_from_their_start() {
        let (set, _) = noisy_logs(1_000, 1);
        let distinct = distinct_traces(&set);
        let len = |d: usize| set.scenarios[distinct[d]].steps.len();
        let g = Group::new(
            vec![
                Piece {
                    d: 0,
                    from: 0,
                    to: len(0) / 2,
                },
                Piece {
                    d: 1,
                    from: 0,
                    to: len(1),
                },
            ],
            0,
        );
        let s = group_set(&set, &distinct, &g);
        assert_eq!(
            s.scenarios[0].steps,
            set.scenarios[distinct[0]].steps[..len(0) / 2]
        );
        assert_eq!(s.scenarios[1].steps, set.scenarios[distinct[1]].steps);
        assert_eq!(s.initial_outputs, set.initial_outputs);
    }

    fn step(inputs: &[bool], outputs: Option<&[bool]>) -> Step {
        Step {
            inputs: inputs.to_vec(),
            outputs: outputs.map(<[bool]>::to_vec),
        }
    }

    #[test]
    fn segments_are_cut_only_where_no_alternative_is_lost() {
        let (t, f) = (true, false);
        let steps = [
            step(&[f], Some(&[t])), // 0: changes the output, next inputs differ: alternative
            step(&[t], None),       // 1: passive
            step(&[f], Some(&[f])), // 2: changes, alternative
            step(&[t], Some(&[f])), // 3: changes nothing
            step(&[f], Some(&[t])), // 4: changes, alternative
            step(&[t], None),       // 5: passive
        ];
        let cut = cuts(&steps, &[f]);
        // Before step l when step l - 1 has no alternative.
        assert_eq!(cut, vec![true, false, true, false, true, false, true]);
        // Corrections at 0 and 4: the cut nearest the middle, past step 1.
        assert_eq!(segments(&cut, &[0, 4]), vec![(0, 2, 1), (2, 6, 1)]);
        // Step 3 changes nothing: the segment of correction 2 ends after it.
        assert_eq!(
            segments(&cut, &[0, 2, 4]),
            vec![(0, 2, 1), (2, 4, 1), (4, 6, 1)]
        );
        assert_eq!(segments(&cut, &[2]), vec![(0, 6, 1)]);
        // Corrections on consecutive steps: the first one's alternative reads the second's
        // inputs, so no cut separates them.
        let steps = [
            step(&[f], Some(&[t])),
            step(&[t], Some(&[f])),
            step(&[f], None),
        ];
        let cut = cuts(&steps, &[f]);
        assert_eq!(segments(&cut, &[0, 1]), vec![(0, 3, 2)]);
    }

    #[test]
    fn windows_grow_around_the_correction_inside_the_segment() {
        let (t, f) = (true, false);
        // 100 steps; step 50 changes the output and the next inputs differ (an alternative,
        // no cut after it); the others are passive (a cut after each).
        let mut steps: Vec<Step> = (0..100).map(|k| step(&[k % 2 == 0], None)).collect();
        steps[50] = step(&[t], Some(&[t]));
        steps[51] = step(&[f], None);
        let set = ScenarioSet {
            inputs: vec!["a".into()],
            outputs: vec!["z".into()],
            initial_outputs: vec![f],
            scenarios: vec![crate::scenario::Scenario {
                origin: crate::scenario::Origin {
                    file: "t".into(),
                    line: 1,
                    rows: None,
                },
                steps,
            }],
        };
        let fixes = [Corrections {
            steps: vec![50],
            used: vec![true],
        }];
        let range = |g: &Group| (g.pieces[0].from, g.pieces[0].to, g.upper);
        let seg = |from, to, upper| Group::new(vec![Piece { d: 0, from, to }], upper);
        let ws: Vec<_> = windows(&set, &[0], &fixes, &seg(0, 100, 1));
        // 8, 16, 32 steps on either side (the correction reads step 51); 64 is the whole.
        assert_eq!(
            ws.iter().map(range).collect::<Vec<_>>(),
            vec![(42, 60, 1), (34, 68, 1), (18, 84, 1)]
        );
        // Clipped to the segment, and never the segment itself.
        let ws: Vec<_> = windows(&set, &[0], &fixes, &seg(45, 70, 1));
        assert_eq!(
            ws.iter().map(range).collect::<Vec<_>>(),
            vec![(45, 60, 1), (45, 68, 1)]
        );
        // A group that needs two corrections or more is bounded whole.
        assert!(windows(&set, &[0], &fixes, &seg(0, 100, 2)).is_empty());
    }

    #[test]
    fn a_short_segment_is_joined_with_the_one_before_it() {
        let seg = |from, to, lower| Group {
            pieces: vec![Piece { d: 0, from, to }],
            upper: 1,
            lower: Some(lower),
            known: Vec::new(),
        };
        let range = |gs: &[Group]| -> Vec<(usize, usize, usize, Option<usize>)> {
            gs.iter()
                .map(|g| (g.pieces[0].from, g.pieces[0].to, g.upper, g.lower))
                .collect()
        };
        // The middle one falls short: it takes the first one's steps, the last stays.
        let joined = join_short_segments(vec![seg(0, 5, 1), seg(5, 9, 0), seg(9, 12, 1)]);
        assert_eq!(range(&joined), vec![(0, 9, 2, None), (9, 12, 1, Some(1))]);
        // The first one has nothing before it: it takes the next one.
        let joined = join_short_segments(vec![seg(0, 5, 0), seg(5, 9, 1)]);
        assert_eq!(range(&joined), vec![(0, 9, 2, None)]);
    }

    #[test]
    fn the_first_part_holds_the_traces_that_show_new_kinds_of_step() {
        let (t, f) = (true, false);
        let trace = |steps: Vec<Step>| crate::scenario::Scenario {
            origin: crate::scenario::Origin {
                file: "t".into(),
                line: 1,
                rows: None,
            },
            steps,
        };
        let set = ScenarioSet {
            inputs: vec!["a".into()],
            outputs: vec!["z".into()],
            initial_outputs: vec![f],
            scenarios: vec![
                // 0: one kind, shown again by 2.
                trace(vec![step(&[f], None), step(&[f], None)]),
                // 1: one new kind beside 0's, a lone skewed step maybe.
                trace(vec![step(&[f], None), step(&[t], Some(&[f]))]),
                // 2: three kinds, 0's among them.
                trace(vec![
                    step(&[f], None),
                    step(&[t], Some(&[t])),
                    step(&[f], Some(&[f])),
                ]),
                // 3: two new kinds once 2 is in.
                trace(vec![
                    step(&[t], Some(&[t])),
                    step(&[t], None),
                    step(&[f], Some(&[t])),
                ]),
            ],
        };
        let distinct = [0, 1, 2, 3];
        assert_eq!(first_part(&set, &distinct, 100), vec![2, 3]);
        // The node budget ends it first.
        assert_eq!(first_part(&set, &distinct, 1), vec![2]);
    }

    /// Segment `from..to` of trace `d` with one correction, proven or not, and the window that
    /// proved its bound if one did.
    fn seg(
        d: usize,
        from: usize,
        to: usize,
        window: Option<(usize, usize)>,
        proven: bool,
    ) -> Group {
        Group {
            pieces: vec![Piece { d, from, to }],
            upper: 1,
            lower: Some(usize::from(proven)),
            known: window
                .map(|(from, to)| (vec![Piece { d, from, to }], 1))
                .into_iter()
                .collect(),
        }
    }

    #[test]
    fn a_short_segment_widens_over_what_its_neighbours_windows_leave() {
        let pieces = |gs: &[Group]| -> Vec<(usize, usize, usize, Option<usize>)> {
            gs.iter()
                .map(|g| (g.pieces[0].d, g.pieces[0].from, g.pieces[0].to, g.lower))
                .collect()
        };
        // Trace 0: proven by windows on both sides of the short segment, which takes 8..22
        // and is bounded anew. Trace 1: its neighbour was proven on its whole piece, nothing
        // to take. Trace 2: the group before it is another trace's.
        let mut groups = vec![
            seg(0, 0, 10, Some((4, 8)), true),
            seg(0, 10, 20, None, false),
            seg(0, 20, 30, Some((22, 26)), true),
            seg(1, 0, 10, Some((0, 10)), true),
            seg(1, 10, 20, None, false),
            seg(2, 0, 12, None, false),
        ];
        assert!(widen_short_segments(&mut groups));
        assert_eq!(
            pieces(&groups),
            vec![
                (0, 0, 8, Some(1)),
                (0, 8, 22, None),
                (0, 22, 30, Some(1)),
                (1, 0, 10, Some(1)),
                (1, 10, 20, Some(0)),
                (2, 0, 12, Some(0)),
            ]
        );
        // Nothing left to take the second time.
        assert!(!widen_short_segments(&mut groups));
    }

    #[test]
    fn only_traces_whose_segments_are_all_proven_lend_the_steps_before_their_first_window() {
        let mut groups = vec![
            // Trace 0: both segments proven, the first by a window from step 20.
            seg(0, 0, 50, Some((20, 40)), true),
            seg(0, 50, 100, Some((60, 80)), true),
            // Trace 1: its first window starts too early to leave anything worth lending.
            seg(1, 0, 50, Some((5, 30)), true),
            // Trace 2: its second segment falls short, so its prefix is bounded again.
            seg(2, 0, 60, Some((30, 50)), true),
            seg(2, 60, 90, None, false),
            // Trace 3: proven on the whole segment, no window: nothing is free.
            seg(3, 0, 40, None, true),
        ];
        groups[5].remember(None);
        let mut lent = HashSet::new();
        let free = free_prefixes(&mut groups, &mut lent);
        assert_eq!(
            free,
            vec![Piece {
                d: 0,
                from: 0,
                to: 20
            }]
        );
        // The lender keeps the steps its bound was proven on, so the groups stay disjoint.
        assert_eq!(
            groups[0].pieces,
            vec![Piece {
                d: 0,
                from: 20,
                to: 50
            }]
        );
        assert_eq!(
            groups[3].pieces,
            vec![Piece {
                d: 2,
                from: 0,
                to: 60
            }]
        );
        // Lent once only.
        assert!(free_prefixes(&mut groups, &mut lent).is_empty());
    }

    #[test]
    fn small_logs_are_encoded_whole() {
        let (set, injected) = noisy_logs(300, 5);
        let opts = one_candidate(injected);
        let mut parted = false;
        let r = synthesize(&set, &opts, Parts::default(), &mut |e| {
            parted |= matches!(e, Event::NoisyPart(_))
        })
        .unwrap();
        assert!(!parted);
        assert_eq!(r.stats.rounds, 0);
    }
}
