//! Integration tests: one test binary, one submodule per area (fast links).

mod cli;
mod closed_loop;
mod common;
mod noisy;
mod synthesis;
