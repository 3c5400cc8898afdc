//! Counterexample-guided inductive synthesis: SAT proposes, NuSMV disposes.
//!
//! In: scenarios, a plant, properties, SAT options, a NuSMV session. Out: the smallest ECC
//! (least C, then T, then N) that reproduces every scenario and leaves every counterexample
//! found on the way, together with NuSMV's report saying every property holds.
//!
//! Loop: minimize on the incremental [`Synthesizer`]; verify in closed loop; if a property
//! fails, its counterexample becomes a negative scenario (the ECC must leave that lasso) and
//! the loop repeats on the same solver. When the current number of states cannot leave every
//! lasso the minimization itself moves on to more states.

use super::closed_loop::{environment_of, negative_of, ClosedLoop};
use super::{Event, Events};
use crate::check;
use crate::nusmv::CheckMode;
use crate::sat::basic::Proofs;
use crate::sat::solver::Bounded;
use crate::sat::{Options, SatError, Synthesis, Synthesizer};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use crate::verify::{Report, Verifier, VerifyError};
use std::time::Instant;

/// Settings of the loop.
#[derive(Debug, Clone)]
pub struct Config {
    /// Options of the SAT synthesizer (bounds, encoding, budgets).
    pub sat: Options,
    /// Give up after this many candidates.
    pub max_iterations: usize,
    /// Report every step of every minimization, not only one line per candidate.
    pub verbose: bool,
    /// With the properties in the encoding: how long the final machine's `T` and `N` may take
    /// to be proven minimal ([`Proofs::Budget`]).
    pub proof_budget: std::time::Duration,
    /// The user's negative scenarios, encoded before the first candidate.
    pub negatives: Vec<crate::scenario::negative::NegativeScenario>,
}

/// [`Iteration::checked_by`] of a final pass that found no smaller machine than the candidate
/// NuSMV verified just before (which is then the result, with that verdict).
pub const UNCHANGED: &str = "unchanged";

/// One iteration, for progress and for the benchmark figures.
#[derive(Debug, Clone, serde::Serialize, schemars::JsonSchema)]
pub struct Iteration {
    /// 1-based number of the candidate.
    pub number: usize,
    /// Who found the verdict: `in-process` (a counterexample, fed back at once), `NuSMV`, or
    /// [`UNCHANGED`].
    pub checked_by: &'static str,
    /// Number of states C of the candidate.
    pub c: usize,
    /// Number of transitions T of the candidate.
    pub t: usize,
    /// Names of the properties the candidate violates (empty: verified).
    pub failing: Vec<String>,
    /// Number of states of the first counterexample fed back, if any.
    pub counterexample_length: Option<usize>,
    /// Wall-clock seconds the SAT minimization of this candidate took.
    pub sat_seconds: f64,
    /// Seconds NuSMV took on this candidate (0 when it was not asked).
    pub nusmv_seconds: f64,
    /// Time of the check that gave the verdict (NuSMV's or the in-process checker's).
    pub check_seconds: f64,
}

/// A verified controller.
#[derive(Debug, Clone)]
pub struct Verified {
    /// The verified machine and its figures.
    pub synthesis: Synthesis,
    /// NuSMV's report: every property holds.
    pub report: Report,
    /// Every candidate in order; the last is the result (or [`UNCHANGED`], keeping it).
    pub iterations: Vec<Iteration>,
    /// The closed-loop model NuSMV verified.
    pub model_text: String,
}

/// Why the loop ended without a verified controller.
#[derive(Debug, thiserror::Error)]
pub enum CegisError {
    /// SAT synthesis found no machine within the limits, or broke an invariant.
    #[error("{0}")]
    Sat(#[from] SatError),
    /// The closed-loop verification of a candidate gave no verdicts.
    #[error("{0}")]
    Verify(#[from] VerifyError),
    /// `--max-iterations` candidates were checked and none was verified.
    #[error("no verified controller after {iterations} candidates (raise --max-iterations); last candidate fails: {failing}")]
    Iterations {
        /// The iteration limit that was reached.
        iterations: usize,
        /// The properties the last candidate failed, comma-separated.
        failing: String,
    },
    /// NuSMV and the in-process checker disagree: one of them has a bug.
    #[error("internal error (a bug in synth, please report it): NuSMV says property {property} is violated ({nusmv}), the in-process checker says it holds on the same closed loop")]
    Disagreement {
        /// The property the two checkers disagree on.
        property: String,
        /// NuSMV's verdict line for it.
        nusmv: String,
    },
    /// Counterexamples found on the way rule out every machine within the state limit.
    #[error("no ECC with at most {max_states} states reproduces the scenarios and avoids every counterexample found so far ({counterexamples}; the last candidate failed {failing}): these properties may not be satisfiable with this plant and these recordings; otherwise raise --max-states")]
    Exhausted {
        /// The state limit (`--max-states`).
        max_states: usize,
        /// Counterexamples (negative scenarios and environments) the loop had added.
        counterexamples: usize,
        /// The properties the last candidate failed, comma-separated.
        failing: String,
    },
    /// A property fails but NuSMV's trace lacks a controller input or output as a Boolean, so
    /// it cannot become a negative scenario.
    #[error("property {property} fails, but NuSMV printed no usable counterexample (it needs every controller input and output as a Boolean in the trace), so the loop cannot continue")]
    NoCounterexample {
        /// The first failing property.
        property: String,
    },
}

/// Runs CEGIS; `verifier` holds the closed-loop model of the current candidate.
pub fn run(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    verifier: &mut Verifier,
    closed: Option<&ClosedLoop>,
    config: &Config,
    events: Events<'_>,
) -> Result<Verified, CegisError> {
    std::thread::scope(|scope| {
        let mut lower = LowerBound::none();
        if config.sat.cube_slots.is_some() {
            lower = LowerBound::start(scope, set, tree, &config.sat, config.verbose, events)?;
        }
        iterate(set, tree, verifier, closed, config, &mut lower, events)
    })
}

/// The tree-exact minimum, which bounds the cube model from below: restricting a cube
/// machine to the recorded inputs gives a tree-exact machine with the same states and no
/// more edges. Its `C` (and a machine with its colouring, the first hint) takes a fraction of a
/// second; proving its `T` minimal takes longer and runs on a second core while the loop
/// looks for candidates, which do not need it. Only the final pass waits for it.
/// How long the tree-exact descent on the main thread may look for fewer transitions.
const TREE_EXACT_BUDGET: std::time::Duration = std::time::Duration::from_millis(300);

/// The least `T` of the tree-exact model at its least `C`, with the colouring of a machine
/// there when it is not the first one's.
type LeastT = Result<(usize, Option<Vec<usize>>), SatError>;

struct LowerBound<'scope> {
    c: usize,
    started: Instant,
    hint: Option<Vec<usize>>,
    proof: Option<std::thread::ScopedJoinHandle<'scope, LeastT>>,
}

impl<'scope> LowerBound<'scope> {
    fn none() -> LowerBound<'scope> {
        LowerBound {
            c: 0,
            started: Instant::now(),
            hint: None,
            proof: None,
        }
    }

    fn start<'env>(
        scope: &'scope std::thread::Scope<'scope, 'env>,
        set: &'env ScenarioSet,
        tree: &'env ScenarioTree,
        sat: &Options,
        verbose: bool,
        events: Events<'_>,
    ) -> Result<LowerBound<'scope>, SatError> {
        let started = Instant::now();
        let tree_exact = Options {
            cube_slots: None,
            minimize_k: false,
            // Only C, T and the colouring are used: no time for guards.
            guard_budget: std::time::Duration::ZERO,
            ..sat.clone()
        };
        // Least C proven; T the least found within a moment (the refutation that would prove
        // it is left to the thread below).
        let first =
            Synthesizer::with_proofs(set, tree, &tree_exact, Proofs::Budget(TREE_EXACT_BUDGET))
                .minimize(&mut |m| {
                    if verbose {
                        events(Event::Solver(m))
                    }
                })?;
        let (c, t) = (first.size.c, first.size.t);
        let proof = scope.spawn(move || {
            // Usually the first machine's T is the least: one refutation proves it.
            if t > 0 && !crate::sat::satisfiable(tree, &tree_exact, c, Some(t - 1)) {
                return Ok((t, None));
            }
            let least = crate::sat::synthesize(set, tree, &tree_exact, &mut |_| {})?;
            Ok((least.size.t, Some(least.colors)))
        });
        Ok(LowerBound {
            c,
            started,
            hint: Some(first.colors),
            proof: Some(proof),
        })
    }

    /// Hands what is known so far to `synth`: the least C and the first colouring.
    fn seed(&mut self, synth: &mut Synthesizer<'_>) {
        if let Some(h) = self.hint.take() {
            synth.assume_lower_bounds(self.c, 0);
            synth.hint(h);
        }
    }

    /// Hands the proven minimum to `synth` once it is there: the bound on `T` and the
    /// colouring of a machine at that bound. With `wait`, waits for it.
    fn settle(
        &mut self,
        synth: &mut Synthesizer<'_>,
        wait: bool,
        events: Events<'_>,
    ) -> Result<(), SatError> {
        if !wait && self.proof.as_ref().is_some_and(|p| !p.is_finished()) {
            return Ok(());
        }
        let Some(proof) = self.proof.take() else {
            return Ok(());
        };
        let (t, colors) = proof
            .join()
            .map_err(|_| SatError::Bug("the lower-bound proof panicked".into()))??;
        synth.assume_lower_bounds(self.c, t);
        if let Some(colors) = colors {
            synth.hint(colors);
        }
        events(Event::LowerBounds {
            c: self.c,
            t,
            seconds: self.started.elapsed().as_secs_f64(),
        });
        Ok(())
    }
}

fn iterate(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    verifier: &mut Verifier,
    closed: Option<&ClosedLoop>,
    config: &Config,
    lower: &mut LowerBound<'_>,
    events: Events<'_>,
) -> Result<Verified, CegisError> {
    // Candidates need no proof of minimality; the final machine gets a budget for it.
    let (candidates, last) = if closed.is_some() {
        (Proofs::Skip, Proofs::Budget(config.proof_budget))
    } else {
        (Proofs::Full, Proofs::Full)
    };
    let mut synth = Synthesizer::with_proofs(set, tree, &config.sat, candidates);
    lower.seed(&mut synth);
    for neg in &config.negatives {
        synth.add_negative(neg.clone());
    }
    let mut iterations = Vec::new();
    let mut last_failing = String::new();
    // Candidates are minimized for their own colouring only (cheap); once one passes, the
    // final pass tries to prove it minimal within the budget, and is checked again if that
    // changed it. Without the closed loop every candidate gets full proofs.
    let mut final_pass = closed.is_none();
    let mut in_process = closed.is_some();
    synth.set_minimize_n(true);

    // The last candidate NuSMV passed: if the final pass finds no smaller machine, its report
    // stands.
    let mut passed: Option<(Synthesis, Report, String)> = None;
    for number in 1..=config.max_iterations {
        lower.settle(&mut synth, final_pass, events)?;
        let t = Instant::now();
        if let (true, Some((p, _, _))) = (final_pass, &passed) {
            // The final pass asks first whether anything smaller exists at all: two bounded
            // refutations, where searching again costs seconds and usually ends at the same
            // size with another machine that would need checking again.
            let Proofs::Budget(budget) = last else {
                unreachable!("the final pass of the closed loop has a budget")
            };
            let (fewer_t, fewer_n) = synth.smaller_exists(p.size, budget);
            let sat = |b: &Bounded| matches!(b, Bounded::Sat(_));
            if !sat(&fewer_t) && !sat(&fewer_n) {
                let (before, report, model_text) = passed.take().expect("checked above");
                let synthesis = Synthesis {
                    transitions_exact: matches!(fewer_t, Bounded::Unsat),
                    guards_exact: matches!(fewer_n, Bounded::Unsat),
                    ..before
                };
                let it = unchanged(number, &synthesis, t.elapsed().as_secs_f64());
                return Ok(kept(synthesis, report, model_text, iterations, it, events));
            }
            // Something smaller exists: search for it from the machine that passed, not from
            // the lower bound's colouring the line above may have just handed over.
            synth.hint(p.colors.clone());
        }
        let synthesis = match synth.minimize(&mut |m| {
            if config.verbose {
                events(Event::Solver(m))
            }
        }) {
            Err(SatError::TooManyStates { max_states })
                if synth.negatives().len() + synth.environments() > 0 =>
            {
                return Err(CegisError::Exhausted {
                    max_states,
                    counterexamples: synth.negatives().len() + synth.environments(),
                    failing: last_failing,
                })
            }
            r => r?,
        };
        let sat_seconds = t.elapsed().as_secs_f64();
        if let Some((before, report, model_text)) = passed.take() {
            // A machine no smaller than the one NuSMV passed is not worth another check: the
            // verified one stands, with what the final pass proved about its size (same C, T
            // and N, so the same bounds).
            if final_pass && !synthesis.size.smaller_than(&before.size) {
                let synthesis = Synthesis {
                    transitions_exact: synthesis.transitions_exact
                        && synthesis.size.t == before.size.t,
                    guards_exact: synthesis.guards_exact && synthesis.size.n == before.size.n,
                    stats: synthesis.stats,
                    ..before
                };
                let it = unchanged(number, &synthesis, sat_seconds);
                return Ok(kept(synthesis, report, model_text, iterations, it, events));
            }
        }
        // The in-process checker first: a counterexample from it costs milliseconds, and
        // NuSMV is asked only about candidates it cannot fault.
        let mut in_process_holds: Vec<bool> = Vec::new();
        if let (Some(closed), true) = (closed, in_process) {
            let tc = Instant::now();
            let problem = verifier.problem();
            match check::check(
                &closed.spec.plant,
                &closed.coupling,
                &synthesis.ecc,
                &problem.props,
                &check::Limits::default(),
            ) {
                Ok(verdicts) => {
                    let names = problem.property_names();
                    let mut failing = Vec::new();
                    let mut envs = Vec::new();
                    for (k, v) in verdicts.iter().enumerate() {
                        in_process_holds.push(matches!(v, check::Verdict::Holds));
                        if let check::Verdict::Violated(lasso) = v {
                            failing.push(names[k].clone());
                            if closed.encodes(k) {
                                envs.push((lasso.states.len(), environment_of(lasso)));
                            }
                        }
                    }
                    let mut added = 0;
                    let mut length = None;
                    for (len, env) in envs {
                        if synth.add_environment(&closed.spec, env).is_ok() {
                            added += 1;
                            length.get_or_insert(len);
                        }
                    }
                    // Without a new environment, the lassos of the properties the encoding
                    // does not carry come back as negative scenarios, as NuSMV's would.
                    if added == 0 {
                        for (k, v) in verdicts.iter().enumerate() {
                            let check::Verdict::Violated(lasso) = v else {
                                continue;
                            };
                            if closed.encodes(k) {
                                continue;
                            }
                            let neg = negative_of(closed, lasso, &names[k]).map_err(|e| {
                                SatError::Bug(format!("in-process counterexample: {e}"))
                            })?;
                            follows_own(&neg, &synthesis.ecc, || {
                                format!("in-process {}", neg.label)
                            })?;
                            if synth.negatives().contains(&neg) {
                                continue;
                            }
                            length.get_or_insert(lasso.states.len());
                            synth.add_negative(neg);
                            added += 1;
                        }
                    }
                    if added > 0 {
                        let it = Iteration {
                            number,
                            checked_by: "in-process",
                            c: synthesis.size.c,
                            t: synthesis.size.t,
                            failing: failing.clone(),
                            counterexample_length: length,
                            sat_seconds,
                            nusmv_seconds: 0.0,
                            check_seconds: tc.elapsed().as_secs_f64(),
                        };
                        events(Event::Candidate(&it));
                        iterations.push(it);
                        last_failing = failing.join(", ");
                        final_pass = false;
                        synth.set_proofs(candidates);
                        continue;
                    }
                }
                // Too large, or no behaviour at all: NuSMV decides (and reports a vacuous
                // plant itself).
                Err(_) => in_process = false,
            }
        }
        // With environments one counterexample per candidate is enough: each rules out every
        // machine that fails on its environment. NuSMV's backward re-check per trace is most of
        // its time.
        let mode = if closed.is_some() {
            CheckMode::FirstCounterexample
        } else {
            CheckMode::AllCounterexamples
        };
        let v = verifier.verify_with(&synthesis.ecc, mode)?;
        let failing: Vec<String> = v.report.failing().iter().map(|s| s.to_string()).collect();
        // A property NuSMV finds violated where the in-process checker found it holding is a
        // bug in one of them.
        for (k, p) in v.report.properties.iter().enumerate() {
            if !p.holds && in_process_holds.get(k) == Some(&true) {
                return Err(CegisError::Disagreement {
                    property: p.name.clone(),
                    nusmv: p.verdict_line.clone(),
                });
            }
        }
        let it = Iteration {
            number,
            checked_by: "NuSMV",
            check_seconds: v.report.nusmv_seconds,
            c: synthesis.size.c,
            t: synthesis.size.t,
            failing: failing.clone(),
            counterexample_length: v.counterexamples.first().map(|c| c.states.len()),
            sat_seconds,
            nusmv_seconds: v.report.nusmv_seconds,
        };
        events(Event::Candidate(&it));
        iterations.push(it);
        if failing.is_empty() && !final_pass {
            passed = Some((synthesis.clone(), v.report, v.model.text));
            final_pass = true;
            synth.set_proofs(last);
            continue;
        }
        if failing.is_empty() {
            return Ok(Verified {
                synthesis,
                report: v.report,
                iterations,
                model_text: v.model.text,
            });
        }
        last_failing = failing.join(", ");
        // Counterexamples of encoded properties become environments: the closed loop along
        // each is required to satisfy every encoded property, whatever the machine does.
        let mut added = 0;
        if let Some(closed) = closed {
            let names = verifier.problem().property_names();
            for cx in &v.counterexamples {
                let Some(k) = names.iter().position(|n| *n == cx.property) else {
                    continue;
                };
                if !closed.encodes(k) {
                    continue;
                }
                if let Some(env) = closed.environment(cx) {
                    if synth.add_environment(&closed.spec, env).is_ok() {
                        added += 1;
                    }
                }
            }
        }
        if added > 0 {
            final_pass = false;
            synth.set_proofs(candidates);
            continue;
        }
        // Safety violations first: their finite prefixes are cheap and strong constraints.
        // Lassos (liveness) only once no safety property fails, one at a time: each unrolls
        // `loop length x C` steps into the solver.
        let all: Vec<_> = v
            .counterexamples
            .iter()
            .filter_map(|c| c.negative_scenario(&set.inputs, &set.outputs))
            .collect();
        let finite: Vec<_> = all
            .iter()
            .filter(|n| n.loop_start.is_none())
            .cloned()
            .collect();
        let negs = if finite.is_empty() {
            all.into_iter().take(1).collect()
        } else {
            finite
        };
        if negs.is_empty() {
            return Err(CegisError::NoCounterexample {
                property: failing[0].clone(),
            });
        }
        for neg in negs {
            follows_own(&neg, &synthesis.ecc, || {
                format!("{} in the simulator", neg.label)
            })?;
            synth.add_negative(neg);
        }
        if closed.is_some() {
            final_pass = false;
            synth.set_proofs(candidates);
        }
    }
    Err(CegisError::Iterations {
        iterations: config.max_iterations,
        failing: last_failing,
    })
}

/// The result when the final pass keeps the verified candidate: its iteration reported and
/// appended.
fn kept(
    synthesis: Synthesis,
    report: Report,
    model_text: String,
    mut iterations: Vec<Iteration>,
    it: Iteration,
    events: Events<'_>,
) -> Verified {
    events(Event::Candidate(&it));
    iterations.push(it);
    Verified {
        synthesis,
        report,
        iterations,
        model_text,
    }
}

/// The iteration of a final pass that kept the verified candidate.
fn unchanged(number: usize, synthesis: &Synthesis, sat_seconds: f64) -> Iteration {
    Iteration {
        number,
        checked_by: UNCHANGED,
        c: synthesis.size.c,
        t: synthesis.size.t,
        failing: Vec::new(),
        counterexample_length: None,
        sat_seconds,
        nusmv_seconds: 0.0,
        check_seconds: 0.0,
    }
}

/// A candidate must follow its own counterexample; if it does not, the checker that found it
/// and the simulator disagree, and feeding it back would loop forever. `what` names it.
fn follows_own(
    neg: &crate::scenario::negative::NegativeScenario,
    ecc: &crate::ecc::Ecc,
    what: impl FnOnce() -> String,
) -> Result<(), SatError> {
    if neg.followed_by(ecc) {
        return Ok(());
    }
    Err(SatError::Bug(format!(
        "the candidate does not follow its own {}",
        what()
    )))
}
