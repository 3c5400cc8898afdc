//! SMV emission: an ECC as a NuSMV module ([`ecc_module`]), and the rules for the names that go
//! into a model (kept with the other languages' in [`crate::ecc::ident`]).
//!
//! In: an [`Ecc`](crate::ecc::Ecc) and user-chosen names. Out: SMV text, or an error naming the
//! identifier that cannot be used. Every name that reaches SMV code passes [`check_identifier`]
//! first, so a model never fails to parse because of a user's naming.

pub mod composition;
pub(crate) mod ecc_module;
pub mod plant;
pub(crate) mod plant_checks;

pub use ecc_module::SmvError;

pub(crate) use crate::ecc::ident::check_smv as check_identifier;
pub(crate) use crate::ecc::ident::{bool_literal, parse_bool_literal};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn booleans_read_back_as_written() {
        for v in [false, true] {
            assert_eq!(parse_bool_literal(bool_literal(v)), Some(v));
        }
        for other in ["true", "1", "idle", ""] {
            assert_eq!(parse_bool_literal(other), None, "{other}");
        }
    }
}
