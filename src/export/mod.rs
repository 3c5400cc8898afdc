//! Export formats of an ECC (placeholder while the emitters are written).

pub mod guard_text;
pub mod json;

#[cfg(test)]
pub(crate) mod samples;
