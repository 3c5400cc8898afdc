//! The Execution Control Chart (ECC) of an IEC 61499 basic function block, as a Moore machine.
//!
//! This module is pure data and the one executable semantics of the project (see [`sim`]);
//! it performs no I/O and depends on no other module of the crate.
//!
//! # The model
//! - Interface: ordered Boolean inputs `x[0..X)`, ordered Boolean outputs `z[0..Z)`, one input
//!   event `REQ` and one output event `CNF`, and initial output values (default all `0`).
//! - States `0..C`; state 0 is the initial state. Each state carries an output [`Algorithm`].
//! - Each state has an *ordered* list of [`Transition`]s `(guard, target)`. On `REQ` with input
//!   vector `x`, the first transition whose guard holds on `x` fires: the machine enters the
//!   target, applies the *target's* algorithm to the outputs and emits `CNF` with the new output
//!   values. If no guard holds nothing happens: no `CNF`, outputs unchanged, state unchanged.
//!
//! Numbering: states, inputs and outputs are 0-based everywhere inside the crate. Exports name
//! states `s0..s{C-1}` (the `.fbt` export calls state 0 `START`, as 4diac expects).

pub(crate) mod conventions;
pub(crate) mod diff;
pub(crate) mod guard;
pub(crate) mod ident;
pub mod modular;
pub(crate) mod network;
pub mod random;
pub(crate) mod sim;

pub(crate) use conventions::Conventions;
pub use guard::Guard;
pub use network::{Network, NetworkRun};
pub(crate) use sim::replay;
pub use sim::{Controller, Fired, Reactive, Run};

use std::fmt;

/// Index of a state, 0-based; state 0 is the initial state.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct StateId(pub usize);

/// Index of an input variable in the interface order, 0-based.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct InputId(pub usize);

/// Index of an output variable in the interface order, 0-based.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct OutputId(pub usize);

impl fmt::Display for StateId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "s{}", self.0)
    }
}

/// One element of a three-valued output algorithm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Tri {
    /// Set the output to `0`.
    Zero,
    /// Set the output to `1`.
    One,
    /// Keep the output's current value (`x`).
    Keep,
}

impl Tri {
    /// The symbol of the JSON contract and the papers: `0`, `1` or `x`.
    pub(crate) fn symbol(self) -> char {
        match self {
            Tri::Zero => '0',
            Tri::One => '1',
            Tri::Keep => 'x',
        }
    }

    /// Reads a symbol (`0`, `1`, `x` or `X`); `None` for any other character.
    pub(crate) fn from_symbol(c: char) -> Option<Tri> {
        match c {
            '0' => Some(Tri::Zero),
            '1' => Some(Tri::One),
            'x' | 'X' => Some(Tri::Keep),
            _ => None,
        }
    }
}

/// The output algorithm of a state, executed when the state is entered.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub enum Algorithm {
    /// One symbol per output from `{0, 1, x}` (the papers' form).
    Tri(Vec<Tri>),
    /// The public fbSAT tool's form: new value of output `z` is `a1[z]` if its old value was 1,
    /// else `a0[z]`. This can also express "flip" (`a0 = 1, a1 = 0`).
    Binary {
        /// New value of each output whose old value is 0.
        a0: Vec<bool>,
        /// New value of each output whose old value is 1.
        a1: Vec<bool>,
    },
}

/// Which algorithm form a synthesis run uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum AlgorithmKind {
    /// `{0, 1, x}` per output.
    #[default]
    Tri,
    /// Two bit strings `a0`, `a1` per state (fbSAT's form).
    Binary,
}

impl Algorithm {
    /// The algorithm that changes nothing.
    pub(crate) fn keep_all(kind: AlgorithmKind, outputs: usize) -> Algorithm {
        match kind {
            AlgorithmKind::Tri => Algorithm::Tri(vec![Tri::Keep; outputs]),
            AlgorithmKind::Binary => Algorithm::Binary {
                a0: vec![false; outputs],
                a1: vec![true; outputs],
            },
        }
    }

    /// Which of the two forms this algorithm is written in.
    pub(crate) fn kind(&self) -> AlgorithmKind {
        match self {
            Algorithm::Tri(_) => AlgorithmKind::Tri,
            Algorithm::Binary { .. } => AlgorithmKind::Binary,
        }
    }

    /// Number of outputs the algorithm is written for.
    pub(crate) fn len(&self) -> usize {
        match self {
            Algorithm::Tri(t) => t.len(),
            Algorithm::Binary { a0, .. } => a0.len(),
        }
    }

    /// New value of one output whose old value is `old`.
    pub(crate) fn apply_one(&self, z: usize, old: bool) -> bool {
        match self {
            Algorithm::Tri(t) => match t[z] {
                Tri::Zero => false,
                Tri::One => true,
                Tri::Keep => old,
            },
            Algorithm::Binary { a0, a1 } => {
                if old {
                    a1[z]
                } else {
                    a0[z]
                }
            }
        }
    }

    /// Apply the algorithm to an output vector in place.
    pub(crate) fn apply(&self, outputs: &mut [bool]) {
        for (z, v) in outputs.iter_mut().enumerate() {
            *v = self.apply_one(z, *v);
        }
    }

    /// The algorithm as text: `x01x...` for tri; `a0/a1` bit strings for binary.
    pub(crate) fn to_strings(&self) -> Vec<String> {
        match self {
            Algorithm::Tri(t) => vec![t.iter().map(|s| s.symbol()).collect()],
            Algorithm::Binary { a0, a1 } => vec![bits_to_string(a0), bits_to_string(a1)],
        }
    }
}

impl fmt::Display for Algorithm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Algorithm::Tri(_) => write!(f, "{}", self.to_strings()[0]),
            Algorithm::Binary { a0, a1 } => {
                write!(f, "0:{} 1:{}", bits_to_string(a0), bits_to_string(a1))
            }
        }
    }
}

/// What a state's algorithm does to one output when the state is entered.
///
/// Both algorithm forms reduce to this: an output's new value is a function of its old value
/// alone, and there are exactly four such functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Effect {
    /// Set to the given value.
    Set(bool),
    /// Leave unchanged.
    Keep,
    /// Negate.
    Flip,
}

impl Effect {
    /// The effect of `algorithm` on output `z`. Derived from [`Algorithm::apply_one`] so that
    /// every emitter agrees with the simulator by construction: `(new if old=0, new if old=1)`
    /// is `(0,0)` set FALSE, `(1,1)` set TRUE, `(0,1)` keep, `(1,0)` flip.
    pub(crate) fn of(algorithm: &Algorithm, z: usize) -> Effect {
        match (algorithm.apply_one(z, false), algorithm.apply_one(z, true)) {
            (false, false) => Effect::Set(false),
            (true, true) => Effect::Set(true),
            (false, true) => Effect::Keep,
            (true, false) => Effect::Flip,
        }
    }

    /// The effects of `algorithm` on every output, in interface order.
    pub(crate) fn all(algorithm: &Algorithm) -> Vec<Effect> {
        (0..algorithm.len())
            .map(|z| Effect::of(algorithm, z))
            .collect()
    }
}

/// `[true, false]` -> `"10"`.
pub(crate) fn bits_to_string(bits: &[bool]) -> String {
    bits.iter().map(|&b| if b { '1' } else { '0' }).collect()
}

/// `"10"` -> `[true, false]`; `None` on any other character.
pub(crate) fn bits_from_str(s: &str) -> Option<Vec<bool>> {
    s.chars()
        .map(|c| match c {
            '0' => Some(false),
            '1' => Some(true),
            _ => None,
        })
        .collect()
}

/// One outgoing transition of a state.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Transition {
    /// The state entered when the transition fires.
    pub target: StateId,
    /// The condition on the inputs under which it fires (if no earlier transition does).
    pub guard: Guard,
}

/// One state of the ECC with its algorithm and its transitions in priority order.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct State {
    /// The state's name in every export (`s0`, `s1`, ... unless the user named it).
    pub name: String,
    /// The outputs it sets when entered.
    pub algorithm: Algorithm,
    /// Outgoing transitions, highest priority first.
    pub transitions: Vec<Transition>,
}

impl State {
    /// The transition that fires on inputs `x`: the first whose guard holds.
    pub(crate) fn fired(&self, x: &[bool]) -> Option<&Transition> {
        self.transitions.iter().find(|t| t.guard.eval(x))
    }
}

/// An Execution Control Chart with its interface.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Ecc {
    /// Names of the Boolean inputs (sampled on every `REQ`), in interface order.
    pub inputs: Vec<String>,
    /// Names of the Boolean outputs (sent with every `CNF`), in interface order.
    pub outputs: Vec<String>,
    /// Output values before the first `REQ`.
    pub initial_outputs: Vec<bool>,
    /// States; index 0 is the initial state.
    pub states: Vec<State>,
}

/// Size figures of an ECC, as the papers report them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, schemars::JsonSchema)]
pub struct Size {
    /// Number of states.
    pub c: usize,
    /// Largest number of outgoing transitions of one state.
    pub k: usize,
    /// Number of transitions.
    pub t: usize,
    /// Total number of literals in all guards.
    pub n: usize,
}

impl Size {
    /// The order in which the minimization ranks machines: fewer states, then fewer
    /// transitions, then fewer guard literals (`K` is not compared).
    pub(crate) fn order_key(&self) -> (usize, usize, usize) {
        (self.c, self.t, self.n)
    }

    /// Whether this machine is smaller than `other` in [`Self::order_key`]'s order.
    pub(crate) fn is_smaller_than(&self, other: &Size) -> bool {
        self.order_key() < other.order_key()
    }
}

/// `C=2 K=1 T=2 N=2` inside a sentence; with `{:#}` the command line's result line
/// `C = 2  K = 1  T = 2  N = 2`.
impl fmt::Display for Size {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (c, k, t, n) = (self.c, self.k, self.t, self.n);
        match f.alternate() {
            true => write!(f, "C = {c}  K = {k}  T = {t}  N = {n}"),
            false => write!(f, "C={c} K={k} T={t} N={n}"),
        }
    }
}

impl Ecc {
    /// The state with this id (panics on an id of another machine).
    pub(crate) fn state(&self, id: StateId) -> &State {
        &self.states[id.0]
    }

    /// Its size as the papers count it: states, largest out-degree, transitions, guard literals.
    pub fn size(&self) -> Size {
        Size {
            c: self.states.len(),
            k: self
                .states
                .iter()
                .map(|s| s.transitions.len())
                .max()
                .unwrap_or(0),
            t: self.states.iter().map(|s| s.transitions.len()).sum(),
            n: self
                .states
                .iter()
                .flat_map(|s| &s.transitions)
                .map(|t| t.guard.literal_count())
                .sum(),
        }
    }

    /// The algorithm form of its states (the initial state's; [`AlgorithmKind::Tri`] when
    /// it has no state).
    pub(crate) fn algorithm_kind(&self) -> AlgorithmKind {
        self.states
            .first()
            .map(|s| s.algorithm.kind())
            .unwrap_or_default()
    }

    /// Checks the internal consistency the rest of the crate relies on: at least one state,
    /// vector lengths match the interface, targets and guard variables in range.
    pub fn validate(&self) -> Result<(), String> {
        if self.states.is_empty() {
            return Err("the ECC has no states".into());
        }
        if self.initial_outputs.len() != self.outputs.len() {
            return Err(format!(
                "initial_outputs has {} values but there are {} outputs",
                self.initial_outputs.len(),
                self.outputs.len()
            ));
        }
        let kind = self.algorithm_kind();
        for (i, s) in self.states.iter().enumerate() {
            if s.algorithm.len() != self.outputs.len() {
                return Err(format!(
                    "state {} ({}) has an algorithm for {} outputs, the interface has {}",
                    i,
                    s.name,
                    s.algorithm.len(),
                    self.outputs.len()
                ));
            }
            if s.algorithm.kind() != kind {
                return Err(format!(
                    "state {} ({}) mixes tri and binary algorithms",
                    i, s.name
                ));
            }
            for (k, t) in s.transitions.iter().enumerate() {
                if t.target.0 >= self.states.len() {
                    return Err(format!(
                        "transition {} of state {} ({}) targets state {}, which does not exist",
                        k, i, s.name, t.target.0
                    ));
                }
                if let Some(v) = t.guard.max_var() {
                    if v.0 >= self.inputs.len() {
                        return Err(format!(
                            "transition {} of state {} ({}) reads input {}, which does not exist",
                            k, i, s.name, v.0
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn size_is_written_inside_a_sentence_and_as_the_result_line() {
        let s = Size {
            c: 5,
            k: 3,
            t: 10,
            n: 15,
        };
        assert_eq!(s.to_string(), "C=5 K=3 T=10 N=15");
        assert_eq!(format!("{s:#}"), "C = 5  K = 3  T = 10  N = 15");
    }

    #[test]
    fn effects_of_both_algorithm_forms() {
        let tri = Algorithm::Tri(vec![Tri::Zero, Tri::One, Tri::Keep]);
        assert_eq!(
            Effect::all(&tri),
            vec![Effect::Set(false), Effect::Set(true), Effect::Keep]
        );
        let bin = Algorithm::Binary {
            a0: vec![false, true, false, true],
            a1: vec![false, true, true, false],
        };
        assert_eq!(
            Effect::all(&bin),
            vec![
                Effect::Set(false),
                Effect::Set(true),
                Effect::Keep,
                Effect::Flip
            ]
        );
    }
}
