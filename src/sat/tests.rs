//! Known minima on tiny hand-made scenario sets: SAT at the minimum, UNSAT one below, per
//! constraint family; encoding sizes snapshotted to catch blow-ups.

use super::*;
use crate::scenario::fbsat;
use std::path::Path;

fn set(text: &str) -> ScenarioSet {
    fbsat::parse(Path::new("t.txt"), text, None, None).unwrap()
}

fn opts(kind: AlgorithmKind) -> Options {
    Options {
        algorithms: kind,
        ..Options::default()
    }
}

/// Asserts the minimum number of states is exactly `c` (SAT at c, UNSAT at c - 1), and that
/// full synthesis finds it and replays every scenario.
fn assert_min_states(text: &str, kind: AlgorithmKind, c: usize) -> Synthesis {
    let s = set(text);
    let tree = ScenarioTree::build(&s).unwrap();
    let o = opts(kind);
    assert!(satisfiable(&tree, &o, c, None), "SAT expected at C = {c}");
    assert!(
        !satisfiable(&tree, &o, c - 1, None),
        "UNSAT expected at C = {}",
        c - 1
    );
    let r = synthesize(&s, &tree, &o, &mut |_| {}).unwrap();
    assert_eq!(r.size.c, c);
    s.check(&r.ecc).unwrap();
    r
}

// A push button toggling a lamp: press (1) switches, release (0) does nothing.
const TOGGLE: &str = "1\nin=REQ[1]; out=CNF[1]; in=REQ[0]; in=REQ[1]; out=CNF[0]; in=REQ[0]; in=REQ[1]; out=CNF[1];\n";

#[test]
fn outputs_and_colouring_need_two_states_for_a_toggle_with_tri_algorithms() {
    let r = assert_min_states(TOGGLE, AlgorithmKind::Tri, 2);
    assert_eq!(r.size.t, 2);
}

#[test]
fn binary_algorithms_flip_with_one_state() {
    let r = assert_min_states(TOGGLE, AlgorithmKind::Binary, 1);
    assert_eq!((r.size.t, r.size.n), (1, 1));
}

#[test]
fn passive_marks_separate_states() {
    // Input 1 sets the output the first time, and is ignored afterwards.
    let r = assert_min_states(
        "1\nin=REQ[1]; out=CNF[1]; in=REQ[1]; in=REQ[0]; in=REQ[1];\n",
        AlgorithmKind::Tri,
        2,
    );
    assert_eq!(r.size.t, 1);
}

#[test]
fn active_edges_force_transitions_to_the_recorded_outputs() {
    // A one-hot rotation 100 -> 010 -> 001 on one input: two states would have to set output 1
    // from 0 both to 1 and to 0 (or flip it), so three are needed.
    assert_min_states(
        "1\nin=REQ[1]; out=CNF[100]; in=REQ[1]; out=CNF[010]; in=REQ[1]; out=CNF[001];\n",
        AlgorithmKind::Tri,
        3,
    );
}

#[test]
fn transition_count_is_minimal_and_one_below_is_unsat() {
    // Two scenarios from the same state to different targets: T = 3 at C = 3 (0->1, 0->2, and
    // 1 and 2 each need nothing more), and T = 2 is impossible.
    let text = "2\nin=REQ[10]; out=CNF[10];\nin=REQ[01]; out=CNF[01]; in=REQ[10]; out=CNF[11];\n";
    let s = set(text);
    let tree = ScenarioTree::build(&s).unwrap();
    let o = opts(AlgorithmKind::Tri);
    let r = synthesize(&s, &tree, &o, &mut |_| {}).unwrap();
    let (c, t) = (r.size.c, r.size.t);
    assert!(satisfiable(&tree, &o, c, Some(t)));
    assert!(!satisfiable(&tree, &o, c, Some(t - 1)));
    s.check(&r.ecc).unwrap();
}

#[test]
fn start_state_costs_one_state_on_a_toggle() {
    let s = set(TOGGLE);
    let tree = ScenarioTree::build(&s).unwrap();
    let o = Options {
        start_state: true,
        ..opts(AlgorithmKind::Tri)
    };
    assert!(satisfiable(&tree, &o, 3, None));
    assert!(!satisfiable(&tree, &o, 2, None));
    let r = synthesize(&s, &tree, &o, &mut |_| {}).unwrap();
    assert!(r
        .ecc
        .states
        .iter()
        .flat_map(|s| &s.transitions)
        .all(|t| t.target.0 != 0));
}

#[test]
fn minimizing_k_never_increases_the_largest_out_degree() {
    let text = "3\nin=REQ[00]; out=CNF[01]; in=REQ[11]; out=CNF[10];\nin=REQ[01]; out=CNF[10]; in=REQ[00]; out=CNF[01];\nin=REQ[10]; out=CNF[11]; in=REQ[01]; out=CNF[00];\n";
    let s = set(text);
    let tree = ScenarioTree::build(&s).unwrap();
    let plain = synthesize(&s, &tree, &opts(AlgorithmKind::Tri), &mut |_| {}).unwrap();
    let with_k = synthesize(
        &s,
        &tree,
        &Options {
            minimize_k: true,
            ..opts(AlgorithmKind::Tri)
        },
        &mut |_| {},
    )
    .unwrap();
    assert_eq!(plain.size.c, with_k.size.c);
    assert!(with_k.size.k <= plain.size.k);
    s.check(&with_k.ecc).unwrap();
}

#[test]
fn encoding_size_is_stable() {
    let s = set(TOGGLE);
    let tree = ScenarioTree::build(&s).unwrap();
    let enc = Encoding::new(&tree, 4, &opts(AlgorithmKind::Tri));
    // Snapshot of the encoding size: a change here means the encoding changed; check why.
    insta::assert_snapshot!(format!(
        "variables {} clauses {}",
        enc.variables, enc.clauses
    ));
}
