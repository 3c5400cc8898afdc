//! Export formats of an ECC (placeholder while the emitters are written).

pub mod guard_text;

#[cfg(test)]
pub(crate) mod samples;
