//! fbsynth: rebuild the lost control logic of a legacy PLC as a minimal IEC 61499 basic
//! function block, and prove it safe with NuSMV before it is loaded into a plant.
//!
//! Layers (each imports only the ones listed before it):
//! - [`ecc`]: the model and its simulator (pure data, no I/O);
//! - [`scenario`]: execution scenarios, their file formats and the scenario tree;
//! - [`sat`]: exact synthesis with varisat;
//! - [`smv`]: SMV emission of an ECC and of the closed loop, and the identifier rules every
//!   exported name obeys;
//! - [`export`]: JSON, IEC 61499 `.fbt`, Structured Text, Graphviz, and writing them all
//!   (including the SMV module) to files;
//! - [`ltl`]: LTL specification files (own grammar) and evaluation on lassos;
//! - [`nusmv`]: running the NuSMV model checker and parsing its output (never imports `sat`);
//! - [`verify`]: closed-loop verification of one ECC, counterexamples as negative scenarios;
//! - [`cegis`]: the loop joining `sat` and `verify`;
//! - [`search`]: metaheuristic synthesis (seeds 004, 001) with verification-aware fitness;
//! - [`ingest`]: streaming ingestion of raw PLC I/O data-flow logs (long/wide, gzip) into
//!   scenario steps;
//! - [`cases`]: benchmark cases (plant simulation, reference controller, their recorded data);
//! - [`cli`]: the `synth` command line.

pub mod cases;
pub mod cegis;
pub mod cli;
pub mod ecc;
pub mod events;
pub mod export;
pub mod files;
pub mod ingest;
pub mod ltl;
pub mod nusmv;
pub mod sat;
pub mod scenario;
pub mod search;
pub mod smv;
pub mod verify;
