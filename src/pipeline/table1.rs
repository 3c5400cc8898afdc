//! Table I of the verification-in-the-loop paper (the function-block reconstruction by search,
//! augmented with closed-loop NuSMV verification over a hand-made surrogate plant model): the
//! search repeated per seed in three fitness configurations, scenarios only, scenarios and
//! LTL without the counterexample term `F_ce`, scenarios and LTL.
//!
//! In: the scenarios, the [`Check`], the configurations and [`Options`] (runs, first seed, the
//! search's settings). Out: per configuration, every run's time, whether the search solved it
//! and NuSMV's final verdict on its machine ([`Row`], [`Run`]); `synth-dev experiment table1`
//! prints them as the paper's table.

use super::search::{self, Start};
use super::{Check, Error, Events};
use crate::ltl::property_name;
use crate::scenario::ScenarioSet;
use crate::search::{Machine, Weights};
use std::time::Instant;

/// One column set of the paper's table: which fitness terms the search uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Configuration {
    /// 1: the scenarios alone (no verification terms).
    Scenarios,
    /// 2: scenarios and LTL, without the counterexample term `F_ce`.
    NoCounterexamples,
    /// 3: scenarios and LTL, every term.
    Full,
}

impl Configuration {
    /// The configuration numbered `n` (1, 2 or 3) as the paper numbers them.
    pub fn numbered(n: usize) -> Result<Configuration, Error> {
        match n {
            1 => Ok(Configuration::Scenarios),
            2 => Ok(Configuration::NoCounterexamples),
            3 => Ok(Configuration::Full),
            _ => Err(Error::Usage(format!("no configuration {n} (1, 2 or 3)"))),
        }
    }

    /// The paper's number of the configuration.
    pub fn number(self) -> usize {
        match self {
            Configuration::Scenarios => 1,
            Configuration::NoCounterexamples => 2,
            Configuration::Full => 3,
        }
    }

    /// The paper's name of the configuration.
    pub fn label(self) -> &'static str {
        match self {
            Configuration::Scenarios => "Scenarios",
            Configuration::NoCounterexamples => "Scenarios + LTL (no F_ce)",
            Configuration::Full => "Scenarios + LTL",
        }
    }

    /// The fitness weights: zero for the terms the configuration leaves out.
    pub(crate) fn weights(self) -> Weights {
        match self {
            Configuration::Scenarios => Weights {
                sat: 0.0,
                ce: 0.0,
                ..Weights::default()
            },
            Configuration::NoCounterexamples => Weights {
                ce: 0.0,
                ..Weights::default()
            },
            Configuration::Full => Weights::default(),
        }
    }
}

/// Settings of the experiment.
#[derive(Debug, Clone)]
pub struct Options {
    /// Runs per configuration, seeds `seed`, `seed + 1`, ...
    pub runs: usize,
    /// The first run's seed.
    pub seed: u64,
    /// The search's settings for every run; its seed and weights are set per run and
    /// configuration, and [`search::Options::start`] says where every run starts.
    pub search: search::Options,
}

/// One run of the search.
#[derive(Debug, Clone)]
pub struct Run {
    /// The run's seed.
    pub seed: u64,
    /// Wall-clock seconds, the time limit for a run the search did not solve.
    pub seconds: f64,
    /// Whether the search ended on a solution (every scenario, every verdict it asked for).
    pub solved: bool,
    /// Whether NuSMV's final check of the run's machine says every property holds.
    pub all_hold: bool,
    /// The properties NuSMV's final check found violated.
    pub failing: Vec<String>,
    /// States of the machine reachable from its initial state.
    pub states_used: usize,
    /// Fitness evaluations of the run.
    pub evaluations: u64,
    /// Candidates judged by the in-process checker.
    pub in_process_checks: u64,
    /// Candidates judged by NuSMV during the search.
    pub nusmv_runs: u64,
    /// Verdicts taken from the cache.
    pub cache_hits: u64,
    /// NuSMV runs saved by replaying counterexamples.
    pub replayed: u64,
}

/// Every run of one configuration.
#[derive(Debug, Clone)]
pub struct Row {
    /// The configuration.
    pub configuration: Configuration,
    /// Its runs, in seed order.
    pub runs: Vec<Run>,
}

impl Row {
    /// Runs the search solved.
    pub fn solved(&self) -> usize {
        self.runs.iter().filter(|r| r.solved).count()
    }

    /// Runs whose machine satisfies every property.
    pub fn all_hold(&self) -> usize {
        self.runs.iter().filter(|r| r.all_hold).count()
    }

    /// Runs whose machine satisfies the property called `name`.
    pub fn holds(&self, name: &str) -> usize {
        (self.runs.iter())
            .filter(|r| !r.failing.iter().any(|f| f == name))
            .count()
    }
}

/// The experiment on one problem, with the start machines every run shares.
pub struct Table1<'a> {
    set: &'a ScenarioSet,
    check: &'a Check,
    opts: Options,
    initial: Vec<Machine>,
}

impl<'a> Table1<'a> {
    /// Prepares the runs: with [`Start::Sat`] the one SAT machine every run starts from
    /// (reported as [`super::Event::SatStart`]).
    pub fn new(
        set: &'a ScenarioSet,
        check: &'a Check,
        opts: Options,
        events: Events<'_>,
    ) -> Result<Table1<'a>, Error> {
        let initial = match opts.search.start {
            Start::Random => vec![],
            Start::Sat => vec![search::sat_start(set, 6, events)?],
        };
        Ok(Table1 {
            set,
            check,
            opts,
            initial,
        })
    }

    /// The names of the properties, in spec order.
    pub fn properties(&self) -> Vec<String> {
        (self.check.problem.props.iter())
            .enumerate()
            .map(|(k, p)| property_name(k, p))
            .collect()
    }

    /// Runs every configuration in turn; `each` hears of every run when it ends, `events` of
    /// the searches' progress.
    pub fn run(
        &self,
        configurations: &[Configuration],
        each: &mut dyn FnMut(Configuration, usize, &Run),
        events: Events<'_>,
    ) -> Result<Vec<Row>, Error> {
        let mut rows = Vec::new();
        for &configuration in configurations {
            let mut runs = Vec::new();
            for k in 0..self.opts.runs.max(1) {
                let run = self.one(configuration, self.opts.seed + k as u64, events)?;
                each(configuration, k, &run);
                runs.push(run);
            }
            rows.push(Row {
                configuration,
                runs,
            });
        }
        Ok(rows)
    }

    /// One search run; NuSMV checks its machine at the end on every property.
    fn one(
        &self,
        configuration: Configuration,
        seed: u64,
        events: Events<'_>,
    ) -> Result<Run, Error> {
        let opts = search::Options {
            seed,
            weights: configuration.weights(),
            ..self.opts.search.clone()
        };
        let t = Instant::now();
        let run = search::run(
            self.set,
            self.check,
            &opts,
            Some(self.initial.clone()),
            events,
        )?;
        let report = &run.verification.report;
        Ok(Run {
            seed,
            seconds: t.elapsed().as_secs_f64(),
            solved: run.outcome.perfect,
            all_hold: report.all_hold(),
            failing: report.failing().iter().map(|s| s.to_string()).collect(),
            states_used: run.reachable_states,
            evaluations: run.outcome.stats.evaluations,
            in_process_checks: run.in_process_checks,
            nusmv_runs: run.nusmv_runs,
            cache_hits: run.cache_hits,
            replayed: run.outcome.stats.replayed,
        })
    }
}
