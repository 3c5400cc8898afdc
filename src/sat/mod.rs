//! Exact synthesis of a minimal ECC from execution scenarios with SAT (varisat).
//!
//! In: a [`ScenarioTree`] (and the [`ScenarioSet`] it came from, for the final replay) and
//! [`Options`]. Out: a [`Synthesis`]: the ECC, its size `C, K, T, N`, and figures.
//!
//! The procedure is seed 000's Algorithm 1 on seed 004's basic model:
//! 1. least number of states `C`;
//! 2. optionally, least largest out-degree `K`;
//! 3. least number of transitions `T` (edges `q -> q'`, each with one guard);
//! 4. for that structure, guards with the least total literal count `N` ([`guards`]).
//!
//! Steps 1-3 run on *one* incremental solver: the encoding is built for up to `C_max` states
//! with "state in use" variables, and every bound (states, `K`, `T`) is a solver assumption on
//! those variables or on totalizer outputs ([`card`]). Only if every `C <= C_max` is
//! unsatisfiable is the encoding rebuilt for a doubled `C_max`.
//!
//! Every machine is replayed through the simulator on every scenario before it is returned;
//! a mismatch is reported as [`SatError::Bug`].

pub mod card;
pub mod constraints;
pub mod decode;
pub mod guards;
pub mod vars;

use crate::ecc::{AlgorithmKind, Ecc, Size, State};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use card::Totalizer;
use decode::{Model, Structure};
use std::time::{Duration, Instant};
use varisat::{ExtendFormula, Lit, Solver, Var};
use vars::Vars;

/// Settings of a synthesis run.
#[derive(Debug, Clone)]
pub struct Options {
    pub algorithms: AlgorithmKind,
    /// Minimize the largest out-degree `K` before `T`.
    pub minimize_k: bool,
    /// Give up above this many states.
    pub max_states: usize,
    /// State 0 is a start state no transition enters (fbSAT's convention, for comparison).
    pub start_state: bool,
    /// Time for guard minimization, over all states; past it the best guards so far are kept.
    pub guard_budget: Duration,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            algorithms: AlgorithmKind::Tri,
            minimize_k: false,
            max_states: 32,
            start_state: false,
            guard_budget: Duration::from_secs(10),
        }
    }
}

/// The result of a synthesis run.
#[derive(Debug, Clone)]
pub struct Synthesis {
    pub ecc: Ecc,
    pub size: Size,
    /// Whether `N` is proven minimal for the structure (guard search finished in budget).
    pub guards_exact: bool,
    pub stats: Stats,
}

/// Figures of a run.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Stats {
    pub tree_nodes: usize,
    pub distinct_inputs: usize,
    pub passive_marks: usize,
    pub variables: usize,
    pub clauses: usize,
    pub solver_calls: usize,
    pub sat_seconds: f64,
    pub guard_seconds: f64,
}

/// Why synthesis produced no machine.
#[derive(Debug, thiserror::Error)]
pub enum SatError {
    #[error(
        "no ECC with at most {max_states} states reproduces the scenarios (raise --max-states)"
    )]
    TooManyStates { max_states: usize },
    #[error("internal error (a bug in synth, please report it): {0}")]
    Bug(String),
}

/// A clause sink that counts what it forwards.
struct Counting<'a, F: ExtendFormula> {
    inner: &'a mut F,
    vars: usize,
    clauses: usize,
}

impl<F: ExtendFormula> ExtendFormula for Counting<'_, F> {
    fn add_clause(&mut self, clause: &[Lit]) {
        self.clauses += 1;
        self.inner.add_clause(clause);
    }
    fn new_var(&mut self) -> Var {
        self.vars += 1;
        self.inner.new_var()
    }
}

/// The incremental solver with the basic encoding for up to `c_max` states.
struct Encoding {
    solver: Solver<'static>,
    vars: Vars,
    total_t: Totalizer,
    /// Out-degree counters, one per state (only when minimizing `K`).
    degree: Vec<Totalizer>,
    /// Assumption literal "every out-degree <= K", per K, made on demand.
    k_bounds: Vec<(usize, Lit)>,
    variables: usize,
    clauses: usize,
    calls: usize,
}

impl Encoding {
    fn new(tree: &ScenarioTree, c_max: usize, opts: &Options) -> Encoding {
        let mut solver = Solver::new();
        let mut sink = Counting {
            inner: &mut solver,
            vars: 0,
            clauses: 0,
        };
        let vars = Vars::new(&mut sink, tree, c_max);
        constraints::basic(&mut sink, &vars, tree, opts.algorithms);
        if opts.start_state {
            constraints::start_state_never_entered(&mut sink, &vars);
        }
        let total_t = Totalizer::new(&mut sink, vars.all_t(), c_max * c_max);
        let degree = if opts.minimize_k {
            (0..c_max)
                .map(|q| Totalizer::new(&mut sink, vars.t_row(q), c_max))
                .collect()
        } else {
            Vec::new()
        };
        let (variables, clauses) = (sink.vars, sink.clauses);
        Encoding {
            solver,
            vars,
            total_t,
            degree,
            k_bounds: Vec::new(),
            variables,
            clauses,
            calls: 0,
        }
    }

    /// The assumption "at most `c` states".
    fn states_at_most(&self, c: usize) -> Option<Lit> {
        (c < self.vars.c_max).then(|| !self.vars.used(c))
    }

    fn k_at_most(&mut self, k: usize) -> Lit {
        if let Some(&(_, l)) = self.k_bounds.iter().find(|(b, _)| *b == k) {
            return l;
        }
        let l = self.solver.new_lit();
        for tot in &self.degree {
            if let Some(b) = tot.at_most(k) {
                self.solver.add_clause(&[!l, b]);
            }
        }
        self.k_bounds.push((k, l));
        l
    }

    fn solve(&mut self, assumptions: &[Lit]) -> Option<Model> {
        self.calls += 1;
        self.solver.assume(assumptions);
        if self
            .solver
            .solve()
            .expect("varisat does not fail without proof output")
        {
            Some(Model::new(&self.solver.model().expect("model after SAT")))
        } else {
            None
        }
    }
}

/// Synthesizes a minimal ECC reproducing every scenario of `set`.
/// `progress` receives one line per step of the search.
pub fn synthesize(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    opts: &Options,
    progress: &mut dyn FnMut(&str),
) -> Result<Synthesis, SatError> {
    let t0 = Instant::now();
    let mut stats = Stats {
        tree_nodes: tree.nodes.len(),
        distinct_inputs: tree.input_vectors.len(),
        passive_marks: tree.passive_marks(),
        ..Stats::default()
    };
    // 1. least C, growing the encoding window when exhausted.
    let mut c_lo = 1;
    let mut c_max = opts.max_states.min(8);
    let (mut enc, c, mut model) = loop {
        progress(&format!(
            "encoding for up to {c_max} states ({} tree nodes, {} distinct inputs)",
            tree.nodes.len(),
            tree.input_vectors.len()
        ));
        let mut enc = Encoding::new(tree, c_max, opts);
        stats.variables += enc.variables;
        stats.clauses += enc.clauses;
        let mut found = None;
        for c in c_lo..=c_max {
            progress(&format!("trying C = {c}"));
            let assume: Vec<Lit> = enc.states_at_most(c).into_iter().collect();
            if let Some(m) = enc.solve(&assume) {
                found = Some((c, m));
                break;
            }
        }
        stats.solver_calls += enc.calls;
        enc.calls = 0;
        match found {
            Some((c, m)) => break (enc, c, m),
            None if c_max >= opts.max_states => {
                return Err(SatError::TooManyStates {
                    max_states: opts.max_states,
                })
            }
            None => {
                c_lo = c_max + 1;
                c_max = (c_max * 2).min(opts.max_states);
            }
        }
    };
    let mut base: Vec<Lit> = enc.states_at_most(c).into_iter().collect();
    let mut structure = Structure::decode(&model, &enc.vars, tree, opts.algorithms);
    progress(&format!(
        "C = {c} is minimal; first machine has K = {}, T = {}",
        structure.max_out_degree(),
        structure.transition_count()
    ));

    // 2. least K (optional).
    if opts.minimize_k {
        let mut k = structure.max_out_degree();
        while k > 0 {
            let l = enc.k_at_most(k - 1);
            let assume: Vec<Lit> = base.iter().copied().chain([l]).collect();
            progress(&format!("trying K = {}", k - 1));
            match enc.solve(&assume) {
                Some(m) => {
                    model = m;
                    structure = Structure::decode(&model, &enc.vars, tree, opts.algorithms);
                    k = structure.max_out_degree();
                }
                None => break,
            }
        }
        let l = enc.k_at_most(k);
        base.push(l);
        progress(&format!("K = {k} is minimal"));
    }

    // 3. least T.
    let mut t = structure.transition_count();
    while t > 0 {
        let Some(bound) = enc.total_t.at_most(t - 1) else {
            break;
        };
        progress(&format!("trying T = {}", t - 1));
        let assume: Vec<Lit> = base.iter().copied().chain([bound]).collect();
        match enc.solve(&assume) {
            Some(m) => {
                structure = Structure::decode(&m, &enc.vars, tree, opts.algorithms);
                t = structure.transition_count();
            }
            None => break,
        }
    }
    progress(&format!("T = {t} is minimal"));
    stats.solver_calls += enc.calls;
    stats.sat_seconds = t0.elapsed().as_secs_f64();

    // 4. guards.
    let tg = Instant::now();
    let deadline = tg + opts.guard_budget;
    let mut exact = true;
    let mut states = Vec::with_capacity(structure.c);
    for q in 0..structure.c {
        let problem = guards::GuardProblem::of_state(&structure, tree, q);
        let g = guards::minimize_state(&problem, deadline);
        exact &= g.exact;
        states.push(State {
            name: format!("s{q}"),
            algorithm: structure.algorithms[q].clone(),
            transitions: g.transitions,
        });
    }
    stats.guard_seconds = tg.elapsed().as_secs_f64();
    let ecc = Ecc {
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        states,
    };
    ecc.validate().map_err(SatError::Bug)?;
    set.check(&ecc)
        .map_err(|m| SatError::Bug(format!("the synthesized ECC does not replay {m}")))?;
    let size = ecc.size();
    progress(&format!(
        "guards: N = {}{}",
        size.n,
        if exact {
            " (minimal)"
        } else {
            " (budget reached, not proven minimal)"
        }
    ));
    Ok(Synthesis {
        ecc,
        size,
        guards_exact: exact,
        stats,
    })
}

/// Whether an ECC with at most `c` states (and at most `t` transitions) reproduces the tree.
/// The building block of the minimization loops, exposed for tests of known minima.
pub fn satisfiable(tree: &ScenarioTree, opts: &Options, c: usize, t: Option<usize>) -> bool {
    let mut enc = Encoding::new(tree, c.max(1), opts);
    let mut assume: Vec<Lit> = Vec::new();
    if c == 0 {
        return false;
    }
    if let Some(t) = t {
        assume.extend(enc.total_t.at_most(t));
    }
    enc.solve(&assume).is_some()
}

#[cfg(test)]
mod tests;
