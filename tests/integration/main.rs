//! Integration tests: one test binary, one submodule per area (fast links).

mod common;
mod synthesis;
