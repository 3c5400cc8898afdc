//! Known minima on tiny hand-made scenario sets: SAT at the minimum, UNSAT one below, per
//! constraint family; encoding sizes snapshotted to catch blow-ups.

use super::basic::Encoding;
use super::*;
use crate::ecc::AlgorithmKind;
use crate::scenario::fbsat;
use crate::scenario::negative::NegativeScenario;
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
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

fn neg(steps: &[(&str, &str, &str)], loop_start: usize) -> NegativeScenario {
    let b = |s: &str| s.chars().map(|c| c == '1').collect::<Vec<bool>>();
    NegativeScenario {
        steps: steps
            .iter()
            .map(|(x, z0, z1)| crate::scenario::negative::NegativeStep {
                inputs: b(x),
                before: b(z0),
                after: b(z1),
            })
            .collect(),
        loop_start: Some(loop_start),
        label: "test".into(),
    }
}

#[test]
fn negative_scenario_is_left_and_costs_a_state() {
    // Scenarios: pressing 1 switches the lamp on. Alone, one state would do (s0 on 1 -> s0? no:
    // s0's algorithm would set the lamp on entry, so C = 1 works with a self-loop setting 1).
    let s = set("1\nin=REQ[1]; out=CNF[1];\n");
    let tree = ScenarioTree::build(&s).unwrap();
    let o = opts(AlgorithmKind::Tri);
    let mut synth = Synthesizer::new(&s, &tree, &o);
    let first = synth.minimize(&mut |_| {}).unwrap();
    assert_eq!(first.size.c, 1);
    // Forbid: after switching on, pressing 0 forever leaves the lamp on (must switch it off).
    let bad = neg(&[("1", "0", "1"), ("0", "1", "1")], 1);
    assert!(
        bad.followed_by(&first.ecc),
        "the one-state machine keeps the lamp on"
    );
    synth.add_negative(bad.clone());
    let second = synth.minimize(&mut |_| {}).unwrap();
    assert!(!bad.followed_by(&second.ecc));
    s.check(&second.ecc).unwrap();
    assert_eq!(second.size.c, 2);
}

#[test]
fn negative_scenario_on_new_inputs_extends_the_alphabet() {
    let s = set("1\nin=REQ[10]; out=CNF[1];\n");
    let tree = ScenarioTree::build(&s).unwrap();
    let mut synth = Synthesizer::new(&s, &tree, &opts(AlgorithmKind::Tri));
    // Never stay dark forever on input 01 (not in the scenarios).
    let bad = neg(&[("01", "0", "0")], 0);
    synth.add_negative(bad.clone());
    let r = synth.minimize(&mut |_| {}).unwrap();
    assert!(!bad.followed_by(&r.ecc));
    s.check(&r.ecc).unwrap();
}

#[test]
fn followed_by_detects_cycles_through_the_loop() {
    let s = set(TOGGLE);
    let tree = ScenarioTree::build(&s).unwrap();
    let r = synthesize(&s, &tree, &opts(AlgorithmKind::Tri), &mut |_| {}).unwrap();
    // The toggle does exactly this forever: press (on), release, press (off), release.
    let its_run = neg(
        &[
            ("1", "0", "1"),
            ("0", "1", "1"),
            ("1", "1", "0"),
            ("0", "0", "0"),
        ],
        0,
    );
    assert!(its_run.followed_by(&r.ecc));
    let other = neg(&[("1", "0", "1"), ("1", "1", "1")], 1);
    assert!(!other.followed_by(&r.ecc));
}

#[test]
fn finite_negative_prefix_forbids_reproducing_it() {
    let s = set("1\nin=REQ[10]; out=CNF[1];\n");
    let tree = ScenarioTree::build(&s).unwrap();
    let mut synth = Synthesizer::new(&s, &tree, &opts(AlgorithmKind::Tri));
    let first = synth.minimize(&mut |_| {}).unwrap();
    // Lighting the lamp on 11 is bad (a safety violation right after that step).
    let mut bad = neg(&[("11", "0", "1")], 0);
    bad.loop_start = None;
    synth.add_negative(bad.clone());
    let second = synth.minimize(&mut |_| {}).unwrap();
    assert!(!bad.followed_by(&second.ecc));
    s.check(&second.ecc).unwrap();
    // The first machine (guard on the first input only, or TRUE) may well have done it.
    let _ = first;
}

#[test]
fn quick_proofs_prove_the_least_transitions_when_every_call_is_quick() {
    // The lamp of two buttons below: every call takes milliseconds, so the quick descent
    // runs on the incremental solver to the end and proves what the full one proves.
    let s = set(EITHER);
    let tree = ScenarioTree::build(&s).unwrap();
    let o = opts(AlgorithmKind::Tri);
    let full = synthesize(&s, &tree, &o, &mut |_| {}).unwrap();
    let quick = basic::Proofs::Quick(solver::Effort::Work(0));
    let r = Synthesizer::with_proofs(&s, &tree, &o, quick)
        .minimize(&mut |_| {})
        .unwrap();
    assert_eq!((r.size.c, r.size.t), (full.size.c, full.size.t));
    assert!(
        r.transitions_exact,
        "T refuted one below on the incremental solver"
    );
    s.check(&r.ecc).unwrap();
}

#[test]
fn smaller_exists_refutes_below_the_minimum_and_finds_above_it() {
    // Two scenarios from the same state to different targets (as above), in the cube model.
    let text = "2\nin=REQ[10]; out=CNF[10];\nin=REQ[01]; out=CNF[01]; in=REQ[10]; out=CNF[11];\n";
    let s = set(text);
    let tree = ScenarioTree::build(&s).unwrap();
    let o = Options {
        max_out_degree: Some(3),
        ..opts(AlgorithmKind::Tri)
    };
    let least = synthesize(&s, &tree, &o, &mut |_| {}).unwrap();
    assert!(least.transitions_exact && least.guards_exact);
    let mut synth = Synthesizer::with_proofs(&s, &tree, &o, basic::Proofs::Skip);
    synth.minimize(&mut |_| {}).unwrap();
    let budget = solver::Effort::Time(std::time::Duration::from_secs(30));
    let (t, n) = synth.smaller_exists(least.size, budget);
    assert!(
        matches!(t, solver::Bounded::Unsat),
        "fewer transitions than the least"
    );
    assert!(
        matches!(n, solver::Bounded::Unsat),
        "fewer literals than the least"
    );
    // One transition and two literals more than needed: both questions find a machine.
    let larger = crate::ecc::Size {
        t: least.size.t + 1,
        n: least.size.n + 2,
        ..least.size
    };
    let (t, n) = synth.smaller_exists(larger, budget);
    assert!(matches!(t, solver::Bounded::Sat(_)));
    assert!(matches!(n, solver::Bounded::Sat(_)));
}

// Either of two buttons switches a lamp on; both released switch it off. Recorded: each
// button alone, then both; nothing happens while both are released.
const EITHER: &str = "1\nin=REQ[00]; in=REQ[10]; out=CNF[1]; in=REQ[00]; out=CNF[0]; in=REQ[01]; out=CNF[1]; in=REQ[00]; out=CNF[0]; in=REQ[11]; out=CNF[1]; in=REQ[10]; in=REQ[00]; out=CNF[0];\n";

#[test]
fn a_disjunctive_guard_saves_the_transition_a_conjunction_needs() {
    let s = set(EITHER);
    let tree = ScenarioTree::build(&s).unwrap();
    // Guards as arbitrary formulas (the DNF of `synth infer`): one transition `x1 | x2`.
    let dnf = synthesize(&s, &tree, &opts(AlgorithmKind::Tri), &mut |_| {}).unwrap();
    s.check(&dnf.ecc).unwrap();
    assert_eq!((dnf.size.c, dnf.size.t), (2, 2));
    let on = (dnf.ecc.states.iter())
        .flat_map(|st| &st.transitions)
        .find(|t| t.guard.as_cube().is_none())
        .expect("a guard that is no conjunction");
    assert_eq!(on.guard.as_dnf().map(|d| d.len()), Some(2));
    assert!(on.guard.eval(&[true, false]) && on.guard.eval(&[false, true]));
    // Conjunctions only (the cube model of the main job): the same states, one more transition.
    let cubes = Options {
        max_out_degree: Some(4),
        ..opts(AlgorithmKind::Tri)
    };
    let conj = synthesize(&s, &tree, &cubes, &mut |_| {}).unwrap();
    s.check(&conj.ecc).unwrap();
    assert_eq!((conj.size.c, conj.size.t), (2, 3));
}

#[test]
fn the_tree_exact_least_literals_bound_the_cube_model_at_its_least_size() {
    // Two scenarios from the same state to different targets (as above).
    let text = "2\nin=REQ[10]; out=CNF[10];\nin=REQ[01]; out=CNF[01]; in=REQ[10]; out=CNF[11];\n";
    let s = set(text);
    let tree = ScenarioTree::build(&s).unwrap();
    let o = opts(AlgorithmKind::Tri);
    let exact = synthesize(&s, &tree, &o, &mut |_| {}).unwrap();
    let ct = (exact.size.c, exact.size.t);
    let budget = std::time::Duration::from_secs(30);
    let least = least_tree_exact(&s, &tree, &o, ct.0, exact.colors.clone(), budget).unwrap();
    assert!(least.transitions_exact && least.guards_exact);
    assert_eq!(least.size, exact.size);
    let n = Some(least.size.n);
    let cubes = Options {
        max_out_degree: Some(3),
        ..o
    };
    let cube = synthesize(&s, &tree, &cubes, &mut |_| {}).unwrap();
    assert_eq!((cube.size.c, cube.size.t), ct);
    assert!(cube.guards_exact);
    assert_eq!(
        Some(cube.size.n),
        n,
        "the bound is the cube model's least N here"
    );
}
