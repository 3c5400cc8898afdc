//! Exact synthesis with SAT (varisat): one minimal ECC from clean scenarios ([`basic`]), from
//! noisy traces ([`noisy`]), or a minimal modular controller ([`modular`]).
//!
//! In: scenarios (as a [`ScenarioTree`](crate::scenario::tree::ScenarioTree) or a trace graph)
//! and each encoding's options. Out: the machine, its sizes and figures, replayed through the
//! simulator on every scenario before it is returned.
//!
//! # One core, three encodings
//! Every encoding is a set of variables ([`vars`], [`cubes`], [`modular::vars`]) and one function
//! per constraint family, writing into a clause sink ([`varisat::ExtendFormula`]); production
//! writes into the one incremental [`solver::Solver`], tests may write into a
//! [`varisat::CnfFormula`]. The families a single ECC and a module share (used states, colouring,
//! passive marks, algorithms, BFS symmetry breaking) are written once in [`constraints`] against
//! one machine's [`vars::Coloring`]; the cube guard model ([`cubes`]) is the same for an ECC and
//! for every module. Every bound of a minimization is a solver assumption (a [`card::Totalizer`]
//! output or a "state in use" literal), tightened by [`solver::Solver::descend`].
//!
//! - [`solver`]: the incremental solver, its figures, models, the descent loop;
//! - [`card`]: the totalizer;
//! - [`vars`]: the basic encoding's variables and the [`vars::Coloring`] view;
//! - [`cubes`]: the cube guard model;
//! - [`constraints`]: the shared families and those of the basic encoding;
//! - [`negative`]: negative scenarios (counterexample lassos) as constraints;
//! - [`decode`]: models back to machine structures;
//! - [`dimacs`]: the size questions around a minimum as DIMACS CNF;
//! - [`guards`]: guard minimization on a fixed structure (tree-exact model);
//! - [`basic`], [`noisy`], [`modular`]: the three encodings' minimization loops.
//!
//! # References
//! - D. Chivilikhin, S. Patil, K. Chukharev, A. Cordonnier, V. Vyatkin. Automatic state machine
//!   reconstruction from legacy PLC using data collection and SAT solver. IEEE Transactions on
//!   Industrial Informatics 16(12), 2020 ("the SAT reconstruction paper"): Algorithm 1, noisy
//!   traces (section IV), modular synthesis (section V).
//! - V. Ulyantsev, I. Zakirzyanov, A. Shalyto. BFS-based symmetry breaking predicates for DFA
//!   identification. LATA 2015 (the BFS families).
//! - O. Bailleux, Y. Boufkhad. Efficient CNF encoding of Boolean cardinality constraints.
//!   CP 2003 (the totalizer).

pub(crate) mod ambiguity;
pub(crate) mod basic;
pub(crate) mod card;
pub(crate) mod closed_loop;
pub(crate) mod constraints;
pub(crate) mod cubes;
pub(crate) mod decode;
pub(crate) mod dimacs;
pub(crate) mod guards;
pub mod modular;
pub(crate) mod negative;
pub mod noisy;
pub(crate) mod solver;
pub(crate) mod step;
pub(crate) mod vars;

pub(crate) use basic::{least_tree_exact, satisfiable, Proofs, Synthesizer};
pub use basic::{synthesize, Options};
pub use basic::{Fixed, Stats, Synthesis};
pub use step::{Bound, Step};

/// Why synthesis produced no machine.
#[derive(Debug, thiserror::Error)]
pub enum SatError {
    /// Every number of states up to the limit is UNSAT for the scenarios (exact synthesis,
    /// noisy synthesis without an error bound, and the CEGIS loop once it runs out of states).
    #[error(
        "no ECC with at most {max_states} states reproduces the scenarios (raise --max-states)"
    )]
    TooManyStates {
        /// The `--max-states` limit that was exhausted.
        max_states: usize,
    },
    /// Noisy synthesis within an error bound: the bound is the likelier culprit, since the
    /// glitches a bound leaves uncorrected contradict the recordings for every number of states.
    #[error("no ECC with at most {max_states} states reproduces the recordings with at most {max_errors} corrected samples: raise --max-errors (a log with more scan-cycle glitches needs more corrections), or --max-states")]
    TooFewErrors {
        /// The `--max-states` limit that was exhausted.
        max_states: usize,
        /// The `--max-errors` bound on corrected samples that was in force.
        max_errors: usize,
    },
    /// Fixed bounds ([`basic::Fixed`]) no machine meets.
    #[error("no ECC with at most {max_states} states within the bounds given ({bounds}) reproduces the scenarios")]
    OutOfBounds {
        /// The fixed bounds as the user gave them (the `Display` of [`basic::Fixed`]).
        bounds: String,
        /// The `--max-states` limit that was exhausted.
        max_states: usize,
    },
    /// The deadline of the run passed ([`crate::deadline`]): the search stopped unfinished.
    #[error("stopped at the time limit")]
    Stopped,
    /// A broken internal invariant: a decoded machine that does not replay its scenarios, a
    /// model lost between two solver calls, an encoding misused by its caller. The message says
    /// which.
    #[error("internal error (a bug in synth, please report it): {0}")]
    Bug(String),
}

#[cfg(test)]
mod tests;
