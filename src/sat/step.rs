//! Progress of a minimization as typed steps: which bound is tried, which is proven least.
//! The caller decides how to show them; [`std::fmt::Display`] gives the usual one-line text.

use crate::ecc::Size;
use std::fmt;

/// A size the minimizations bound, in the glossary's letters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bound {
    /// States.
    C,
    /// Largest out-degree.
    K,
    /// Transitions.
    T,
    /// Guard literals.
    N,
    /// Corrected errors of a noisy log.
    Errors,
    /// Modular: inputs used, summed over the modules.
    InputsUsed,
    /// Modular: states in all, summed over the modules.
    TotalStates,
}

impl fmt::Display for Bound {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Bound::C => "C",
            Bound::K => "K",
            Bound::T => "T",
            Bound::N => "N",
            Bound::Errors => "ε",
            Bound::InputsUsed => "A (inputs used)",
            Bound::TotalStates => "N' (states used)",
        })
    }
}

/// One step of a minimization.
#[derive(Debug, Clone, PartialEq)]
pub enum Step {
    /// The solver is asked for a machine with `bound <= value`.
    Trying {
        /// The size bounded.
        bound: Bound,
        /// The bound assumed in this call.
        value: usize,
    },
    /// `value` is the least `bound`.
    Minimal {
        /// The size minimized.
        bound: Bound,
        /// The least value found: satisfiable here, refuted one below (unless a floor or a
        /// proof budget ended the descent).
        value: usize,
    },
    /// The first states bound of a single machine, with the problem's figures.
    TryingStates {
        /// The number of states `C` tried.
        c: usize,
        /// Nodes of the scenario tree, root included.
        tree_nodes: usize,
        /// Input vectors of the alphabet (the tree's, then those counterexamples brought).
        inputs: usize,
        /// Negative scenarios encoded so far.
        negatives: usize,
    },
    /// The least C, and the first machine's K and T.
    StatesMinimal {
        /// The least number of states.
        c: usize,
        /// Largest out-degree of the first machine found with `c` states (not yet minimized).
        k: usize,
        /// Transitions of that machine (not yet minimized).
        t: usize,
    },
    /// Guards minimized after the structure (tree-exact model).
    Guards {
        /// Guard literals in all.
        n: usize,
        /// Whether `n` is proven least (the guard search finished within its budget).
        exact: bool,
    },
    /// The encoding is rebuilt for a larger window of states.
    Reencoding {
        /// The new window: states at most (per module with `per_module`).
        states: usize,
        /// Whether the window bounds each module of a modular controller.
        per_module: bool,
    },
    /// The trace graph of a noisy log.
    TraceGraph {
        /// Nodes of the graph.
        nodes: usize,
        /// Distinct scenarios (chains) in the graph.
        traces: usize,
        /// Alternative edges: places where a glitch may be corrected.
        alternatives: usize,
        /// Distinct input vectors.
        inputs: usize,
    },
    /// A candidate of the noisy enumeration.
    Candidate {
        /// Its position in the enumeration, from 1.
        number: usize,
        /// Corrected errors `ε`: alternative edges it uses.
        errors: usize,
        /// Its size `C, K, T, N`.
        size: Size,
    },
    /// Modular: the states bound per module.
    TryingModules {
        /// States per module at most, tried.
        states: usize,
        /// The number of modules `M`.
        modules: usize,
        /// Nodes of the scenario tree, root included.
        tree_nodes: usize,
    },
    /// Modular: the least largest module.
    LargestModule {
        /// States of the largest module.
        states: usize,
    },
    /// The plateau search: with at most `states` states the least machine has `n` guard
    /// literals; the fewest so far are `best`.
    Plateau {
        /// The number of states of this round (fixed, as fbSAT's `-C`).
        states: usize,
        /// Guard literals of the least machine with that many states.
        n: usize,
        /// The fewest guard literals so far, this round included.
        best: usize,
    },
    /// Modular: no module of at most `states` states fits, which the least single machine shows
    /// is for want of transitions per state: `max_out_degree` from now on.
    WideningOutDegree {
        /// The largest out-degree `K` from now on (one more than before).
        max_out_degree: usize,
        /// The states bound refuted: the least single machine's number of states.
        states: usize,
    },
}

impl fmt::Display for Step {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Step::Trying { bound, value } => write!(f, "trying {bound} = {value}"),
            Step::Minimal {
                bound: bound @ (Bound::InputsUsed | Bound::TotalStates),
                value,
            } => write!(f, "{bound} = {value} (minimal)"),
            Step::Minimal {
                bound: Bound::Errors,
                value,
            } => write!(f, "least ε = {value}"),
            Step::Minimal { bound, value } => write!(f, "{bound} = {value} is minimal"),
            Step::TryingStates {
                c,
                tree_nodes,
                inputs,
                negatives,
            } => write!(
                f,
                "trying C = {c} ({tree_nodes} tree nodes, {inputs} inputs, {negatives} negative scenarios)"
            ),
            Step::StatesMinimal { c, k, t } => {
                write!(f, "C = {c} is minimal; first machine has K = {k}, T = {t}")
            }
            Step::Guards { n, exact } => write!(
                f,
                "guards: N = {n}{}",
                if *exact {
                    " (minimal)"
                } else {
                    " (not proven minimal)"
                }
            ),
            Step::Reencoding { states, per_module } => write!(
                f,
                "re-encoding for up to {states} states{}",
                if *per_module { " per module" } else { "" }
            ),
            Step::TraceGraph {
                nodes,
                traces,
                alternatives,
                inputs,
            } => write!(
                f,
                "trace graph: {nodes} nodes, {traces} distinct traces, {alternatives} alternative edges, {inputs} distinct inputs"
            ),
            Step::Candidate {
                number,
                errors,
                size,
            } => write!(f, "candidate {number}: ε = {errors}, {size}"),
            Step::TryingModules {
                states,
                modules,
                tree_nodes,
            } => write!(
                f,
                "trying at most {states} states per module ({modules} modules, {tree_nodes} tree nodes)"
            ),
            Step::LargestModule { states } => {
                write!(f, "largest module: {states} states (minimal)")
            }
            Step::Plateau { states, n, best } => write!(
                f,
                "plateau: at most {states} states: N = {n} (fewest so far {best})"
            ),
            Step::WideningOutDegree { max_out_degree, states } => write!(
                f,
                "no modules of at most {states} states (the least single machine's) with {} transitions per state: widening to {max_out_degree}",
                max_out_degree - 1
            ),
        }
    }
}

/// Where a minimization reports its steps.
pub(crate) type Progress<'a> = &'a mut dyn FnMut(Step);
