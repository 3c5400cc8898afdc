//! Benchmark cases owned by the project: a plant simulation, a hand-made reference controller
//! (the "legacy PLC" whose logic is to be recovered) and the generator of the recorded data.
//!
//! In: nothing but the case's own constants (and, for `pnp`, a work-piece order; for `tank`, a
//! seed of the noisy plant).
//! Out: [`ScenarioSet`](crate::scenario::ScenarioSet)s and the data files under `specs/` that
//! are committed beside the code and checked against the generator by a test.
//!
//! The reference controllers ([`mod@reference`]) are always compiled: `synth learn --oracle
//! case:NAME` answers with them. The plant simulations and recorders (`distribution`, `pnp`,
//! `tank` and the closed loop they share) need the cargo feature `cases`: the tests and the
//! developer binary `synth-dev` enable it, the `synth` binary does without.

pub mod reference;

#[cfg(feature = "cases")]
pub mod distribution;
#[cfg(feature = "cases")]
pub mod free_inputs;
#[cfg(feature = "cases")]
pub mod pnp;
#[cfg(feature = "cases")]
mod simulate;
#[cfg(feature = "cases")]
pub mod station;
#[cfg(feature = "cases")]
pub mod tank;

#[cfg(feature = "cases")]
pub use simulate::{closed_loop, Drive, Scanned, Simulated};
