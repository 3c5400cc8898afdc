//! fbsynth: rebuild the lost control logic of a legacy PLC as a minimal IEC 61499 basic
//! function block, and prove it safe with NuSMV before it is loaded into a plant.
//!
//! Layers (each imports only the ones listed before it):
//! - [`ecc`]: the model and its simulator (pure data, no I/O);
//! - [`scenario`]: execution scenarios, their file formats and the scenario tree;
//! - [`sat`]: exact synthesis with varisat;
//! - [`export`]: JSON, IEC 61499 `.fbt`, Structured Text, Graphviz;
//! - [`smv`]: SMV emission of an ECC and of the closed loop;
//! - [`cli`]: the `synth` command line.

pub mod ecc;
pub mod ltl;
