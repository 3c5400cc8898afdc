//! Modular synthesis: the outputs distributed over M basic function blocks that read the
//! same inputs, wired by a composite block (the parallel decomposition of the modular
//! synthesis in Chivilikhin et al., "Automatic state machine reconstruction from legacy PLC
//! using data collection and SAT solver").

use super::{Error, Event, Events};
use crate::sat::modular::synthesize_modular;
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;

pub use crate::sat::modular::{parse_pins, ModularOptions as Options, ModularSynthesis};

/// The smallest modular controller for `set` (least largest module, then fewest inputs used,
/// then fewest states in all); replayed on every scenario.
pub fn run(
    set: &ScenarioSet,
    opts: &Options,
    events: Events<'_>,
) -> Result<ModularSynthesis, Error> {
    let tree = ScenarioTree::build(set)?;
    Ok(synthesize_modular(set, &tree, opts, &mut |m| {
        events(Event::Solver(m))
    })?)
}

/// Number of nodes of the scenario tree of `set` (a figure of the benchmarks).
pub fn tree_nodes(set: &ScenarioSet) -> Result<usize, Error> {
    Ok(ScenarioTree::build(set)?.nodes.len())
}
