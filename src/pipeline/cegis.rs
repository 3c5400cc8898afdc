//! Counterexample-guided inductive synthesis: SAT proposes, NuSMV disposes.
//!
//! In: scenarios, a plant, properties, SAT options, a NuSMV dialogue. Out: the smallest ECC
//! (least C, then T, then N) that reproduces every scenario and leaves every counterexample
//! found on the way, together with NuSMV's report saying every property holds.
//!
//! Loop: minimize on the incremental [`Synthesizer`]; verify in closed loop; if a property
//! fails, its counterexample becomes a negative scenario (the ECC must leave that lasso) and
//! the loop repeats on the same solver. When the current number of states cannot leave every
//! lasso the minimization itself moves on to more states.

use super::loop_encoding::{environment_of, negative_of, LoopEncoding};
use super::{Event, Events};
use crate::check;
use crate::nusmv::CheckMode;
use crate::sat::basic::Proofs;
use crate::sat::solver::{Bounded, Effort};
use crate::sat::{Options, SatError, Synthesis, Synthesizer};
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;
use crate::verify::{Report, VerificationResult, Verifier, VerifyError};
use std::time::{Duration, Instant};

/// Settings of the loop.
#[derive(Debug, Clone)]
pub(crate) struct Config {
    /// Options of the SAT synthesizer (bounds, encoding, budgets).
    pub(crate) sat: Options,
    /// Give up after this many candidates.
    pub(crate) max_iterations: usize,
    /// Report every step of every minimization, not only one line per candidate.
    pub(crate) verbose: bool,
    /// With the properties in the encoding: how long the final machine's `T` and `N` may take
    /// to be proven minimal ([`Proofs::Budget`]).
    pub(crate) proof_budget: std::time::Duration,
    /// The user's negative scenarios, encoded before the first candidate.
    pub(crate) negatives: Vec<crate::scenario::negative::NegativeScenario>,
    /// When to stop with [`CegisError::Stalled`]; `None`: never.
    pub(crate) stall: Option<Stall>,
    /// Counterexamples an earlier turn of the loop on the same problem learned, encoded before
    /// the first candidate.
    pub(crate) learned: Learned,
}

/// When the loop stops with [`CegisError::Stalled`] (another engine's turn): its candidates of
/// one number of states keep being refuted, one behaviour at a time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Stall {
    /// After this many refuted candidates in a row with the same number of states.
    pub rounds: usize,
    /// After at least 3 of them and this much of the loop's own CPU time refuting them.
    pub time: Duration,
    /// The same, sooner, once a candidate's descent in `T` with that many states has run out
    /// of its work budget: a sign, counted in the solver's work rather than on the clock, that
    /// the SAT calls there are growing.
    pub hard_time: Duration,
}

/// Counterexamples a turn of the loop learned: facts about every machine that satisfies the
/// properties with this plant, so another turn on the same problem (with other bounds) starts
/// from them instead of finding them again one candidate at a time.
#[derive(Debug, Clone, Default)]
pub struct Learned {
    /// Behaviours no verified machine shows (beside the user's negative scenarios).
    pub(crate) negatives: Vec<crate::scenario::negative::NegativeScenario>,
    /// Runs of the plant's free variables along which every encoded property must hold.
    pub(crate) environments: Vec<crate::sat::closed_loop::Environment>,
}

impl Learned {
    /// How many counterexamples were learned.
    pub fn len(&self) -> usize {
        self.negatives.len() + self.environments.len()
    }

    /// Whether none was.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
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
    pub(crate) counterexample_length: Option<usize>,
    /// Wall-clock seconds the SAT minimization of this candidate took.
    pub sat_seconds: f64,
    /// Seconds NuSMV took on this candidate (0 when it was not asked).
    pub nusmv_seconds: f64,
    /// Time of the check that gave the verdict (NuSMV's or the in-process checker's).
    pub(crate) check_seconds: f64,
}

/// A verified controller.
#[derive(Debug, Clone)]
pub(crate) struct Verified {
    /// The verified machine and its figures.
    pub(crate) synthesis: Synthesis,
    /// NuSMV's report: every property holds.
    pub(crate) report: Report,
    /// Every candidate in order; the last is the result (or [`UNCHANGED`], keeping it).
    pub(crate) iterations: Vec<Iteration>,
    /// The closed-loop model NuSMV verified.
    pub(crate) model_text: String,
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
    /// Candidates kept being refuted without the loop moving on to more states or
    /// transitions ([`Config::stall`]).
    #[error("no progress: {rounds} candidates in a row with C = {c} in {seconds:.1} s, refuted one counterexample at a time ({} counterexamples learned)", learned.len())]
    Stalled {
        /// Refuted candidates in a row.
        rounds: usize,
        /// Their number of states.
        c: usize,
        /// Seconds since the first of them.
        seconds: f64,
        /// What the loop learned, for another turn.
        learned: Box<Learned>,
    },
    /// A property fails but NuSMV's trace lacks a controller input or output as a Boolean, so
    /// it cannot become a negative scenario.
    #[error("property {property} fails, but NuSMV printed no usable counterexample (it needs every controller input and output as a Boolean in the trace), so the loop cannot continue")]
    NoCounterexample {
        /// The first failing property.
        property: String,
    },
}

impl CegisError {
    /// A stall's message and what the loop learned, for the next turn; any other error as
    /// it is.
    pub(crate) fn into_stall(self) -> Result<(String, Learned), CegisError> {
        let why = self.to_string();
        match self {
            CegisError::Stalled { learned, .. } => Ok((why, *learned)),
            other => Err(other),
        }
    }
}

/// Runs CEGIS; `verifier` holds the closed-loop model of the current candidate.
pub(crate) fn run(
    set: &ScenarioSet,
    tree: &ScenarioTree,
    verifier: &mut Verifier,
    closed: Option<&LoopEncoding>,
    config: &Config,
    events: Events<'_>,
) -> Result<Verified, CegisError> {
    std::thread::scope(|scope| {
        let mut lower = LowerBound::none();
        if config.sat.max_out_degree.is_some() {
            lower = LowerBound::start(scope, set, tree, &config.sat, config.verbose, events)?;
        }
        Cegis::new(set, tree, verifier, closed, config, &mut lower, events).run()
    })
}

/// The tree-exact minimum, which bounds the cube model from below: restricting a cube
/// machine to the recorded inputs gives a tree-exact machine with the same states and no
/// more edges. Its `C` (and a machine with its colouring, the first hint) takes a fraction of a
/// second; proving its `T` minimal takes longer and runs on a second core while the loop
/// looks for candidates, which do not need it. Only the final pass waits for it.
/// How hard the tree-exact descent on the main thread may look for fewer transitions (about
/// 300 ms of a release build), counted in the solver's work so that the first hint does not
/// depend on the machine's load.
const TREE_EXACT_BUDGET: Effort = Effort::Work(1_500_000);

/// How long the tree-exact model's guards may take to be proven least at its least `C` and
/// `T` (every colouring there enumerated), on the second core.
const LEAST_N_BUDGET: std::time::Duration = std::time::Duration::from_secs(5);

/// What the tree-exact model proves below the cube model, at its least `C`.
struct Least {
    /// The least `T`.
    t: usize,
    /// The colouring of a machine with `t` transitions, when it is not the first one's.
    colors: Option<Vec<usize>>,
    /// The least `N` at `C` and `t`, when proven within [`LEAST_N_BUDGET`].
    n: Option<usize>,
}

/// The least `T` (and `N`) of the tree-exact model at its least `C`.
type LeastT = Result<Least, SatError>;

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
            max_out_degree: None,
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
        let c = first.size.c;
        let first_colors = first.colors.clone();
        let proof = scope.spawn(move || {
            // Usually the first machine's T is the least: one refutation proves it, on the
            // solver that then enumerates the colourings for the least N.
            let least = crate::sat::least_tree_exact(
                set,
                tree,
                &tree_exact,
                c,
                first_colors.clone(),
                LEAST_N_BUDGET,
            )?;
            // Cut short (the deadline): nothing proven beyond C.
            let proven = least.transitions_exact && least.size.c == c;
            let n = (proven && least.guards_exact).then_some(least.size.n);
            let colors = (least.colors != first_colors).then_some(least.colors);
            Ok(Least {
                t: if proven { least.size.t } else { 0 },
                colors,
                n,
            })
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
        let Least { t, colors, n } = proof
            .join()
            .map_err(|_| SatError::Bug("the lower-bound proof panicked".into()))??;
        synth.assume_lower_bounds(self.c, t);
        if let Some(n) = n {
            synth.assume_least_n(self.c, t, n);
        }
        if let Some(colors) = colors {
            synth.hint(colors);
        }
        events(Event::LowerBounds {
            c: self.c,
            t,
            n,
            seconds: self.started.elapsed().as_secs_f64(),
        });
        Ok(())
    }
}

/// A candidate NuSMV verified, kept while the final pass looks for a smaller machine: if it
/// finds none, this machine and its report stand.
struct Passed {
    synthesis: Synthesis,
    report: Report,
    model_text: String,
}

/// What the in-process checker made of a candidate.
enum InProcess {
    /// A counterexample went back into the synthesizer: the next candidate is due.
    Refuted,
    /// Nothing to feed back; per property whether the checker found it holding (empty when
    /// it was not asked or gave up).
    Unrefuted(Vec<bool>),
}

/// The loop: [`Self::propose`] a candidate on the incremental synthesizer, [`Self::verify`]
/// it in closed loop (in process first, then NuSMV), [`Self::refine`] the synthesizer with
/// what failed, and once a candidate passes, one [`Self::final_pass`] that proves it minimal
/// within the budget or finds the smaller machine to check instead.
///
/// Candidates are minimized for their own colouring only (cheap); without the closed loop
/// every candidate gets full proofs (and every candidate is final).
struct Cegis<'a, 'l, 'e> {
    set: &'a ScenarioSet,
    verifier: &'a mut Verifier,
    closed: Option<&'a LoopEncoding>,
    config: &'a Config,
    lower: &'a mut LowerBound<'l>,
    events: Events<'e>,
    synth: Synthesizer<'a>,
    /// How hard candidates are proven minimal ([`Proofs::Skip`] with the closed loop).
    candidate_proofs: Proofs,
    /// How hard the final machine is proven minimal.
    final_proofs: Proofs,
    /// Every candidate so far, in order.
    iterations: Vec<Iteration>,
    /// The properties the latest refuted candidate failed, comma-separated.
    last_failing: String,
    /// Whether the next minimization is the final pass.
    in_final_pass: bool,
    /// Whether the in-process checker is asked (it gives up on a closed loop too large, and
    /// is not asked again).
    in_process: bool,
    /// The latest candidate NuSMV passed, during the final pass.
    passed: Option<Passed>,
    /// C of the latest refuted candidate, how many in a row had it, and when the first of them
    /// was refuted (wall clock and this thread's CPU time, [`thread_cpu`]).
    same: (usize, usize, Instant, Duration),
}

impl<'a, 'l, 'e> Cegis<'a, 'l, 'e> {
    /// The loop on a synthesizer for `tree` with the user's negative scenarios, started from
    /// what `lower` knows so far.
    fn new(
        set: &'a ScenarioSet,
        tree: &'a ScenarioTree,
        verifier: &'a mut Verifier,
        closed: Option<&'a LoopEncoding>,
        config: &'a Config,
        lower: &'a mut LowerBound<'l>,
        events: Events<'e>,
    ) -> Self {
        // Candidates need no proof of minimality; the final machine gets a budget for it.
        let (candidate_proofs, final_proofs) = if closed.is_some() {
            (
                Proofs::Skip,
                Proofs::Budget(Effort::Time(config.proof_budget)),
            )
        } else {
            (Proofs::Full, Proofs::Full)
        };
        let mut synth = Synthesizer::with_proofs(set, tree, &config.sat, candidate_proofs);
        lower.seed(&mut synth);
        for neg in &config.negatives {
            synth.add_negative(neg.clone());
        }
        for neg in &config.learned.negatives {
            if !synth.negatives().contains(neg) {
                synth.add_negative(neg.clone());
            }
        }
        if let Some(closed) = closed {
            for env in &config.learned.environments {
                // A duplicate is refused, and adds nothing anyway.
                let _ = synth.add_environment(&closed.spec, env.clone());
            }
        }
        synth.set_minimize_n(true);
        Cegis {
            set,
            verifier,
            closed,
            config,
            lower,
            events,
            synth,
            candidate_proofs,
            final_proofs,
            iterations: Vec::new(),
            last_failing: String::new(),
            in_final_pass: closed.is_none(),
            in_process: closed.is_some(),
            passed: None,
            same: (0, 0, Instant::now(), thread_cpu()),
        }
    }

    /// Candidates until one is verified (and, with the closed loop, proven minimal or kept by
    /// the final pass), or [`Config::max_iterations`] of them.
    fn run(mut self) -> Result<Verified, CegisError> {
        for number in 1..=self.config.max_iterations {
            self.lower
                .settle(&mut self.synth, self.in_final_pass, self.events)?;
            let t = Instant::now();
            if let Some(verified) = self.final_pass(number, t) {
                return Ok(verified);
            }
            let synthesis = self.propose()?;
            let sat_seconds = t.elapsed().as_secs_f64();
            if let Some(verified) = self.keep_passed(number, &synthesis, sat_seconds) {
                return Ok(verified);
            }
            let holds = match self.check_in_process(number, &synthesis, sat_seconds)? {
                InProcess::Refuted => {
                    self.stalled(&synthesis)?;
                    continue;
                }
                InProcess::Unrefuted(holds) => holds,
            };
            let (v, failing) = self.verify(number, &synthesis, sat_seconds, &holds)?;
            if failing.is_empty() {
                match self.passed(synthesis, v) {
                    Some(verified) => return Ok(verified),
                    None => continue,
                }
            }
            self.last_failing = failing.join(", ");
            self.refine(&v, &failing, &synthesis.ecc)?;
            self.stalled(&synthesis)?;
        }
        // Out of iterations with a machine NuSMV passed: it is the result, verified, only
        // not proven the least in transitions and guards (the final pass did not end).
        if let Some(passed) = self.passed.take() {
            let synthesis = Synthesis {
                transitions_exact: false,
                guards_exact: false,
                ..passed.synthesis
            };
            return Ok(Verified {
                synthesis,
                report: passed.report,
                iterations: std::mem::take(&mut self.iterations),
                model_text: passed.model_text,
            });
        }
        Err(CegisError::Iterations {
            iterations: self.config.max_iterations,
            failing: self.last_failing,
        })
    }

    /// Counts the refuted `candidate` against [`Config::stall`]: `Err` when that many in a row
    /// had its number of states, or when they took that long ([`Stall`]).
    fn stalled(&mut self, candidate: &Synthesis) -> Result<(), CegisError> {
        let c = candidate.size.c;
        self.same = match self.same {
            (last, n, since, cpu) if last == c => (c, n + 1, since, cpu),
            _ => (c, 1, Instant::now(), thread_cpu()),
        };
        let (_, n, since, cpu) = self.same;
        // The loop's own CPU time, not the wall clock: on a machine other programs load, the
        // wall clock would make the loop hand over before candidates it reaches on an idle one.
        let spent = thread_cpu().saturating_sub(cpu);
        let Some(stall) = self.config.stall.filter(|_| self.passed.is_none()) else {
            return Ok(());
        };
        let time = match self.synth.transitions_gave_up(c) {
            true => stall.hard_time,
            false => stall.time,
        };
        if n >= stall.rounds || n >= 3 && spent >= time {
            return Err(CegisError::Stalled {
                rounds: n,
                c,
                seconds: since.elapsed().as_secs_f64(),
                learned: Box::new(self.learned()),
            });
        }
        Ok(())
    }

    /// Counterexamples (negative scenarios and environments) added so far.
    fn counterexamples(&self) -> usize {
        self.synth.negatives().len() + self.synth.environments().len()
    }

    /// The counterexamples the loop learned (the user's negative scenarios left out).
    fn learned(&self) -> Learned {
        Learned {
            negatives: (self.synth.negatives().iter())
                .filter(|n| !self.config.negatives.contains(n))
                .cloned()
                .collect(),
            environments: self.synth.environments().to_vec(),
        }
    }

    /// Back to candidates after a counterexample: no final pass, candidate proofs.
    fn restart_candidates(&mut self) {
        self.in_final_pass = false;
        self.synth.set_proofs(self.candidate_proofs);
    }

    /// The final pass, in the closed loop, asks first whether anything smaller than the
    /// machine NuSMV passed exists at all: two bounded refutations
    /// ([`Synthesizer::smaller_exists`]), where searching again costs seconds and usually ends
    /// at the same size with another machine that would need checking again. Returns the
    /// passed machine, with what was proven about its size, when nothing smaller exists;
    /// otherwise hints its colouring for the search that follows.
    fn final_pass(&mut self, number: usize, started: Instant) -> Option<Verified> {
        let p = match (self.in_final_pass, &self.passed) {
            (true, Some(p)) => &p.synthesis,
            _ => return None,
        };
        let Proofs::Budget(budget) = self.final_proofs else {
            unreachable!("the final pass of the closed loop has a budget")
        };
        let (fewer_t, fewer_n) = self.synth.smaller_exists(p.size, budget);
        let sat = |b: &Bounded| matches!(b, Bounded::Sat(_));
        if sat(&fewer_t) || sat(&fewer_n) {
            // Something smaller exists: search for it from the machine that passed, not from
            // the lower bound's colouring the settling above may have just handed over.
            let colors = p.colors.clone();
            self.synth.hint(colors);
            return None;
        }
        let passed = self.passed.take().expect("checked above");
        let synthesis = Synthesis {
            transitions_exact: matches!(fewer_t, Bounded::Unsat),
            guards_exact: matches!(fewer_n, Bounded::Unsat),
            ..passed.synthesis
        };
        let it = unchanged(number, &synthesis, started.elapsed().as_secs_f64());
        Some(self.kept(synthesis, passed.report, passed.model_text, it))
    }

    /// Propose: the next candidate, the least machine on the synthesizer that reproduces
    /// every scenario and leaves every counterexample so far. Running out of states once
    /// counterexamples were added is [`CegisError::Exhausted`].
    fn propose(&mut self) -> Result<Synthesis, CegisError> {
        let (verbose, events) = (self.config.verbose, &mut self.events);
        let minimized = self.synth.minimize(&mut |m| {
            if verbose {
                events(Event::Solver(m))
            }
        });
        match minimized {
            Err(SatError::TooManyStates { max_states }) if self.counterexamples() > 0 => {
                Err(CegisError::Exhausted {
                    max_states,
                    counterexamples: self.counterexamples(),
                    failing: self.last_failing.clone(),
                })
            }
            r => Ok(r?),
        }
    }

    /// After the final pass's search: a machine no smaller than the one NuSMV passed is not
    /// worth another check. The verified one stands, with what the final pass proved about
    /// its size (same C, T and N, so the same bounds). A smaller one is checked next; the
    /// passed machine stays the result should the iterations run out first.
    fn keep_passed(
        &mut self,
        number: usize,
        synthesis: &Synthesis,
        sat_seconds: f64,
    ) -> Option<Verified> {
        let passed = self.passed.take()?;
        if !self.in_final_pass || synthesis.size.is_smaller_than(&passed.synthesis.size) {
            self.passed = Some(passed);
            return None;
        }
        let before = passed.synthesis;
        let synthesis = Synthesis {
            transitions_exact: synthesis.transitions_exact && synthesis.size.t == before.size.t,
            guards_exact: synthesis.guards_exact && synthesis.size.n == before.size.n,
            stats: synthesis.stats.clone(),
            ..before
        };
        let it = unchanged(number, &synthesis, sat_seconds);
        Some(self.kept(synthesis, passed.report, passed.model_text, it))
    }

    /// The result when the final pass keeps the verified candidate: its iteration reported
    /// and appended.
    fn kept(
        &mut self,
        synthesis: Synthesis,
        report: Report,
        model_text: String,
        it: Iteration,
    ) -> Verified {
        (self.events)(Event::Candidate(&it));
        self.iterations.push(it);
        Verified {
            synthesis,
            report,
            iterations: std::mem::take(&mut self.iterations),
            model_text,
        }
    }

    /// Verify, first step: the in-process checker, whose counterexample costs milliseconds,
    /// so that NuSMV is asked only about candidates it cannot fault. A counterexample goes
    /// back into the synthesizer at once ([`Self::refine_in_process`]). Too large a closed
    /// loop, or one with no behaviour at all: NuSMV decides (and reports a vacuous plant
    /// itself), from now on alone.
    fn check_in_process(
        &mut self,
        number: usize,
        synthesis: &Synthesis,
        sat_seconds: f64,
    ) -> Result<InProcess, CegisError> {
        let (Some(closed), true) = (self.closed, self.in_process) else {
            return Ok(InProcess::Unrefuted(Vec::new()));
        };
        let started = Instant::now();
        let verdicts = match check::check(
            &closed.spec.plant,
            &closed.coupling,
            &synthesis.ecc,
            &closed.checked,
            &check::Limits::default(),
        ) {
            Ok(verdicts) => verdicts,
            Err(e) => {
                if e.is_bound() {
                    (self.events)(Event::InProcessStopped { why: e.to_string() });
                } else {
                    (self.events)(Event::InProcessRefused { why: e.to_string() });
                }
                self.in_process = false;
                return Ok(InProcess::Unrefuted(Vec::new()));
            }
        };
        let names = &closed.names;
        // Of the problem's own properties; a safety part fails only with its property.
        let own = &verdicts[..closed.own];
        let holds = (own.iter())
            .map(|v| matches!(v, check::ExplicitVerdict::Holds))
            .collect();
        let (added, length) = self.refine_in_process(closed, &verdicts, names, &synthesis.ecc)?;
        if added == 0 {
            return Ok(InProcess::Unrefuted(holds));
        }
        let failing: Vec<String> = (own.iter().zip(names))
            .filter(|(v, _)| matches!(v, check::ExplicitVerdict::Violated(_)))
            .map(|(_, name)| name.clone())
            .collect();
        let it = Iteration {
            number,
            checked_by: "in-process",
            c: synthesis.size.c,
            t: synthesis.size.t,
            failing: failing.clone(),
            counterexample_length: length,
            sat_seconds,
            nusmv_seconds: 0.0,
            check_seconds: started.elapsed().as_secs_f64(),
        };
        (self.events)(Event::Candidate(&it));
        self.iterations.push(it);
        self.last_failing = failing.join(", ");
        self.restart_candidates();
        Ok(InProcess::Refuted)
    }

    /// Refine with the in-process checker's lassos: those of encoded properties become
    /// environments; without a new environment, those of the properties the encoding does
    /// not carry come back as negative scenarios, as NuSMV's would. Returns how many were
    /// added and the length of the first.
    fn refine_in_process(
        &mut self,
        closed: &LoopEncoding,
        verdicts: &[check::ExplicitVerdict],
        names: &[String],
        ecc: &crate::ecc::Ecc,
    ) -> Result<(usize, Option<usize>), CegisError> {
        let violated = || {
            (verdicts.iter().enumerate()).filter_map(|(k, v)| match v {
                check::ExplicitVerdict::Violated(lasso) => Some((k, lasso)),
                _ => None,
            })
        };
        let mut added = 0;
        let mut length = None;
        for (_, lasso) in violated().filter(|&(k, _)| closed.encodes(k)) {
            if self
                .synth
                .add_environment(&closed.spec, environment_of(lasso))
                .is_ok()
            {
                added += 1;
                length.get_or_insert(lasso.states.len());
            }
        }
        if added > 0 {
            return Ok((added, length));
        }
        for (k, lasso) in violated().filter(|&(k, _)| !closed.encodes(k)) {
            let neg = negative_of(closed, lasso, &names[k])
                .map_err(|e| SatError::Bug(format!("in-process counterexample: {e}")))?;
            follows_own(&neg, ecc, || format!("in-process {}", neg.label))?;
            if self.synth.negatives().contains(&neg) {
                continue;
            }
            length.get_or_insert(lasso.states.len());
            self.synth.add_negative(neg);
            added += 1;
        }
        Ok((added, length))
    }

    /// Verify, second step: NuSMV's verdict on the candidate in closed loop, reported as an
    /// iteration, with the names of the failing properties. A property NuSMV finds violated
    /// where the in-process checker found it holding (`holds`) is a bug in one of them.
    fn verify(
        &mut self,
        number: usize,
        synthesis: &Synthesis,
        sat_seconds: f64,
        holds: &[bool],
    ) -> Result<(VerificationResult, Vec<String>), CegisError> {
        // With environments one counterexample per candidate is enough: each rules out every
        // machine that fails on its environment. NuSMV's backward re-check per trace is most of
        // its time.
        let mode = if self.closed.is_some() {
            CheckMode::FirstCounterexample
        } else {
            CheckMode::AllCounterexamples
        };
        let v = self.verifier.verify_with(&synthesis.ecc, mode)?;
        let failing: Vec<String> = v.report.failing().iter().map(|s| s.to_string()).collect();
        for (k, p) in v.report.properties.iter().enumerate() {
            if !p.holds && holds.get(k) == Some(&true) {
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
        (self.events)(Event::Candidate(&it));
        self.iterations.push(it);
        Ok((v, failing))
    }

    /// A candidate NuSMV passed: the result if this was the final pass, else kept while the
    /// final pass starts (`None`).
    fn passed(&mut self, synthesis: Synthesis, v: VerificationResult) -> Option<Verified> {
        if !self.in_final_pass {
            self.passed = Some(Passed {
                synthesis,
                report: v.report,
                model_text: v.model.text,
            });
            self.in_final_pass = true;
            self.synth.set_proofs(self.final_proofs);
            return None;
        }
        Some(Verified {
            synthesis,
            report: v.report,
            iterations: std::mem::take(&mut self.iterations),
            model_text: v.model.text,
        })
    }

    /// Refine with NuSMV's counterexamples: those of encoded properties become environments
    /// (the closed loop along each is required to satisfy every encoded property, whatever
    /// the machine does); without a new one, the counterexamples become negative scenarios,
    /// safety violations first: their finite prefixes are cheap and strong constraints.
    /// Lassos (liveness) only once no safety property fails, one at a time: each unrolls
    /// `loop length x C` steps into the solver.
    fn refine(
        &mut self,
        v: &VerificationResult,
        failing: &[String],
        ecc: &crate::ecc::Ecc,
    ) -> Result<(), CegisError> {
        if self.add_environments(v) > 0 {
            self.restart_candidates();
            return Ok(());
        }
        let all: Vec<_> = (v.counterexamples.iter())
            .filter_map(|c| c.negative_scenario(&self.set.inputs, &self.set.outputs))
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
            follows_own(&neg, ecc, || format!("{} in the simulator", neg.label))?;
            self.synth.add_negative(neg);
        }
        if self.closed.is_some() {
            self.restart_candidates();
        }
        Ok(())
    }

    /// The environments of NuSMV's counterexamples of encoded properties, added to the
    /// synthesizer; returns how many were new.
    fn add_environments(&mut self, v: &VerificationResult) -> usize {
        let Some(closed) = self.closed else {
            return 0;
        };
        let names = self.verifier.problem().property_names();
        let mut added = 0;
        for cx in &v.counterexamples {
            let Some(k) = names.iter().position(|n| *n == cx.property) else {
                continue;
            };
            if !closed.encodes(k) {
                continue;
            }
            if let Some(env) = closed.environment(cx) {
                if self.synth.add_environment(&closed.spec, env).is_ok() {
                    added += 1;
                }
            }
        }
        added
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

/// CPU time this thread has used (zero where the clock cannot be read: the stall trigger then
/// counts candidates only). SAT and the in-process checker run on the loop's thread.
fn thread_cpu() -> Duration {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec through a pointer to a live local.
    let read = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) } == 0;
    match read {
        true => Duration::new(
            ts.tv_sec.max(0) as u64,
            ts.tv_nsec.clamp(0, 999_999_999) as u32,
        ),
        false => Duration::ZERO,
    }
}
