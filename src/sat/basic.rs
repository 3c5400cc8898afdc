//! Exact synthesis of one minimal ECC from execution scenarios with the basic encoding.
//!
//! In: a [`ScenarioTree`] (and the [`ScenarioSet`] it came from, for the final replay) and
//! [`Options`]. Out: a [`Synthesis`]: the ECC, its size `C, K, T, N`, and figures.
//!
//! The procedure is the SAT reconstruction paper's Algorithm 1 on the metaheuristic paper's basic model:
//! 1. least number of states `C`;
//! 2. optionally, least largest out-degree `K`;
//! 3. least number of transitions `T`;
//! 4. guards with the least total literal count `N`.
//!
//! Two guard models ([`GuardModel`]):
//! - tree-exact (default, `synth infer`): transitions exist only on recorded inputs, `T`
//!   counts edges `q -> q'` (each with one guard, a DNF), and guards are minimized per state
//!   on a fixed structure afterwards ([`super::guards`]); unrecorded inputs are don't-cares.
//!   Several machines may have the least `C` and `T` and need different guards, so every one
//!   of them is visited (each structure blocked once seen) within the guard budget, and `N` is
//!   the least over all (on 40 random recordings, 14 got a smaller `N` than the first
//!   structure's, e.g. 24 -> 15; fbSAT's tests-39: 20 -> 16);
//! - cube (`Options::max_out_degree`, the main job): guards are conjunctions of literals inside the
//!   encoding with first-fire priority ([`super::cubes`]), `T` counts transitions and `N` is
//!   minimized on the same solver, so the machine is determined on every input. Verification
//!   in the loop needs that: counterexamples run on inputs nobody recorded.
//!
//! Negative scenarios ([`super::negative`]) can be added between minimizations
//! ([`Synthesizer`]).
//!
//! Steps 1-3 (and 4 in the cube model) run on *one* incremental [`Solver`]: the encoding is
//! built for up to `C_max` states with "state in use" variables, and every bound (states, `K`,
//! `T`, `N`) is a solver assumption on those variables or on totalizer outputs
//! ([`super::card`]). Only if every `C <= C_max` is unsatisfiable is the encoding rebuilt for a
//! `C_max` a quarter (at least two states) larger.
//!
//! Every machine is replayed through the simulator on every scenario before it is returned;
//! a mismatch is reported as [`SatError::Bug`].

use super::card::Totalizer;
use super::closed_loop;
use super::decode::{self, Structure};
use super::solver::{Bounded, Effort, Model, Solver};
use super::vars::{GuardModel, Vars};
use super::{constraints, guards, negative, SatError};
use crate::ecc::{AlgorithmKind, Ecc, Size, State};
use crate::sat::step::{Bound, Progress, Step};
use crate::scenario::negative::NegativeScenario;
use crate::scenario::tree::{InputVec, NodeId, ScenarioTree};
use crate::scenario::ScenarioSet;
use std::sync::Arc;
use std::time::{Duration, Instant};
use varisat::{ExtendFormula, Lit};

/// Settings of a synthesis run.
#[derive(Debug, Clone)]
pub struct Options {
    /// The algorithm form of every state: `Tri` (`{0, 1, x}` per output) or fbSAT's `Binary`.
    pub algorithms: AlgorithmKind,
    /// Minimize the largest out-degree `K` before `T`.
    pub minimize_k: bool,
    /// Give up above this many states.
    pub max_states: usize,
    /// State 0 is a start state no transition enters (fbSAT's convention, for comparison).
    pub start_state: bool,
    /// Time for guard minimization, over all states; past it the best guards so far are kept.
    pub guard_budget: Duration,
    /// `Some(k)`: guards are conjunctions of literals inside the encoding, at most `k`
    /// transitions per state ([`super::cubes`]); `None`: transitions on recorded inputs only, guards
    /// minimized afterwards (the tree-exact model).
    pub max_out_degree: Option<usize>,
    /// Sizes asked for rather than minimized ([`Fixed`]).
    pub fixed: Fixed,
    /// Where every solver call stops ([`Solver::until`]); the guard budget ends there too.
    pub deadline: crate::deadline::Deadline,
}

/// Fixed bounds (fbSAT's `-C`, `-K`, `-T`): a machine within them, the rest still minimized.
/// `states`: no fewer states are looked for (with [`Synthesizer`]: the search starts and ends
/// there); `max_out_degree` and `transitions`: upper bounds every solver call assumes.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Fixed {
    /// fbSAT's `-C`: the number of states to look for; fewer are not tried.
    pub states: Option<usize>,
    /// fbSAT's `-K`: at most this many transitions leave any one state.
    pub(crate) max_out_degree: Option<usize>,
    /// fbSAT's `-T`: at most this many transitions in all.
    pub(crate) transitions: Option<usize>,
}

impl Fixed {
    /// Whether any bound is given.
    pub(crate) fn any(&self) -> bool {
        *self != Fixed::default()
    }
}

impl std::fmt::Display for Fixed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = [
            self.states.map(|c| format!("{c} states")),
            self.max_out_degree
                .map(|k| format!("at most {k} transitions per state")),
            self.transitions.map(|t| format!("at most {t} transitions")),
        ]
        .into_iter()
        .flatten()
        .collect();
        f.write_str(&parts.join(", "))
    }
}

impl Options {
    /// The form its machines take: algorithms and start state.
    pub(crate) fn conventions(&self) -> crate::ecc::Conventions {
        crate::ecc::Conventions {
            algorithms: self.algorithms,
            start_state: self.start_state,
        }
    }
}

impl Default for Options {
    fn default() -> Self {
        Options {
            algorithms: AlgorithmKind::Tri,
            minimize_k: false,
            max_states: 32,
            start_state: false,
            guard_budget: Duration::from_secs(10),
            max_out_degree: None,
            fixed: Fixed::default(),
            deadline: crate::deadline::Deadline::NONE,
        }
    }
}

/// The result of a synthesis run.
#[derive(Debug, Clone)]
pub struct Synthesis {
    /// The machine, replayed through the simulator on every scenario.
    pub ecc: Ecc,
    /// Its `C, K, T, N`; `C` and `T` are least, `K` only with [`Options::minimize_k`], `N` when
    /// `guards_exact`.
    pub size: Size,
    /// Whether `N` is proven minimal for the structure (guard search finished in budget).
    pub(crate) guards_exact: bool,
    /// Whether `T` is proven minimal for `C` (see [`Proofs`]).
    pub(crate) transitions_exact: bool,
    /// Figures of the run (encoding size, solver calls, time).
    pub stats: Stats,
    /// The state of every scenario tree node (a hint for the next search, see
    /// [`Synthesizer::hint`]).
    pub(crate) colors: Vec<usize>,
}

/// Figures of a run.
#[derive(Debug, Clone, Default, serde::Serialize, schemars::JsonSchema)]
#[schemars(rename = "SatStats")]
pub struct Stats {
    /// Nodes of the scenario tree, root included.
    pub(crate) tree_nodes: usize,
    /// Distinct input vectors recorded in the tree (the alphabet before any counterexample).
    pub(crate) distinct_inputs: usize,
    /// Passive marks of the tree: `(node, input)` pairs on which nothing may fire.
    pub(crate) passive_marks: usize,
    /// Variables written, summed over every (re)build of the encoding and every negative
    /// scenario or environment added.
    pub(crate) variables: usize,
    /// Clauses written, counted like `variables`.
    pub(crate) clauses: usize,
    /// SAT calls made, over every minimization of this synthesizer.
    pub(crate) solver_calls: usize,
    /// Wall-clock seconds of steps 1-3 (`C`, `K`, `T`) of the latest minimization.
    pub(crate) sat_seconds: f64,
    /// Wall-clock seconds of step 4 (guards, `N`) of the latest minimization.
    pub(crate) guard_seconds: f64,
    /// Syntheses over growing parts of long recordings ([`crate::pipeline::lazy`]); 1 when
    /// the recordings were encoded whole, 0 when not counted.
    pub rounds: usize,
    /// Recorded steps in the part encoded last (all of them when `rounds` is 1).
    pub steps_encoded: usize,
}

/// The incremental solver with the basic encoding for up to `c_max` states, its input
/// alphabet (the tree's input vectors, then those counterexamples bring) and the assumption
/// literals that keep it open for more.
pub(super) struct Encoding {
    solver: Solver,
    vars: Vars,
    total_t: Totalizer,
    /// Guard literal counter `N`: `Some` exactly in the cube model ([`GuardModel::Cubes`]).
    total_n: Option<Totalizer>,
    /// Out-degree counters, one per state (only when minimizing `K`).
    degree: Vec<Totalizer>,
    /// Assumption literal "every out-degree <= K", per K, made on demand.
    k_bounds: Vec<(usize, Lit)>,
    /// `sel[u]` of [`constraints::no_unexercised_transitions`], per tree input.
    sel: Vec<Lit>,
    /// Open tails of the edge definitions, assumed false.
    tails: Vec<Lit>,
    /// The bounds of [`Options::fixed`] on `K` and `T`, assumed by every call.
    fixed: Vec<Lit>,
    /// Input vectors by alphabet index, and whether a counterexample uses each.
    alphabet: Vec<Vec<bool>>,
    in_counterexample: Vec<bool>,
    start_state: bool,
    /// Variables and clauses of the encoding as built (bounds made on demand not counted).
    pub(super) variables: usize,
    pub(super) clauses: usize,
    /// Solver calls already counted in the synthesizer's figures.
    calls_counted: usize,
}

impl Encoding {
    pub(super) fn new(tree: &ScenarioTree, c_max: usize, opts: &Options) -> Encoding {
        Encoding::build(tree, c_max, opts, false)
    }

    /// The encoding; with `keep`, the solver keeps a copy of the clauses for budgeted proofs.
    fn build(tree: &ScenarioTree, c_max: usize, opts: &Options, keep: bool) -> Encoding {
        let mut solver = Solver::until(opts.deadline);
        if keep {
            solver.keep_clauses();
        }
        let sink = &mut solver;
        let vars = Vars::new(sink, tree, c_max, opts.max_out_degree);
        // Allocated in both guard models, so that both number their variables alike; only the
        // tree-exact model constrains them.
        let sel: Vec<Lit> = (0..vars.inputs).map(|_| sink.new_lit()).collect();
        let tails: Vec<Lit> = (0..c_max * c_max).map(|_| sink.new_lit()).collect();
        constraints::basic(
            sink,
            &vars,
            tree,
            opts.algorithms,
            opts.start_state,
            &sel,
            &tails,
        );
        let (total_t, total_n) = match &vars.guards {
            GuardModel::Cubes(cv) => (
                Totalizer::new(sink, cv.all_en(), c_max * cv.max_out_degree),
                Some(Totalizer::new(sink, &cv.all_literals(), 200)),
            ),
            GuardModel::TreeExact => (Totalizer::new(sink, vars.all_t(), c_max * c_max), None),
        };
        let degree = if opts.minimize_k || opts.fixed.max_out_degree.is_some() {
            (0..c_max)
                .map(|q| match &vars.guards {
                    GuardModel::Cubes(cv) => {
                        Totalizer::new(sink, cv.en_row(0, q), cv.max_out_degree)
                    }
                    GuardModel::TreeExact => Totalizer::new(sink, vars.t_row(q), c_max),
                })
                .collect()
        } else {
            Vec::new()
        };
        let stats = solver.stats();
        let mut enc = Encoding {
            solver,
            vars,
            total_t,
            total_n,
            degree,
            k_bounds: Vec::new(),
            sel,
            tails,
            fixed: Vec::new(),
            alphabet: tree.input_vectors.clone(),
            in_counterexample: vec![false; tree.input_vectors.len()],
            start_state: opts.start_state,
            variables: stats.variables,
            clauses: stats.clauses,
            calls_counted: 0,
        };
        if let Some(k) = opts.fixed.max_out_degree {
            let l = enc.k_at_most(k);
            enc.fixed.push(l);
        }
        if let Some(b) = opts.fixed.transitions.and_then(|t| enc.total_t.at_most(t)) {
            enc.fixed.push(b);
        }
        enc
    }

    /// Solver calls made since the last time this was asked.
    fn new_calls(&mut self) -> usize {
        let calls = self.solver.stats().calls - self.calls_counted;
        self.calls_counted += calls;
        calls
    }

    /// Runs `write` on the solver; adds what it writes to the encoding's size.
    fn grow_by<T>(&mut self, write: impl FnOnce(&mut Self) -> T) -> T {
        let before = self.solver.stats();
        let out = write(self);
        let after = self.solver.stats();
        self.variables += after.variables - before.variables;
        self.clauses += after.clauses - before.clauses;
        out
    }

    /// The alphabet index of an input vector used by a counterexample, added if new.
    fn counterexample_input(&mut self, x: &[bool]) -> InputVec {
        if let Some(u) = self.alphabet.iter().position(|a| a == x) {
            self.in_counterexample[u] = true;
            return InputVec(u);
        }
        let u = self.grow_by(|e| {
            let u = e.vars.add_input(&mut e.solver);
            constraints::per_input(&mut e.solver, &e.vars, u, x, e.start_state);
            constraints::extend_edges(&mut e.solver, &e.vars, u, &mut e.tails);
            u
        });
        self.alphabet.push(x.to_vec());
        self.in_counterexample.push(true);
        u
    }

    /// The closed loop along `env` with every property of `spec` ([`closed_loop`]); needs the
    /// cube guard model.
    fn add_environment(&mut self, spec: &closed_loop::Spec, env: &closed_loop::Environment) {
        self.grow_by(|e| {
            if let GuardModel::Cubes(cv) = &e.vars.guards {
                closed_loop::encode(&mut e.solver, &e.vars, cv, spec, env);
            }
        });
    }

    fn add_negative(&mut self, neg: &NegativeScenario) -> Vec<InputVec> {
        let ids: Vec<InputVec> = neg
            .steps
            .iter()
            .map(|s| self.counterexample_input(&s.inputs))
            .collect();
        self.grow_by(|e| negative::leave_lasso(&mut e.solver, &e.vars, neg, &ids));
        ids
    }

    /// Assumptions every call makes: closed edge tails, and "scenario inputs only" selectors.
    fn base_assumptions(&self) -> Vec<Lit> {
        let mut a: Vec<Lit> = self.tails.iter().map(|&t| !t).collect();
        a.extend(
            self.sel
                .iter()
                .zip(&self.in_counterexample)
                .filter(|(_, &ce)| !ce)
                .map(|(&s, _)| s),
        );
        a.extend_from_slice(&self.fixed);
        a
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

    /// The literals "tree node `v` has state `colors[v]`" of a colouring of the tree.
    fn colouring(&self, colors: &[usize]) -> Vec<Lit> {
        (colors.iter().enumerate())
            .map(|(v, &q)| self.vars.color(NodeId(v), q))
            .collect()
    }

    fn solve(&mut self, assumptions: &[Lit]) -> Option<Model> {
        let mut all = self.base_assumptions();
        all.extend_from_slice(assumptions);
        self.solver.solve(&all)
    }
}

/// How hard a candidate ([`Proofs::Skip`]) may look for fewer transitions than its colouring
/// gives, down to the proven bound: a refutation in closed loop can take minutes. Counted in
/// the solver's work (about 1.5 s of a release build on one core), so that which `T` the loop
/// goes on with does not depend on the machine's load: a descent that runs out is not tried
/// again, and a loop stuck one transition too high can refute candidates for minutes.
const CANDIDATE_T_BUDGET: Effort = Effort::Work(6_000_000);

/// Hints kept by a [`Synthesizer`] (the colourings of its latest machines).
const MAX_HINTS: usize = 6;

/// How hard [`Synthesizer::minimize`] works to prove `T` minimal once a machine is found.
/// With the properties inside the encoding ([`super::closed_loop`]) proving that no machine
/// with one transition fewer exists can take minutes where finding the machine took a
/// second, so a loop that only needs candidates skips it and the final machine gets a budget.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Proofs {
    /// Every bound proven (the default).
    Full,
    /// Fewest transitions with the colouring found (or hinted) only; nothing proven.
    Skip,
    /// As `Full`, but the refutation that ends the descent is tried on a fresh solver within
    /// this effort; if it does not finish, `T` is reported as not proven minimal.
    Budget(Effort),
    /// As `Full` while each call on the incremental solver takes under [`QUICK_CALL`]; after a
    /// slower one, every further bound of `T` on a fresh solver within this effort, and `T`
    /// is reported as not proven minimal if one does not finish. For a machine that others
    /// will try to make smaller anyway: the refutation after a slow call usually takes longer
    /// still.
    Quick(Effort),
}

/// A call on the incremental solver longer than this makes a [`Proofs::Quick`] descent
/// budgeted.
const QUICK_CALL: Duration = Duration::from_secs(1);

/// Exact synthesis, kept incremental across calls: negative scenarios can be added between
/// minimizations (CEGIS), and every call continues on the same solver.
pub(crate) struct Synthesizer<'a> {
    set: &'a ScenarioSet,
    tree: &'a ScenarioTree,
    opts: Options,
    enc: Encoding,
    /// The bounds proven so far and the latest machine's size.
    known: Known,
    negatives: Vec<NegativeScenario>,
    /// Alphabet indices of the steps of each negative scenario in the current encoding
    /// (`None`: it cannot be followed at all, its first outputs are not the initial ones).
    negative_ids: Vec<Option<Vec<InputVec>>>,
    /// The closed loop the environments are encoded with, and the environments.
    closed_loop: Option<Arc<closed_loop::Spec>>,
    environments: Vec<closed_loop::Environment>,
    /// Cube model: minimize `N` after `T` (otherwise the first guards found are kept).
    minimize_n: bool,
    /// Colourings of the tree nodes to try first, newest last (see [`Self::hint`]).
    hints: Vec<Vec<usize>>,
    proofs: Proofs,
    stats: Stats,
}

impl<'a> Synthesizer<'a> {
    /// A synthesizer for `tree` (built from `set`, which the final replay uses) that proves every
    /// bound ([`Proofs::Full`]). Nothing is solved before [`Self::minimize`].
    pub(crate) fn new(
        set: &'a ScenarioSet,
        tree: &'a ScenarioTree,
        opts: &Options,
    ) -> Synthesizer<'a> {
        Synthesizer::with_proofs(set, tree, opts, Proofs::Full)
    }

    /// A synthesizer that starts with `proofs` (see [`Self::set_proofs`]); anything but `Full`
    /// keeps a copy of the clauses for budgeted proofs from the start.
    pub(crate) fn with_proofs(
        set: &'a ScenarioSet,
        tree: &'a ScenarioTree,
        opts: &Options,
        proofs: Proofs,
    ) -> Synthesizer<'a> {
        let mut opts = opts.clone();
        if let Some(c) = opts.fixed.states {
            opts.max_states = c;
        }
        let opts = &opts;
        let c_max = opts.max_states.clamp(1, 8);
        let enc = Encoding::build(tree, c_max, opts, proofs != Proofs::Full);
        let stats = Stats {
            tree_nodes: tree.nodes.len(),
            distinct_inputs: tree.input_vectors.len(),
            passive_marks: tree.passive_marks(),
            variables: enc.variables,
            clauses: enc.clauses,
            ..Stats::default()
        };
        let mut synth = Synthesizer {
            set,
            tree,
            opts: opts.clone(),
            enc,
            known: Known {
                c_lo: 1,
                t_lo: None,
                n_lo: None,
                t_timed_out: None,
                last: None,
            },
            negatives: Vec::new(),
            negative_ids: Vec::new(),
            closed_loop: None,
            environments: Vec::new(),
            minimize_n: true,
            hints: Vec::new(),
            proofs,
            stats,
        };
        if let Some(c) = opts.fixed.states {
            synth.assume_lower_bounds(c, 0);
        }
        synth
    }

    /// Starts the search at known lower bounds: no machine has fewer than `c` states, and none
    /// with `c` states has fewer than `t` transitions. The caller vouches for them, e.g. with
    /// the minimum of the tree-exact model, which bounds the cube model from below: restricting
    /// a cube machine to the recorded inputs gives a tree-exact machine with the same states and
    /// no more edges.
    pub(crate) fn assume_lower_bounds(&mut self, c: usize, t: usize) {
        self.known.c_lo = self.known.c_lo.max(c);
        // A bound proven on the loop's constraints may already be higher.
        self.known.t_lo = match self.known.t_lo {
            Some((c0, t0)) if c0 == c && t0 > t => Some((c0, t0)),
            _ => Some((c, t)),
        };
        if self.known.c_lo > self.enc.vars.c_max && self.known.c_lo <= self.opts.max_states {
            // Straight to a window that holds the bound (one spare state), rather than
            // refuting the smaller window first.
            self.grow((self.known.c_lo + 1).min(self.opts.max_states));
        }
    }

    /// Starts the guard descent at a known lower bound: with `c` states and `t` transitions no
    /// machine's cube guards have fewer than `n` literals. The caller vouches for it, e.g. with
    /// [`least_literals`] of the tree-exact model at its least `c` and `t`.
    pub(crate) fn assume_least_n(&mut self, c: usize, t: usize, n: usize) {
        self.known.n_lo = match self.known.n_lo {
            Some((c0, t0, n0)) if (c0, t0) == (c, t) && n0 > n => Some((c0, t0, n0)),
            _ => Some((c, t, n)),
        };
    }

    /// Forbids the machine to follow `neg` forever. Applies to every later [`Self::minimize`].
    pub(crate) fn add_negative(&mut self, neg: NegativeScenario) {
        let (v0, c0) = (self.enc.variables, self.enc.clauses);
        let ids = (neg.steps.first().map(|s| &s.before) == Some(&self.set.initial_outputs))
            .then(|| self.enc.add_negative(&neg));
        self.negative_ids.push(ids);
        self.stats.variables += self.enc.variables - v0;
        self.stats.clauses += self.enc.clauses - c0;
        self.negatives.push(neg);
    }

    /// Requires every property of `spec` on the closed loop along `env`, for every later
    /// [`Self::minimize`] ([`closed_loop`]). Needs the cube guard model; every call must pass
    /// the same `spec`.
    pub(crate) fn add_environment(
        &mut self,
        spec: &Arc<closed_loop::Spec>,
        env: closed_loop::Environment,
    ) -> Result<(), SatError> {
        if !matches!(self.enc.vars.guards, GuardModel::Cubes(_)) {
            return Err(SatError::Bug(
                "closed-loop environments need the cube guard model".into(),
            ));
        }
        if self.environments.contains(&env) {
            return Err(SatError::Bug(
                "the same environment was added twice: the loop would not progress".into(),
            ));
        }
        let (v0, c0) = (self.enc.variables, self.enc.clauses);
        self.enc.add_environment(spec, &env);
        self.stats.variables += self.enc.variables - v0;
        self.stats.clauses += self.enc.clauses - c0;
        self.closed_loop = Some(spec.clone());
        self.environments.push(env);
        Ok(())
    }

    /// A colouring of the scenario tree's nodes to try first: the next [`Self::minimize`] looks
    /// for a machine at the least possible `C` with this colouring, then for fewer transitions
    /// with it, before it proves minimality without it. A colouring from the tree-exact model
    /// (or from the previous candidate) usually still fits, and searching the guards for a
    /// fixed colouring is fast where the free search for the least `T` is not. Minimality does
    /// not depend on it: every bound is still proven on the whole problem.
    pub(crate) fn hint(&mut self, colors: Vec<usize>) {
        self.hints.retain(|h| *h != colors);
        self.hints.push(colors);
        // The newest few: each refuted hint costs a solver call.
        if self.hints.len() > MAX_HINTS {
            self.hints.remove(0);
        }
    }

    /// How hard the next [`Self::minimize`] calls work to prove `T` minimal ([`Proofs`]).
    /// Anything but `Full` keeps a copy of the clauses for the budgeted proof, from the next
    /// encoding built on.
    pub(crate) fn set_proofs(&mut self, proofs: Proofs) {
        self.proofs = proofs;
        if matches!(proofs, Proofs::Budget(_)) && !self.enc.solver.keeps_clauses() {
            self.grow(self.enc.vars.c_max);
        }
    }

    /// Whether [`Self::minimize`] minimizes `N` in the cube model (the default). A loop that
    /// only needs candidates turns it off until one passes, then on for the final machine.
    pub(crate) fn set_minimize_n(&mut self, on: bool) {
        self.minimize_n = on;
    }

    /// The environments encoded so far ([`Self::add_environment`]), in order.
    pub(crate) fn environments(&self) -> &[closed_loop::Environment] {
        &self.environments
    }

    /// The negative scenarios added so far ([`Self::add_negative`]), in order; the CEGIS loop
    /// reads them to count counterexamples and to skip one it already has.
    pub(crate) fn negatives(&self) -> &[NegativeScenario] {
        &self.negatives
    }

    /// Whether a candidate's descent in `T` with `c` states ran out of its work budget
    /// ([`Proofs::Skip`]; it is not tried again at that `C`).
    pub(crate) fn transitions_gave_up(&self, c: usize) -> bool {
        matches!(self.known.t_timed_out, Some((c1, _)) if c1 == c)
    }

    /// Rebuilds the encoding for a larger window of states, with every negative scenario.
    fn grow(&mut self, c_max: usize) {
        self.enc = Encoding::build(
            self.tree,
            c_max,
            &self.opts,
            self.proofs != Proofs::Full || self.enc.solver.keeps_clauses(),
        );
        self.stats.variables += self.enc.variables;
        self.stats.clauses += self.enc.clauses;
        for (neg, ids) in self.negatives.iter().zip(self.negative_ids.iter_mut()) {
            if ids.is_some() {
                *ids = Some(self.enc.add_negative(neg));
            }
        }
        if let Some(spec) = &self.closed_loop {
            for env in &self.environments {
                self.enc.add_environment(spec, env);
            }
        }
    }

    /// Whether a machine smaller than one of `size` exists, each question tried on a fresh
    /// solver for `budget`: with `size.c` states and fewer than `size.t` transitions, and with
    /// at most `size.t` transitions and fewer than `size.n` guard literals. `Sat` carries no
    /// machine the caller can use directly (run [`Self::minimize`] for it); `Unknown` when the
    /// budget ran out or the encoding keeps no clauses for such proofs.
    pub(crate) fn smaller_exists(&mut self, size: Size, budget: Effort) -> (Bounded, Bounded) {
        let t_known = self.known.t_lo == Some((size.c, size.t));
        let n_known = self.known.n_lo == Some((size.c, size.t, size.n));
        let enc = &mut self.enc;
        let mut base = enc.base_assumptions();
        base.extend(enc.vars.states_at_most(size.c));
        let fewer_t = match size.t.checked_sub(1).map(|b| enc.total_t.at_most(b)) {
            _ if t_known => Bounded::Unsat,
            None => Bounded::Unsat,
            Some(None) => Bounded::Unknown,
            Some(Some(b)) => {
                let assume: Vec<Lit> = base.iter().copied().chain([b]).collect();
                enc.solver.solve_spending(&assume, &mut budget.start())
            }
        };
        let fewer_n = match (&enc.total_n, size.n.checked_sub(1)) {
            _ if n_known => Bounded::Unsat,
            (_, None) => Bounded::Unsat,
            (None, _) => Bounded::Unknown,
            (Some(total_n), Some(n)) => match total_n.at_most(n) {
                Some(bn) => {
                    let assume: Vec<Lit> = base
                        .iter()
                        .copied()
                        .chain(enc.total_t.at_most(size.t))
                        .chain([bn])
                        .collect();
                    enc.solver.solve_spending(&assume, &mut budget.start())
                }
                None => Bounded::Unknown,
            },
        };
        self.stats.solver_calls += enc.new_calls();
        (fewer_t, fewer_n)
    }

    /// Finds the least `C`, then (optionally) `K`, then `T`, then minimal guards (Algorithm 1
    /// of Chivilikhin et al., "Automatic state machine reconstruction from legacy PLC using
    /// data collection and SAT solver"), and replays the machine on every scenario.
    pub(crate) fn minimize(&mut self, progress: Progress<'_>) -> Result<Synthesis, SatError> {
        let t0 = Instant::now();
        let (c, model, hint) = match self.hinted_machine(progress) {
            Some((model, hint)) => (self.known.c_lo, model, Some(hint)),
            None => {
                let (c, model) = self.least_states(progress)?;
                (c, model, None)
            }
        };
        let mut descent = self.descent(c, &model, hint, progress);
        if descent.opts.minimize_k {
            descent.least_k();
        }
        let transitions_exact = descent.least_t();
        descent.stats.sat_seconds = t0.elapsed().as_secs_f64();
        let tg = Instant::now();
        let (states, exact) = if descent.enc.total_n.is_some() {
            descent.least_n()
        } else {
            descent.least_guards(descent.opts.deadline.cap(tg + descent.opts.guard_budget))
        };
        let structure = descent.structure;
        self.stats.guard_seconds = tg.elapsed().as_secs_f64();
        self.replayed(states, structure.colors, exact, transitions_exact, progress)
    }

    /// Phase 0: a machine at the least possible `C` with one of the hinted colourings, newest
    /// first ([`Self::hint`]), with that colouring. `None` when none fits (or the encoding's
    /// window has fewer states than the least possible).
    fn hinted_machine(&mut self, progress: Progress<'_>) -> Option<(Model, Vec<usize>)> {
        let c = self.known.c_lo;
        let usable: Vec<Vec<usize>> = self
            .hints
            .iter()
            .rev()
            .filter(|h| h.len() == self.tree.nodes.len() && h.iter().all(|&q| q < c))
            .cloned()
            .collect();
        if c > self.enc.vars.c_max {
            return None;
        }
        for h in usable {
            let mut assume: Vec<Lit> = self.enc.vars.states_at_most(c).into_iter().collect();
            assume.extend(self.enc.colouring(&h));
            progress(Step::TryingStates {
                c,
                tree_nodes: self.tree.nodes.len(),
                inputs: self.enc.alphabet.len(),
                negatives: self.negatives.len(),
            });
            if let Some(m) = self.enc.solve(&assume) {
                return Some((m, h));
            }
        }
        None
    }

    /// Phase 1: the least `C` and a machine with that many states, by ascent from the proven
    /// lower bound; an exhausted window is rebuilt a quarter larger ([`Self::grow`]) up to
    /// [`Options::max_states`]. Every refuted bound raises the proven lower bound.
    fn least_states(&mut self, progress: Progress<'_>) -> Result<(usize, Model), SatError> {
        let (max_states, fixed) = (self.opts.max_states, self.opts.fixed);
        loop {
            let c_max = self.enc.vars.c_max;
            let (nodes, inputs) = (self.tree.nodes.len(), self.enc.alphabet.len());
            let negatives = self.negatives.len();
            let base = self.enc.base_assumptions();
            let vars = &self.enc.vars;
            let found = self.enc.solver.ascend(
                self.known.c_lo..=c_max,
                |c| base.iter().copied().chain(vars.states_at_most(c)).collect(),
                |c| {
                    progress(Step::TryingStates {
                        c,
                        tree_nodes: nodes,
                        inputs,
                        negatives,
                    })
                },
            );
            // Stopped at the deadline: "no model" proved nothing, and a wider window costs.
            if self.enc.solver.stopped() {
                return Err(SatError::Stopped);
            }
            // No machine with fewer states than the least satisfiable bound (or than the window).
            self.known.c_lo = found
                .as_ref()
                .map_or(self.known.c_lo.max(c_max + 1), |(c, _)| *c);
            match found {
                Some(f) => return Ok(f),
                None if c_max >= max_states && fixed.any() => {
                    return Err(SatError::OutOfBounds {
                        bounds: fixed.to_string(),
                        max_states,
                    })
                }
                None if c_max >= max_states => return Err(SatError::TooManyStates { max_states }),
                None => {
                    // A quarter more states (at least two), not twice as many: every state of
                    // the window beyond the least C adds variables and symmetric machines to
                    // every later call, and the least C is usually just above the window.
                    let next = (c_max + (c_max / 4).max(2)).min(max_states);
                    progress(Step::Reencoding {
                        states: next,
                        per_module: false,
                    });
                    self.grow(next);
                }
            }
        }
    }

    /// The phases after the least `C` ([`Descent`]), starting from `model`, a machine with `c`
    /// states.
    fn descent<'s>(
        &'s mut self,
        c: usize,
        model: &Model,
        hint: Option<Vec<usize>>,
        progress: Progress<'s>,
    ) -> Descent<'s> {
        let read = Reader {
            tree: self.tree,
            algorithms: self.opts.algorithms,
            negatives: (self.negatives.iter())
                .zip(&self.negative_ids)
                .filter_map(|(n, ids)| ids.as_deref().map(|ids| (n, ids)))
                .collect(),
            closed_loop: !self.environments.is_empty(),
        };
        let base: Vec<Lit> = self.enc.vars.states_at_most(c).into_iter().collect();
        let structure = read.structure(model, &self.enc.vars, &self.enc.alphabet);
        progress(Step::StatesMinimal {
            c,
            k: structure.max_out_degree(),
            t: structure.transition_count(),
        });
        Descent {
            enc: &mut self.enc,
            reader: read,
            known: &mut self.known,
            stats: &mut self.stats,
            opts: &self.opts,
            proofs: self.proofs,
            minimize_n: self.minimize_n,
            progress,
            c,
            base,
            t: structure.transition_count(),
            structure,
            hint,
        }
    }

    /// The machine with guards `states`, checked: well formed, replaying every scenario,
    /// following no negative scenario (a failure is a bug of the encoding, [`SatError::Bug`]).
    /// Its size and colouring become the start of the next minimization.
    fn replayed(
        &mut self,
        states: Vec<State>,
        colors: Vec<usize>,
        guards_exact: bool,
        transitions_exact: bool,
        progress: Progress<'_>,
    ) -> Result<Synthesis, SatError> {
        let ecc = Ecc {
            inputs: self.set.inputs.clone(),
            outputs: self.set.outputs.clone(),
            initial_outputs: self.set.initial_outputs.clone(),
            states,
        };
        ecc.validate().map_err(SatError::Bug)?;
        self.set
            .check(&ecc)
            .map_err(|m| SatError::Bug(format!("the synthesized ECC does not replay {m}")))?;
        if let Some(neg) = self.negatives.iter().find(|n| n.followed_by(&ecc)) {
            return Err(SatError::Bug(format!(
                "the synthesized ECC follows the negative scenario {}",
                neg.label
            )));
        }
        let size = ecc.size();
        self.known.last = Some(size);
        progress(Step::Guards {
            n: size.n,
            exact: guards_exact,
        });
        self.hint(colors.clone());
        Ok(Synthesis {
            ecc,
            size,
            guards_exact,
            transitions_exact,
            stats: self.stats.clone(),
            colors,
        })
    }
}

/// What earlier minimizations of a [`Synthesizer`] established, kept across calls: negative
/// scenarios and environments only remove machines, so no minimum ever drops.
#[derive(Debug, Clone, Copy)]
struct Known {
    /// No machine with fewer states exists.
    c_lo: usize,
    /// `(c, t)`: with `c` states no machine has fewer than `t` transitions.
    t_lo: Option<(usize, usize)>,
    /// `(c, t, n)`: with `c` states and `t` transitions no cube guards have fewer than `n`
    /// literals (cube model).
    n_lo: Option<(usize, usize, usize)>,
    /// `(c, b)`: a free search for at most `b` transitions with `c` states gave up at its
    /// deadline.
    t_timed_out: Option<(usize, usize)>,
    /// The size of the latest machine (where the next candidate's search starts).
    last: Option<Size>,
}

/// Reads machines out of models of the encoding ([`Structure::decode`]): what decoding needs
/// besides the model and the alphabet.
struct Reader<'s> {
    tree: &'s ScenarioTree,
    algorithms: AlgorithmKind,
    /// The negative scenarios that can be followed, with their alphabet indices.
    negatives: Vec<decode::IndexedNegative<'s>>,
    /// Whether environments are encoded ([`closed_loop`]).
    closed_loop: bool,
}

impl Reader<'_> {
    /// The machine of `model`, an assignment of `vars` over `alphabet`.
    fn structure(&self, model: &Model, vars: &Vars, alphabet: &[Vec<bool>]) -> Structure {
        Structure::decode(
            model,
            vars,
            self.tree,
            self.algorithms,
            alphabet,
            &self.negatives,
            self.closed_loop,
        )
    }
}

/// Phases 2-4 of [`Synthesizer::minimize`], at the least `C`: least `K` (optional), least `T`,
/// then the guards. Each phase descends a bound on a counter ([`super::card`]) under
/// assumptions and keeps the machine of the latest model; what it proves goes into
/// [`Known`] for later calls.
struct Descent<'s> {
    enc: &'s mut Encoding,
    reader: Reader<'s>,
    known: &'s mut Known,
    stats: &'s mut Stats,
    opts: &'s Options,
    proofs: Proofs,
    minimize_n: bool,
    progress: Progress<'s>,
    /// The least number of states.
    c: usize,
    /// "At most `c` states", and "every out-degree at most `K`" once `K` is minimized.
    base: Vec<Lit>,
    /// The transition count of `structure` while `T` is minimized; the least `T` after.
    t: usize,
    /// The machine of the latest model.
    structure: Structure,
    /// The colouring the machine is looked for with first (phase 0's, or without proofs the
    /// first machine's).
    hint: Option<Vec<usize>>,
}

impl Descent<'_> {
    /// `base` with every call's assumptions first ([`Encoding::base_assumptions`]).
    fn base_t(&self) -> Vec<Lit> {
        let mut base_t = self.enc.base_assumptions();
        base_t.extend_from_slice(&self.base);
        base_t
    }

    /// Reads the machine of `model` into `structure`.
    fn read(&mut self, model: &Model) {
        self.structure = self
            .reader
            .structure(model, &self.enc.vars, &self.enc.alphabet);
    }

    /// Tells the progress callback that `value` is tried for `bound`.
    fn trying(&mut self, bound: Bound, value: usize) {
        (self.progress)(Step::Trying { bound, value });
    }

    /// Phase 2: the least largest out-degree `K`, by descent (the last bound refuted); the bound
    /// "every out-degree at most `K`" joins `base`.
    fn least_k(&mut self) {
        let mut k = self.structure.max_out_degree();
        while k > 0 {
            let l = self.enc.k_at_most(k - 1);
            let assume: Vec<Lit> = self.base.iter().copied().chain([l]).collect();
            self.trying(Bound::K, k - 1);
            match self.enc.solve(&assume) {
                Some(m) => {
                    self.read(&m);
                    k = self.structure.max_out_degree();
                }
                None => break,
            }
        }
        let l = self.enc.k_at_most(k);
        self.base.push(l);
        (self.progress)(Step::Minimal {
            bound: Bound::K,
            value: k,
        });
    }

    /// Phase 3: the least `T` at `C` (and `K`), first with the hinted colouring, then with any
    /// colouring as hard as [`Proofs`] asks. Returns whether `T` is proven least; a proven `T`
    /// becomes [`Known::t_lo`].
    fn least_t(&mut self) -> bool {
        let minimize_k = self.opts.minimize_k;
        self.t = self.structure.transition_count();
        let base_t = self.base_t();
        // A lower bound from an earlier call (same C, no K bound): every bound below it is
        // already known to be unsatisfiable.
        let t_lo = match self.known.t_lo {
            Some((c0, lo)) if c0 == self.c && !minimize_k => Some(lo),
            _ => None,
        };
        let t_floor = t_lo.unwrap_or(0);
        let hinted_floor = match minimize_k {
            false => self.jump_t(&base_t, t_floor),
            true => t_floor,
        };
        // Without proofs, the colouring just found serves as the hint when none was given.
        if let (None, Proofs::Skip) = (&self.hint, self.proofs) {
            self.hint = Some(self.structure.colors.clone());
        }
        if let (Some(hint), false) = (&self.hint, minimize_k) {
            // Fewer transitions with the hinted colouring first: easy calls that usually
            // end at the minimum, so that the free search below has one bound to refute.
            let mut hinted_base = base_t.clone();
            hinted_base.extend(self.enc.colouring(hint));
            self.t = self.descend_t(&hinted_base, hinted_floor.max(t_floor));
        }
        let transitions_exact = match (t_lo, self.proofs) {
            (Some(lo), _) if lo == self.t => true,
            (t_lo, Proofs::Skip) => self.candidate_t(&base_t, t_lo),
            (_, Proofs::Budget(budget)) => self.descend_t_within(&base_t, t_floor, budget),
            (_, Proofs::Quick(effort)) => self.descend_t_quick(&base_t, t_floor, effort),
            (Some(lo), Proofs::Full) if lo < self.t && self.hint.is_none() => {
                self.ascend_t(lo);
                true
            }
            (_, Proofs::Full) => {
                self.t = self.descend_t(&base_t, t_floor);
                true
            }
        };
        if !minimize_k && transitions_exact {
            self.known.t_lo = Some((self.c, self.t));
        }
        (self.progress)(Step::Minimal {
            bound: Bound::T,
            value: self.t,
        });
        self.stats.solver_calls += self.enc.new_calls();
        transitions_exact
    }

    /// One call straight to the latest machine's `T` (plus one without proofs), with the
    /// hinted colouring if any. Without proofs the first machine found has many more
    /// transitions than needed (the transitions are free even with a hinted colouring); one
    /// bounded call just above the latest machine's count usually lands near the least, where
    /// descending one transition at a time takes dozens of calls. With the hint the call is
    /// cheap; without, it is a free search and gets a deadline. With a budget (the final
    /// pass) the hint is the colouring of the latest machine, which nothing added since has
    /// ruled out: straight to its `T`. Returns the floor of the hinted descent: above the
    /// target when the call refuted it for the hinted colouring.
    fn jump_t(&mut self, base_t: &[Lit], t_floor: usize) -> usize {
        let jump = match self.proofs {
            Proofs::Skip => 1,
            Proofs::Budget(_) if self.hint.is_some() => 0,
            _ => return t_floor,
        };
        let c = self.c;
        let target = match (self.known.t_lo, self.known.last) {
            (Some((c0, lo)), Some(last)) if c0 == c && last.c == c => Some(lo.max(last.t) + jump),
            (_, Some(last)) if last.c == c => Some(last.t + jump),
            _ => None,
        };
        let Some((target, b)) = target
            .filter(|&b| b < self.t)
            .and_then(|b| Some((b, self.enc.total_t.at_most(b)?)))
        else {
            return t_floor;
        };
        self.trying(Bound::T, target);
        let mut assume: Vec<Lit> = base_t.iter().copied().chain([b]).collect();
        let found = match &self.hint {
            Some(h) => {
                assume.extend(self.enc.colouring(h));
                self.enc.solver.solve(&assume)
            }
            None => {
                match (self.enc.solver).solve_spending(&assume, &mut CANDIDATE_T_BUDGET.start()) {
                    Bounded::Sat(m) => Some(m),
                    _ => None,
                }
            }
        };
        match found {
            Some(m) => {
                self.read(&m);
                self.t = self.structure.transition_count();
                t_floor
            }
            // Proven for the hinted colouring only: its descent below stops above.
            None if self.hint.is_some() => target + 1,
            None => t_floor,
        }
    }

    /// Without proofs ([`Proofs::Skip`]), fewer transitions with any colouring only down to a
    /// proven bound `t_lo`: every step there finds a machine, and the step that fails (if the
    /// loop's constraints need more) proves a bound that later calls keep. A bound that timed
    /// out once is not tried again: the loop only adds constraints. Returns whether `T` is
    /// proven least.
    fn candidate_t(&mut self, base_t: &[Lit], t_lo: Option<usize>) -> bool {
        let Some(lo) = t_lo.filter(|&lo| lo > 0 && lo < self.t) else {
            return false;
        };
        let floor = match self.known.t_timed_out {
            Some((c1, b)) if c1 == self.c => lo.max(b + 1),
            _ => lo,
        };
        let exact = self.descend_t_within(base_t, floor, CANDIDATE_T_BUDGET);
        if !exact {
            self.known.t_timed_out = Some((self.c, self.t - 1));
        }
        exact && floor == lo
    }

    /// The least `T` by ascent from the proven bound `lo`: the first satisfiable bound is
    /// the least (used when no hint made the descent cheap).
    fn ascend_t(&mut self, lo: usize) {
        let mut bound = lo;
        while bound < self.t {
            let Some(b) = self.enc.total_t.at_most(bound) else {
                break;
            };
            self.trying(Bound::T, bound);
            let assume: Vec<Lit> = self.base.iter().copied().chain([b]).collect();
            if let Some(m) = self.enc.solve(&assume) {
                self.read(&m);
                self.t = self.structure.transition_count();
                break;
            }
            bound += 1;
        }
    }

    /// The least `T` from `self.t` down to `floor` under `base` ([`Solver::descend`] on the
    /// transition counter); `structure` ends as the machine of the last model found.
    fn descend_t(&mut self, base: &[Lit], floor: usize) -> usize {
        let enc = &mut *self.enc;
        let (vars, alphabet, total_t) = (&enc.vars, &enc.alphabet, &enc.total_t);
        let (read, structure, progress) = (&self.reader, &mut self.structure, &mut self.progress);
        enc.solver.descend(
            base,
            self.t,
            floor,
            |b| total_t.at_most(b),
            |b| {
                progress(Step::Trying {
                    bound: Bound::T,
                    value: b,
                })
            },
            |m| {
                *structure = read.structure(&m, vars, alphabet);
                structure.transition_count()
            },
        )
    }

    /// As [`Self::descend_t`] into `self.t`, each call on a fresh solver that gives up at
    /// `budget` in all; says whether the result is proven least (`false`: the budget ran out
    /// first).
    fn descend_t_within(&mut self, base: &[Lit], floor: usize, budget: Effort) -> bool {
        let mut allowance = budget.start();
        self.descend_t_by(base, floor, |solver, assume| {
            solver.solve_spending(assume, &mut allowance)
        })
    }

    /// As [`Self::descend_t`] into `self.t` while each call takes under [`QUICK_CALL`]; after
    /// a slower one, each further bound on a fresh solver within `effort` in all. Says whether
    /// the result is proven least.
    fn descend_t_quick(&mut self, base: &[Lit], floor: usize, effort: Effort) -> bool {
        let mut allowance = None;
        self.descend_t_by(base, floor, |solver, assume| {
            if let Some(allowance) = &mut allowance {
                return solver.solve_spending(assume, allowance);
            }
            let started = Instant::now();
            let answer = match solver.solve(assume) {
                Some(m) => Bounded::Sat(m),
                None if solver.stopped() => Bounded::Unknown,
                None => Bounded::Unsat,
            };
            if started.elapsed() > QUICK_CALL {
                allowance = Some(effort.start());
            }
            answer
        })
    }

    /// Fewer transitions than `self.t`, one bound at a time down to `floor`, each asked by
    /// `solve`; says whether the result is proven least (`false`: a call gave up).
    fn descend_t_by(
        &mut self,
        base: &[Lit],
        floor: usize,
        mut solve: impl FnMut(&mut Solver, &[Lit]) -> Bounded,
    ) -> bool {
        while self.t > floor {
            let Some(b) = self.enc.total_t.at_most(self.t - 1) else {
                break;
            };
            self.trying(Bound::T, self.t - 1);
            let assume: Vec<Lit> = base.iter().copied().chain([b]).collect();
            match solve(&mut self.enc.solver, &assume) {
                Bounded::Sat(m) => {
                    self.read(&m);
                    self.t = self.structure.transition_count();
                }
                Bounded::Unsat => break,
                Bounded::Unknown => return false,
            }
        }
        true
    }

    /// Phase 4 in the cube model: the least guard literal count `N` on the same solver, at the
    /// least `C` and `T` (with the machine's colouring unless every bound is proven). Returns
    /// the states and whether `N` is proven least; a proven `N` becomes [`Known::n_lo`].
    fn least_n(&mut self) -> (Vec<State>, bool) {
        let (c, t) = (self.c, self.t);
        let n = self.structure.literal_count();
        let start = match self.known.n_lo {
            Some((c0, t0, lo)) if c0 == c && t0 == t => lo,
            _ if !self.minimize_n => n,
            _ => 0,
        };
        // Descend from the current N; stop at the known lower bound.
        let mut base_n = self.base_t();
        base_n.extend(self.enc.total_t.at_most(t));
        if self.proofs != Proofs::Full {
            // The least N for this colouring: the free descent is the same kind of
            // proof the budget above gave up on.
            base_n.extend(self.enc.colouring(&self.structure.colors));
        }
        let (n, start) = self.jump_n(&base_n, n, start);
        let n = self.descend_n(&base_n, n, start);
        let (n, exact) = match (self.minimize_n, self.proofs) {
            (true, Proofs::Budget(budget)) => self.free_n_within(n, start, budget),
            (minimize_n, proofs) => (n, minimize_n && proofs == Proofs::Full),
        };
        if exact {
            self.known.n_lo = Some((c, t, n));
        }
        // Decoded with the cube model's slots: one list of transitions per state.
        let transitions = self.structure.cube_transitions.clone().unwrap_or_default();
        let states = (0..self.structure.c)
            .zip(transitions)
            .map(|(q, transitions)| State {
                name: format!("s{q}"),
                algorithm: self.structure.algorithms[q].clone(),
                transitions,
            })
            .collect();
        (states, exact)
    }

    /// One call straight to the latest machine's `N` (one literal more per extra transition):
    /// near it is where this one usually ends. Returns `N` and the floor of the descent,
    /// above the target when the call refuted it.
    fn jump_n(&mut self, base_n: &[Lit], n: usize, start: usize) -> (usize, usize) {
        let t = self.t;
        let target = (self.known.last)
            .filter(|l| l.c == self.c && l.t <= t)
            .map(|l| l.n + (t - l.t))
            .filter(|&b| b < n && b >= start);
        let Some(target) = target.filter(|_| self.minimize_n) else {
            return (n, start);
        };
        let Some(b) = self
            .enc
            .total_n
            .as_ref()
            .and_then(|tot| tot.at_most(target))
        else {
            return (n, start);
        };
        self.trying(Bound::N, target);
        let assume: Vec<Lit> = base_n.iter().copied().chain([b]).collect();
        match self.enc.solver.solve(&assume) {
            Some(m) => {
                self.read(&m);
                (self.structure.literal_count(), start)
            }
            None => (n, target + 1),
        }
    }

    /// The least `N` from `n` down to `start` under `base_n` ([`Solver::descend`] on the
    /// literal counter); `structure` ends as the machine of the last model found.
    fn descend_n(&mut self, base_n: &[Lit], n: usize, start: usize) -> usize {
        let enc = &mut *self.enc;
        let Some(total_n) = &enc.total_n else {
            return n;
        };
        let (vars, alphabet) = (&enc.vars, &enc.alphabet);
        let (read, structure, progress) = (&self.reader, &mut self.structure, &mut self.progress);
        enc.solver.descend(
            base_n,
            n,
            start,
            |b| total_n.at_most(b),
            |b| {
                progress(Step::Trying {
                    bound: Bound::N,
                    value: b,
                })
            },
            |m| {
                *structure = read.structure(&m, vars, alphabet);
                structure.literal_count()
            },
        )
    }

    /// Fewer literals than `n` with any colouring (at the least `C` and `T`), each call on a
    /// fresh solver within `budget` in all. Returns `N` and whether it is proven least
    /// (`false`: the budget ran out first).
    fn free_n_within(&mut self, mut n: usize, start: usize, budget: Effort) -> (usize, bool) {
        let mut allowance = budget.start();
        let mut free: Vec<Lit> = self.base_t();
        free.extend(self.enc.total_t.at_most(self.t));
        loop {
            if n <= start {
                return (n, true);
            }
            let Some(b) = self.enc.total_n.as_ref().and_then(|tot| tot.at_most(n - 1)) else {
                return (n, true);
            };
            self.trying(Bound::N, n - 1);
            let assume: Vec<Lit> = free.iter().copied().chain([b]).collect();
            match self.enc.solver.solve_spending(&assume, &mut allowance) {
                Bounded::Sat(m) => {
                    self.read(&m);
                    n = self.structure.literal_count();
                }
                Bounded::Unsat => return (n, true),
                Bounded::Unknown => return (n, false),
            }
        }
    }

    /// Phase 4 in the tree-exact model: guards minimized per state on the structure
    /// ([`guards::all_states`]), then on every other structure with the least `C` and `T`
    /// ([`least_guards_over_structures`]), until `deadline`. Returns the states and whether
    /// `N` is proven least; `structure` takes the colouring the guards belong to.
    fn least_guards(&mut self, deadline: Instant) -> (Vec<State>, bool) {
        let tree = self.reader.tree;
        let first = guards::all_states(&self.structure, tree, deadline);
        // The least N of this structure; other machines with C states and T
        // transitions may need fewer literals.
        let mut base_n = self.base_t();
        base_n.extend(self.enc.total_t.at_most(self.t));
        let read = &self.reader;
        let (states, exact, colors) = least_guards_over_structures(
            &mut *self.enc,
            tree,
            &base_n,
            &self.structure,
            first,
            deadline,
            &|m, enc| read.structure(m, &enc.vars, &enc.alphabet),
        );
        self.structure.colors = colors;
        (states, exact)
    }
}

/// How many structures [`least_guards_over_structures`] looks at, at most.
const MAX_STRUCTURES: usize = 10_000;

/// The guards with the fewest literals over every machine the assumptions `base` allow (the
/// least C and T): the structures (colourings of the tree, which fix every recorded move) are
/// enumerated on the solver, each blocked once seen (under an activation literal, so later
/// calls are not affected), and each one's guards are minimized. `first` is the first
/// structure's result. The count is proven least when the enumeration ends and every
/// structure's guards are proven minimal before `deadline`. Also returns the colouring of the
/// structure the guards belong to.
fn least_guards_over_structures(
    enc: &mut Encoding,
    tree: &ScenarioTree,
    base: &[Lit],
    first: &Structure,
    (mut best, mut exact): (Vec<State>, bool),
    deadline: Instant,
    decode: &dyn Fn(&Model, &Encoding) -> Structure,
) -> (Vec<State>, bool, Vec<usize>) {
    let literals = |states: &[State]| -> usize {
        (states.iter())
            .flat_map(|s| &s.transitions)
            .map(|t| t.guard.literal_count())
            .sum()
    };
    let active = enc.solver.new_lit();
    let mut assume = base.to_vec();
    assume.push(active);
    let mut colors = first.colors.clone();
    let mut best_colors = colors.clone();
    let mut complete = false;
    for _ in 0..MAX_STRUCTURES {
        let block: Vec<Lit> = std::iter::once(!active)
            .chain(enc.colouring(&colors).into_iter().map(|l| !l))
            .collect();
        enc.solver.add_clause(&block);
        if best
            .iter()
            .all(|s| s.transitions.iter().all(|t| t.guard.literal_count() == 0))
            || Instant::now() >= deadline
        {
            complete = literals(&best) == 0;
            break;
        }
        let Some(m) = enc.solver.solve(&assume) else {
            complete = true;
            break;
        };
        let structure = decode(&m, enc);
        let (states, ok) = guards::all_states(&structure, tree, deadline);
        exact &= ok;
        if literals(&states) < literals(&best) {
            best = states;
            best_colors = structure.colors.clone();
        }
        colors = structure.colors;
    }
    (best, exact && complete, best_colors)
}

/// One minimal ECC for the scenarios: least `C`, optionally least `K`, least `T`, then guards
/// with least `N` (Algorithm 1), on a fresh [`Synthesizer`]. Fails with
/// [`SatError::TooManyStates`] or [`SatError::OutOfBounds`] when no machine of at most
/// `opts.max_states` states reproduces the tree.
pub fn synthesize(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    opts: &Options,
    progress: Progress<'_>,
) -> Result<Synthesis, SatError> {
    Synthesizer::new(set, tree, opts).minimize(progress)
}

/// The question "an ECC with at most `c` states (and at most `t` transitions) reproduces the
/// tree" as one CNF formula: the encoding with every assumption of the solver call as a unit
/// clause, for an independent solver to answer ([`satisfiable`] asks varisat the same).
pub(crate) fn formula(
    tree: &ScenarioTree,
    opts: &Options,
    c: usize,
    t: Option<usize>,
) -> varisat::CnfFormula {
    let enc = Encoding::build(tree, c.max(1), opts, true);
    let mut assume = enc.base_assumptions();
    if let Some(b) = t.and_then(|t| enc.total_t.at_most(t)) {
        assume.push(b);
    }
    let kept = enc.solver.clauses().expect("clauses are kept");
    let mut f = varisat::CnfFormula::new();
    f.set_var_count(kept.var_count());
    for clause in kept.iter() {
        f.add_clause(clause);
    }
    if c == 0 {
        // No machine has no state.
        let l = f.new_lit();
        f.add_clause(&[l]);
        f.add_clause(&[!l]);
    }
    for a in assume {
        f.add_clause(&[a]);
    }
    f
}

/// The least machine of the tree-exact model with `c` states (the least, proven by the
/// caller): least `T` (proven), then guards with the fewest literals over every machine with
/// `c` states and that `T` (each colouring of the tree enumerated, each state's guards
/// minimized with its priority order; [`Synthesis::guards_exact`] when done within
/// `budget`). `hint` is the colouring of a machine with `c` states, tried first.
///
/// Its `T` and `N` bound the cube model from below at the same `c`: a cube machine restricted
/// to the recorded inputs is a tree-exact machine with the same colouring and no more edges;
/// with as many transitions as this `T`, each of them is the one edge of its source and
/// target, and its cubes, in their priority order, are guards that colouring admits (a cube
/// is a one-term DNF). So the closed loop's machines with `c` states and this `T`, which
/// reproduce the recordings too, need at least this `N` (when exact).
pub(crate) fn least_tree_exact(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    opts: &Options,
    c: usize,
    hint: Vec<usize>,
    budget: Duration,
) -> Result<Synthesis, SatError> {
    let opts = Options {
        max_out_degree: None,
        minimize_k: false,
        guard_budget: budget,
        fixed: Fixed {
            states: Some(c),
            ..opts.fixed
        },
        ..opts.clone()
    };
    let mut synth = Synthesizer::new(set, tree, &opts);
    synth.hint(hint);
    synth.minimize(&mut |_| {})
}

/// Whether an ECC with at most `c` states (and at most `t` transitions) reproduces the tree.
/// The building block of the minimization loops, exposed for tests of known minima.
pub(crate) fn satisfiable(tree: &ScenarioTree, opts: &Options, c: usize, t: Option<usize>) -> bool {
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
