//! Synthesis from noisy traces: the SAT reconstruction paper, section IV (trace graph, alternative edges,
//! Algorithm 1).
//!
//! In: a [`ScenarioSet`] whose recordings may carry scan-cycle skew, laid out as a
//! [`TraceGraph`], and [`NoisyOptions`]. Out: a [`NoisySynthesis`]: the minimal sizes `N`
//! (states), `K` (largest number of distinct successor states), `R` (transitions) and the
//! distinct minimal machines in order of increasing number of corrected errors `ε`, each a
//! [`Candidate`] with its corrected, error-free traces.
//!
//! # Encoding
//! The colouring of the basic encoding ([`constraints`]) is reused on the graph's node layout:
//! colours, transition function `y`, algorithms, edge variables `t` and BFS symmetry breaking
//! do not depend on which label an edge carries. What does is written here, one function per
//! family:
//! - [`selection`]: `e[a]` (one per alternative `a`) chooses the alternative edge over the
//!   recorded one. The paper's `e_{u,v,g}` with ALO/AMO over the two edges of a pair is exactly
//!   one Boolean: `e[a]` for the alternative, `!e[a]` for the recorded edge.
//! - [`selected_edges`]: the paper's `c[u,n1] & c[v,n2] & e_{u,v,g} -> y[n1,g,n2]`, plus the
//!   propagation `c[u,n1] & e_{u,v,g} & y[n1,g,n2] -> c[v,n2]`.
//! - [`no_unselected_transitions`]: a transition exists only on an input where a *selected*
//!   edge leaves a node of its colour (the tree-exact model's rule; the paper makes uncovered
//!   transitions self-loops instead, ours do not exist, which the project's ECC semantics
//!   writes as "nothing fires").
//! - the cardinality constraint (3), `card({e[a]}, ε)`, is a [`Totalizer`] over the `e[a]`.
//!
//! # Algorithm 1
//! Least `N`, then least `K`, then least `R` (`R` counts the ECC's transitions: distinct
//! `(state, successor)` pairs, the project's `T`; each gets one minimized guard), all with
//! `ε` free up to `--max-errors`. Then, with `N, K, R` fixed, `ε = 0, 1, ...`: every model is
//! decoded, its edge choice blocked (`OR_a e[a] != e_j[a]`), and the search repeats at the same
//! `ε` until it is unsatisfiable. Each model at bound `ε` uses exactly `ε` alternatives (all
//! choices with fewer are blocked before the bound rises), so candidates come in
//! non-decreasing order of `ε`. Choices that give a machine already found are blocked and
//! skipped, so the candidates are distinct machines. The first `ε` is the least one, found by
//! descending from a model's error count rather than climbing from 0: the same candidates, but
//! one UNSAT proof instead of one per value below it (hundreds on long logs).
//!
//! Every machine is replayed through the simulator on its corrected traces before it is
//! returned; a mismatch is reported as [`SatError::Bug`].

use super::card::Totalizer;
use super::constraints;
use super::decode::Structure;
use super::guards;
use super::solver::{Model, Solver};
use super::vars::Vars;
use super::SatError;
use crate::deadline::Deadline;
use crate::ecc::{AlgorithmKind, Ecc, Size};
use crate::sat::step::{Bound, Progress, Step};
use crate::scenario::trace_graph::TraceGraph;
use crate::scenario::tree::{InputVec, NodeId};
use crate::scenario::ScenarioSet;
use std::time::{Duration, Instant};
use varisat::{ExtendFormula, Lit};

/// Settings of a noisy synthesis run.
#[derive(Debug, Clone)]
pub struct NoisyOptions {
    /// The algorithm form of every state: `Tri` (`{0, 1, x}` per output) or fbSAT's `Binary`.
    pub algorithms: AlgorithmKind,
    /// Give up above this many states.
    pub max_states: usize,
    /// At most this many alternative edges per machine (`None`: as many as there are).
    pub max_errors: Option<usize>,
    /// Stop after this many distinct candidates.
    pub enumerate: usize,
    /// Stop enumerating after this many solver calls (edge choices that repeat a machine
    /// also cost calls).
    pub max_calls: usize,
    /// Time for guard minimization of one candidate.
    pub guard_budget: Duration,
    /// `C, K, T` known not to be undercut (proven on a part of the log): the search starts
    /// there instead of proving every smaller size again. Sound only for a part of these
    /// recordings, as [`crate::pipeline::lazy_noisy`] uses it.
    pub at_least: Option<(usize, usize, usize)>,
    /// Where every solver call stops ([`Solver::until`]); the guard budget ends there too.
    pub deadline: Deadline,
}

impl Default for NoisyOptions {
    fn default() -> Self {
        NoisyOptions {
            algorithms: AlgorithmKind::Tri,
            max_states: 32,
            max_errors: None,
            enumerate: 5,
            max_calls: 200,
            guard_budget: Duration::from_secs(10),
            at_least: None,
            deadline: Deadline::NONE,
        }
    }
}

/// One minimal machine with the edge choice that gave it.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// The machine, replayed through the simulator on its corrected traces.
    pub ecc: Ecc,
    /// Its size `C, K, T, N`: `C, K, T` are Algorithm 1's least `N, K, R`.
    pub(crate) size: Size,
    /// Number of alternative edges used: errors corrected in the traces.
    pub errors: usize,
    /// Per alternative of the graph: used or not.
    pub(crate) used: Vec<bool>,
    /// The traces with the chosen edges; the machine reproduces them.
    pub corrected: ScenarioSet,
    /// Whether every guard's literal count is proven minimal.
    pub(crate) guards_exact: bool,
}

/// What the caller wants after seeing a candidate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flow {
    /// Look for the next candidate.
    Continue,
    /// End the enumeration with the candidates so far (`exhausted` is false).
    Stop,
}

/// Figures of a run.
#[derive(Debug, Clone, Default, serde::Serialize, schemars::JsonSchema)]
pub struct NoisyStats {
    /// Nodes of the trace graph.
    pub graph_nodes: usize,
    /// Distinct scenarios (one chain each) in the graph.
    pub distinct_traces: usize,
    /// Alternative edges: places where a scan-cycle glitch may be corrected.
    pub(crate) alternatives: usize,
    /// Distinct input vectors in the graph.
    pub(crate) distinct_inputs: usize,
    /// Variables of the encoding as built, summed over every window of states tried.
    pub variables: usize,
    /// Clauses of the encoding as built (blocking clauses of the enumeration not counted).
    pub clauses: usize,
    /// SAT calls made, minimization and enumeration.
    pub(crate) solver_calls: usize,
    /// Rounds of synthesis in parts (0: the whole log encoded at once).
    pub rounds: usize,
    /// Graph nodes of the last part encoded (in parts; 0 otherwise).
    pub encoded_nodes: usize,
    /// Seconds to find the least C, K and T (the paper's `N`, `K`, `R`).
    pub minimize_seconds: f64,
    /// Seconds spent enumerating (SAT calls, decoding, guards, replay, caller's checks).
    pub enumerate_seconds: f64,
}

/// The result of Algorithm 1.
#[derive(Debug, Clone)]
pub struct NoisySynthesis {
    /// Least number of states.
    pub n: usize,
    /// Least largest number of distinct successors of one state, given `n`.
    pub k: usize,
    /// Least number of transitions, given `n` and `k`.
    pub r: usize,
    /// Distinct minimal machines, in non-decreasing order of errors.
    pub candidates: Vec<Candidate>,
    /// Whether enumeration ran until no further choice exists within the error bound
    /// (false: stopped by `enumerate`, `max_calls` or the caller).
    pub(crate) exhausted: bool,
    /// Figures of the run (graph, encoding size, solver calls, time).
    pub stats: NoisyStats,
}

/// The selection variables `e[a]`, one per alternative of the graph.
pub(crate) fn selection(f: &mut impl ExtendFormula, graph: &TraceGraph) -> Vec<Lit> {
    graph.alternatives.iter().map(|_| f.new_lit()).collect()
}

/// The candidate edges into node `w`: `(label, condition)` where the condition literal must
/// hold for the edge to be the selected one (`None`: the recorded edge, always selected).
fn edges_into(graph: &TraceGraph, e: &[Lit], w: NodeId) -> Vec<(InputVec, Option<Lit>)> {
    let (_, recorded) = graph.parent(w);
    match graph.alternative_of.get(&w) {
        None => vec![(recorded, None)],
        Some(&a) => vec![
            (recorded, Some(!e[a])),
            (graph.alternatives[a].input, Some(e[a])),
        ],
    }
}

/// Selected active edges become transitions (the SAT reconstruction paper, IV.B), in a
/// compact form of the paper's `c[u,n1] & c[v,n2] & e_{u,v,g} -> y[n1,g,n2]`:
/// - `c[p,q] & sel -> !y[q,g,⊥]` (something fires), and
/// - `c[p,q] & sel & y[q,g,q'] -> c[w,q']` (and it enters the child's colour),
///
/// where `sel` is `!e[a]` for the recorded edge, `e[a]` for the alternative, and true for an
/// edge without alternative. Together with "exactly one target per `(q, g)`" and "exactly one
/// colour per node" they imply the paper's clause: the target is not `⊥`, and any target other
/// than `c[w]`'s colour would give `w` a second colour. `C` + `C²` clauses per edge instead of
/// `2·C²`, which matters on logs of 10^5 samples.
pub(crate) fn selected_edges(f: &mut impl ExtendFormula, v: &Vars, graph: &TraceGraph, e: &[Lit]) {
    for w in 1..graph.tree.nodes.len() {
        let w = NodeId(w);
        let (p, _) = graph.parent(w);
        for (g, sel) in edges_into(graph, e, w) {
            let not_sel: Vec<Lit> = sel.map(|s| !s).into_iter().collect();
            for q in 0..v.c_max {
                let mut fires = vec![!v.color(p, q), !v.y(q, g, v.none())];
                fires.extend(&not_sel);
                f.add_clause(&fires);
                for q2 in 0..v.c_max {
                    let mut prop = vec![!v.color(p, q), !v.y(q, g, q2), v.color(w, q2)];
                    prop.extend(&not_sel);
                    f.add_clause(&prop);
                }
            }
        }
    }
}

/// Transitions only where a selected edge needs them:
/// `y[q,g,⊥] | OR_{edges (p,w) labelled g} s[p,w,q]`, with `s = c[p,q]` for an edge without
/// alternative and, for one with, a fresh `s -> c[p,q]`, `s -> sel`.
pub(crate) fn no_unselected_transitions(
    f: &mut impl ExtendFormula,
    v: &Vars,
    graph: &TraceGraph,
    e: &[Lit],
) {
    // Per input: (source node, selection condition) of every candidate edge, deduplicated.
    let mut sources: Vec<Vec<(NodeId, Option<Lit>)>> = vec![Vec::new(); v.inputs];
    for w in 1..graph.tree.nodes.len() {
        let w = NodeId(w);
        let (p, _) = graph.parent(w);
        for (g, sel) in edges_into(graph, e, w) {
            if !sources[g.0].contains(&(p, sel)) {
                sources[g.0].push((p, sel));
            }
        }
    }
    for q in 0..v.c_max {
        for (g, srcs) in sources.iter().enumerate() {
            let mut clause = vec![v.y(q, InputVec(g), v.none())];
            for &(p, sel) in srcs {
                match sel {
                    None => clause.push(v.color(p, q)),
                    Some(sel) => {
                        let s = f.new_lit();
                        f.add_clause(&[!s, v.color(p, q)]);
                        f.add_clause(&[!s, sel]);
                        clause.push(s);
                    }
                }
            }
            f.add_clause(&clause);
        }
    }
}

/// Every family of the noisy encoding for up to `v.c_max` states; returns the selection
/// variables. Edge-definition tails are closed with unit clauses (no inputs are added later).
pub(crate) fn encode(
    f: &mut impl ExtendFormula,
    v: &Vars,
    graph: &TraceGraph,
    kind: AlgorithmKind,
) -> Vec<Lit> {
    let tree = &graph.tree;
    constraints::ecc_coloring(f, v, tree, false);
    let e = selection(f, graph);
    selected_edges(f, v, graph, &e);
    constraints::passive_marks(f, tree, &[v.coloring()], constraints::idle(v));
    no_unselected_transitions(f, v, graph, &e);
    // Outputs along an edge do not depend on its label, so the shared family applies as is.
    constraints::algorithms(f, tree, &[v.coloring()], kind);
    let tails: Vec<Lit> = (0..v.c_max * v.c_max).map(|_| f.new_lit()).collect();
    for &t in &tails {
        f.add_clause(&[!t]);
    }
    constraints::ecc_edges_and_bfs(f, v, &tails);
    e
}

/// The solver with the noisy encoding for up to `c_max` states and its counters.
struct NoisyEncoding {
    solver: Solver,
    vars: Vars,
    e: Vec<Lit>,
    total_t: Totalizer,
    degree: Vec<Totalizer>,
    errors: Totalizer,
}

impl NoisyEncoding {
    fn new(
        graph: &TraceGraph,
        c_max: usize,
        kind: AlgorithmKind,
        max_errors: Option<usize>,
        stats: &mut NoisyStats,
        deadline: Deadline,
    ) -> Self {
        let mut solver = Solver::until(deadline);
        let sink = &mut solver;
        let vars = Vars::new(sink, &graph.tree, c_max, None);
        let e = encode(sink, &vars, graph, kind);
        let total_t = Totalizer::new(sink, vars.all_t(), c_max * c_max);
        let degree = (0..c_max)
            .map(|q| Totalizer::new(sink, vars.t_row(q), c_max))
            .collect();
        // The totalizer costs O(n·width) clauses: count only as far as the bound needs.
        let width = max_errors.map_or(e.len(), |m| (m + 1).min(e.len()));
        let errors = Totalizer::new(sink, &e, width);
        stats.variables += solver.stats().variables;
        stats.clauses += solver.stats().clauses;
        NoisyEncoding {
            solver,
            vars,
            e,
            total_t,
            degree,
            errors,
        }
    }

    /// "At most `max_errors` alternatives" (`None`: no bound).
    fn error_bound(&self, max_errors: Option<usize>) -> Option<Lit> {
        max_errors.and_then(|m| self.errors.at_most(m))
    }

    /// Step 2 of Algorithm 1: the least `K` under `base` from `k` up to `n`, ascending as
    /// Algorithm 1 does (`K = N` always holds).
    fn least_k(&mut self, base: &[Lit], n: usize, mut k: usize) -> usize {
        while k < n
            && self
                .solve(&[base.to_vec(), self.k_at_most(k)].concat())
                .is_none()
        {
            k += 1;
        }
        k
    }

    /// Step 3 of Algorithm 1: the least `R` under `base`, descending from a model's count and
    /// stopping at the proven `t_floor`, which is tried first.
    fn least_r(
        &mut self,
        base: &[Lit],
        t_floor: usize,
        graph: &TraceGraph,
        kind: AlgorithmKind,
        progress: Progress<'_>,
    ) -> Result<usize, SatError> {
        let at_floor = (self.total_t.at_most(t_floor))
            .filter(|_| t_floor > 0)
            .and_then(|b| self.solve(&[base.to_vec(), vec![b]].concat()));
        let first = match at_floor {
            Some(m) => m,
            None => self
                .solve(base)
                .ok_or_else(|| SatError::Bug("N, K satisfiable, then not".into()))?,
        };
        let r = self.decode(&first, graph, kind).transition_count();
        let (vars, total_t) = (&self.vars, &self.total_t);
        Ok(self.solver.descend(
            base,
            r,
            t_floor,
            |b| total_t.at_most(b),
            |b| {
                progress(Step::Trying {
                    bound: Bound::T,
                    value: b,
                })
            },
            |m| decode(&m, vars, graph, kind).transition_count(),
        ))
    }

    fn k_at_most(&self, k: usize) -> Vec<Lit> {
        self.degree.iter().filter_map(|d| d.at_most(k)).collect()
    }

    fn solve(&mut self, assumptions: &[Lit]) -> Option<Model> {
        self.solver.solve(assumptions)
    }

    fn decode(&self, model: &Model, graph: &TraceGraph, kind: AlgorithmKind) -> Structure {
        decode(model, &self.vars, graph, kind)
    }

    /// Forbids the edge choice of `used` from now on.
    fn block(&mut self, used: &[bool]) {
        let clause: Vec<Lit> = self
            .e
            .iter()
            .zip(used)
            .map(|(&e, &u)| if u { !e } else { e })
            .collect();
        self.solver.add_clause(&clause);
    }
}

/// The structure of a model of the noisy encoding (on the graph's node layout).
fn decode(model: &Model, vars: &Vars, graph: &TraceGraph, kind: AlgorithmKind) -> Structure {
    let tree = &graph.tree;
    Structure::decode(model, vars, tree, kind, &tree.input_vectors, &[], false)
}

/// The SAT reconstruction paper's Algorithm 1 on `set`. `accept` sees every candidate as it is found (e.g. to
/// check it with a model checker) and may stop the enumeration; `progress` receives one line
/// per step of the search.
pub fn synthesize_noisy(
    set: &ScenarioSet,
    opts: &NoisyOptions,
    progress: Progress<'_>,
    accept: &mut dyn FnMut(&Candidate) -> Flow,
) -> Result<NoisySynthesis, SatError> {
    let t0 = Instant::now();
    let graph = TraceGraph::build(set);
    let mut stats = NoisyStats {
        graph_nodes: graph.tree.nodes.len(),
        distinct_traces: graph.chains.len(),
        alternatives: graph.alternatives.len(),
        distinct_inputs: graph.tree.input_vectors.len(),
        ..NoisyStats::default()
    };
    progress(Step::TraceGraph {
        nodes: stats.graph_nodes,
        traces: stats.distinct_traces,
        alternatives: stats.alternatives,
        inputs: stats.distinct_inputs,
    });
    let (c0, k0, t0_) = opts.at_least.unwrap_or((1, 1, 0));
    let (n, mut enc) = least_n(&graph, opts, c0, &mut stats, progress)?;
    let mut base: Vec<Lit> = enc.error_bound(opts.max_errors).into_iter().collect();
    progress(Step::Minimal {
        bound: Bound::C,
        value: n,
    });
    let k = enc.least_k(&base, n, if n == c0 { k0.max(1) } else { 1 });
    base.extend(enc.k_at_most(k));
    progress(Step::Minimal {
        bound: Bound::K,
        value: k,
    });
    // With a proven floor at these N and K, the floor is tried first: on a grown part it
    // usually still holds.
    let t_floor = if (n, k) == (c0, k0) { t0_ } else { 0 };
    let r = enc.least_r(&base, t_floor, &graph, opts.algorithms, progress)?;
    base.extend(enc.total_t.at_most(r));
    progress(Step::Minimal {
        bound: Bound::T,
        value: r,
    });
    stats.minimize_seconds = t0.elapsed().as_secs_f64();
    let t1 = Instant::now();
    let mut found = Enumeration {
        set,
        graph: &graph,
        opts,
        enc: &mut enc,
        base: &base,
        candidates: Vec::new(),
    };
    let exhausted = found.run(progress, accept)?;
    let candidates = found.candidates;
    stats.solver_calls += enc.solver.stats().calls;
    stats.enumerate_seconds = t1.elapsed().as_secs_f64();
    Ok(NoisySynthesis {
        n,
        k,
        r,
        candidates,
        exhausted,
        stats,
    })
}

/// Step 1 of Algorithm 1: the least `N` from `c0` up, and the encoding for exactly `N`
/// states with a model there. One encoding per `N`, for exactly `N` states (the SAT
/// reconstruction paper's `findModel(T, N)`): an encoding with spare states leaves the solver
/// symmetric choices that slow down every later call far more than re-encoding costs.
fn least_n(
    graph: &TraceGraph,
    opts: &NoisyOptions,
    c0: usize,
    stats: &mut NoisyStats,
    progress: Progress<'_>,
) -> Result<(usize, NoisyEncoding), SatError> {
    let mut n = c0.max(1);
    loop {
        if opts.deadline.passed() {
            return Err(SatError::Stopped);
        }
        if n > opts.max_states {
            return Err(match opts.max_errors {
                Some(max_errors) => SatError::TooFewErrors {
                    max_states: opts.max_states,
                    max_errors,
                },
                None => SatError::TooManyStates {
                    max_states: opts.max_states,
                },
            });
        }
        progress(Step::Trying {
            bound: Bound::C,
            value: n,
        });
        let mut enc = NoisyEncoding::new(
            graph,
            n,
            opts.algorithms,
            opts.max_errors,
            stats,
            opts.deadline,
        );
        let assume: Vec<Lit> = enc.error_bound(opts.max_errors).into_iter().collect();
        if enc.solve(&assume).is_some() {
            return Ok((n, enc));
        }
        stats.solver_calls += enc.solver.stats().calls;
        n += 1;
    }
}

/// Step 4 of Algorithm 1: every distinct minimal machine within the sizes `base` fixes, by
/// increasing ε, until `enumerate` candidates, `max_calls` solver calls, the error bound, or
/// the caller says stop.
struct Enumeration<'a> {
    set: &'a ScenarioSet,
    graph: &'a TraceGraph,
    opts: &'a NoisyOptions,
    enc: &'a mut NoisyEncoding,
    /// The least `N`, `K` and `R` (and the error bound) as assumptions.
    base: &'a [Lit],
    /// The candidates found, in order.
    candidates: Vec<Candidate>,
}

impl Enumeration<'_> {
    /// Enumerates into `candidates`; returns whether every choice within the error bound was
    /// seen (`exhausted`). Each model at bound `ε` uses exactly `ε` alternatives: every choice
    /// with fewer is blocked before the bound rises.
    fn run(
        &mut self,
        progress: Progress<'_>,
        accept: &mut dyn FnMut(&Candidate) -> Flow,
    ) -> Result<bool, SatError> {
        let alternatives = self.graph.alternatives.len();
        let eps_max = (self.opts.max_errors)
            .unwrap_or(alternatives)
            .min(alternatives);
        let (mut eps, last) = self.least_errors()?;
        // The descent's last model is the first candidate: found again after the UNSAT proof
        // below it, it would cost a call as long as the proof.
        let mut first = Some(last);
        progress(Step::Minimal {
            bound: Bound::Errors,
            value: eps,
        });
        let mut calls = 0;
        loop {
            if self.candidates.len() >= self.opts.enumerate || calls >= self.opts.max_calls {
                return Ok(false);
            }
            if eps > eps_max {
                return Ok(true);
            }
            calls += 1;
            let assume: Vec<Lit> = (self.base.iter().copied())
                .chain(self.enc.errors.at_most(eps))
                .collect();
            let Some(model) = first.take().or_else(|| self.enc.solve(&assume)) else {
                eps += 1;
                continue;
            };
            let Some(candidate) = self.candidate(&model, eps)? else {
                continue;
            };
            progress(Step::Candidate {
                number: self.candidates.len() + 1,
                errors: candidate.errors,
                size: candidate.size,
            });
            let flow = accept(&candidate);
            self.candidates.push(candidate);
            if flow == Flow::Stop {
                return Ok(false);
            }
        }
    }

    /// The least ε and a model there. Found by descending from a model's error count (SAT
    /// calls, one UNSAT at the end) instead of climbing from 0 through one UNSAT proof per
    /// value: the same candidates, since no choice with fewer errors exists.
    fn least_errors(&mut self) -> Result<(usize, Model), SatError> {
        let Some(mut last) = self.enc.solve(self.base) else {
            return Err(SatError::Bug("N, K, R satisfiable, then not".into()));
        };
        let (e, errors) = (&self.enc.e, &self.enc.errors);
        let eps = self.enc.solver.descend(
            self.base,
            last.count(e),
            0,
            |b| errors.at_most(b),
            |_| {},
            |m| {
                let n = m.count(e);
                last = m;
                n
            },
        );
        Ok((eps, last))
    }

    /// The machine of `model` (a model at bound `eps`), its edge choice blocked from now on:
    /// `None` when it repeats a machine already found. Checked: well formed, replaying its
    /// corrected traces, and using exactly `eps` alternatives.
    fn candidate(&mut self, model: &Model, eps: usize) -> Result<Option<Candidate>, SatError> {
        let (set, graph) = (self.set, self.graph);
        let used: Vec<bool> = self.enc.e.iter().map(|&l| model.value(l)).collect();
        self.enc.block(&used);
        let structure = self.enc.decode(model, graph, self.opts.algorithms);
        let deadline = (self.opts.deadline).cap(Instant::now() + self.opts.guard_budget);
        let (states, guards_exact) = guards::all_states(&structure, &graph.tree, deadline);
        let ecc = Ecc {
            inputs: set.inputs.clone(),
            outputs: set.outputs.clone(),
            initial_outputs: set.initial_outputs.clone(),
            states,
        };
        if self.candidates.iter().any(|c| c.ecc == ecc) {
            return Ok(None);
        }
        ecc.validate().map_err(SatError::Bug)?;
        let corrected = graph.corrected(set, &used);
        corrected.check(&ecc).map_err(|m| {
            SatError::Bug(format!(
                "a noisy candidate does not replay its corrected traces: {m}"
            ))
        })?;
        let errors = used.iter().filter(|&&u| u).count();
        if errors != eps {
            return Err(SatError::Bug(format!(
                "a model at bound ε = {eps} uses {errors} alternatives"
            )));
        }
        Ok(Some(Candidate {
            size: ecc.size(),
            ecc,
            errors,
            used,
            corrected,
            guards_exact,
        }))
    }
}

/// The least number of alternative edges with which some machine of at most `c` states, at
/// most `k` successors per state and at most `t` transitions reproduces the noisy `set`, when
/// one with at most `upper` is known to exist (a machine within those sizes replays `set`
/// with `upper` corrections; not checked here). A lower bound, for a part of a log, on the corrections of every
/// machine of those sizes: [`crate::pipeline::noisy`] sums them over disjoint parts to prove
/// the least `ε` of a whole log without encoding it whole.
pub(crate) fn least_errors_within(
    set: &ScenarioSet,
    kind: AlgorithmKind,
    sizes: (usize, usize, usize),
    upper: usize,
) -> Result<usize, SatError> {
    least_errors_knowing(set, kind, sizes, upper, &[], Deadline::NONE)
}

/// Steps of a scenario set: `(scenario, steps)`.
pub(crate) type Stretch = (usize, std::ops::Range<usize>);

/// [`least_errors_within`], told bounds already proven on disjoint stretches of `set`: every
/// machine within the sizes needs at least `n` corrections on the stretches of each
/// `(stretches, n)` of `known`. Implied constraints, so the answer is the same; they make the
/// proof short when the stretches' bounds add up to one less than `upper`: then every step
/// outside them is taken as recorded, and the proof is about which of a few corrections to
/// make, not about every step of the set. The solver stops at `deadline` (the answer then
/// means nothing).
pub(crate) fn least_errors_knowing(
    set: &ScenarioSet,
    kind: AlgorithmKind,
    (c, k, t): (usize, usize, usize),
    upper: usize,
    known: &[(Vec<Stretch>, usize)],
    deadline: Deadline,
) -> Result<usize, SatError> {
    if upper == 0 {
        return Ok(0);
    }
    let graph = TraceGraph::build(set);
    let stats = &mut NoisyStats::default();
    let mut enc = NoisyEncoding::new(&graph, c, kind, Some(upper), stats, deadline);
    let chain_of = |s: usize| graph.chains.iter().find(|ch| ch.scenarios.contains(&s));
    let mut inside = vec![false; enc.e.len()];
    for (stretches, n) in known {
        let alternatives: Vec<usize> = stretches
            .iter()
            .filter_map(|(s, steps)| Some((chain_of(*s)?, steps)))
            .flat_map(|(ch, steps)| ch.nodes[steps.clone()].iter().flatten())
            .filter_map(|node| graph.alternative_of.get(node).copied())
            .collect();
        for &a in &alternatives {
            inside[a] = true;
        }
        if *n == 1 {
            let clause: Vec<Lit> = alternatives.iter().map(|&a| enc.e[a]).collect();
            enc.solver.add_clause(&clause);
        }
    }
    let tight = known.iter().map(|(_, n)| n).sum::<usize>() + 1 >= upper;
    let outside: Vec<Lit> = if tight {
        (enc.e.iter().zip(&inside))
            .filter(|(_, &i)| !i)
            .map(|(&e, _)| !e)
            .collect()
    } else {
        Vec::new()
    };
    let base: Vec<Lit> = enc
        .k_at_most(k)
        .into_iter()
        .chain(enc.total_t.at_most(t))
        .chain(outside)
        .collect();
    // The machine's count is usually the least: one UNSAT call below it decides.
    let below: Vec<Lit> = base
        .iter()
        .copied()
        .chain(enc.errors.at_most(upper - 1))
        .collect();
    let Some(m) = enc.solve(&below) else {
        return Ok(upper);
    };
    let (e, errors) = (&enc.e, &enc.errors);
    let found = m.count(e);
    Ok(enc.solver.descend(
        &base,
        found,
        0,
        |b| errors.at_most(b),
        |_| {},
        |m| m.count(e),
    ))
}

/// Whether some machine with at most `n` states (and at most `r` transitions) reproduces the
/// noisy traces with at most `eps` alternative edges. For tests of known minima.
pub(crate) fn satisfiable(
    set: &ScenarioSet,
    kind: AlgorithmKind,
    n: usize,
    r: Option<usize>,
    eps: usize,
) -> bool {
    if n == 0 {
        return false;
    }
    let graph = TraceGraph::build(set);
    let stats = &mut NoisyStats::default();
    let mut enc = NoisyEncoding::new(&graph, n, kind, Some(eps), stats, Deadline::NONE);
    let assume: Vec<Lit> = r
        .and_then(|r| enc.total_t.at_most(r))
        .into_iter()
        .chain(enc.errors.at_most(eps))
        .collect();
    enc.solve(&assume).is_some()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::fbsat;
    use std::path::Path;

    /// `z := a` over inputs `a b`. Trace 1 is clean; trace 2 recorded the rise of `z` one
    /// sample early, on `01` instead of `11`, which contradicts trace 1's passive `01` at the
    /// start. One corrected error and two states explain both.
    const SKEWED: &str = "2\n\
        in=REQ[00]; in=REQ[01]; in=REQ[10]; out=CNF[1]; in=REQ[00]; out=CNF[0];\n\
        in=REQ[01]; out=CNF[1]; in=REQ[11]; in=REQ[10]; in=REQ[00]; out=CNF[0];\n";

    fn set(text: &str) -> ScenarioSet {
        fbsat::parse(Path::new("s.txt"), text, None, None).unwrap()
    }

    fn run(set: &ScenarioSet, opts: &NoisyOptions) -> NoisySynthesis {
        synthesize_noisy(set, opts, &mut |_| {}, &mut |_| Flow::Continue).unwrap()
    }

    #[test]
    fn known_minimum_sat_at_k_unsat_below() {
        let s = set(SKEWED);
        let kind = AlgorithmKind::Tri;
        // No error allowed: the root answers 01 both ways, no machine at all.
        assert!(!satisfiable(&s, kind, 4, None, 0));
        // One error: two states, two transitions, and not one state or one transition.
        assert!(satisfiable(&s, kind, 2, Some(2), 1));
        assert!(!satisfiable(&s, kind, 1, None, 1));
        assert!(!satisfiable(&s, kind, 2, Some(1), 1));
    }

    #[test]
    fn algorithm_1_finds_the_correction() {
        let s = set(SKEWED);
        let r = run(&s, &NoisyOptions::default());
        assert_eq!((r.n, r.k, r.r), (2, 1, 2));
        let first = &r.candidates[0];
        assert_eq!(first.errors, 1);
        // The corrected trace 2 starts on 11, the input that really raised z.
        assert_eq!(
            first.corrected.scenarios[1].steps[0].inputs,
            vec![true, true]
        );
        assert_eq!(first.corrected.scenarios[0], s.scenarios[0]);
        // Max errors 0 leaves nothing.
        let none = synthesize_noisy(
            &s,
            &NoisyOptions {
                max_states: 4,
                max_errors: Some(0),
                ..NoisyOptions::default()
            },
            &mut |_| {},
            &mut |_| Flow::Continue,
        );
        assert!(
            matches!(none, Err(SatError::TooFewErrors { max_errors: 0, .. })),
            "{none:?}"
        );
    }

    #[test]
    fn a_fixed_machine_explains_each_trace_with_its_least_corrections() {
        use crate::scenario::trace_graph::least_corrections;
        let s = set(SKEWED);
        let r = run(&s, &NoisyOptions::default());
        let first = &r.candidates[0];
        let fixes: Vec<_> = s
            .scenarios
            .iter()
            .map(|sc| least_corrections(&first.ecc, &s.initial_outputs, &sc.steps).unwrap())
            .collect();
        // Trace 1 as recorded; trace 2 with its first step on 11.
        assert_eq!(fixes[0].steps, Vec::<usize>::new());
        assert_eq!(fixes[1].steps, vec![0]);
        // One entry per alternative, in the graph's order: the candidate's edge choice.
        let used: Vec<bool> = fixes.iter().flat_map(|f| f.used.clone()).collect();
        assert_eq!(used, first.used);
        // Outputs that rise on 00, where the machine stays idle and no alternative exists.
        let bad = set("1\nin=REQ[00]; out=CNF[1];\n");
        assert_eq!(
            least_corrections(&first.ecc, &bad.initial_outputs, &bad.scenarios[0].steps),
            None
        );
    }

    #[test]
    fn the_least_errors_within_sizes_bound_every_machine_of_those_sizes() {
        let s = set(SKEWED);
        let kind = AlgorithmKind::Tri;
        // No machine explains both traces without a correction, whatever its size.
        assert_eq!(least_errors_within(&s, kind, (2, 1, 2), 1).unwrap(), 1);
        assert_eq!(least_errors_within(&s, kind, (4, 4, 16), 1).unwrap(), 1);
        // Trace 1 alone needs none: the bound comes down to 0 from a loose upper bound.
        let one = ScenarioSet {
            scenarios: vec![s.scenarios[0].clone()],
            ..s.clone()
        };
        assert_eq!(least_errors_within(&one, kind, (2, 1, 2), 1).unwrap(), 0);
    }

    #[test]
    fn clean_traces_need_no_correction_and_match_exact_synthesis() {
        let s = set(
            "2\nin=REQ[00]; in=REQ[10]; out=CNF[1]; in=REQ[00]; out=CNF[0];\n\
                     in=REQ[01]; in=REQ[11]; out=CNF[1]; in=REQ[01]; out=CNF[0];\n",
        );
        let r = run(&s, &NoisyOptions::default());
        assert_eq!(r.candidates[0].errors, 0);
        assert_eq!(r.candidates[0].corrected, s);
        let tree = crate::scenario::tree::ScenarioTree::build(&s).unwrap();
        let exact =
            super::super::synthesize(&s, &tree, &super::super::Options::default(), &mut |_| {})
                .unwrap();
        assert_eq!(r.n, exact.size.c);
        assert_eq!(r.r, exact.size.t);
    }

    /// `z` rises after `01` and the next sample is `10`: either input may have raised it;
    /// `00` brings it down again.
    /// Both readings give a two-state machine (`b` or `a` as the guard), found in ε order.
    #[test]
    fn enumeration_is_ordered_by_errors_and_distinct() {
        let s = set("1\nin=REQ[00]; in=REQ[01]; out=CNF[1]; in=REQ[10]; in=REQ[00]; out=CNF[0];\n");
        let r = run(
            &s,
            &NoisyOptions {
                enumerate: 20,
                ..NoisyOptions::default()
            },
        );
        assert!(r.exhausted);
        let errors: Vec<usize> = r.candidates.iter().map(|c| c.errors).collect();
        assert_eq!(errors, vec![0, 1]);
        let guards: Vec<String> = r
            .candidates
            .iter()
            .map(|c| format!("{:?}", c.ecc.states[0].transitions[0].guard))
            .collect();
        assert_ne!(guards[0], guards[1]);
        for (i, a) in r.candidates.iter().enumerate() {
            assert_eq!(a.size.c, r.n);
            assert_eq!(a.corrected.check(&a.ecc), Ok(()));
            for b in &r.candidates[i + 1..] {
                assert_ne!(a.ecc, b.ecc);
            }
        }
    }
}
