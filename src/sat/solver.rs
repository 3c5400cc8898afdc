//! The one incremental solver every encoding writes into, and the loops that tighten a bound.
//!
//! In: clauses (through [`ExtendFormula`], so an encoding can write into a [`varisat::CnfFormula`]
//! in tests and into this solver in production) and assumption literals. Out: [`Model`]s, and the
//! figures of the run ([`SolverStats`]).
//!
//! Every bound of a minimization (states in use, transitions, guard literals, errors, inputs read)
//! is a solver *assumption*: a literal that says "at most `b`", usually a [`Totalizer`] output
//! ([`super::card`]). One solver therefore serves every bound of every loop, keeping what it
//! learnt; [`Solver::ascend`] (the least size that admits a machine) and [`Solver::descend`]
//! (tightening a counter from a model's value) are the loops all encodings share.
//!
//! [`Totalizer`]: super::card::Totalizer

use std::ops::RangeInclusive;
use varisat::{ExtendFormula, Lit, Var};

/// What a solver has been given and asked.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SolverStats {
    /// Variables allocated.
    pub variables: usize,
    /// Clauses added (assumptions are not clauses).
    pub clauses: usize,
    /// Solve calls made, budgeted ones ([`Solver::solve_within`]) included.
    pub calls: usize,
}

/// An incremental varisat solver that counts what it is given.
pub struct Solver {
    inner: varisat::Solver<'static>,
    stats: SolverStats,
    /// Every clause given, when kept (see [`Solver::keep_clauses`]).
    log: Option<varisat::CnfFormula>,
}

/// The outcome of a solve with a time budget.
pub enum Bounded {
    /// Satisfiable under the assumptions, with a model.
    Sat(Model),
    /// Unsatisfiable under the assumptions (in a minimization: nothing within the bounds they
    /// state).
    Unsat,
    /// The budget ran out first.
    Unknown,
}

/// Stops a solver at a deadline: varisat's solve loop has no interrupt, but it stops when a
/// proof processor fails.
struct Deadline(std::time::Instant);

impl varisat::checker::ProofProcessor for Deadline {
    fn process_step(
        &mut self,
        _step: &varisat::checker::CheckedProofStep,
        _data: varisat::checker::CheckerData,
    ) -> Result<(), anyhow::Error> {
        if std::time::Instant::now() > self.0 {
            Err(anyhow::anyhow!("time budget exhausted"))
        } else {
            Ok(())
        }
    }
}

impl Default for Solver {
    fn default() -> Self {
        Solver::new()
    }
}

impl Solver {
    /// An empty solver that keeps no copy of its clauses.
    pub fn new() -> Solver {
        Solver {
            inner: varisat::Solver::new(),
            stats: SolverStats::default(),
            log: None,
        }
    }

    /// Keeps a copy of every clause from now on, for [`Self::solve_within`]. Call before any
    /// clause is given.
    pub fn keep_clauses(&mut self) {
        self.log = Some(varisat::CnfFormula::new());
    }

    /// Whether [`Self::keep_clauses`] was called.
    pub fn keeps_clauses(&self) -> bool {
        self.log.is_some()
    }

    /// Solves the clauses kept so far under `assumptions` on a fresh solver that gives up at
    /// `deadline` (`Unknown`), so that a proof that may take minutes can be tried for seconds.
    /// The incremental solver is untouched. `Unknown` without kept clauses.
    pub fn solve_within(&mut self, assumptions: &[Lit], deadline: std::time::Instant) -> Bounded {
        let Some(log) = &self.log else {
            return Bounded::Unknown;
        };
        self.stats.calls += 1;
        let mut stop = Deadline(deadline);
        let mut fresh = varisat::Solver::new();
        fresh.add_proof_processor(&mut stop);
        fresh.add_formula(log);
        fresh.assume(assumptions);
        match fresh.solve() {
            Ok(true) => match fresh.model() {
                Some(m) => Bounded::Sat(Model::new(&m)),
                None => Bounded::Unknown,
            },
            Ok(false) => Bounded::Unsat,
            Err(_) => Bounded::Unknown,
        }
    }

    /// Every clause given so far, when kept (see [`Solver::keep_clauses`]).
    pub fn clauses(&self) -> Option<&varisat::CnfFormula> {
        self.log.as_ref()
    }

    /// Variables and clauses written so far, and solver calls made.
    pub fn stats(&self) -> SolverStats {
        self.stats
    }

    /// Solves under `assumptions` (they hold for this call only); the model when satisfiable.
    pub fn solve(&mut self, assumptions: &[Lit]) -> Option<Model> {
        self.stats.calls += 1;
        self.inner.assume(assumptions);
        if self
            .inner
            .solve()
            .expect("varisat does not fail without proof output")
        {
            Some(Model::new(&self.inner.model().expect("model after SAT")))
        } else {
            None
        }
    }

    /// The least value `b` of `range` whose assumptions `bound(b)` are satisfiable, with its
    /// model, by ascent (`None`: none is). `trying` hears every value before its call.
    pub fn ascend(
        &mut self,
        range: RangeInclusive<usize>,
        bound: impl Fn(usize) -> Vec<Lit>,
        mut trying: impl FnMut(usize),
    ) -> Option<(usize, Model)> {
        for b in range {
            trying(b);
            if let Some(m) = self.solve(&bound(b)) {
                return Some((b, m));
            }
        }
        None
    }

    /// The least value of a quantity that a bound literal caps, by descent: `value` is the
    /// quantity in a model already found. While `value > floor` and `bound(value - 1)` exists,
    /// solves under `base` and that bound; `found` reads every model's value (and keeps what it
    /// needs of the model). Returns the least value: unsatisfiable one below, or at `floor`.
    /// `trying` hears every bound before its call.
    pub fn descend(
        &mut self,
        base: &[Lit],
        mut value: usize,
        floor: usize,
        bound: impl Fn(usize) -> Option<Lit>,
        mut trying: impl FnMut(usize),
        mut found: impl FnMut(Model) -> usize,
    ) -> usize {
        while value > floor {
            let Some(b) = bound(value - 1) else {
                break;
            };
            trying(value - 1);
            let assume: Vec<Lit> = base.iter().copied().chain([b]).collect();
            match self.solve(&assume) {
                Some(m) => value = found(m),
                None => break,
            }
        }
        value
    }
}

impl ExtendFormula for Solver {
    fn add_clause(&mut self, clause: &[Lit]) {
        self.stats.clauses += 1;
        self.inner.add_clause(clause);
        if let Some(log) = &mut self.log {
            log.add_clause(clause);
        }
    }
    fn new_var(&mut self) -> Var {
        self.stats.variables += 1;
        let v = self.inner.new_var();
        if let Some(log) = &mut self.log {
            log.set_var_count(log.var_count().max(v.index() + 1));
        }
        v
    }
}

/// A satisfying assignment, looked up by literal.
pub struct Model(Vec<bool>);

impl Model {
    /// The assignment that makes every literal of `lits` true (varisat's model);
    /// variables not mentioned are false.
    pub fn new(lits: &[Lit]) -> Model {
        let mut values = vec![false; lits.len() + 1];
        for l in lits {
            let i = l.var().index();
            if i >= values.len() {
                values.resize(i + 1, false);
            }
            values[i] = l.is_positive();
        }
        Model(values)
    }

    /// Whether `l` is true in the model (a variable beyond the model counts as false).
    pub fn value(&self, l: Lit) -> bool {
        self.0.get(l.var().index()).copied().unwrap_or(false) == l.is_positive()
    }

    /// How many of `lits` are true.
    pub fn count(&self, lits: &[Lit]) -> usize {
        lits.iter().filter(|&&l| self.value(l)).count()
    }
}
