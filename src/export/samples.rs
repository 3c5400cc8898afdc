//! Hand-made ECCs shared by the snapshot tests of every emitter (test-only).
//!
//! Out: three small machines that together exercise everything an emitter must print: one
//! state with a self-loop; tri algorithms with priorities, `TRUE` and `|` guards, an initial
//! output of 1 and a state whose algorithm changes nothing; binary algorithms with a flip.

use crate::ecc::{Algorithm, Ecc, Guard, InputId, State, StateId, Transition, Tri};

/// One insta snapshot per sample ECC, named after the sample, of `$emit(&ecc)`. A macro, not a
/// function, so that the snapshot files keep the name of the emitter's test module.
macro_rules! snapshot_each_sample {
    ($emit:expr) => {
        for (name, ecc) in $crate::export::samples::all() {
            insta::assert_snapshot!(name, $emit(&ecc));
        }
    };
}
pub(crate) use snapshot_each_sample;

fn var(i: usize) -> Guard {
    Guard::Var(InputId(i))
}

fn not(g: Guard) -> Guard {
    Guard::Not(Box::new(g))
}

fn tri_alg(s: &str) -> Algorithm {
    Algorithm::Tri(s.chars().map(|c| Tri::from_symbol(c).unwrap()).collect())
}

fn bin(a0: &str, a1: &str) -> Algorithm {
    Algorithm::Binary {
        a0: crate::ecc::bits_from_str(a0).unwrap(),
        a1: crate::ecc::bits_from_str(a1).unwrap(),
    }
}

fn state(i: usize, algorithm: Algorithm, transitions: Vec<(usize, Guard)>) -> State {
    State {
        name: format!("s{i}"),
        algorithm,
        transitions: transitions
            .into_iter()
            .map(|(t, guard)| Transition {
                target: StateId(t),
                guard,
            })
            .collect(),
    }
}

/// One state that switches the lamp on at every `start`.
pub(crate) fn one_state() -> Ecc {
    Ecc {
        inputs: vec!["start".into()],
        outputs: vec!["lamp".into()],
        initial_outputs: vec![false],
        states: vec![state(0, tri_alg("1"), vec![(0, var(0))])],
    }
}

/// A pick-and-place-like cylinder controller: 4 states, tri algorithms.
pub(crate) fn tri() -> Ecc {
    // inputs: 0 c1Home, 1 c1End, 2 vac, 3 go
    Ecc {
        inputs: vec!["c1Home".into(), "c1End".into(), "vac".into(), "go".into()],
        outputs: vec!["c1Extend".into(), "c1Retract".into(), "vacOn".into()],
        initial_outputs: vec![false, false, true],
        states: vec![
            state(
                0,
                tri_alg("xxx"),
                vec![
                    (1, Guard::And(vec![var(3), var(0)])),
                    (3, Guard::Or(vec![not(var(2)), var(1)])),
                ],
            ),
            state(
                1,
                tri_alg("100"),
                vec![(2, Guard::And(vec![var(1), not(var(2))])), (0, not(var(3)))],
            ),
            state(2, tri_alg("011"), vec![(3, Guard::True)]),
            state(
                3,
                tri_alg("0x0"),
                vec![
                    (
                        0,
                        Guard::And(vec![var(0), Guard::Or(vec![var(2), not(var(3))])]),
                    ),
                    (3, Guard::True),
                ],
            ),
        ],
    }
}

/// A lamp with a buzzer: binary algorithms, state 1 flips the lamp, state 2 flips the buzzer.
pub(crate) fn binary() -> Ecc {
    // inputs: 0 toggle, 1 reset
    Ecc {
        inputs: vec!["toggle".into(), "reset".into()],
        outputs: vec!["lamp".into(), "buzzer".into()],
        initial_outputs: vec![false, false],
        states: vec![
            state(
                0,
                bin("00", "00"),
                vec![(1, Guard::And(vec![var(0), not(var(1))]))],
            ),
            state(
                1,
                bin("10", "01"),
                vec![
                    (2, Guard::And(vec![var(0), var(1)])),
                    (0, var(1)),
                    (1, var(0)),
                ],
            ),
            state(2, bin("11", "10"), vec![(0, not(var(0)))]),
        ],
    }
}

/// All samples with a short name each, for tests that run over every one.
pub(crate) fn all() -> Vec<(&'static str, Ecc)> {
    vec![
        ("one_state", one_state()),
        ("tri", tri()),
        ("binary", binary()),
    ]
}

#[test]
fn samples_are_valid() {
    for (name, e) in all() {
        assert_eq!(e.validate(), Ok(()), "{name}");
    }
}
