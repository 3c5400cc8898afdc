//! A verified machine made smaller by local moves that the in-process checker accepts: the
//! guide's machine is least only for the recordings and the guide's own runs, and carries
//! transitions and literals those runs ask for but the properties do not.
//!
//! In: the recordings, a [`Check`] and a machine that reproduces them and keeps every
//! property. Out: the smallest machine the moves reach ([`shrink`]), which reproduces the
//! recordings and which the in-process checker finds keeping every property; the caller has
//! NuSMV judge it (an in-process verdict guides, never certifies).
//!
//! Moves, each kept when the machine still reproduces every recording and keeps every
//! property, the first that helps taken and the search restarted from it until none helps:
//! merging two states (the second's transitions appended to the first's, every transition
//! into it redirected), dropping a transition (states no transition reaches any more
//! dropped too), and dropping one literal of a guard. When none helps, every state's guards
//! are written anew ([`reguarded`]): the fewest literals (SAT, [`crate::sat::guards`]) that
//! answer as the machine does on every pair of state and inputs the recordings and the
//! closed loop reach, other inputs being don't-cares. The closed loop stays the same, so
//! the verdicts do; the local moves start again from the new guards. When that does not help
//! either, another state becomes the initial one ([`rerooted`]; the same size, kept when it
//! keeps everything) and a move or new guards after it are looked for: the guide's machine may
//! start in a state the closed loop also enters for other work, whose transitions then serve
//! both. Each step makes the machine smaller in (C, T, N); nothing proves the end least.

use super::Check;
use crate::check;
use crate::ecc::{Conventions, Ecc, Guard, Run, Size, StateId};
use crate::sat::guards::{minimize_state, GuardProblem};
use crate::scenario::ScenarioSet;
use rayon::prelude::*;
use std::time::{Duration, Instant};

/// A machine made smaller by the moves.
pub(crate) struct Shrunk {
    /// The machine.
    pub(crate) ecc: Ecc,
    /// Whether no move helps any more (else [`MAX_TRIES`] or the deadline ended the search).
    pub(crate) converged: bool,
}

/// Most moves judged by the in-process checker: a bound on the work that, unlike a time,
/// gives the same machine on every run. The moves after another initial state are not
/// counted: at most one pass per state.
const MAX_TRIES: usize = 3_000;

/// The least time between two reports of [`shrink`]'s progress.
pub(crate) const PROGRESS_EVERY: Duration = Duration::from_secs(2);

/// The machine reached from `ecc` by the moves (module documentation) until none helps, after
/// [`MAX_TRIES`] moves judged, or at `deadline` (the run's time limit); `None` when no move
/// helps or the in-process checker cannot judge this plant. Every machine it keeps is in
/// `conventions` (a merge into a start state is refused). `progress` hears the smallest
/// machine so far and the moves judged towards [`MAX_TRIES`], at most once every
/// [`PROGRESS_EVERY`].
pub(crate) fn shrink(
    set: &ScenarioSet,
    check: &Check,
    ecc: &Ecc,
    conventions: Conventions,
    deadline: Instant,
    progress: &mut dyn FnMut(Size, usize),
) -> Option<Shrunk> {
    let keeps = Keeps::of(set, check, conventions)?;
    let mut best = ecc.clone();
    let mut improved = false;
    let mut converged = false;
    let mut tries = 0;
    let mut reported = Instant::now();
    while Instant::now() < deadline {
        let (kept, judged) = first_kept_move(&keeps, &best, MAX_TRIES - tries, deadline);
        tries += judged;
        let smaller = match kept {
            Some(m) => Some(m),
            None if Instant::now() >= deadline || tries >= MAX_TRIES => break,
            None => {
                let guards_until = deadline.min(Instant::now() + GUARD_TIME);
                let memo = &mut check::PlantMemo::default();
                (keeps.by_new_guards(&best, best.size(), guards_until, memo))
                    .or_else(|| after_new_root(&keeps, &best, deadline, guards_until))
            }
        };
        match smaller {
            Some(m) => {
                best = m;
                improved = true;
                if reported.elapsed() >= PROGRESS_EVERY {
                    progress(best.size(), tries);
                    reported = Instant::now();
                }
            }
            None => {
                converged = true;
                break;
            }
        }
    }
    improved.then_some(Shrunk {
        ecc: best,
        converged,
    })
}

/// What a machine the moves reach must do: stay in the asked form, reproduce the recordings
/// and keep every property in the in-process checker.
struct Keeps<'a> {
    set: &'a ScenarioSet,
    check: &'a Check,
    conventions: Conventions,
    model: &'a crate::plant::Model,
    wiring: check::Wiring,
    automata: check::Automata,
    limits: check::Limits,
}

impl<'a> Keeps<'a> {
    /// `None` when the in-process checker cannot read the plant of `check`.
    fn of(set: &'a ScenarioSet, check: &'a Check, conventions: Conventions) -> Option<Keeps<'a>> {
        let problem = &check.problem;
        let model = problem.model.as_ref().ok()?;
        Some(Keeps {
            set,
            check,
            conventions,
            model,
            wiring: check::Wiring::new(model, &problem.coupling).ok()?,
            automata: check::Automata::of(&problem.props),
            limits: check::Limits::default(),
        })
    }

    /// Whether `e` keeps everything; `memo` holds the plant states met so far on this core
    /// (the machines judged differ, the plant does not).
    fn judge(&self, memo: &mut check::PlantMemo, e: &Ecc) -> bool {
        let props = &self.check.problem.props;
        self.conventions.broken(e).is_none()
            && self.set.check(e).is_ok()
            && check::Judge::of(self.model, &self.wiring, e, &self.limits, memo)
                .and_then(|j| j.all_hold(props, &self.automata))
                .unwrap_or(false)
    }

    /// `e` with its guards written anew ([`reguarded`], until `until`) when that makes it
    /// smaller than `size` and it keeps everything.
    fn by_new_guards(
        &self,
        e: &Ecc,
        size: Size,
        until: Instant,
        memo: &mut check::PlantMemo,
    ) -> Option<Ecc> {
        (reguarded(self.set, self.check, e, until))
            .filter(|x| x.size().is_smaller_than(&size) && self.judge(memo, x))
    }
}

/// The first move from `best` (in the order of [`moves`], at most `most` of them) that makes
/// it smaller and keeps everything, and how many moves were judged.
fn first_kept_move(
    keeps: &Keeps<'_>,
    best: &Ecc,
    most: usize,
    deadline: Instant,
) -> (Option<Ecc>, usize) {
    let size = best.size();
    let mut smaller: Vec<Ecc> = (moves(best).into_iter())
        .filter(|m| m.size().is_smaller_than(&size))
        .take(most)
        .collect();
    // The first move in order that keeps everything, as one core would find it, judged on
    // every core: the machine reached does not depend on the cores or their timing.
    let kept = (smaller.par_iter())
        .map_init(check::PlantMemo::default, |memo, m| {
            Instant::now() < deadline && keeps.judge(memo, m)
        })
        .position_first(|kept| kept);
    match kept {
        Some(i) => (Some(smaller.swap_remove(i)), i + 1),
        None => (None, smaller.len()),
    }
}

/// Another state as the initial one ([`rerooted`]): the same size, but a state entered only
/// at the start may then merge or lose transitions. The first root (in order) that keeps
/// everything and after which a move or new guards (written until `guards_until`) make the
/// machine smaller than `best`, that machine.
fn after_new_root(
    keeps: &Keeps<'_>,
    best: &Ecc,
    deadline: Instant,
    guards_until: Instant,
) -> Option<Ecc> {
    let size = best.size();
    let smaller_after = |m: &Ecc, memo: &mut check::PlantMemo| {
        let by_move = (moves(m).into_iter())
            .filter(|x| x.size().is_smaller_than(&size))
            .find(|x| Instant::now() < deadline && keeps.judge(memo, x));
        by_move.or_else(|| keeps.by_new_guards(m, size, guards_until, memo))
    };
    let roots: Vec<Ecc> = (1..best.states.len()).map(|r| rerooted(best, r)).collect();
    (roots.par_iter())
        .map_init(check::PlantMemo::default, |memo, m| {
            (Instant::now() < deadline && keeps.judge(memo, m))
                .then(|| smaller_after(m, memo))
                .flatten()
        })
        .find_map_first(|found| found)
}

/// The longest the guards of one machine are written anew ([`reguarded`]); past it each
/// state keeps the fewest literals found so far.
const GUARD_TIME: Duration = Duration::from_secs(2);

/// `ecc` with every state's guards written anew: per state, the fewest literals that answer
/// as `ecc` does (the same transition's target, or none) on every input vector the state
/// sees in the recordings or in the closed loop with the plant; a state keeps its guards
/// where the new ones are no fewer. `None` when the in-process checker cannot explore the
/// closed loop.
fn reguarded(set: &ScenarioSet, check: &Check, ecc: &Ecc, deadline: Instant) -> Option<Ecc> {
    let problem = &check.problem;
    let model = problem.model.as_ref().ok()?;
    let wiring = check::Wiring::new(model, &problem.coupling).ok()?;
    let mut seen = check::reached_inputs(model, &wiring, ecc, &check::Limits::default()).ok()?;
    for sc in &set.scenarios {
        let mut run = Run::new(ecc);
        for step in &sc.steps {
            seen.push((run.state, step.inputs.clone()));
            run.step(&step.inputs);
        }
    }
    let mut per_state = vec![Vec::new(); ecc.states.len()];
    for (q, x) in seen {
        if !per_state[q.0].contains(&x) {
            per_state[q.0].push(x);
        }
    }
    let mut e = ecc.clone();
    for (q, xs) in per_state.iter().enumerate() {
        let p = guard_problem(ecc, q, xs);
        let fresh = minimize_state(&p, deadline).transitions;
        let literals = |ts: &[crate::ecc::Transition]| -> (usize, usize) {
            (ts.iter().map(|t| t.guard.literal_count()).sum(), ts.len())
        };
        if literals(&fresh) < literals(&e.states[q].transitions) {
            e.states[q].transitions = fresh;
        }
    }
    Some(reachable(e))
}

/// What state `q` of `ecc` answers on the input vectors `xs`, as a guard problem: per target
/// the vectors on which a transition to it fires, and those on which none does.
fn guard_problem(ecc: &Ecc, q: usize, xs: &[Vec<bool>]) -> GuardProblem {
    let mut p = GuardProblem {
        inputs: ecc.inputs.len(),
        ..GuardProblem::default()
    };
    for x in xs {
        let fired = ecc.states[q].fired(x);
        let Some(t) = fired else {
            p.negative.push(x.clone());
            continue;
        };
        let i = match p.targets.iter().position(|&d| d == t.target.0) {
            Some(i) => i,
            None => {
                p.targets.push(t.target.0);
                p.positive.push(Vec::new());
                p.targets.len() - 1
            }
        };
        p.positive[i].push(x.clone());
    }
    p
}

/// Every machine one move away from `ecc`: merges first (they save the most), then dropped
/// transitions, then dropped literals.
fn moves(ecc: &Ecc) -> Vec<Ecc> {
    let c = ecc.states.len();
    let mut all = Vec::new();
    for b in 1..c {
        for a in 0..b {
            all.push(merged(ecc, a, b));
        }
    }
    for (q, st) in ecc.states.iter().enumerate() {
        for i in 0..st.transitions.len() {
            let mut e = ecc.clone();
            e.states[q].transitions.remove(i);
            all.push(reachable(e));
        }
    }
    for (q, st) in ecc.states.iter().enumerate() {
        for (i, t) in st.transitions.iter().enumerate() {
            let Some(terms) = t.guard.as_dnf() else {
                continue;
            };
            for (j, term) in terms.iter().enumerate() {
                for k in 0..term.len() {
                    let mut fewer = terms.clone();
                    fewer[j].remove(k);
                    let mut e = ecc.clone();
                    e.states[q].transitions[i].guard = Guard::dnf(&fewer);
                    all.push(e);
                }
            }
        }
    }
    all
}

/// `ecc` with state `b` merged into state `a < b`: `b`'s transitions after `a`'s, every
/// transition into `b` going to `a`, the states after `b` renumbered.
fn merged(ecc: &Ecc, a: usize, b: usize) -> Ecc {
    let mut e = ecc.clone();
    let moved = e.states.remove(b).transitions;
    e.states[a].transitions.extend(moved);
    retargeted(&mut e, |q| match q {
        q if q == b => a,
        q if q > b => q - 1,
        q => q,
    });
    reachable(e)
}

/// `ecc` started in state `r` instead of state 0 (the two swap numbers; the initial outputs
/// stay), without the states no longer reached.
fn rerooted(ecc: &Ecc, r: usize) -> Ecc {
    let mut e = ecc.clone();
    e.states.swap(0, r);
    retargeted(&mut e, |q| match q {
        0 => r,
        q if q == r => 0,
        q => q,
    });
    reachable(e)
}

/// Every transition of `ecc` sent to the state `number` gives its target.
fn retargeted(ecc: &mut Ecc, number: impl Fn(usize) -> usize) {
    for st in &mut ecc.states {
        for t in &mut st.transitions {
            t.target = StateId(number(t.target.0));
        }
    }
}

/// `ecc` without the states no transition path from the initial state reaches, the rest
/// renumbered in order.
fn reachable(mut ecc: Ecc) -> Ecc {
    let mut seen = vec![false; ecc.states.len()];
    let mut stack = vec![0];
    seen[0] = true;
    while let Some(q) = stack.pop() {
        for t in &ecc.states[q].transitions {
            if !seen[t.target.0] {
                seen[t.target.0] = true;
                stack.push(t.target.0);
            }
        }
    }
    let mut index = vec![0; seen.len()];
    let mut next = 0;
    for (q, &s) in seen.iter().enumerate() {
        index[q] = next;
        next += usize::from(s);
    }
    let mut q = 0;
    ecc.states.retain(|_| {
        q += 1;
        seen[q - 1]
    });
    retargeted(&mut ecc, |q| index[q]);
    ecc
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::{Algorithm, State, Transition};

    fn state(transitions: Vec<(usize, Guard)>) -> State {
        State {
            name: String::new(),
            algorithm: Algorithm::keep_all(crate::ecc::AlgorithmKind::Tri, 0),
            transitions: (transitions.into_iter())
                .map(|(q, guard)| Transition {
                    target: StateId(q),
                    guard,
                })
                .collect(),
        }
    }

    /// The guards written anew answer as the machine on every input vector the state saw (the
    /// same target, or none) with the fewest literals: here one literal where the machine has
    /// two, the unseen vectors being don't-cares.
    #[test]
    fn new_guards_answer_as_the_machine_where_the_state_was_seen() {
        let x = |i: usize| Guard::Var(crate::ecc::InputId(i));
        let ecc = Ecc {
            inputs: vec!["a".into(), "b".into()],
            outputs: vec![],
            initial_outputs: vec![],
            states: vec![
                state(vec![(1, Guard::And(vec![x(0), x(1)]))]),
                state(vec![(0, Guard::True)]),
            ],
        };
        let seen = vec![vec![true, true], vec![false, false]];
        let p = guard_problem(&ecc, 0, &seen);
        assert_eq!(p.targets, vec![1]);
        assert_eq!(p.positive, vec![vec![vec![true, true]]]);
        assert_eq!(p.negative, vec![vec![false, false]]);
        let fresh = minimize_state(&p, Instant::now() + Duration::from_secs(5)).transitions;
        assert_eq!(fresh.len(), 1);
        assert_eq!(fresh[0].guard.literal_count(), 1);
        for x in &seen {
            let before = ecc.states[0].transitions[0].guard.eval(x);
            assert_eq!(fresh[0].guard.eval(x), before, "{x:?}");
        }
    }

    /// A machine of one input and no outputs with these states.
    fn machine(states: Vec<State>) -> Ecc {
        Ecc {
            inputs: vec!["x".into()],
            outputs: vec![],
            initial_outputs: vec![],
            states,
        }
    }

    /// Each state's transitions' targets, in order.
    fn targets(e: &Ecc) -> Vec<Vec<usize>> {
        (e.states.iter())
            .map(|s| s.transitions.iter().map(|t| t.target.0).collect())
            .collect()
    }

    /// Rerooting swaps the numbers of the old and the new initial state, redirects every
    /// transition with them, and drops what the new initial state does not reach.
    #[test]
    fn a_new_root_swaps_numbers_and_unreached_states_go() {
        let ecc = machine(vec![
            state(vec![(2, Guard::True)]),
            state(vec![(0, Guard::True)]),
            state(vec![(1, Guard::True), (2, Guard::True)]),
        ]);
        let r = rerooted(&ecc, 2);
        // Old 2 is now 0 (it goes to old 1 and itself), old 1 to old 0, now 2.
        assert_eq!(targets(&r), vec![vec![1, 0], vec![2], vec![0]]);
        // A root that reaches only itself keeps only itself.
        let mut lone = ecc.clone();
        lone.states[1].transitions[0].target = StateId(1);
        assert_eq!(rerooted(&lone, 1).states.len(), 1);
    }

    #[test]
    fn a_merge_redirects_and_renumbers_and_unreachable_states_go() {
        let ecc = machine(vec![
            state(vec![(1, Guard::True)]),
            state(vec![(2, Guard::True)]),
            state(vec![(0, Guard::True)]),
            state(vec![(0, Guard::True)]),
        ]);
        let m = merged(&ecc, 0, 1);
        // State 3 was never reached; state 2 becomes 1, state 1's transition now 0's second.
        assert_eq!(m.states.len(), 2);
        assert_eq!(targets(&m), vec![vec![0, 1], vec![0]]);
    }
}
