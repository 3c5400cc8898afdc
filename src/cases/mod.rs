//! Benchmark cases owned by the project: a plant simulation, a hand-made reference controller
//! (the "legacy PLC" whose logic is to be recovered) and the generator of the recorded data.
//!
//! In: nothing but the case's own constants (and, for [`pnp`], a work-piece order).
//! Out: [`ScenarioSet`](crate::scenario::ScenarioSet)s and the data files under `specs/` that
//! are committed beside the code and checked against the generator by a test.

pub mod distribution;
pub mod pnp;
