//! The form a machine is asked in: its algorithm form and whether state 0 is a start state
//! that no transition enters (the fbSAT tool's conventions).
//!
//! In: an [`Ecc`] and the [`Conventions`] asked for. Out: whether the machine keeps them
//! ([`Conventions::broken`]), or the same behaviour written in them ([`Conventions::written`]):
//! a three-valued algorithm is a binary one (`0` is `a0 = a1 = 0`, `1` is `a0 = a1 = 1`, `x` is
//! `a0 = 0, a1 = 1`), and a machine whose initial state is entered gets a fresh start state
//! that leaves as the initial state does. Both keep every run of the machine, step by step.

use super::{Algorithm, AlgorithmKind, Ecc, State, StateId, Tri};
use std::fmt;

/// The form of a machine: its algorithms and whether it has a start state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Conventions {
    /// The form of every state's algorithm.
    pub(crate) algorithms: AlgorithmKind,
    /// State 0 is a start state no transition enters.
    pub(crate) start_state: bool,
}

impl Conventions {
    /// The conventions of the project's own syntheses: three-valued algorithms, no start state.
    pub(crate) fn is_default(self) -> bool {
        self == Conventions::default()
    }

    /// Which convention `ecc` breaks, first found; `None` when it keeps them all.
    pub(crate) fn broken(self, ecc: &Ecc) -> Option<String> {
        if let Some(s) = (ecc.states.iter()).find(|s| s.algorithm.kind() != self.algorithms) {
            return Some(format!(
                "state {} has a {} algorithm, {} algorithms were asked for",
                s.name,
                kind_name(s.algorithm.kind()),
                kind_name(self.algorithms)
            ));
        }
        if !self.start_state {
            return None;
        }
        let entering = (ecc.states.iter()).find(|s| enters_start(s))?;
        Some(format!(
            "state {} enters the start state {}",
            entering.name, ecc.states[0].name
        ))
    }

    /// `ecc` written in these conventions, with the same runs: three-valued algorithms as
    /// binary ones, and a fresh start state when a transition enters state 0. A binary
    /// algorithm asked to be three-valued is left as it is ([`Self::broken`] names it).
    pub(crate) fn written(self, ecc: &Ecc) -> Ecc {
        let mut e = ecc.clone();
        if self.algorithms == AlgorithmKind::Binary {
            for s in &mut e.states {
                s.algorithm = binary(&s.algorithm);
            }
        }
        if self.start_state && entered(&e) {
            e = with_start_state(e);
        }
        e
    }
}

/// Whether a transition enters state 0.
fn entered(ecc: &Ecc) -> bool {
    ecc.states.iter().any(enters_start)
}

/// Whether a transition of `s` enters state 0.
fn enters_start(s: &State) -> bool {
    s.transitions.iter().any(|t| t.target == StateId(0))
}

/// `algorithm` in the binary form (the same effect on every output).
fn binary(algorithm: &Algorithm) -> Algorithm {
    let Algorithm::Tri(t) = algorithm else {
        return algorithm.clone();
    };
    let (a0, a1) = (t.iter())
        .map(|v| match v {
            Tri::Zero => (false, false),
            Tri::One => (true, true),
            Tri::Keep => (false, true),
        })
        .unzip();
    Algorithm::Binary { a0, a1 }
}

/// `ecc` with a new state 0 that leaves as the old state 0 does and that nothing enters; the
/// old states follow, renumbered by one. Its algorithm runs never (no transition enters it),
/// so it changes nothing.
fn with_start_state(mut ecc: Ecc) -> Ecc {
    for s in &mut ecc.states {
        for t in &mut s.transitions {
            t.target = StateId(t.target.0 + 1);
        }
    }
    let start = State {
        name: fresh_name(&ecc),
        algorithm: Algorithm::keep_all(ecc.states[0].algorithm.kind(), ecc.outputs.len()),
        transitions: ecc.states[0].transitions.clone(),
    };
    ecc.states.insert(0, start);
    ecc
}

/// A state name no state of `ecc` has: `start`, else `start1`, `start2`, ...
fn fresh_name(ecc: &Ecc) -> String {
    let taken = |n: &str| ecc.states.iter().any(|s| s.name == n);
    (0..)
        .map(|i| match i {
            0 => "start".to_string(),
            i => format!("start{i}"),
        })
        .find(|n| !taken(n))
        .expect("some name is free")
}

fn kind_name(k: AlgorithmKind) -> &'static str {
    match k {
        AlgorithmKind::Tri => "three-valued",
        AlgorithmKind::Binary => "binary",
    }
}

/// `binary algorithms, a start state no transition enters`; empty for the defaults.
impl fmt::Display for Conventions {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<&str> = [
            (self.algorithms == AlgorithmKind::Binary).then_some("binary algorithms"),
            self.start_state
                .then_some("a start state no transition enters"),
        ]
        .into_iter()
        .flatten()
        .collect();
        f.write_str(&parts.join(", "))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::{Guard, InputId, Run, Transition};

    /// A machine of two states over one input and two outputs, state 1 going back to 0.
    fn toggler() -> Ecc {
        let go = |q: usize, guard: Guard| Transition {
            target: StateId(q),
            guard,
        };
        let x = Guard::Var(InputId(0));
        Ecc {
            inputs: vec!["x".into()],
            outputs: vec!["a".into(), "b".into()],
            initial_outputs: vec![false, true],
            states: vec![
                State {
                    name: "s0".into(),
                    algorithm: Algorithm::Tri(vec![Tri::Zero, Tri::Keep]),
                    transitions: vec![go(1, x.clone())],
                },
                State {
                    name: "s1".into(),
                    algorithm: Algorithm::Tri(vec![Tri::One, Tri::Zero]),
                    transitions: vec![go(0, Guard::Not(Box::new(x))), go(1, Guard::True)],
                },
            ],
        }
    }

    /// Every input sequence of length up to 6, outputs and CNF after each step.
    fn runs(ecc: &Ecc) -> Vec<Vec<(bool, Vec<bool>)>> {
        (0..1u32 << 6)
            .map(|bits| {
                let mut run = Run::new(ecc);
                (0..6)
                    .map(|i| {
                        let fired = run.step(&[bits >> i & 1 == 1]).is_some();
                        (fired, run.outputs.clone())
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn written_in_fbsat_conventions_the_machine_runs_the_same() {
        let ecc = toggler();
        let fbsat = Conventions {
            algorithms: AlgorithmKind::Binary,
            start_state: true,
        };
        assert!(fbsat.broken(&ecc).is_some());
        let w = fbsat.written(&ecc);
        assert_eq!(fbsat.broken(&w), None);
        // One state more: state 0 was entered.
        assert_eq!(w.states.len(), 3);
        assert_eq!(w.states[0].name, "start");
        assert_eq!(runs(&w), runs(&ecc));
    }

    #[test]
    fn a_machine_already_in_the_conventions_is_left_as_it_is() {
        let ecc = toggler();
        assert_eq!(Conventions::default().broken(&ecc), None);
        assert_eq!(Conventions::default().written(&ecc), ecc);
        let binary = Conventions {
            algorithms: AlgorithmKind::Binary,
            start_state: false,
        };
        let w = binary.written(&ecc);
        assert_eq!(w.states.len(), 2);
        assert_eq!(binary.written(&w), w);
        let start = Conventions {
            algorithms: AlgorithmKind::Binary,
            start_state: true,
        };
        let s = start.written(&w);
        assert_eq!(start.written(&s), s);
    }

    #[test]
    fn broken_conventions_are_named() {
        let ecc = toggler();
        let binary = Conventions {
            algorithms: AlgorithmKind::Binary,
            start_state: false,
        };
        assert_eq!(
            binary.broken(&ecc).unwrap(),
            "state s0 has a three-valued algorithm, binary algorithms were asked for"
        );
        let start = Conventions {
            algorithms: AlgorithmKind::Tri,
            start_state: true,
        };
        assert_eq!(
            start.broken(&ecc).unwrap(),
            "state s1 enters the start state s0"
        );
    }
}
