//! fbsynth: rebuild the lost control logic of a legacy PLC as a minimal IEC 61499 basic
//! function block, and prove it safe with NuSMV before it is loaded into a plant.
//!
//! Start at [`pipeline`]: one function per method (exact SAT with NuSMV in the loop, search,
//! noisy logs, modular, refinement) over one verification problem
//! ([`verify::Problem`]). Below it, dependencies point toward the model:
//! - [`ecc`]: the model and its simulator (pure data, no I/O), and the identifier and literal
//!   rules of every language the tool writes ([`ecc::ident`]);
//! - [`scenario`]: execution scenarios, their file formats and the scenario tree;
//! - [`sat`]: exact synthesis with varisat (never imports `nusmv`);
//! - [`search`]: metaheuristic synthesis with verification-aware fitness;
//! - [`ltl`]: LTL specification files (own grammar) and evaluation on lassos;
//! - [`plant`]: the surrogate plant as a finite-state model (the SMV subset the plants use);
//! - [`check`]: an in-process explicit-state model checker of the closed loop (plant model ×
//!   ECC × LTL), fast enough to prune synthesis candidates; NuSMV stays the authority;
//! - [`game`]: the closed loop as a game (plant × outputs × property monitors × recordings),
//!   solved explicitly: whether any controller keeps the properties after the recordings;
//! - [`smv`]: SMV emission of an ECC and of the closed loop;
//! - [`nusmv`]: running the NuSMV model checker and parsing its output (never imports `sat`);
//! - [`verify`]: the verification problem and the one verifier (closed loop, counterexamples
//!   as negative scenarios);
//! - [`export`]: JSON, IEC 61499 `.fbt`, Structured Text, PLCopen XML, Graphviz, PNML;
//! - [`ingest`] and [`events`]: raw PLC I/O logs to scenarios and to process-mining event logs;
//! - [`files`]: reading user files (gzip, byte order mark) and atomic writing;
//! - [`quote`]: user input quoted in messages, cut when it is long;
//! - [`cases`]: the project's benchmark cases, reference controllers with (feature `cases`)
//!   their plant simulations and the recorders of the shipped data.
//!
//! - `command`: what each command of `synth` does between its arguments and what it prints
//!   (the files it reads, the pipeline it calls, the result folder it writes);
//! - [`cli`]: the `synth` command line (argument parsing, progress, printing, exit codes) over
//!   the commands; `synth`'s `main` calls [`cli::run`].

// Every public item says what it means in the domain; clippy's -D warnings keeps it so.
#![warn(missing_docs)]
#![cfg_attr(not(test), allow(dead_code, unused_imports))]

pub mod cases;
pub(crate) mod check;
pub mod cli;
pub(crate) mod command;
pub(crate) mod deadline;
pub mod ecc;
pub mod events;
pub mod export;
pub mod files;
pub(crate) mod game;
pub mod ingest;
pub mod live;
pub mod ltl;
pub mod nusmv;
pub mod pipeline;
pub mod plant;
pub(crate) mod quote;
pub mod sat;
pub mod scenario;
pub mod search;
pub(crate) mod signals;
pub mod smv;
pub(crate) mod verify;
