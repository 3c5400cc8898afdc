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
//! A solver made [`Solver::until`] a [`Deadline`] stops its calls there: varisat's search loop
//! has no interrupt, but it stops when writing its proof fails, so such a solver writes its
//! proof (varisat's own format, the one that takes assumptions) into a sink that fails once the
//! deadline has passed. A call stopped so, and every call after it, answers "no model"; the
//! caller that set the deadline discards the result ([`crate::deadline`]).
//!
//! [`Totalizer`]: super::card::Totalizer

use crate::deadline::Deadline;
use std::ops::RangeInclusive;
use std::time::{Duration, Instant};
use varisat::{ExtendFormula, Lit, Var};

/// What a solver has been given and asked.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub(crate) struct SolverStats {
    /// Variables allocated.
    pub(crate) variables: usize,
    /// Clauses added (assumptions are not clauses).
    pub(crate) clauses: usize,
    /// Solve calls made, budgeted ones ([`Solver::solve_within`]) included.
    pub(crate) calls: usize,
}

/// An incremental varisat solver that counts what it is given.
pub(crate) struct Solver {
    inner: varisat::Solver<'static>,
    stats: SolverStats,
    /// Every clause given, when kept (see [`Solver::keep_clauses`]).
    log: Option<varisat::CnfFormula>,
    /// Where every call stops.
    deadline: Deadline,
    /// A call was stopped at the deadline: varisat cannot be asked again.
    stopped: bool,
}

/// The outcome of a solve with a time budget.
pub(crate) enum Bounded {
    /// Satisfiable under the assumptions, with a model.
    Sat(Model),
    /// Unsatisfiable under the assumptions (in a minimization: nothing within the bounds they
    /// state).
    Unsat,
    /// The budget ran out first.
    Unknown,
}

/// How much a budgeted solve ([`Solver::solve_spending`]) may do before it answers `Unknown`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Effort {
    /// Until this much time has passed: what a user sets in seconds.
    Time(Duration),
    /// Until the solver has written this many bytes of its proof (the clauses it learns and
    /// deletes). Counted in the search's own steps, it gives the same answer on every machine
    /// and under any load, so that the loop's own choices (how far a candidate's `T` may
    /// descend) do not depend on the clock.
    Work(u64),
}

impl Effort {
    /// The allowance for the calls this effort covers, starting now.
    pub(crate) fn start(self) -> Allowance {
        match self {
            Effort::Time(d) => Allowance::until(Instant::now() + d),
            Effort::Work(bytes) => Allowance {
                until: None,
                work: bytes,
            },
        }
    }
}

/// What is left of an [`Effort`] across the calls it covers.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Allowance {
    until: Option<Instant>,
    work: u64,
}

impl Allowance {
    /// Every call stops at `at`.
    pub(crate) fn until(at: Instant) -> Allowance {
        Allowance {
            until: Some(at),
            work: u64::MAX,
        }
    }
}

/// The proof sink of a solver with a deadline or of a budgeted solve: it takes bytes until
/// the allowance (its own, or one lent) is spent or the time is up, then fails, which stops
/// the solver's search.
struct Meter<A: std::borrow::BorrowMut<Allowance>>(A);

impl<A: std::borrow::BorrowMut<Allowance>> std::io::Write for Meter<A> {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        let allowance = self.0.borrow_mut();
        let spent = allowance.until.is_some_and(|at| Instant::now() >= at);
        let len = buf.len() as u64;
        if spent || len > allowance.work {
            allowance.work = 0;
            return Err(std::io::Error::new(
                std::io::ErrorKind::TimedOut,
                "budget spent",
            ));
        }
        allowance.work -= len;
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        self.write(&[]).map(|_| ())
    }
}

impl Default for Solver {
    fn default() -> Self {
        Solver::new()
    }
}

impl Solver {
    /// An empty solver that keeps no copy of its clauses.
    pub(crate) fn new() -> Solver {
        Solver::until(Deadline::NONE)
    }

    /// An empty solver whose calls stop at `deadline` (module documentation).
    pub(crate) fn until(deadline: Deadline) -> Solver {
        let mut inner = varisat::Solver::new();
        if let Some(at) = deadline.instant() {
            inner.write_proof(Meter(Allowance::until(at)), varisat::ProofFormat::Varisat);
        }
        Solver {
            inner,
            stats: SolverStats::default(),
            log: None,
            deadline,
            stopped: false,
        }
    }

    /// Whether a call was stopped at the deadline (its answer, and every later one, means
    /// nothing).
    pub(crate) fn stopped(&self) -> bool {
        self.stopped
    }

    /// Keeps a copy of every clause from now on, for [`Self::solve_within`]. Call before any
    /// clause is given.
    pub(crate) fn keep_clauses(&mut self) {
        self.log = Some(varisat::CnfFormula::new());
    }

    /// Whether [`Self::keep_clauses`] was called.
    pub(crate) fn keeps_clauses(&self) -> bool {
        self.log.is_some()
    }

    /// Solves the clauses kept so far under `assumptions` on a fresh solver that gives up at
    /// `deadline` (`Unknown`), so that a proof that may take minutes can be tried for seconds.
    /// The incremental solver is untouched. `Unknown` without kept clauses.
    pub(crate) fn solve_within(&mut self, assumptions: &[Lit], deadline: Instant) -> Bounded {
        self.solve_spending(assumptions, &mut Allowance::until(deadline))
    }

    /// As [`Self::solve_within`], spending from `allowance` (what is left stays in it for the
    /// next call); the solver's own deadline caps it.
    pub(crate) fn solve_spending(
        &mut self,
        assumptions: &[Lit],
        allowance: &mut Allowance,
    ) -> Bounded {
        let Some(log) = &self.log else {
            return Bounded::Unknown;
        };
        if self.stopped || self.deadline.passed() {
            return Bounded::Unknown;
        }
        self.stats.calls += 1;
        if let Some(at) = self.deadline.instant() {
            allowance.until = Some(allowance.until.map_or(at, |u| u.min(at)));
        }
        let mut fresh = varisat::Solver::new();
        fresh.write_proof(Meter(allowance), varisat::ProofFormat::Varisat);
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
    pub(crate) fn clauses(&self) -> Option<&varisat::CnfFormula> {
        self.log.as_ref()
    }

    /// Variables and clauses written so far, and solver calls made.
    pub(crate) fn stats(&self) -> SolverStats {
        self.stats
    }

    /// Solves under `assumptions` (they hold for this call only); the model when satisfiable.
    /// With a deadline ([`Solver::until`]): `None` once it has passed.
    pub(crate) fn solve(&mut self, assumptions: &[Lit]) -> Option<Model> {
        self.stats.calls += 1;
        if self.stopped || self.deadline.passed() {
            self.stopped = true;
            return None;
        }
        self.inner.assume(assumptions);
        match self.inner.solve() {
            Ok(true) => Some(Model::new(&self.inner.model().expect("model after SAT"))),
            Ok(false) => None,
            // Only the deadline's proof sink fails.
            Err(e) => {
                assert!(
                    self.deadline.instant().is_some(),
                    "varisat does not fail without proof output: {e}"
                );
                self.stopped = true;
                None
            }
        }
    }

    /// The least value `b` of `range` whose assumptions `bound(b)` are satisfiable, with its
    /// model, by ascent (`None`: none is). `trying` hears every value before its call.
    pub(crate) fn ascend(
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
    pub(crate) fn descend(
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
pub(crate) struct Model(Vec<bool>);

impl Model {
    /// The assignment that makes every literal of `lits` true (varisat's model);
    /// variables not mentioned are false.
    pub(crate) fn new(lits: &[Lit]) -> Model {
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
    pub(crate) fn value(&self, l: Lit) -> bool {
        self.0.get(l.var().index()).copied().unwrap_or(false) == l.is_positive()
    }

    /// How many of `lits` are true.
    pub(crate) fn count(&self, lits: &[Lit]) -> usize {
        lits.iter().filter(|&&l| self.value(l)).count()
    }
}

/// The pigeonhole formula: `holes + 1` pigeons in `holes` holes, unsatisfiable and hard for
/// resolution, so a CDCL solver works on it for long (minutes from 11 holes on): a job that
/// only a deadline ends, for tests.
#[cfg(test)]
pub(crate) fn pigeons(s: &mut Solver, holes: usize) {
    let p: Vec<Vec<Lit>> = (0..=holes)
        .map(|_| (0..holes).map(|_| s.new_lit()).collect())
        .collect();
    for row in &p {
        s.add_clause(row);
    }
    for h in 0..holes {
        for a in 0..p.len() {
            for b in a + 1..p.len() {
                s.add_clause(&[!p[a][h], !p[b][h]]);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::{Duration, Instant};

    #[test]
    fn a_call_stops_at_the_deadline_and_every_later_one_too() {
        let mut s = Solver::until(Deadline::after(Duration::from_millis(200)));
        pigeons(&mut s, 11);
        let t = Instant::now();
        assert!(s.solve(&[]).is_none());
        assert!(s.stopped());
        // Generous: the point is that it returns at all (the proof alone takes minutes).
        assert!(t.elapsed() < Duration::from_secs(30), "{:?}", t.elapsed());
        assert!(s.solve(&[]).is_none());
        assert!(matches!(
            s.solve_within(&[], Instant::now() + Duration::from_secs(60)),
            Bounded::Unknown
        ));
    }

    #[test]
    fn a_deadline_far_away_changes_no_answer() {
        let far = Deadline::after(Duration::from_secs(3600));
        for holes in 1..5 {
            let (mut a, mut b) = (Solver::new(), Solver::until(far));
            pigeons(&mut a, holes);
            pigeons(&mut b, holes);
            assert!(a.solve(&[]).is_none());
            assert!(b.solve(&[]).is_none());
            assert!(!b.stopped());
        }
        let mut s = Solver::until(far);
        let x = s.new_lit();
        s.add_clause(&[x]);
        assert!(s.solve(&[]).is_some_and(|m| m.value(x)));
        assert!(s.solve(&[!x]).is_none());
        assert!(!s.stopped());
    }

    #[test]
    fn a_work_budget_ends_a_hard_call_and_spends_the_same_on_every_run() {
        let spend = |holes: usize, work: u64| {
            let mut s = Solver::new();
            s.keep_clauses();
            pigeons(&mut s, holes);
            let mut allowance = Effort::Work(work).start();
            let answer = s.solve_spending(&[], &mut allowance);
            (answer, allowance.work)
        };
        // Eleven holes take minutes: the budget ends the call, and nothing is left of it.
        let (answer, left) = spend(11, 200_000);
        assert!(matches!(answer, Bounded::Unknown));
        assert_eq!(left, 0);
        // Four holes are refuted well within it, and two runs spend exactly the same.
        let (answer, left) = spend(4, 10_000_000);
        assert!(matches!(answer, Bounded::Unsat));
        assert!(left < 10_000_000);
        assert_eq!(spend(4, 10_000_000).1, left);
    }
}
