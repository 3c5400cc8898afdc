//! Integration tests: one test binary, one submodule per area (fast links).

// The benchmark cases are not part of the library; the tests compile the binary's copy.
#[path = "../../src/cases/mod.rs"]
#[allow(dead_code)]
mod cases;

mod ambiguity;
mod cli;
mod closed_loop;
mod common;
mod events;
mod limits;
mod logs;
mod modes;
mod modular;
mod noisy;
mod pipeline;
mod robustness;
mod schemas;
mod synthesis;
mod tank;
