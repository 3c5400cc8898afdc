//! SMV emission: an ECC as a NuSMV module ([`ecc_module`]), and the rules for the names that go
//! into a model.
//!
//! In: an [`Ecc`](crate::ecc::Ecc) and user-chosen names. Out: SMV text, or an error naming the
//! identifier that cannot be used. Every name that reaches SMV code passes [`check_identifier`]
//! first, so a model never fails to parse because of a user's naming.

pub mod closed_loop;
pub mod ecc_module;
pub mod plant;

pub use ecc_module::{state_value, write_ecc_module, SmvError};

use crate::ecc::Algorithm;

/// Words NuSMV 2.5/2.6 reserves (case-sensitive), plus the LTL/CTL operator letters, which
/// NuSMV's lexer also treats as keywords.
const KEYWORDS: &[&str] = &[
    "MODULE",
    "VAR",
    "IVAR",
    "DEFINE",
    "ASSIGN",
    "TRANS",
    "INIT",
    "INVAR",
    "SPEC",
    "LTLSPEC",
    "CTLSPEC",
    "INVARSPEC",
    "COMPUTE",
    "FAIRNESS",
    "JUSTICE",
    "COMPASSION",
    "CONSTANTS",
    "FROZENVAR",
    "ISA",
    "PSLSPEC",
    "PRED",
    "MIRROR",
    "NAME",
    "process",
    "array",
    "of",
    "boolean",
    "integer",
    "real",
    "word",
    "unsigned",
    "signed",
    "TRUE",
    "FALSE",
    "case",
    "esac",
    "init",
    "next",
    "self",
    "mod",
    "union",
    "in",
    "xor",
    "xnor",
    "G",
    "F",
    "X",
    "U",
    "V",
    "Y",
    "Z",
    "H",
    "O",
    "S",
    "T",
    "A",
    "E",
    "AG",
    "AF",
    "AX",
    "EG",
    "EF",
    "EX",
    "AU",
    "EU",
    "ABF",
    "ABG",
    "EBF",
    "EBG",
    "BU",
    "count",
    "toint",
    "bool",
    "word1",
    "uwconst",
    "swconst",
    "resize",
    "extend",
    "sizeof",
    "floor",
];

/// Checks that a user-chosen name (input, output, module) can be used verbatim in SMV code.
///
/// SMV itself allows `[A-Za-z_][A-Za-z0-9_$#-]*`; we accept only the portable core
/// `[A-Za-z][A-Za-z0-9_]*`, which is also a legal IEC 61131-3 identifier in almost all cases,
/// and reject NuSMV keywords (case-sensitive, as NuSMV is). Names starting with `_` are reserved
/// for identifiers the emitters generate, so generated names never collide with user names.
/// The error says why the name is rejected; the caller adds where the name came from.
pub fn check_identifier(name: &str) -> Result<(), String> {
    let mut chars = name.chars();
    match chars.next() {
        None => return Err("the name is empty".into()),
        Some('_') => {
            return Err("names starting with `_` are reserved for generated identifiers".into())
        }
        Some(c) if !c.is_ascii_alphabetic() => {
            return Err(format!(
                "a name must start with a letter A-Z or a-z, not `{c}`"
            ))
        }
        Some(_) => {}
    }
    if let Some(c) = chars.find(|c| !(c.is_ascii_alphanumeric() || *c == '_')) {
        return Err(format!(
            "a name may contain only letters A-Z a-z, digits and `_`, not `{c}`"
        ));
    }
    if KEYWORDS.contains(&name) {
        return Err("it is a NuSMV keyword".into());
    }
    Ok(())
}

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
    fn identifiers_accept_plain_names() {
        for ok in ["a", "c1Home", "vac_on", "Z9", "Process", "s0", "REQ2"] {
            assert_eq!(check_identifier(ok), Ok(()), "{ok}");
        }
    }

    #[test]
    fn identifiers_reject_keywords_reserved_and_odd_characters() {
        let cases = [
            ("", "empty"),
            ("_state", "reserved"),
            ("1a", "start with a letter"),
            ("a-b", "not `-`"),
            ("a$b", "not `$`"),
            ("vác", "not `á`"),
            ("next", "keyword"),
            ("X", "keyword"),
            ("AG", "keyword"),
            ("process", "keyword"),
            ("TRUE", "keyword"),
        ];
        for (name, why) in cases {
            let err = check_identifier(name).unwrap_err();
            assert!(err.contains(why), "{name}: {err}");
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
