//! Exact synthesis: the smallest ECC (least C, then K if asked, then T, then N) that
//! reproduces the scenarios and, given a [`Check`], satisfies every property in closed loop
//! as NuSMV certifies (counterexample-guided refinement, [`super::cegis`]).

use super::cegis::{self, Iteration};
use super::{Check, Error, Event, Events};
use crate::sat::{self, Synthesis};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use crate::verify::Report;
use std::path::PathBuf;

pub use crate::sat::Options as SatOptions;

/// Settings of exact synthesis.
#[derive(Debug, Clone)]
pub struct Options {
    /// The SAT synthesis: algorithms, bounds, guard model. With a [`Check`] the cube guard
    /// model is always used (at most [`DEFAULT_OUT_DEGREE`] transitions per state unless
    /// set), so the machine is defined on every input: counterexamples run on inputs nobody
    /// recorded.
    pub sat: SatOptions,
    /// With a check: give up after this many candidates.
    pub max_iterations: usize,
    /// Report every step of every minimization as [`Event::Solver`].
    pub verbose: bool,
    /// With a check: where to keep the closed-loop model of the last candidate when the
    /// loop fails (so the user can read what NuSMV choked on).
    pub keep_failed_model: Option<PathBuf>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            sat: SatOptions::default(),
            max_iterations: 500,
            verbose: false,
            keep_failed_model: None,
        }
    }
}

/// The out-degree bound of the closed-loop guard model when none is given.
pub const DEFAULT_OUT_DEGREE: usize = 6;

impl Options {
    fn sat(&self, verified: bool) -> SatOptions {
        let mut sat = self.sat.clone();
        if verified && sat.cube_slots.is_none() {
            sat.cube_slots = Some(DEFAULT_OUT_DEGREE);
        }
        sat
    }
}

/// NuSMV's word that a machine is correct in closed loop.
#[derive(Debug, Clone)]
pub struct Certificate {
    /// The verdict on every property (all hold).
    pub report: Report,
    /// The closed-loop model NuSMV verified.
    pub model_text: String,
}

/// The result of exact synthesis.
#[derive(Debug, Clone)]
pub struct Exact {
    /// The machine, its size and figures (replayed on every scenario).
    pub synthesis: Synthesis,
    /// With a check: NuSMV's certificate.
    pub certificate: Option<Certificate>,
    /// With a check: every candidate of the loop.
    pub iterations: Vec<Iteration>,
}

/// Synthesizes the smallest machine for `set`; with `check`, the smallest that NuSMV also
/// verifies.
pub fn run(
    set: &ScenarioSet,
    check: Option<&Check>,
    opts: &Options,
    events: Events<'_>,
) -> Result<Exact, Error> {
    let tree = ScenarioTree::build(set)?;
    let Some(check) = check else {
        let synthesis = sat::synthesize(set, &tree, &opts.sat(false), &mut |m| {
            events(Event::Solver(m))
        })?;
        return Ok(Exact {
            synthesis,
            certificate: None,
            iterations: Vec::new(),
        });
    };
    let mut verifier = check.verifier()?;
    let config = cegis::Config {
        sat: opts.sat(true),
        max_iterations: opts.max_iterations,
        verbose: opts.verbose,
    };
    match cegis::run(set, &tree, &mut verifier, &config, events) {
        Ok(v) => Ok(Exact {
            synthesis: v.synthesis,
            certificate: Some(Certificate {
                report: v.report,
                model_text: v.model_text,
            }),
            iterations: v.iterations,
        }),
        Err(e) => {
            if let (Some(keep), Some(model)) = (&opts.keep_failed_model, verifier.last_model()) {
                // Best effort: the error below is what the user needs first.
                if let Some(dir) = keep.parent() {
                    let _ = std::fs::create_dir_all(dir);
                }
                if let Ok(text) = std::fs::read(model) {
                    let _ = crate::files::write_atomic(keep, &text);
                }
            }
            Err(e.into())
        }
    }
}
