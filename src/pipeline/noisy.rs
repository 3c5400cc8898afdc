//! Synthesis from noisy sampled logs: the scan-cycle error model of Chivilikhin, Patil,
//! Chukharev, Cordonnier and Vyatkin, "Automatic state machine reconstruction from legacy
//! PLC using data collection and SAT solver". Minimal machines are enumerated by number of corrected
//! errors ε; with a [`Check`] every candidate is verified by NuSMV and the enumeration stops at
//! the first one that satisfies every property.

use super::{Check, Error, Event, Events};
use crate::sat::noisy::{synthesize_noisy, Candidate, Flow, NoisySynthesis};
use crate::scenario::ScenarioSet;

pub use crate::sat::noisy::NoisyOptions as Options;

/// The candidates and, with a check, NuSMV's verdict on each.
pub struct Noisy {
    /// Minimal machines by ε, with the least C, K and T.
    pub synthesis: NoisySynthesis,
    /// Per candidate: `Some(true)` every property holds, `Some(false)` one fails, `None`
    /// not checked.
    pub verdicts: Vec<Option<bool>>,
}

impl Noisy {
    /// The 1-based number of the first candidate NuSMV verified.
    pub fn first_verified(&self) -> Option<usize> {
        self.verdicts
            .iter()
            .position(|v| *v == Some(true))
            .map(|k| k + 1)
    }
}

/// Enumerates minimal machines for the noisy `set`; with `check`, verifies each one.
pub fn run(
    set: &ScenarioSet,
    check: Option<&Check>,
    opts: &Options,
    events: Events<'_>,
) -> Result<Noisy, Error> {
    let mut verifier = check.map(Check::verifier).transpose()?;
    let mut verdicts: Vec<Option<bool>> = Vec::new();
    let mut check_error: Option<Error> = None;
    // Both closures report progress: share the sink through a cell.
    let events = std::cell::RefCell::new(events);
    let mut accept = |c: &Candidate| -> Flow {
        let Some(verifier) = verifier.as_mut() else {
            verdicts.push(None);
            return Flow::Continue;
        };
        match verifier.verify(&c.ecc) {
            Ok(v) => {
                let failing: Vec<String> =
                    v.report.failing().iter().map(|s| s.to_string()).collect();
                (events.borrow_mut())(Event::CandidateVerdict { failing: &failing });
                let holds = v.report.all_hold();
                verdicts.push(Some(holds));
                if holds {
                    Flow::Stop
                } else {
                    Flow::Continue
                }
            }
            Err(e) => {
                check_error = Some(e.into());
                Flow::Stop
            }
        }
    };
    let synthesis = synthesize_noisy(
        set,
        opts,
        &mut |m| (events.borrow_mut())(Event::Solver(m)),
        &mut accept,
    )?;
    if let Some(e) = check_error {
        return Err(e);
    }
    verdicts.resize(synthesis.candidates.len(), None);
    Ok(Noisy {
        synthesis,
        verdicts,
    })
}
