//! The verification terms' source: closed-loop NuSMV runs through a [`Verifier`], cached
//! by machine.
//!
//! In: a candidate [`Ecc`]. Out: its [`Verdicts`] (properties that hold, longest
//! counterexample, counterexample inputs for the weighted mutation). Identical candidates are
//! common in a search (neutral mutations, restarts from the shared best), so verdicts are
//! cached in a map shared by every colony; NuSMV's answer for one model does not depend on who
//! asks, so the cache does not change what a seeded run computes.

use super::fitness::Verdicts;
use super::machine::input_bits;
use crate::ecc::Ecc;
use crate::verify::{Verification, Verifier, VerifyError};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// Something that gives verdicts on candidates; one per colony.
pub trait Checker: Send {
    fn check(&mut self, ecc: &Ecc) -> Result<Arc<Verdicts>, VerifyError>;
}

/// Shared cache and counters of every [`Oracle`] made from one [`Shared`].
#[derive(Debug, Default)]
pub struct Shared {
    cache: Mutex<HashMap<Ecc, Arc<Verdicts>>>,
    /// NuSMV runs.
    pub runs: AtomicU64,
    /// Answers from the cache.
    pub hits: AtomicU64,
}

/// The verifier of one colony with the shared cache.
pub struct Oracle {
    verifier: Verifier,
    shared: Arc<Shared>,
}

impl Oracle {
    /// A colony's oracle: its own verifier, the cache shared with the others.
    pub fn new(verifier: Verifier, shared: Arc<Shared>) -> Oracle {
        Oracle { verifier, shared }
    }
}

/// The verdicts of one verification run.
pub fn verdicts_of(v: &Verification, ecc: &Ecc) -> Verdicts {
    let props = &v.report.properties;
    let satisfied = props.iter().filter(|p| p.holds).count();
    let longest = props
        .iter()
        .filter(|p| !p.holds)
        .map(|p| p.counterexample_length.unwrap_or(1))
        .max()
        .unwrap_or(0);
    let negatives: Vec<_> = v
        .counterexamples
        .iter()
        .filter_map(|c| c.negative_scenario(&ecc.inputs, &ecc.outputs))
        .collect();
    let counterexamples = negatives
        .iter()
        .map(|n| n.steps.iter().map(|s| input_bits(&s.inputs)).collect())
        .collect();
    Verdicts {
        satisfied,
        total: props.len(),
        longest_counterexample: longest,
        counterexamples,
        negatives,
    }
}

impl Checker for Oracle {
    fn check(&mut self, ecc: &Ecc) -> Result<Arc<Verdicts>, VerifyError> {
        if let Some(v) = self
            .shared
            .cache
            .lock()
            .expect("no panic holds it")
            .get(ecc)
        {
            self.shared.hits.fetch_add(1, Ordering::Relaxed);
            return Ok(v.clone());
        }
        let v = self.verifier.verify(ecc)?;
        self.shared.runs.fetch_add(1, Ordering::Relaxed);
        let verdicts = Arc::new(verdicts_of(&v, ecc));
        self.shared
            .cache
            .lock()
            .expect("no panic holds it")
            .insert(ecc.clone(), verdicts.clone());
        Ok(verdicts)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nusmv::test_support::nusmv_or_skip;
    use crate::scenario::tree::ScenarioTree;
    use crate::search::{run, Config, Machine, ScenarioData};
    use crate::verify::Problem;
    use std::path::Path;
    use std::time::Duration;

    /// The verification-in-the-loop paper's setting: one Pick-and-Place scenario (a piece on track 1) and its three
    /// properties. SAT's machine for the scenario alone is the start; the search must make
    /// `G (pp1 -> F vp1)` hold, and NuSMV confirms the result.
    #[test]
    fn search_finds_a_verified_controller_for_seed_001s_case() {
        let Some(nusmv) = nusmv_or_skip() else {
            return;
        };
        let mut set = crate::cases::pnp::generate();
        set.scenarios.truncate(1);
        let dir = tempfile::tempdir().unwrap();
        let spec = dir.path().join("s.ltl");
        std::fs::write(
            &spec,
            "c1_exclusive: G !(c1Extend & c1Retract)\nc2_exclusive: G !(c2Extend & c2Retract)\ntrack1_served: G (pp1 -> F vp1)\n",
        )
        .unwrap();
        let plant = Path::new(env!("CARGO_MANIFEST_DIR")).join("smv/pnp_surrogate.smv");
        let problem = Arc::new(Problem::load(&spec, &plant, &set.inputs, &set.outputs).unwrap());
        let tree = ScenarioTree::build(&set).unwrap();
        let opts = crate::sat::Options {
            cube_slots: Some(6),
            ..Default::default()
        };
        let start = crate::sat::synthesize(&set, &tree, &opts, &mut |_| {}).unwrap();
        let shared = Arc::new(Shared::default());
        let config = Config {
            states: 6,
            colonies: 2,
            threads: 2,
            seed: 3,
            time_limit: Some(Duration::from_secs(120)),
            initial: vec![Machine::from_ecc(&start.ecc).unwrap()],
            ..Config::default()
        };
        let checkers: Vec<Box<dyn Checker>> = (0..2)
            .map(|_| {
                let verifier = Verifier::new(problem.clone(), &nusmv).unwrap();
                Box::new(Oracle::new(verifier, shared.clone())) as Box<dyn Checker>
            })
            .collect();
        let data = ScenarioData::new(&set).unwrap();
        let out = run(&data, &config, checkers, &mut |_| {}).unwrap();
        assert!(out.perfect, "no verified controller: {:?}", out.score);
        set.check(&out.ecc).unwrap();
        let v = Verifier::new(problem, &nusmv)
            .unwrap()
            .verify(&out.ecc)
            .unwrap();
        assert!(v.report.all_hold(), "{}", v.report.to_text());
    }
}
