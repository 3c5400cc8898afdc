//! Whether two machines over one interface behave alike, and if not, the shortest input
//! sequence that tells them apart.
//!
//! In: two [`Ecc`]s with the same inputs and outputs. Out: [`Difference`] (or `None` for
//! equivalent machines): the inputs of each `REQ` from the initial states, and what each
//! machine answers to the last one. Behaviour is what [`Run::step`] shows a recording: per
//! `REQ`, `CNF` with the output values, or nothing.
//!
//! The search is breadth-first over pairs of configurations (state and output values of each
//! machine), so the sequence found is a shortest one; every input vector is tried in each
//! pair, which bounds the interface to [`MAX_INPUTS`] inputs.

use super::sim::Run;
use super::{Ecc, StateId};
use std::collections::{HashMap, VecDeque};

/// Inputs the search enumerates at most (2^16 input vectors per configuration pair).
pub(crate) const MAX_INPUTS: usize = 16;

/// Two machines that answer one input sequence differently.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Difference {
    /// The input vector of each `REQ`, from the initial states.
    pub(crate) inputs: Vec<Vec<bool>>,
    /// What each machine answers to the last `REQ`: `CNF` outputs, or `None` for nothing.
    pub(crate) first: Option<Vec<bool>>,
    /// The same for the second machine.
    pub(crate) second: Option<Vec<bool>>,
}

/// Why two machines cannot be compared.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DiffError {
    /// The input names differ (both lists, comma-separated).
    #[error("the machines have different interfaces: inputs [{0}] and [{1}]")]
    Inputs(String, String),
    /// The output names differ (both lists, comma-separated).
    #[error("the machines have different interfaces: outputs [{0}] and [{1}]")]
    Outputs(String, String),
    /// The exhaustive comparison would enumerate more input vectors than it allows.
    #[error("{0} inputs are too many to compare every input vector (at most {MAX_INPUTS})")]
    TooManyInputs(usize),
}

/// Refuses machines over other interfaces, or too many inputs to enumerate.
fn difference_interface(a: &Ecc, b: &Ecc) -> Result<(), DiffError> {
    if a.inputs != b.inputs {
        return Err(DiffError::Inputs(a.inputs.join(" "), b.inputs.join(" ")));
    }
    if a.outputs != b.outputs {
        return Err(DiffError::Outputs(a.outputs.join(" "), b.outputs.join(" ")));
    }
    match a.inputs.len() {
        n if n > MAX_INPUTS => Err(DiffError::TooManyInputs(n)),
        _ => Ok(()),
    }
}

type Config = Configuration;

/// A configuration pair reached, and the pair and input vector (index) it was reached from.
type Parents = HashMap<(Config, Config), Option<((Config, Config), usize)>>;

/// The shortest input sequence on which `a` and `b` answer differently, or `None` when they
/// are equivalent.
pub(crate) fn difference(a: &Ecc, b: &Ecc) -> Result<Option<Difference>, DiffError> {
    difference_interface(a, b)?;
    let n = a.inputs.len();
    let vectors: Vec<Vec<bool>> = (0..1u32 << n)
        .map(|v| (0..n).map(|i| v >> (n - 1 - i) & 1 == 1).collect())
        .collect();
    let start: (Config, Config) = (
        (StateId(0), a.initial_outputs.clone()),
        (StateId(0), b.initial_outputs.clone()),
    );
    if a.initial_outputs != b.initial_outputs {
        // Told apart before any REQ: the first CNF of either shows it, or the initial values
        // themselves when both stay silent. Reported on the empty sequence.
        return Ok(Some(Difference {
            inputs: Vec::new(),
            first: Some(a.initial_outputs.clone()),
            second: Some(b.initial_outputs.clone()),
        }));
    }
    Ok(difference_from(a, b, &[start], &vectors).map(|(_, d)| d))
}

/// One machine's configuration: state and output values.
pub(crate) type Configuration = (StateId, Vec<bool>);

/// The shortest input sequence over `vectors` on which `a` and `b` answer differently, from
/// any of the configuration pairs `starts`; with the index of the start it begins at (the
/// earliest in `starts` among the shortest). `None` when no such sequence exists.
pub(crate) fn difference_from(
    a: &Ecc,
    b: &Ecc,
    starts: &[(Configuration, Configuration)],
    vectors: &[Vec<bool>],
) -> Option<(usize, Difference)> {
    let mut parent = Parents::new();
    let mut origin: HashMap<(Config, Config), usize> = HashMap::new();
    let mut queue = VecDeque::new();
    for (i, start) in starts.iter().enumerate() {
        if !parent.contains_key(start) {
            parent.insert(start.clone(), None);
            origin.insert(start.clone(), i);
            queue.push_back(start.clone());
        }
    }
    while let Some(pair) = queue.pop_front() {
        for (k, x) in vectors.iter().enumerate() {
            let (mut ra, mut rb) = (run_at(a, &pair.0), run_at(b, &pair.1));
            let oa = ra.step(x).map(|_| ra.outputs.clone());
            let ob = rb.step(x).map(|_| rb.outputs.clone());
            if oa != ob {
                let mut inputs = vec![x.clone()];
                let mut at = &pair;
                while let Some(Some((before, v))) = parent.get(at) {
                    inputs.push(vectors[*v].clone());
                    at = before;
                }
                inputs.reverse();
                let diff = Difference {
                    inputs,
                    first: oa,
                    second: ob,
                };
                return Some((origin[at], diff));
            }
            let next = ((ra.state, ra.outputs), (rb.state, rb.outputs));
            if !parent.contains_key(&next) {
                parent.insert(next.clone(), Some((pair.clone(), k)));
                queue.push_back(next);
            }
        }
    }
    None
}

/// Two states put side by side by [`structure`], with what differs between them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct StatePair {
    /// The state of the first machine.
    pub(crate) first: StateId,
    /// The state of the second machine matched to it.
    pub(crate) second: StateId,
    /// One line per difference (algorithm, transitions by priority), empty when alike.
    pub(crate) changes: Vec<String>,
}

/// The states of two machines matched up, for reviewing one against the other.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Structure {
    /// Matched states, in the order the matching reached them.
    pub(crate) pairs: Vec<StatePair>,
    /// States of either machine that no state of the other was matched to.
    pub(crate) unmatched_first: Vec<StateId>,
    /// The same for the second machine.
    pub(crate) unmatched_second: Vec<StateId>,
}

/// Matches the states of `a` and `b` (same interface, checked by [`difference`]): the initial
/// states, then, breadth-first, the states both machines enter on one input vector from a
/// matched pair, then those their transitions of equal priority lead to, each state at its
/// first match. A transition is compared by its priority,
/// its guard and its target seen through the matching.
pub(crate) fn structure(a: &Ecc, b: &Ecc) -> Result<Structure, DiffError> {
    difference_interface(a, b)?;
    let m = Matching::of(a, b);
    let pairs = (m.order.iter())
        .map(|&(sa, sb)| StatePair {
            first: sa,
            second: sb,
            changes: changes(a, b, sa, sb, &m.to_second),
        })
        .collect();
    let unmatched = |m: &[Option<StateId>]| {
        (0..m.len())
            .filter(|&i| m[i].is_none())
            .map(StateId)
            .collect()
    };
    Ok(Structure {
        pairs,
        unmatched_first: unmatched(&m.to_second),
        unmatched_second: unmatched(&m.to_first),
    })
}

/// The states of two machines matched up ([`structure`]).
struct Matching {
    /// The matched pairs, in the order they were matched.
    order: Vec<(StateId, StateId)>,
    /// Per state of the first machine, its match in the second.
    to_second: Vec<Option<StateId>>,
    /// Per state of the second machine, its match in the first.
    to_first: Vec<Option<StateId>>,
}

impl Matching {
    fn of(a: &Ecc, b: &Ecc) -> Matching {
        let n = a.inputs.len();
        let mut m = Matching {
            order: vec![(StateId(0), StateId(0))],
            to_second: vec![None; a.states.len()],
            to_first: vec![None; b.states.len()],
        };
        m.to_second[0] = Some(StateId(0));
        m.to_first[0] = Some(StateId(0));
        let mut candidates = Vec::new();
        let mut k = 0;
        while k < m.order.len() {
            let (sa, sb) = m.order[k];
            k += 1;
            for v in 0..1u32 << n {
                let x: Vec<bool> = (0..n).map(|i| v >> (n - 1 - i) & 1 == 1).collect();
                let fire = |e: &Ecc, s: StateId| e.states[s.0].fired(&x).map(|t| t.target);
                if let (Some(ta), Some(tb)) = (fire(a, sa), fire(b, sb)) {
                    candidates.push((ta, tb));
                }
            }
            // Then transitions of equal priority, which also reach the targets of transitions
            // that never fire (a guard covered by the ones before it).
            let (xa, xb) = (&a.states[sa.0].transitions, &b.states[sb.0].transitions);
            candidates.extend(xa.iter().zip(xb).map(|(ta, tb)| (ta.target, tb.target)));
            for (ta, tb) in candidates.drain(..) {
                if m.to_second[ta.0].is_none() && m.to_first[tb.0].is_none() {
                    m.to_second[ta.0] = Some(tb);
                    m.to_first[tb.0] = Some(ta);
                    m.order.push((ta, tb));
                }
            }
        }
        m
    }
}

/// What differs between state `sa` of `a` and its match `sb` of `b`: the algorithm, and each
/// transition by priority, `a`'s targets seen through the matching `to_second`.
fn changes(
    a: &Ecc,
    b: &Ecc,
    sa: StateId,
    sb: StateId,
    to_second: &[Option<StateId>],
) -> Vec<String> {
    let name = |s: Option<StateId>| s.map_or("an unmatched state".to_string(), |s| s.to_string());
    let (x, y) = (a.state(sa), b.state(sb));
    let mut changes = Vec::new();
    if x.algorithm != y.algorithm {
        changes.push(format!(
            "algorithm {} became {}",
            x.algorithm.to_strings().join("/"),
            y.algorithm.to_strings().join("/")
        ));
    }
    let shown = |t: Option<&super::Transition>, e: &Ecc, target: Option<StateId>| {
        t.map(|t| format!("{} -> {}", t.guard.display(&e.inputs), name(target)))
    };
    for i in 0..x.transitions.len().max(y.transitions.len()) {
        let ta = x.transitions.get(i);
        let tb = y.transitions.get(i);
        // A's transition written in B's numbering, to compare like with like.
        let left = shown(ta, a, ta.and_then(|t| to_second[t.target.0]));
        let right = shown(tb, b, tb.map(|t| t.target));
        if left != right {
            let quoted = |t: Option<String>| t.map_or("none".into(), |t| format!("`{t}`"));
            changes.push(format!(
                "transition {}: {} became {}",
                i + 1,
                quoted(left),
                quoted(right)
            ));
        }
    }
    changes
}

/// A run of `ecc` resumed in configuration `c`.
fn run_at<'a>(ecc: &'a Ecc, c: &Config) -> Run<'a> {
    let mut run = Run::new(ecc);
    run.state = c.0;
    run.outputs.clone_from(&c.1);
    run
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::random::random_ecc;
    use crate::ecc::{replay, Reactive};

    /// A copy of `ecc` with its states in another order (state 0 stays initial).
    fn renumbered(ecc: &Ecc) -> Ecc {
        let c = ecc.states.len();
        // State i becomes state new[i]: 0 stays, the others reversed.
        let new = |i: usize| if i == 0 { 0 } else { c - i };
        let mut states = ecc.states.clone();
        for (i, s) in ecc.states.iter().enumerate() {
            let mut s = s.clone();
            for t in &mut s.transitions {
                t.target = StateId(new(t.target.0));
            }
            states[new(i)] = s;
        }
        Ecc {
            states,
            ..ecc.clone()
        }
    }

    #[test]
    fn a_machine_and_its_renumbered_copy_are_equivalent() {
        for seed in 0..20 {
            let ecc = random_ecc(seed, 5, 3, 2);
            assert_eq!(difference(&ecc, &renumbered(&ecc)), Ok(None), "seed {seed}");
        }
    }

    #[test]
    fn a_changed_target_is_found_and_the_sequence_shows_it() {
        let mut found = 0;
        for seed in 0..20 {
            let a = random_ecc(seed, 5, 3, 2);
            let mut b = a.clone();
            let Some(t) = b.states.iter_mut().flat_map(|s| &mut s.transitions).next() else {
                continue;
            };
            t.target = StateId((t.target.0 + 1) % a.states.len());
            let Some(d) = difference(&a, &b).unwrap() else {
                // A changed target may lead to a state that behaves the same.
                continue;
            };
            found += 1;
            // Replaying the sequence shows exactly the reported answers.
            let answers = |m: &Ecc| {
                let mut run = Run::new(m);
                let mut last = None;
                for x in &d.inputs {
                    last = run.react(x).map(<[bool]>::to_vec);
                }
                last
            };
            assert_eq!(answers(&a), d.first, "seed {seed}");
            assert_eq!(answers(&b), d.second, "seed {seed}");
            assert_ne!(d.first, d.second);
            // Every shorter prefix is answered alike.
            let steps: Vec<(&[bool], Option<Vec<bool>>)> = {
                let mut run = Run::new(&a);
                (d.inputs.iter())
                    .map(|x| (x.as_slice(), run.react(x).map(<[bool]>::to_vec)))
                    .collect()
            };
            let prefix = &steps[..steps.len() - 1];
            assert!(replay(&b, prefix.iter().map(|(x, o)| (*x, o.as_deref()))).is_ok());
        }
        assert!(found >= 10, "only {found} of 20 changes were visible");
    }

    #[test]
    fn a_renumbered_copy_matches_state_for_state_without_change() {
        for seed in 0..20 {
            let ecc = random_ecc(seed, 5, 3, 2);
            let s = structure(&ecc, &renumbered(&ecc)).unwrap();
            assert!(
                s.pairs.iter().all(|p| p.changes.is_empty()),
                "seed {seed}: {s:?}"
            );
            let c = ecc.states.len();
            for p in &s.pairs {
                let expected = if p.first.0 == 0 { 0 } else { c - p.first.0 };
                assert_eq!(p.second.0, expected, "seed {seed}");
            }
            assert_eq!(s.unmatched_first.len(), s.unmatched_second.len());
        }
    }

    #[test]
    fn a_changed_target_is_one_change_of_its_state() {
        let a = random_ecc(3, 4, 2, 1);
        let mut b = a.clone();
        let (state, index) = (0..b.states.len())
            .find_map(|s| (!b.states[s].transitions.is_empty()).then_some((s, 0)))
            .unwrap();
        let t = &mut b.states[state].transitions[index];
        t.target = StateId((t.target.0 + 1) % a.states.len());
        let s = structure(&a, &b).unwrap();
        let changed: Vec<&StatePair> = s.pairs.iter().filter(|p| !p.changes.is_empty()).collect();
        assert!(!changed.is_empty(), "{s:?}");
        assert!(changed.iter().any(
            |p| p.first.0 == state && p.changes.iter().any(|c| c.starts_with("transition 1: "))
        ));
    }

    #[test]
    fn other_interfaces_are_refused() {
        let a = random_ecc(1, 3, 3, 2);
        let mut b = a.clone();
        b.inputs[0] = "other".into();
        assert!(matches!(difference(&a, &b), Err(DiffError::Inputs(..))));
    }
}
