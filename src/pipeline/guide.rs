//! A verified machine where the properties ask for behaviour nobody recorded: the closed-loop
//! game as a guide for SAT.
//!
//! In: the recordings and a [`Check`]. Out: a machine that reproduces the recordings and that
//! NuSMV verifies ([`Outcome::Verified`]), or why the guide has none ([`Outcome::NotHere`]; the
//! caller goes on with the exact loop).
//!
//! The exact loop learns what the recordings do not show one counterexample at a time, and
//! where a property needs a whole behaviour nobody recorded (Pick-and-Place from one scenario:
//! tracks 2 and 3 never carry a work piece) there are too many wrong machines to rule out one by
//! one. The game ([`crate::game`]) answers that question for every behaviour of the plant at
//! once, but its strategy is large. So:
//! 1. solve the game (positions: plant × outputs × property monitors × recordings);
//! 2. the least machine SAT finds for the recordings alone, its guards narrowed to the input
//!    vectors recorded ([`repair::narrowed`]), repaired until it wins the game
//!    ([`crate::game::repair`]): its answers to the recordings are kept, and where nothing was
//!    recorded the game alone decides, not the generalizations SAT chose for fewest literals
//!    (they reach into the closed loop and the runs of step 3 keep them). Where its merged
//!    states join recorded answers the game needs apart, and the caller allows it
//!    ([`RepairStart`]), the recordings' tree as a machine is repaired instead;
//! 3. that machine recorded along every node of its closed loop with the game, and the least
//!    machine for the recordings and those runs (plain exact synthesis, [`crate::sat`]) in the
//!    user's conventions ([`Conventions`]: binary algorithms, a start state); its `T` is
//!    proven only while the solver's calls stay quick ([`sat::Proofs::Quick`]), its `N` only
//!    within [`RUNS_GUARD_BUDGET`];
//! 4. NuSMV judges it; if it fails, the repaired machine itself, which the game says wins,
//!    written in the user's conventions (the same runs, [`Conventions::written`]): if NuSMV
//!    refutes that one too, one of the two checkers is wrong ([`Error::Bug`]).
//!
//! The result is least (C, then T, then N, unless its line says T and N are as found) for
//! the recordings *and the runs* among the machines in the user's conventions; a smaller
//! machine that answers differently where nothing was recorded is not ruled out.
//!
//! Steps 1 and 2 work with three-valued algorithms and no start state whatever the user asked:
//! the repair's moves are three-valued, and a machine in fbSAT's conventions ([`Conventions`])
//! has the runs of one without them. Step 3 asks the user's: a machine that answers as the
//! repaired one along runs through every node of its closed loop may still answer otherwise
//! where a node is reached along another path, so it is not sure to win; NuSMV judges it, and
//! the repaired machine written in the user's conventions is there when it fails.
//!
//! Pick-and-Place (`specs/pnp.ltl`) from its first scenario alone gives C 9, K 6, T 28, N 88,
//! which the main job's polish ([`super::polish`]) makes C 8, K 3, T 13, N 23; from its first
//! two, C 10, K 6, T 31, N 89, polished to C 8, K 4, T 13, N 21. Times are in `BENCHMARKS.md`.

use super::exact::Certificate;
use super::{Check, Error, Event, Events};
use crate::ecc::{Conventions, Ecc, Size};
use crate::game::{self, repair};
use crate::nusmv::CheckMode;
use crate::sat;
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use std::time::Instant;

/// Most fixes the repair makes before it gives up.
pub(crate) const MAX_ROUNDS: usize = 1_000;

/// One stage of the guide, for progress.
#[derive(Debug, Clone)]
pub enum Stage {
    /// The game is solved and won.
    Game {
        /// Positions of the game.
        positions: usize,
        /// Seconds it took.
        seconds: f64,
    },
    /// The least machine for the recordings alone, repaired until it wins the game.
    Repaired {
        /// The least machine for the recordings alone.
        base: Size,
        /// The repair started from the recordings' tree as a machine
        /// ([`repair::tree_machine`], this size), the least machine's merges blocking it.
        from_tree: Option<Size>,
        /// The repaired machine (overrides on whole input vectors).
        size: Size,
        /// Fixes made.
        rounds: usize,
        /// Seconds for both.
        seconds: f64,
    },
    /// The repaired machine recorded along its closed loop, and the least machine for the
    /// recordings and those runs.
    Small {
        /// The form it was asked in (empty: the defaults), as in "binary algorithms".
        conventions: String,
        /// Runs that pass every node of the closed loop.
        runs: usize,
        /// Their steps.
        steps: usize,
        /// The machine (`None`: none within the state limit).
        size: Option<Size>,
        /// Whether its `T` and `N` are proven least for the runs.
        proven: bool,
        /// SAT seconds.
        seconds: f64,
    },
    /// The repaired machine written in the user's conventions, with the same runs (only when
    /// they are not the defaults and the least machine for the runs failed).
    Written {
        /// The conventions, as in "binary algorithms".
        conventions: String,
        /// Its size.
        size: Size,
    },
    /// NuSMV's verdict on a machine.
    Verdict {
        /// Which machine: "least" (for the runs, proven), "fewest-states" (for the runs, `T`
        /// and `N` as found) or "repaired".
        machine: &'static str,
        /// The properties it fails (empty: verified).
        failing: Vec<String>,
        /// NuSMV seconds.
        seconds: f64,
    },
}

impl std::fmt::Display for Stage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Stage::Game { positions, seconds } => write!(
                f,
                "guide: the closed-loop game is won ({positions} positions, {seconds:.2} s)"
            ),
            Stage::Repaired {
                base,
                from_tree: None,
                size,
                rounds,
                seconds,
            } => write!(
                f,
                "guide: the least machine for the recordings alone ({base}), narrowed to the inputs recorded, repaired in {rounds} rounds until it wins the game: C={} ({seconds:.2} s)",
                size.c
            ),
            Stage::Repaired {
                base,
                from_tree: Some(tree),
                size,
                rounds,
                seconds,
            } => write!(
                f,
                "guide: the least machine for the recordings alone ({base}) cannot be repaired (its states join recorded answers the game needs apart); the recordings' tree as a machine ({tree}) repaired in {rounds} rounds until it wins the game: C={} ({seconds:.2} s)",
                size.c
            ),
            Stage::Small {
                conventions,
                runs,
                steps,
                size,
                proven,
                seconds,
            } => small_line(f, conventions, (*runs, *steps), *size, *proven, *seconds),
            Stage::Written { conventions, size } => write!(
                f,
                "guide: the repaired machine written with {conventions}, the same runs: {size}"
            ),
            Stage::Verdict {
                machine,
                failing,
                seconds,
            } if failing.is_empty() => write!(
                f,
                "guide: NuSMV: every property holds on the {machine} machine ({seconds:.2} s)"
            ),
            Stage::Verdict {
                machine,
                failing,
                seconds,
            } => write!(
                f,
                "guide: NuSMV: the {machine} machine fails {} ({seconds:.2} s)",
                failing.join(", ")
            ),
        }
    }
}

/// The line of [`Stage::Small`]: which machine for the recordings and the runs (how many,
/// and their steps), and what is proven of it.
fn small_line(
    f: &mut std::fmt::Formatter<'_>,
    conventions: &str,
    (runs, steps): (usize, usize),
    size: Option<Size>,
    proven: bool,
    seconds: f64,
) -> std::fmt::Result {
    let which = match proven {
        true => "least",
        false => "the fewest-states",
    };
    let with = match conventions.is_empty() {
        true => String::new(),
        false => format!(" with {conventions}"),
    };
    let size_text = match size {
        Some(size) => size.to_string(),
        None => "none within the state limit, the repaired machine is judged".into(),
    };
    let unproven = match (proven, size) {
        (false, Some(_)) => "; T and N as found, not proven least within the guide's budget",
        _ => "",
    };
    write!(
        f,
        "guide: {which} machine{with} for the recordings and {runs} closed-loop runs of it \
         ({steps} steps): {size_text}{unproven} (SAT {seconds:.2} s)"
    )
}

/// A verified machine from the guide.
pub(crate) struct Guided {
    /// The machine; it reproduces the recordings.
    pub(crate) ecc: Ecc,
    /// Its size.
    pub(crate) size: Size,
    /// NuSMV's verdicts on it (all hold) and the model it checked.
    pub(crate) certificate: Certificate,
    /// Which machine the guide's is; [`Self::polished`] says whether it was made smaller since.
    pub(crate) origin: Origin,
    /// Whether it was made smaller by local moves after the guide ([`super::polish`]).
    pub(crate) polished: bool,
    /// The fewest states of any machine in the user's conventions that reproduces the
    /// recordings, when the guide proved it ([`Guide::least_states`]).
    pub(crate) least_states: Option<usize>,
    /// Every stage, in order.
    pub(crate) stages: Vec<Stage>,
    /// NuSMV checks made.
    pub(crate) nusmv_calls: usize,
    /// Seconds in NuSMV.
    pub(crate) nusmv_seconds: f64,
    /// Seconds in SAT.
    pub(crate) sat_seconds: f64,
}

/// What the repair may start from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum RepairStart {
    /// The least machine for the recordings alone; the guide declines when its merged states
    /// keep it from winning.
    Least,
    /// Then the recordings' tree as a machine ([`repair::tree_machine`]): more states to
    /// start from, a larger machine for SAT to shrink.
    LeastOrTree,
}

/// Which machine the guide gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Origin {
    /// The least machine for the recordings and the runs: `C`, `T` and `N` proven.
    LeastForRuns,
    /// The machine with the fewest states for the recordings and the runs, its `T` and `N`
    /// as found (a proof ran out of its budget).
    ForRuns,
    /// The repaired machine (the one for the runs failed NuSMV, or there was none).
    Repaired,
}

/// How hard the least machine for the runs is proven least, once a call of its descent has
/// been slow ([`sat::Proofs::Quick`]; in the solver's work, about two seconds): the polish and
/// the exact loop below the guide's machine look for smaller ones anyway, while refuting one
/// transition fewer can take longer than all the rest of the guide.
const RUNS_PROOF_EFFORT: crate::sat::solver::Effort = crate::sat::solver::Effort::Work(8_000_000);

/// The longest the guards of the least machine for the runs are minimized (the default is
/// 10 s): the main job's polish writes every state's guards anew from the closed loop
/// ([`super::polish`]), so these guards are only where it starts, and on a few hundred runs
/// the full budget is often spent without proving the least `N`.
const RUNS_GUARD_BUDGET: std::time::Duration = std::time::Duration::from_secs(3);

/// What the guide gives.
pub(crate) enum Outcome {
    /// A verified machine.
    Verified(Box<Guided>),
    /// No machine from the guide, and why.
    NotHere(String),
}

/// The guide's exact synthesis: the default options, stopped at the check's deadline.
fn sat_options(check: &Check) -> sat::Options {
    sat::Options {
        deadline: check.deadline(),
        ..sat::Options::default()
    }
}

/// The guide (module documentation) on `set` with `check`, its machine in `conventions`; its
/// SAT calls and the game stop at the check's deadline ([`Check::deadline`]).
pub(crate) fn run(
    set: &ScenarioSet,
    check: &Check,
    conventions: Conventions,
    start: RepairStart,
    events: Events<'_>,
) -> Result<Outcome, Error> {
    let mut guide = Guide {
        set,
        events,
        stages: Vec::new(),
        sat_seconds: 0.0,
        nusmv_calls: 0,
        nusmv_seconds: 0.0,
        sat: sat_options(check),
        conventions,
        start,
        least_states: None,
    };
    let (tree, strategy) = match guide.game(check)? {
        Ok(won) => won,
        Err(why) => return Ok(Outcome::NotHere(why)),
    };
    let repaired = match guide.repaired(&tree, &strategy)? {
        Ok(repaired) => repaired,
        Err(why) => return Ok(Outcome::NotHere(why)),
    };
    let small = guide.least_for_runs(&strategy, &repaired)?;
    guide.judged(check, small, repaired.ecc)
}

/// What a stage gives, or why the guide has no machine here ([`Outcome::NotHere`]).
type OrWhy<T> = Result<T, String>;

/// The guide's run: its stages so far and its figures.
struct Guide<'a, 'e> {
    set: &'a ScenarioSet,
    events: Events<'e>,
    stages: Vec<Stage>,
    sat_seconds: f64,
    nusmv_calls: usize,
    nusmv_seconds: f64,
    /// The options of every SAT synthesis: the defaults, stopped at the check's deadline.
    sat: sat::Options,
    /// The form of the guide's machine (step 3 on).
    conventions: Conventions,
    /// What the repair may start from.
    start: RepairStart,
    /// The least C of the recordings alone (step 2), a bound on every machine in the user's
    /// conventions: SAT proved it for three-valued algorithms without a start state; a start
    /// state only narrows the machines, binary algorithms widen them (a toggle needs one state
    /// instead of two), so `None` with binary algorithms.
    least_states: Option<usize>,
}

impl Guide<'_, '_> {
    /// Reports stage `s` and keeps it.
    fn stage(&mut self, s: Stage) {
        (self.events)(Event::Guide(s.clone()));
        self.stages.push(s);
    }

    /// Step 1: the closed-loop game of the recordings' tree, solved and won; why not when
    /// the game does not read the plant, does not apply, or is lost.
    fn game(&mut self, check: &Check) -> Result<OrWhy<(ScenarioTree, Box<game::Strategy>)>, Error> {
        let set = self.set;
        let problem = &check.problem;
        let model = match problem.model.as_ref() {
            Ok(model) => model,
            Err(why) => return Ok(Err(format!("the game does not read this plant: {why}"))),
        };
        let coupling = match crate::check::Wiring::new(model, &problem.coupling) {
            Ok(c) => c,
            Err(e) => return Ok(Err(format!("the game does not apply: {e}"))),
        };
        let tree = ScenarioTree::build(set)?;
        let started = Instant::now();
        let outcome = game::solve(
            model,
            &coupling,
            &problem.props,
            &tree,
            &set.initial_outputs,
            super::explain::GAME_POSITIONS,
            check.deadline(),
        );
        let strategy = match outcome {
            Ok(game::Outcome::Won(s)) => s,
            Ok(game::Outcome::Lost) => return Ok(Err(format!(
                "the closed-loop game is lost ({:.1} s): no controller of any size answers the recordings as recorded and keeps every property against every behaviour of the plant (in the tool's own model of it)",
                started.elapsed().as_secs_f64()
            ))),
            Err(e) => return Ok(Err(format!("the game does not apply: {e}"))),
        };
        self.stage(Stage::Game {
            positions: strategy.positions,
            seconds: started.elapsed().as_secs_f64(),
        });
        Ok(Ok((tree, strategy)))
    }

    /// Step 2: the least machine SAT finds for the recordings alone (`tree`), repaired until
    /// it wins the game ([`repair::repair`]); both replay the recordings.
    fn repaired(
        &mut self,
        tree: &ScenarioTree,
        strategy: &game::Strategy,
    ) -> Result<OrWhy<repair::Repaired>, Error> {
        let set = self.set;
        let started = Instant::now();
        let base = match sat::synthesize(set, tree, &self.sat, &mut |_| {}) {
            Ok(b) => b,
            Err(e @ (sat::SatError::TooManyStates { .. } | sat::SatError::OutOfBounds { .. })) => {
                return Ok(Err(format!("for the recordings alone: {e}")))
            }
            Err(e) => return Err(e.into()),
        };
        set.check(&base.ecc).map_err(|d| {
            Error::Bug(format!(
                "the machine for the recordings does not replay them: {d}"
            ))
        })?;
        self.least_states =
            (self.conventions.algorithms == crate::ecc::AlgorithmKind::Tri).then_some(base.size.c);
        let mut from_tree = None;
        let narrowed = repair::narrowed(tree, &base.ecc);
        let repaired = match repair::repair(strategy, &narrowed, MAX_ROUNDS) {
            Ok(r) => r,
            Err(e @ repair::RepairError::Recorded(_)) if self.start == RepairStart::LeastOrTree => {
                let tree_machine = repair::tree_machine(tree, &base.ecc);
                from_tree = Some(tree_machine.size());
                match repair::repair(strategy, &tree_machine, MAX_ROUNDS) {
                    Ok(r) => r,
                    Err(_) => return Ok(Err(self.unrepaired(strategy, e))),
                }
            }
            Err(e) => return Ok(Err(self.unrepaired(strategy, e))),
        };
        self.sat_seconds = started.elapsed().as_secs_f64();
        self.stage(Stage::Repaired {
            base: base.size,
            from_tree,
            size: repaired.ecc.size(),
            rounds: repaired.rounds,
            seconds: self.sat_seconds,
        });
        set.check(&repaired.ecc).map_err(|d| {
            Error::Bug(format!(
                "the repaired machine does not replay the recordings: {d}"
            ))
        })?;
        Ok(Ok(repaired))
    }

    /// Why the guide has no machine when the game is won but the repair failed with `e`.
    fn unrepaired(&self, strategy: &game::Strategy, e: repair::RepairError) -> String {
        format!(
            "the closed-loop game is won ({} positions): a controller that answers the recordings as recorded and keeps every property exists (in the tool's own model of the plant; NuSMV has not checked it), but the repair of the recordings' machine failed: {e}",
            strategy.positions
        )
    }

    /// Step 3: the repaired machine recorded along every node of its closed loop with the
    /// game ([`repair::covering_runs`]), and the least machine for the recordings and those
    /// runs (`None`: too many states for the runs, the repaired machine is judged alone).
    fn least_for_runs(
        &mut self,
        strategy: &game::Strategy,
        repaired: &repair::Repaired,
    ) -> Result<Option<sat::Synthesis>, Error> {
        let started = Instant::now();
        let runs = repair::covering_runs(strategy, &repaired.ecc)
            .map_err(|e| Error::Bug(format!("the repaired machine loses the game: {e}")))?;
        let steps = runs.iter().map(|r| r.steps.len()).sum();
        let n_runs = runs.len();
        let mut guided = self.set.clone();
        guided.scenarios.extend(runs);
        let tree = ScenarioTree::build(&guided)?;
        let opts = sat::Options {
            algorithms: self.conventions.algorithms,
            start_state: self.conventions.start_state,
            guard_budget: RUNS_GUARD_BUDGET,
            ..self.sat.clone()
        };
        let proofs = sat::Proofs::Quick(RUNS_PROOF_EFFORT);
        let small = match sat::Synthesizer::with_proofs(&guided, &tree, &opts, proofs)
            .minimize(&mut |_| {})
        {
            Ok(small) => {
                guided.check(&small.ecc).map_err(|d| {
                    Error::Bug(format!(
                        "the least machine does not replay its scenarios: {d}"
                    ))
                })?;
                Some(small)
            }
            Err(sat::SatError::TooManyStates { .. } | sat::SatError::OutOfBounds { .. }) => None,
            Err(e) => return Err(e.into()),
        };
        let seconds = started.elapsed().as_secs_f64();
        self.sat_seconds += seconds;
        self.stage(Stage::Small {
            conventions: self.conventions.to_string(),
            runs: n_runs,
            steps,
            size: small.as_ref().map(|s| s.size),
            proven: small.as_ref().is_some_and(proven_least),
            seconds,
        });
        Ok(small)
    }

    /// Step 4: NuSMV judges the least machine for the runs, then if it fails the repaired
    /// machine, which the game says wins: if NuSMV refutes that one too, one of the two
    /// checkers is wrong ([`Error::Bug`]).
    fn judged(
        mut self,
        check: &Check,
        small: Option<sat::Synthesis>,
        repaired: Ecc,
    ) -> Result<Outcome, Error> {
        let mut verifier = check.verifier()?;
        let verified_small = match small.map(|s| (proven_least(&s), s.ecc)) {
            Some((proven, ecc)) => match self.judge(&mut verifier, &ecc, runs_machine(proven))? {
                (v, true) => Some((v, proven, ecc)),
                (_, false) => None,
            },
            None => None,
        };
        let (certificate, origin, ecc) = match verified_small {
            Some((v, true, ecc)) => (v, Origin::LeastForRuns, ecc),
            Some((v, false, ecc)) => (v, Origin::ForRuns, ecc),
            None => {
                let repaired = self.written(repaired)?;
                match self.judge(&mut verifier, &repaired, "repaired")? {
                    (v, true) => (v, Origin::Repaired, repaired),
                    (v, false) => {
                        return Err(Error::Bug(format!(
                            "the closed-loop game says the repaired machine keeps every property, NuSMV says it fails {}",
                            v.report.failing().join(", ")
                        )))
                    }
                }
            }
        };
        if let Some(broken) = self.conventions.broken(&ecc) {
            return Err(Error::Bug(format!(
                "the guide's machine is not in the form asked ({}): {broken}",
                self.conventions
            )));
        }
        Ok(Outcome::Verified(Box::new(Guided {
            size: ecc.size(),
            ecc,
            certificate: Certificate {
                report: certificate.report,
                model_text: certificate.model.text,
            },
            origin,
            polished: false,
            least_states: self.least_states,
            stages: self.stages,
            nusmv_calls: self.nusmv_calls,
            nusmv_seconds: self.nusmv_seconds,
            sat_seconds: self.sat_seconds,
        })))
    }

    /// The repaired machine written in the user's conventions ([`Conventions::written`]), and
    /// replayed on the recordings.
    fn written(&mut self, repaired: Ecc) -> Result<Ecc, Error> {
        if self.conventions.is_default() {
            return Ok(repaired);
        }
        let written = self.conventions.written(&repaired);
        self.set.check(&written).map_err(|d| {
            Error::Bug(format!(
                "the repaired machine written with {} does not replay the recordings: {d}",
                self.conventions
            ))
        })?;
        self.stage(Stage::Written {
            conventions: self.conventions.to_string(),
            size: written.size(),
        });
        Ok(written)
    }

    /// NuSMV's verdicts on `ecc` (the `machine` of [`Stage::Verdict`]), and whether every
    /// property holds.
    fn judge(
        &mut self,
        verifier: &mut crate::verify::Verifier,
        ecc: &Ecc,
        machine: &'static str,
    ) -> Result<(crate::verify::VerificationResult, bool), Error> {
        let v = verifier.verify_with(ecc, CheckMode::VerdictsOnly)?;
        self.nusmv_calls += 1;
        self.nusmv_seconds += v.report.nusmv_seconds;
        let failing: Vec<String> = v.report.failing().iter().map(|s| s.to_string()).collect();
        self.stage(Stage::Verdict {
            machine,
            failing: failing.clone(),
            seconds: v.report.nusmv_seconds,
        });
        Ok((v, failing.is_empty()))
    }
}

/// What the machine for the runs is called in NuSMV's verdict: "least" only when its `T` and
/// `N` are `proven`.
fn runs_machine(proven: bool) -> &'static str {
    match proven {
        true => "least",
        false => "fewest-states",
    }
}

/// Whether a synthesis proved its `T` and `N` least.
fn proven_least(s: &sat::Synthesis) -> bool {
    s.transitions_exact && s.guards_exact
}

#[cfg(test)]
mod tests {
    use super::*;

    /// NuSMV's line on the machine for the runs calls it least only when its `T` and `N` are
    /// proven, as the line before it does.
    #[test]
    fn the_verdict_calls_the_machine_for_the_runs_least_only_when_proven() {
        let verdict = |proven| {
            Stage::Verdict {
                machine: runs_machine(proven),
                failing: Vec::new(),
                seconds: 0.1,
            }
            .to_string()
        };
        assert_eq!(
            verdict(true),
            "guide: NuSMV: every property holds on the least machine (0.10 s)"
        );
        assert_eq!(
            verdict(false),
            "guide: NuSMV: every property holds on the fewest-states machine (0.10 s)"
        );
    }
}
