//! Integration tests: one test binary, one submodule per area (fast links).

mod cli;
mod common;
mod synthesis;
