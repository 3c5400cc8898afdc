//! The verification terms' source: closed-loop NuSMV runs through a [`Verifier`]
//! ([`Oracle`]), or the in-process checker [`crate::check`] ([`InProcess`]), cached by
//! machine.
//!
//! In: a candidate [`Ecc`]. Out: its [`Verdicts`] (properties that hold, longest
//! counterexample, counterexample inputs for the weighted mutation). Identical candidates are
//! common in a search (neutral mutations, restarts from the shared best), so verdicts are
//! cached in a map shared by every colony; the answer for one model does not depend on who
//! asks, so the cache does not change what a seeded run computes.
//!
//! [`InProcess`] answers in about a millisecond where NuSMV takes 50-2000 ms, so the search
//! can judge every child instead of one in a thousand; it only guides. Whoever runs the search
//! has NuSMV check the machine it ends with, and only that verdict is reported as verified.

use super::fitness::Verdicts;
use super::machine::input_bits;
use crate::check::{self, Automata, CheckError, ExplicitVerdict, Limits, PlantMemo, Wiring};
use crate::ecc::Ecc;
use crate::ltl::Property;
use crate::plant::Model;
use crate::verify::{Problem, VerificationResult, Verifier, VerifyError};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// Why a candidate could not be judged.
#[derive(Debug, thiserror::Error)]
pub enum OracleError {
    /// The closed-loop verification with NuSMV failed (see [`VerifyError`]).
    #[error(transparent)]
    Nusmv(#[from] VerifyError),
    /// The in-process checker refused the candidate or the plant (not for too many states:
    /// those candidates go to NuSMV).
    #[error("the in-process checker: {0}")]
    InProcess(#[from] CheckError),
}

/// Something that gives verdicts on candidates; one per colony.
pub(crate) trait Checker: Send {
    /// The verdicts on `ecc` in closed loop with the plant (both checkers cache them).
    fn check(&mut self, ecc: &Ecc) -> Result<Arc<Verdicts>, OracleError>;
}

/// Shared cache and counters of every [`Oracle`] made from one [`Shared`].
#[derive(Debug, Default)]
pub(crate) struct Shared {
    cache: Mutex<HashMap<Ecc, Arc<Verdicts>>>,
    /// NuSMV runs.
    pub(crate) runs: AtomicU64,
    /// In-process checks.
    pub(crate) in_process: AtomicU64,
    /// Answers from the cache.
    pub(crate) hits: AtomicU64,
}

/// The verifier of one colony with the shared cache.
pub(crate) struct Oracle {
    verifier: Verifier,
    shared: Arc<Shared>,
}

impl Oracle {
    /// A colony's oracle: its own verifier, the cache shared with the others.
    pub(crate) fn new(verifier: Verifier, shared: Arc<Shared>) -> Oracle {
        Oracle { verifier, shared }
    }
}

/// The verdicts of one verification run.
pub(crate) fn verdicts_of(v: &VerificationResult, ecc: &Ecc) -> Verdicts {
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

impl Shared {
    fn cached(&self, ecc: &Ecc) -> Option<Arc<Verdicts>> {
        let v = self
            .cache
            .lock()
            .expect("no panic holds it")
            .get(ecc)
            .cloned();
        if v.is_some() {
            self.hits.fetch_add(1, Ordering::Relaxed);
        }
        v
    }

    fn keep(&self, ecc: &Ecc, verdicts: Verdicts) -> Arc<Verdicts> {
        let verdicts = Arc::new(verdicts);
        self.cache
            .lock()
            .expect("no panic holds it")
            .insert(ecc.clone(), verdicts.clone());
        verdicts
    }
}

impl Oracle {
    fn nusmv(&mut self, ecc: &Ecc) -> Result<Verdicts, OracleError> {
        let v = self.verifier.verify(ecc)?;
        self.shared.runs.fetch_add(1, Ordering::Relaxed);
        Ok(verdicts_of(&v, ecc))
    }
}

impl Checker for Oracle {
    fn check(&mut self, ecc: &Ecc) -> Result<Arc<Verdicts>, OracleError> {
        if let Some(v) = self.shared.cached(ecc) {
            return Ok(v);
        }
        let v = self.nusmv(ecc)?;
        Ok(self.shared.keep(ecc, v))
    }
}

/// The plant, wiring and properties the in-process checker needs, shared by the colonies.
#[derive(Debug)]
pub(crate) struct Closed {
    model: Arc<Model>,
    coupling: Wiring,
    props: Vec<Property>,
    automata: Automata,
    names: Vec<String>,
}

impl Closed {
    /// The in-process view of `problem` for a controller over the interface it was loaded
    /// with; `None` when the plant is outside what [`crate::check`] reads or the names do not
    /// wire up (NuSMV then gives every verdict).
    pub(crate) fn new(problem: &Problem) -> Option<Closed> {
        let model = problem.model.clone().ok()?;
        let coupling = Wiring::new(&model, &problem.coupling).ok()?;
        Some(Closed {
            model,
            coupling,
            props: problem.props.clone(),
            automata: Automata::of(&problem.props),
            names: problem.property_names(),
        })
    }
}

/// A colony's in-process checker with the shared cache; a machine on which it cannot decide
/// (a property outside its subset, too many states) goes to NuSMV.
pub(crate) struct InProcess {
    closed: Arc<Closed>,
    nusmv: Oracle,
    memo: PlantMemo,
}

impl InProcess {
    /// A colony's in-process checker of `closed`, falling back to `nusmv` (whose cache it
    /// shares) when it cannot decide.
    pub(crate) fn new(closed: Arc<Closed>, nusmv: Oracle) -> InProcess {
        InProcess {
            closed,
            nusmv,
            memo: PlantMemo::default(),
        }
    }

    fn decide(&mut self, ecc: &Ecc) -> Result<Option<Verdicts>, OracleError> {
        let c = self.closed.clone();
        let r = check::check_with(
            &c.model,
            &c.coupling,
            ecc,
            &c.props,
            &c.automata,
            &Limits::default(),
            &mut self.memo,
        );
        let verdicts = match r {
            Ok(v) => v,
            // Past a bound of the checker (states, transitions, memory), NuSMV judges.
            Err(e) if e.is_bound() => return Ok(None),
            Err(e) => return Err(e.into()),
        };
        let mut out = Verdicts {
            satisfied: 0,
            total: verdicts.len(),
            longest_counterexample: 0,
            counterexamples: Vec::new(),
            negatives: Vec::new(),
        };
        for (k, v) in verdicts.iter().enumerate() {
            match v {
                ExplicitVerdict::Holds => out.satisfied += 1,
                ExplicitVerdict::Unsupported(_) => return Ok(None),
                ExplicitVerdict::Violated(lasso) => {
                    let n = c.coupling.negative(&c.model, lasso, &c.names[k])?;
                    out.longest_counterexample = out.longest_counterexample.max(n.steps.len());
                    out.counterexamples
                        .push(n.steps.iter().map(|s| input_bits(&s.inputs)).collect());
                    out.negatives.push(n);
                }
            }
        }
        Ok(Some(out))
    }
}

impl Checker for InProcess {
    fn check(&mut self, ecc: &Ecc) -> Result<Arc<Verdicts>, OracleError> {
        if let Some(v) = self.nusmv.shared.cached(ecc) {
            return Ok(v);
        }
        let v = match self.decide(ecc)? {
            Some(v) => {
                self.nusmv.shared.in_process.fetch_add(1, Ordering::Relaxed);
                v
            }
            None => self.nusmv.nusmv(ecc)?,
        };
        Ok(self.nusmv.shared.keep(ecc, v))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::nusmv::nusmv_for_tests;
    use crate::scenario::tree::ScenarioTree;
    use crate::search::{run, Config, Machine, ScenarioData};
    use crate::verify::Problem;
    use std::path::Path;
    use std::time::Duration;

    /// The verification-in-the-loop paper's setting: its Pick-and-Place scenario, its three
    /// properties on the project's plant, and SAT's machine for the scenario alone.
    fn seed_001s_case() -> (
        crate::scenario::ScenarioSet,
        Arc<Problem>,
        crate::sat::Synthesis,
    ) {
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
            max_out_degree: Some(6),
            ..Default::default()
        };
        let start = crate::sat::synthesize(&set, &tree, &opts, &mut |_| {}).unwrap();
        (set, problem, start)
    }

    /// One Pick-and-Place scenario (a piece on track 1) and its three
    /// properties. SAT's machine for the scenario alone is the start; the search must make
    /// `G (pp1 -> F vp1)` hold, and NuSMV confirms the result.
    #[test]
    fn search_finds_a_verified_controller_for_seed_001s_case() {
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let (set, problem, start) = seed_001s_case();
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

    /// The in-process judge agrees with NuSMV on the machines a search meets: SAT's machine
    /// for the scenario (fails `track1_served`) and random ones, labelled from the scenario.
    #[test]
    fn in_process_verdicts_agree_with_nusmv_s() {
        use rand::SeedableRng;
        let Some(nusmv) = nusmv_for_tests() else {
            return;
        };
        let (set, problem, start) = seed_001s_case();
        let closed = Arc::new(Closed::new(&problem).unwrap());
        let data = ScenarioData::new(&set).unwrap();
        let mut eval = crate::search::Evaluator::new(&data);
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let mut machines = vec![Machine::from_ecc(&start.ecc).unwrap()];
        machines.extend((0..24).map(|_| Machine::random(&mut rng, set.inputs.len(), 6, 4)));
        let shared = || Arc::new(Shared::default());
        let mut nusmv_judge =
            Oracle::new(Verifier::new(problem.clone(), &nusmv).unwrap(), shared());
        let mut in_process = InProcess::new(
            closed,
            Oracle::new(Verifier::new(problem, &nusmv).unwrap(), shared()),
        );
        let mut failing = 0;
        for m in &machines {
            eval.evaluate(m);
            let ecc = m.to_ecc(
                &data.inputs,
                &data.outputs,
                &data.initial_outputs,
                &eval.algorithms(),
            );
            let a = in_process.check(&ecc).unwrap();
            let b = nusmv_judge.check(&ecc).unwrap();
            assert_eq!((a.satisfied, a.total), (b.satisfied, b.total), "{ecc:?}");
            // Every counterexample the in-process judge gives is followed by the machine.
            assert!(a.negatives.iter().all(|n| n.followed_by(&ecc)));
            failing += usize::from(!a.all_hold());
        }
        assert!(
            failing > 0,
            "no machine fails a property: the comparison shows nothing"
        );
        assert_eq!(in_process.nusmv.shared.runs.load(Ordering::Relaxed), 0);
    }
}
