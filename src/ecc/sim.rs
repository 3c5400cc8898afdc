//! The simulator: the one executable semantics of an ECC.
//!
//! Every other part of the project agrees with [`Run::step`]: the SAT decoder replays its
//! machines through it, the search fitness is computed with it, and the SMV emitter is
//! differential-tested against it inside NuSMV.

use super::{Ecc, StateId};

/// A transition that fired on one `REQ`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fired {
    /// The state the machine was in.
    pub(crate) source: StateId,
    /// Index of the transition in the source state's priority list.
    pub(crate) index: usize,
    /// The state entered.
    pub(crate) target: StateId,
}

/// A running instance of an ECC: current state and output values.
#[derive(Debug, Clone)]
pub struct Run<'a> {
    ecc: &'a Ecc,
    /// The current state.
    pub(crate) state: StateId,
    /// The current output values.
    pub outputs: Vec<bool>,
}

impl<'a> Run<'a> {
    /// The machine in its initial state with its initial outputs.
    pub fn new(ecc: &'a Ecc) -> Run<'a> {
        Run {
            ecc,
            state: StateId(0),
            outputs: ecc.initial_outputs.clone(),
        }
    }

    /// The machine in state `state` with output values `outputs`, as if it had run there.
    pub(crate) fn at(ecc: &'a Ecc, state: StateId, outputs: Vec<bool>) -> Run<'a> {
        Run {
            ecc,
            state,
            outputs,
        }
    }

    /// One `REQ` with input vector `x`. Returns the fired transition (the machine then emitted
    /// `CNF` with `self.outputs`), or `None` when no guard held (no `CNF`, nothing changed).
    pub fn step(&mut self, x: &[bool]) -> Option<Fired> {
        let source = self.state;
        let (index, t) = self.ecc.states[source.0]
            .transitions
            .iter()
            .enumerate()
            .find(|(_, t)| t.guard.eval(x))?;
        self.state = t.target;
        self.ecc.states[t.target.0]
            .algorithm
            .apply(&mut self.outputs);
        Some(Fired {
            source,
            index,
            target: t.target,
        })
    }
}

/// The first step where a machine and a recorded trace disagree.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Mismatch {
    /// 0-based index of the `REQ` in the trace.
    pub(crate) step: usize,
    /// Recorded outputs of `CNF`, or `None` if the trace records no `CNF`.
    pub(crate) expected: Option<Vec<bool>>,
    /// Outputs the machine emitted with `CNF`, or `None` if it emitted nothing.
    pub(crate) actual: Option<Vec<bool>>,
}

/// Something that reacts to `REQ`: a running ECC ([`Run`]) or a running modular composite
/// ([`super::modular::ModularRun`]).
pub trait Reactive {
    /// One `REQ` with input vector `x`: the outputs emitted with `CNF`, or `None` when nothing
    /// happened.
    fn react(&mut self, x: &[bool]) -> Option<&[bool]>;
}

impl Reactive for Run<'_> {
    fn react(&mut self, x: &[bool]) -> Option<&[bool]> {
        self.step(x).map(|_| self.outputs.as_slice())
    }
}

/// A controller a recorded trace can be replayed on: an [`Ecc`] or a
/// [`super::modular::Modular`] composite.
pub trait Controller {
    /// The running instance [`Controller::start`] returns.
    type Run<'a>: Reactive
    where
        Self: 'a;
    /// The controller in its initial state with its initial outputs.
    fn start(&self) -> Self::Run<'_>;
}

impl Controller for Ecc {
    type Run<'a> = Run<'a>;
    fn start(&self) -> Run<'_> {
        Run::new(self)
    }
}

/// Replays a trace of `(inputs, expected CNF outputs or None)` on `controller` from its initial
/// state and returns the first disagreement.
pub(crate) fn replay<'t, I>(controller: &impl Controller, steps: I) -> Result<(), Mismatch>
where
    I: IntoIterator<Item = (&'t [bool], Option<&'t [bool]>)>,
{
    let mut run = controller.start();
    for (k, (x, expected)) in steps.into_iter().enumerate() {
        let actual = run.react(x);
        if actual != expected {
            return Err(Mismatch {
                step: k,
                expected: expected.map(|o| o.to_vec()),
                actual: actual.map(|o| o.to_vec()),
            });
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::{Algorithm, Guard, InputId, State, Transition, Tri};

    /// A toggle: input `b` pressed switches the lamp; state 1 = on.
    fn toggle() -> Ecc {
        let b = Guard::Var(InputId(0));
        Ecc {
            inputs: vec!["b".into()],
            outputs: vec!["lamp".into()],
            initial_outputs: vec![false],
            states: vec![
                State {
                    name: "s0".into(),
                    algorithm: Algorithm::Tri(vec![Tri::Zero]),
                    transitions: vec![Transition {
                        target: StateId(1),
                        guard: b.clone(),
                    }],
                },
                State {
                    name: "s1".into(),
                    algorithm: Algorithm::Tri(vec![Tri::One]),
                    transitions: vec![Transition {
                        target: StateId(0),
                        guard: b,
                    }],
                },
            ],
        }
    }

    #[test]
    fn first_true_guard_fires_and_target_algorithm_applies() {
        let e = toggle();
        let mut r = Run::new(&e);
        assert_eq!(r.step(&[false]), None);
        assert_eq!(r.outputs, vec![false]);
        let f = r.step(&[true]).unwrap();
        assert_eq!((f.source, f.target), (StateId(0), StateId(1)));
        assert_eq!(r.outputs, vec![true]);
        r.step(&[true]);
        assert_eq!(r.outputs, vec![false]);
    }

    #[test]
    fn priority_order_decides() {
        let mut e = toggle();
        e.states[0].transitions.insert(
            0,
            Transition {
                target: StateId(0),
                guard: Guard::True,
            },
        );
        let mut r = Run::new(&e);
        let f = r.step(&[true]).unwrap();
        assert_eq!((f.index, f.target), (0, StateId(0)));
    }

    #[test]
    fn replay_reports_first_mismatch() {
        let e = toggle();
        let t: [(&[bool], Option<&[bool]>); 3] = [
            (&[false], None),
            (&[true], Some(&[true])),
            (&[false], Some(&[true])),
        ];
        let m = replay(&e, t).unwrap_err();
        assert_eq!(m.step, 2);
        assert_eq!(m.actual, None);
    }

    #[test]
    fn binary_algorithm_can_flip() {
        let a = Algorithm::Binary {
            a0: vec![true],
            a1: vec![false],
        };
        let mut o = vec![false];
        a.apply(&mut o);
        assert_eq!(o, vec![true]);
        a.apply(&mut o);
        assert_eq!(o, vec![false]);
    }
}
