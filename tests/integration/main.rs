//! Integration tests: one test binary, one submodule per area (fast links).

mod cli;
mod closed_loop;
mod common;
mod events;
mod modular;
mod noisy;
mod synthesis;
mod tank;
