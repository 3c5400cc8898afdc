//! SMV emission: an ECC as a NuSMV module ([`ecc_module`]), and the rules for the names that go
//! into a model (kept with the other languages' in [`crate::ecc::ident`]).
//!
//! In: an [`Ecc`](crate::ecc::Ecc) and user-chosen names. Out: SMV text, or an error naming the
//! identifier that cannot be used. Every name that reaches SMV code passes [`check_identifier`]
//! first, so a model never fails to parse because of a user's naming.

pub mod closed_loop;
pub mod ecc_module;
pub mod plant;

pub use ecc_module::{state_value, write_ecc_module, SmvError};

pub use crate::ecc::ident::check_smv as check_identifier;
pub use crate::ecc::ident::{bool_literal, parse_bool_literal};

use crate::ecc::Algorithm;

/// What a state's algorithm does to one output when the state is entered.
///
/// Both algorithm forms reduce to this: an output's new value is a function of its old value
/// alone, and there are exactly four such functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Effect {
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
    pub fn of(algorithm: &Algorithm, z: usize) -> Effect {
        match (algorithm.apply_one(z, false), algorithm.apply_one(z, true)) {
            (false, false) => Effect::Set(false),
            (true, true) => Effect::Set(true),
            (false, true) => Effect::Keep,
            (true, false) => Effect::Flip,
        }
    }

    /// The effects of `algorithm` on every output, in interface order.
    pub fn all(algorithm: &Algorithm) -> Vec<Effect> {
        (0..algorithm.len())
            .map(|z| Effect::of(algorithm, z))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::Tri;

    #[test]
    fn booleans_read_back_as_written() {
        for v in [false, true] {
            assert_eq!(parse_bool_literal(bool_literal(v)), Some(v));
        }
        for other in ["true", "1", "idle", ""] {
            assert_eq!(parse_bool_literal(other), None, "{other}");
        }
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
