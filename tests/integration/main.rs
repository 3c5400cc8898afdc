//! Integration tests: one test binary, one submodule per area (fast links).

// The benchmark cases, from the library (its feature `cases`, which the dev-dependency on this
// crate turns on), as `crate::cases` in every test module.
use fbsynth::cases;

mod ambiguity;
mod cli;
mod closed_loop;
mod common;
mod events;
mod iec;
mod layering;
mod learn_plant;
mod limits;
mod live;
mod logs;
mod modes;
mod modular;
mod noisy;
mod nusmv_answers;
mod outputs;
mod pipeline;
mod plant_rules;
mod plants;
mod robustness;
mod schemas;
mod semantics;
mod st_grammar;
mod synthesis;
mod tank;
