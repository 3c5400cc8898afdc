//! The parallel search, in the spirit of pMuACO: several colonies, each a `(1+λ)` evolution
//! strategy over [`Machine`]s, that share their best machine in synchronous rounds.
//!
//! In: [`ScenarioData`], a [`Config`], and (with properties) one [`Checker`] per colony.
//! Out: an [`Outcome`] with the best machine as an [`Ecc`], its scores and run figures.
//!
//! One generation of a colony: `λ` children of the current machine. While the parent fails a
//! scenario, a child is made with probability [`Config::repair_probability`] by the repair
//! mutation at the first divergence of a failing scenario ([`operators::repair`]); otherwise
//! by one operator chosen uniformly (the verification-aware one only when the parent has
//! counterexamples);
//! the best child replaces the parent when it is at least as fit (neutral moves let the search
//! drift across plateaus). A child's verification terms are computed by NuSMV with
//! probability `p`, always when its scenario part exceeds 99% of the maximum, and otherwise
//! inherited from its parent (the verification-in-the-loop paper, section III.B).
//!
//! Determinism: every colony has its own ChaCha generator seeded from `(seed, colony)`, the
//! colonies run `generations_per_round` generations independently (in parallel on rayon),
//! and between rounds the sharing step runs on one thread in colony order. The outcome
//! therefore depends on the seed, the configuration and where the run stops, not on the
//! number of threads; a run that stops on a perfect machine or on `max_evaluations` repeats
//! exactly, one stopped by the clock stops at a round that depends on the machine's speed.

use super::data::ScenarioData;
use super::fitness::{Divergence, Evaluator, ScenarioScore, Verdicts, Weights};
use super::machine::{input_bits, Machine, SearchState};
use super::operators::{self, Operator};
use super::oracle::{Checker, OracleError};
use crate::ecc::Ecc;
use crate::scenario::negative::NegativeScenario;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Settings of a search run.
#[derive(Debug, Clone)]
pub(crate) struct Config {
    /// Number of states of every candidate.
    pub(crate) states: usize,
    /// Most significant inputs of one transition group.
    pub(crate) max_vars: usize,
    /// Colonies (independent of the number of threads, so results do not depend on it).
    pub(crate) colonies: usize,
    /// Children per generation (the `λ` of `(1+λ)`).
    pub(crate) offspring: usize,
    /// Generations between two sharing steps.
    pub(crate) generations_per_round: usize,
    /// A colony without improvement for this many rounds restarts (see [`Restart`]).
    pub(crate) stagnation_rounds: usize,
    /// ... or after this many of its own verifications without improvement: on a plateau of
    /// machines that all reproduce the scenarios every child is verified, and a round costs
    /// a thousand times more than while climbing.
    pub(crate) stagnation_checks: u64,
    /// Where a stagnating colony restarts.
    pub(crate) restart: Restart,
    /// The fitness constants `c1..c5`.
    pub(crate) weights: Weights,
    /// Probability `p` of verifying a child whose scenario part is below the threshold.
    pub(crate) verify_probability: f64,
    /// Share of the scenario part's maximum above which a child is always verified.
    pub(crate) verify_threshold: f64,
    /// The verification-in-the-loop paper's `λ`: weight added per counterexample visit of a transition.
    pub(crate) counterexample_weight: f64,
    /// Probability that "add or delete transitions" touches a state.
    pub(crate) add_delete_probability: f64,
    /// Probability that a child of a parent failing a scenario is made by the repair
    /// mutation at a first divergence ([`operators::repair`]) rather than by a random one.
    pub(crate) repair_probability: f64,
    /// Probability that a repair redirects an earlier step instead of the divergence itself.
    pub(crate) repair_back_probability: f64,
    /// Skip NuSMV for a child that still follows a counterexample its colony has seen (its
    /// verdicts: those properties fail, the rest inherited), beyond the verification-in-the-loop paper.
    pub(crate) replay_counterexamples: bool,
    /// Seed of every colony's generator (colony `k` uses stream `k`): same seed, same run.
    pub(crate) seed: u64,
    /// Worker threads (rayon).
    pub(crate) threads: usize,
    /// Stop after the round in which this much wall-clock time has passed; `None`: no limit.
    pub(crate) time_limit: Option<Duration>,
    /// Stop after the round in which this many scenario evaluations were reached.
    pub(crate) max_evaluations: Option<u64>,
    /// Stop after this many rounds in a row in which the elite reproduced no more scenarios and
    /// satisfied no more properties (smaller fitness gains do not count); `None`: never.
    pub(crate) give_up_rounds: Option<usize>,
    /// Starting machines (e.g. from SAT); colony `k` starts from `initial[k % len]`, padded
    /// to `states` states. Empty: random starts.
    pub(crate) initial: Vec<Machine>,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            states: 8,
            max_vars: 4,
            colonies: 4,
            offspring: 8,
            generations_per_round: 25,
            stagnation_rounds: 10,
            stagnation_checks: u64::MAX,
            restart: Restart::Elite,
            weights: Weights::default(),
            verify_probability: 0.001,
            verify_threshold: 0.99,
            counterexample_weight: 1.0,
            add_delete_probability: 0.2,
            repair_probability: 0.5,
            repair_back_probability: 0.3,
            replay_counterexamples: true,
            seed: 0,
            threads: 1,
            time_limit: None,
            max_evaluations: None,
            give_up_rounds: None,
            initial: Vec::new(),
        }
    }
}

/// Counterexamples a colony keeps for replay, newest last. Every child above the threshold is
/// replayed on all of them; with in-process verdicts a colony collects thousands, and an
/// unbounded list made replay a third of the run time (Table I, configuration 3, seed 2).
const KNOWN_COUNTEREXAMPLES: usize = 64;

/// Where a stagnating colony restarts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Restart {
    /// From the shared best when that is better than its own, else from a random machine
    /// (keeps the colonies near a good start such as SAT's machine).
    Elite,
    /// Always from a random machine. From random starts the shared best is usually a
    /// machine that reproduces the scenarios and fails a liveness property; colonies pulled
    /// back to it stay there (Table I, configuration 3, seeds 3 and 4: not solved in 60 s),
    /// while fresh machines are independent tries.
    Random,
}

/// Why a search stopped without an outcome.
#[derive(Debug, thiserror::Error)]
pub enum SearchError {
    /// A colony's checker failed to verify a candidate (NuSMV or the in-process checker).
    #[error("verification of a candidate failed: {0}")]
    Verify(#[from] OracleError),
    /// [`Config::states`], [`Config::colonies`] or [`Config::offspring`] is 0.
    #[error("the search needs at least one state, one colony and one child per generation")]
    Config,
    /// Rayon could not build the thread pool (carries its message).
    #[error("cannot start the thread pool: {0}")]
    Threads(String),
    /// Checkers were given, but not one per colony: `(checkers, colonies)`.
    #[error("{0} checkers given for {1} colonies")]
    Checkers(usize, usize),
}

/// Figures of a run.
#[derive(Debug, Clone, Default, serde::Serialize, schemars::JsonSchema)]
pub(crate) struct Stats {
    /// Scenario fitness evaluations.
    pub(crate) evaluations: u64,
    /// Verification requests (NuSMV runs plus cache hits).
    pub(crate) verifications: u64,
    /// Verifications saved because the child still followed a parent's counterexample.
    pub(crate) replayed: u64,
    /// Rounds run (each `generations_per_round` generations of every colony, then sharing).
    pub rounds: usize,
    /// Wall-clock time of the run, in seconds.
    pub(crate) seconds: f64,
}

/// What the progress callback sees after every round.
#[derive(Debug, Clone)]
pub struct Progress {
    /// The round just finished (1-based).
    pub(crate) round: usize,
    /// Fitness of the best machine so far (over all colonies and rounds).
    pub(crate) best_fitness: f64,
    /// Scenario terms of the best machine so far.
    pub(crate) best_score: ScenarioScore,
    /// `(satisfied, total)` of the best machine's latest verdicts, if it has any.
    pub(crate) properties: Option<(usize, usize)>,
    /// Scenario evaluations so far, over all colonies.
    pub(crate) evaluations: u64,
    /// Wall-clock time since the start of the run, in seconds.
    pub(crate) seconds: f64,
}

/// The result of a run.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The best machine found, in the search's representation.
    pub(crate) machine: Machine,
    /// The machine with its labeled algorithms.
    pub ecc: Ecc,
    /// Its scenario terms.
    pub(crate) score: ScenarioScore,
    /// Verdicts the search saw for it (computed for this machine, not inherited).
    pub(crate) verdicts: Option<Verdicts>,
    /// Its fitness `F` under [`Config::weights`].
    pub(crate) fitness: f64,
    /// Every scenario reproduced and (with properties) every property held in the search.
    pub(crate) perfect: bool,
    /// Figures of the run.
    pub(crate) stats: Stats,
}

impl Outcome {
    /// Every scenario reproduced and (with properties) every property held in the search.
    pub fn perfect(&self) -> bool {
        self.perfect
    }

    /// `(reproduced, scenarios)`: the scenarios the machine reproduces exactly, of all.
    pub fn reproduced(&self) -> (usize, usize) {
        (self.score.reproduced, self.score.scenarios)
    }

    /// Scenario fitness evaluations of the run, over all colonies.
    pub fn evaluations(&self) -> u64 {
        self.stats.evaluations
    }

    /// Wall-clock time of the run, in seconds.
    pub fn seconds(&self) -> f64 {
        self.stats.seconds
    }
}

#[derive(Debug, Clone)]
struct Individual {
    machine: Machine,
    score: ScenarioScore,
    /// The first divergence of every scenario it fails.
    divergences: Vec<Divergence>,
    /// Its labeled algorithms, `(set to 0, set to 1)` per state.
    masks: Vec<(u32, u32)>,
    verdicts: Option<Arc<Verdicts>>,
    /// The verdicts were computed for this machine, not inherited.
    own: bool,
    fitness: f64,
}

struct Colony<'a> {
    rng: ChaCha8Rng,
    eval: Evaluator<'a>,
    checker: Option<Box<dyn Checker>>,
    current: Individual,
    stagnant: usize,
    /// Own verifications since the last improvement.
    checks_stagnant: u64,
    evaluations: u64,
    verifications: u64,
    replayed: u64,
    /// Counterexamples NuSMV gave this colony (controller view), oldest first.
    known: Vec<NegativeScenario>,
    error: Option<OracleError>,
}

/// The verdicts of a machine known to follow the counterexamples `followed`: the properties
/// they belong to are violated (at most `total - k` hold), the rest is inherited.
fn known_violations(inherited: Option<&Verdicts>, followed: &[&NegativeScenario]) -> Verdicts {
    let mut labels: Vec<&str> = followed.iter().map(|n| n.label.as_str()).collect();
    labels.sort();
    labels.dedup();
    let total = inherited.map_or(labels.len(), |v| v.total);
    let satisfied = inherited
        .map_or(0, |v| v.satisfied)
        .min(total.saturating_sub(labels.len()));
    Verdicts {
        satisfied,
        total,
        longest_counterexample: followed.iter().map(|n| n.steps.len()).max().unwrap_or(1),
        counterexamples: followed
            .iter()
            .map(|n| n.steps.iter().map(|s| input_bits(&s.inputs)).collect())
            .collect(),
        negatives: followed.iter().map(|n| (*n).clone()).collect(),
    }
}

/// Pads a machine with states without transitions up to `states`.
fn padded(m: &Machine, states: usize) -> Machine {
    let mut m = m.clone();
    while m.states.len() < states {
        m.states.push(SearchState::default());
    }
    m
}

impl Colony<'_> {
    fn perfect(&self, ind: &Individual) -> bool {
        ind.score.perfect()
            && (self.checker.is_none()
                || (ind.own && ind.verdicts.as_ref().is_some_and(|v| v.all_hold())))
    }

    /// Scores a machine; verifies it when `force`, when the scenario part is above the
    /// threshold, or with probability `p`; else inherits `parent`'s verdicts.
    fn assess(
        &mut self,
        machine: Machine,
        parent: Option<&Individual>,
        config: &Config,
        force: bool,
    ) -> Individual {
        let score = self.eval.evaluate(&machine);
        let divergences = self.eval.divergences().to_vec();
        let masks = self.eval.label_masks().to_vec();
        self.evaluations += 1;
        let w = &config.weights;
        let mut verdicts = parent.and_then(|p| p.verdicts.clone());
        let mut own = false;
        if let (Some(checker), None) = (self.checker.as_mut(), &self.error) {
            let above = w.scenario_part(&score) > config.verify_threshold * w.scenario_max();
            if force || above || verdicts.is_none() || self.rng.gen_bool(config.verify_probability)
            {
                let data = self.eval.data();
                let ecc = machine.to_ecc(
                    &data.inputs,
                    &data.outputs,
                    &data.initial_outputs,
                    &self.eval.algorithms(),
                );
                // Beyond the verification-in-the-loop paper: a child that still follows a counterexample this colony
                // has seen violates that property for sure; NuSMV would only repeat it.
                // Only with inherited verdicts: they say how many properties there are.
                let followed: Vec<&NegativeScenario> =
                    if config.replay_counterexamples && verdicts.is_some() {
                        self.known.iter().filter(|n| n.followed_by(&ecc)).collect()
                    } else {
                        vec![]
                    };
                if !followed.is_empty() {
                    self.replayed += 1;
                    verdicts = Some(Arc::new(known_violations(verdicts.as_deref(), &followed)));
                } else {
                    self.verifications += 1;
                    self.checks_stagnant += 1;
                    match checker.check(&ecc) {
                        Ok(v) => {
                            for n in &v.negatives {
                                if !self.known.contains(n) {
                                    if self.known.len() == KNOWN_COUNTEREXAMPLES {
                                        self.known.remove(0);
                                    }
                                    self.known.push(n.clone());
                                }
                            }
                            verdicts = Some(v);
                            own = true;
                        }
                        Err(e) => self.error = Some(e),
                    }
                }
            }
        }
        let fitness = w.total(&score, verdicts.as_deref());
        Individual {
            machine,
            score,
            divergences,
            masks,
            verdicts,
            own,
            fitness,
        }
    }

    fn mutate(&mut self, parent: &Individual, config: &Config) -> Machine {
        let cxs: &[Vec<u32>] = parent
            .verdicts
            .as_deref()
            .map_or(&[], |v| v.counterexamples.as_slice());
        let mut ops = vec![
            Operator::ChangeTarget,
            Operator::AddDelete,
            Operator::SwapSignificance,
            Operator::ResizeSignificance,
        ];
        if !cxs.is_empty() {
            ops.push(Operator::WeightedChangeTarget);
            ops.push(Operator::ReactOnCounterexample);
        }
        let mut m = parent.machine.clone();
        if !parent.divergences.is_empty() && self.rng.gen_bool(config.repair_probability) {
            let at = parent.divergences[self.rng.gen_range(0..parent.divergences.len())];
            let site = operators::Site {
                data: self.eval.data(),
                masks: &parent.masks,
                at,
            };
            if operators::repair(
                &mut self.rng,
                &mut m,
                &site,
                config.max_vars,
                config.repair_back_probability,
            ) {
                return m;
            }
        }
        // An operator with nothing to act on leaves the machine alone; another one is tried.
        for _ in 0..8 {
            let op = ops[self.rng.gen_range(0..ops.len())];
            let rng = &mut self.rng;
            let done = match op {
                Operator::ChangeTarget => operators::change_target(rng, &mut m),
                Operator::AddDelete => {
                    operators::add_or_delete(rng, &mut m, config.add_delete_probability)
                }
                Operator::SwapSignificance => operators::swap_significance(rng, &mut m),
                Operator::ResizeSignificance => {
                    operators::resize_significance(rng, &mut m, config.max_vars)
                }
                Operator::WeightedChangeTarget => operators::weighted_change_target(
                    rng,
                    &mut m,
                    cxs,
                    config.counterexample_weight,
                ),
                Operator::ReactOnCounterexample => {
                    operators::react_on_counterexample(rng, &mut m, cxs, config.max_vars)
                }
            };
            if done {
                break;
            }
        }
        m
    }

    /// Runs up to `generations` generations; stops early on a perfect machine.
    fn run(&mut self, generations: usize, config: &Config) {
        let start = self.current.fitness;
        for _ in 0..generations {
            if self.perfect(&self.current) || self.error.is_some() {
                break;
            }
            let parent = self.current.clone();
            let mut best: Option<Individual> = None;
            for _ in 0..config.offspring {
                let child = self.mutate(&parent, config);
                let child = self.assess(child, Some(&parent), config, false);
                let perfect = self.perfect(&child);
                if best.as_ref().is_none_or(|b| child.fitness > b.fitness) || perfect {
                    best = Some(child);
                }
                if perfect {
                    break;
                }
            }
            let best = best.expect("offspring >= 1");
            if best.fitness >= self.current.fitness || self.perfect(&best) {
                self.current = best;
            }
        }
        if self.current.fitness > start {
            self.stagnant = 0;
            self.checks_stagnant = 0;
        } else {
            self.stagnant += 1;
        }
    }
}

/// Runs the search. `checkers`: one per colony when there are properties, else empty.
pub(crate) fn run(
    data: &ScenarioData,
    config: &Config,
    checkers: Vec<Box<dyn Checker>>,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Outcome, SearchError> {
    let mut colonies = colonies(data, config, checkers)?;
    let start = Instant::now();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(config.threads.max(1))
        .build()
        .map_err(|e| SearchError::Threads(e.to_string()))?;
    // The best machine so far: colonies restart, the elite stays.
    let mut elite: Option<(usize, Individual)> = None;
    let mut round = 0;
    // The round since which the elite has reproduced `progress.0` scenarios and satisfied
    // `progress.1` properties.
    let (mut progress_key, mut progress_since) = ((0, 0), 0);
    loop {
        round += 1;
        pool.install(|| {
            colonies
                .par_iter_mut()
                .for_each(|c| c.run(config.generations_per_round, config))
        });
        if let Some(k) = colonies.iter().position(|c| c.error.is_some()) {
            return Err(colonies[k].error.take().expect("found").into());
        }
        let evaluations: u64 = colonies.iter().map(|c| c.evaluations).sum();
        let best_k = best_colony(&colonies);
        let candidate = &colonies[best_k];
        if elite
            .as_ref()
            .is_none_or(|(k, e)| candidate.beats(&colonies[*k], e))
        {
            elite = Some((best_k, candidate.current.clone()));
        }
        let (elite_k, best) = elite.clone().expect("set above");
        let key = (
            best.score.reproduced,
            best.verdicts.as_ref().map_or(0, |v| v.satisfied),
        );
        if key > progress_key {
            (progress_key, progress_since) = (key, round);
        }
        let done = colonies[elite_k].perfect(&best);
        progress(&Progress {
            round,
            best_fitness: best.fitness,
            best_score: best.score,
            properties: best.verdicts.as_ref().map(|v| (v.satisfied, v.total)),
            evaluations,
            seconds: start.elapsed().as_secs_f64(),
        });
        let out_of_budget = config.time_limit.is_some_and(|t| start.elapsed() >= t)
            || config.max_evaluations.is_some_and(|m| evaluations >= m)
            || (config.give_up_rounds).is_some_and(|g| round - progress_since >= g);
        if done || out_of_budget {
            let stats = stats(&colonies, evaluations, round, start);
            return Ok(colonies[elite_k].outcome(data, best, done, stats));
        }
        // Sharing: a stagnating colony restarts from the elite when that is better than its
        // own (with [`Restart::Elite`]), else from a random machine.
        for c in colonies.iter_mut() {
            c.restart_if_stagnant(&best, config, data.inputs.len());
        }
    }
}

/// The colonies, each with its checker when there are properties, after checking the config.
fn colonies<'a>(
    data: &'a ScenarioData,
    config: &Config,
    checkers: Vec<Box<dyn Checker>>,
) -> Result<Vec<Colony<'a>>, SearchError> {
    if config.states == 0 || config.colonies == 0 || config.offspring == 0 {
        return Err(SearchError::Config);
    }
    if !checkers.is_empty() && checkers.len() != config.colonies {
        return Err(SearchError::Checkers(checkers.len(), config.colonies));
    }
    let mut checkers: Vec<Option<Box<dyn Checker>>> = checkers.into_iter().map(Some).collect();
    checkers.resize_with(config.colonies, || None);
    Ok((checkers.into_iter().enumerate())
        .map(|(k, checker)| Colony::new(data, config, k, checker))
        .collect())
}

/// The search's figures after `round` rounds begun at `start`, `evaluations` in all.
fn stats(colonies: &[Colony], evaluations: u64, round: usize, start: Instant) -> Stats {
    Stats {
        evaluations,
        verifications: colonies.iter().map(|c| c.verifications).sum(),
        replayed: colonies.iter().map(|c| c.replayed).sum(),
        rounds: round,
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// The first colony with the highest fitness (a perfect one first).
fn best_colony(colonies: &[Colony]) -> usize {
    (0..colonies.len())
        .max_by(|&a, &b| {
            let key = |k: usize| {
                let c = &colonies[k];
                (c.perfect(&c.current), c.current.fitness)
            };
            let (pa, fa) = key(a);
            let (pb, fb) = key(b);
            pa.cmp(&pb).then(fa.total_cmp(&fb)).then(b.cmp(&a))
        })
        .expect("colonies >= 1")
}

impl<'a> Colony<'a> {
    /// Colony `k` of the run: its own random stream of the seed, and a first machine (the
    /// configured initial one, padded, or a random one) assessed with a check.
    fn new(
        data: &'a ScenarioData,
        config: &Config,
        k: usize,
        checker: Option<Box<dyn Checker>>,
    ) -> Colony<'a> {
        let mut rng = ChaCha8Rng::seed_from_u64(config.seed);
        rng.set_stream(k as u64);
        let machine = match config.initial.get(k % config.initial.len().max(1)) {
            Some(m) => padded(m, config.states),
            None => Machine::random(&mut rng, data.inputs.len(), config.states, config.max_vars),
        };
        let mut c = Colony {
            rng,
            eval: Evaluator::new(data),
            checker,
            current: Individual {
                machine: machine.clone(),
                score: ScenarioScore {
                    ed: 0.0,
                    fe: 0.0,
                    sc: 0.0,
                    reproduced: 0,
                    scenarios: 0,
                },
                divergences: Vec::new(),
                masks: Vec::new(),
                verdicts: None,
                own: false,
                fitness: f64::NEG_INFINITY,
            },
            stagnant: 0,
            checks_stagnant: 0,
            evaluations: 0,
            verifications: 0,
            replayed: 0,
            known: Vec::new(),
            error: None,
        };
        c.current = c.assess(machine, None, config, true);
        c
    }
}

impl Colony<'_> {
    /// Whether this colony's machine should replace the elite `e` (kept by colony `holder`):
    /// perfect where the elite is not, or as perfect and fitter.
    fn beats(&self, holder: &Colony, e: &Individual) -> bool {
        let (pc, pe) = (self.perfect(&self.current), holder.perfect(e));
        pc && !pe || (pc == pe && self.current.fitness > e.fitness)
    }

    /// The result with `best`, the elite this colony holds, and the run's `stats`.
    fn outcome(
        &mut self,
        data: &ScenarioData,
        best: Individual,
        perfect: bool,
        stats: Stats,
    ) -> Outcome {
        // Labeling again gives the best machine's algorithms.
        self.eval.evaluate(&best.machine);
        let ecc = best.machine.to_ecc(
            &data.inputs,
            &data.outputs,
            &data.initial_outputs,
            &self.eval.algorithms(),
        );
        Outcome {
            perfect,
            verdicts: if best.own {
                best.verdicts.as_deref().cloned()
            } else {
                None
            },
            machine: best.machine,
            ecc,
            score: best.score,
            fitness: best.fitness,
            stats,
        }
    }

    /// After too many rounds (or checks) without improvement, starts again: from the elite
    /// `best` when that is fitter and [`Restart::Elite`] is set, else from a random machine.
    fn restart_if_stagnant(&mut self, best: &Individual, config: &Config, inputs: usize) {
        if self.stagnant < config.stagnation_rounds
            && self.checks_stagnant < config.stagnation_checks
        {
            return;
        }
        self.stagnant = 0;
        self.checks_stagnant = 0;
        if config.restart == Restart::Elite && best.fitness > self.current.fitness {
            self.current = best.clone();
        } else {
            let m = Machine::random(&mut self.rng, inputs, config.states, config.max_vars);
            self.current = self.assess(m, None, config, true);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::pnp;
    use crate::scenario::ScenarioSet;

    fn quick(seed: u64) -> Config {
        Config {
            seed,
            states: 4,
            colonies: 3,
            threads: 2,
            generations_per_round: 20,
            max_evaluations: Some(3_000),
            ..Config::default()
        }
    }

    /// The first `scenarios` scenarios of the Pick-and-Place case.
    fn pnp_scenarios(scenarios: usize) -> ScenarioSet {
        let mut set = pnp::generate();
        set.scenarios.truncate(scenarios);
        set
    }

    /// A search without properties.
    fn search(data: &ScenarioData, config: &Config) -> Outcome {
        run(data, config, vec![], &mut |_| {}).unwrap()
    }

    #[test]
    fn same_seed_same_machine_whatever_the_threads() {
        let data = ScenarioData::new(&pnp_scenarios(2)).unwrap();
        let a = search(&data, &quick(5));
        let b = search(
            &data,
            &Config {
                threads: 1,
                ..quick(5)
            },
        );
        assert_eq!(a.machine, b.machine);
        assert_eq!(a.ecc, b.ecc);
        assert_eq!(a.stats.evaluations, b.stats.evaluations);
        let c = search(&data, &quick(6));
        assert_ne!(a.machine, c.machine, "another seed searches elsewhere");
    }

    /// The metaheuristic paper's experiment in small: from random machines, every one of the
    /// ten Pick-and-Place scenarios reproduced within a fixed budget of evaluations.
    #[test]
    fn from_random_machines_the_search_reproduces_every_pnp_scenario() {
        let set = pnp::generate();
        assert_eq!(set.scenarios.len(), 10);
        let data = ScenarioData::new(&set).unwrap();
        let config = Config {
            seed: 1,
            states: 10,
            threads: 2,
            max_evaluations: Some(3_000_000),
            stagnation_rounds: 100,
            restart: Restart::Random,
            ..Config::default()
        };
        let out = search(&data, &config);
        assert!(out.perfect, "{:?} after {:?}", out.score, out.stats);
        set.check(&out.ecc).unwrap();
    }

    #[test]
    fn the_outcome_is_the_machine_the_scores_describe() {
        let set = pnp_scenarios(1);
        let data = ScenarioData::new(&set).unwrap();
        let out = search(&data, &quick(1));
        out.ecc.validate().unwrap();
        let mut ev = Evaluator::new(&data);
        assert_eq!(ev.evaluate(&out.machine), out.score);
        if out.perfect {
            set.check(&out.ecc).unwrap();
        }
    }
}
