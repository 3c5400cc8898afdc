//! Modular synthesis: the outputs distributed over M basic function blocks that read the
//! same inputs, wired by a composite block (the parallel decomposition of the modular
//! synthesis in Chivilikhin et al., "Automatic state machine reconstruction from legacy PLC
//! using data collection and SAT solver").
//!
//! In: a [`ScenarioSet`] and [`Options`]: the number of modules M, the transition slots K per
//! state (default 3), outputs pinned to modules ([`parse_pins`] reads `--pin 1=OUT,OUT`;
//! modules are numbered from 1), the bound on states and the form of the algorithms. Out: a
//! [`ModularSynthesis`]: the controller ([`crate::ecc::modular::Modular`]), its sizes and
//! solver figures. [`crate::export::modular::write_modular`] writes it.
//!
//! # What is minimized
//! Lexicographically, on one incremental solver where every bound is an assumption: the
//! states of the largest module, then A (inputs read, summed over the modules), then N'
//! (states, summed over the modules). The encoding is the paper's ([`crate::sat::modular`]):
//! per module a colouring of the scenario tree; an owner module per output, exactly one; which
//! inputs each module reads; K ordered transition slots per state, each with a conjunction of
//! literals over the module's inputs and first-fire semantics; "state in use" variables with
//! the BFS symmetry breaking adapted to unused states (only used states need a BFS parent);
//! and, when nothing is pinned, interchangeable modules ordered by their smallest output.
//! Since a guard is a single conjunction, a disjunction needs several slots: K bounds what one
//! state can say. Afterwards, transitions no scenario fires and guard literals no scenario
//! needs are dropped, and the composite is replayed on every scenario (a mismatch is a bug,
//! exit code 70). Unknown output names, module numbers outside `1..M` and an output pinned
//! twice are usage errors (exit code 2).
//!
//! # The composite
//! Every module receives every `REQ` (with the inputs it reads) and behaves as a basic ECC.
//! The composite's outputs are the union of the modules' outputs, and it emits `CNF` iff at
//! least one module fired. A recorded active step thus needs some module to fire, a passive
//! step needs all to stay put, and a module whose outputs change must fire. This is the
//! project's step model, so the composite replays scenarios like a single ECC
//! ([`crate::ecc::modular::ModularRun`]). As in the paper, a module may own no output; it then
//! only contributes `CNF`s and, in the `.fbt`, has no output data connection.
//!
//! With [`Topology::Consecutive`] the modules form a chain instead (fbSAT's consecutive
//! modular synthesis; semantics in [`crate::ecc::modular`]): every module fires on every
//! active step, each rewriting the outputs of the one before, and module 1 alone decides the
//! passive steps. The encoding ([`crate::sat::modular::constraints::chain_values`]) passes the
//! output values down the chain; the decoded chain is made complete after module 1 and written
//! as one ECC ([`crate::ecc::modular::Modular::flatten`]).
//!
//! Files (`N` is `--name`, default `SynthesizedFB`):
//! - `N.fbt`: an IEC 61499 composite FB type with one instance `M<i>` of `N_M<i>` per module.
//!   IEC 61499 forbids event fan-in and fan-out, so `REQ` goes through a chain of `E_SPLIT` to
//!   each module in order and the modules' `CNF`s through a chain of `E_MERGE`; data inputs fan
//!   out to the modules that read them, each output comes from its owner. On a `REQ` where k
//!   modules fire the composite emits k `CNF`s; the outputs are complete once all have run.
//! - `N_M<i>.fbt`, `.json`, `.dot` (and `.svg` with Graphviz): each module as a basic FB.
//! - `N.smv`: the modules and `MODULE N(REQ, inputs...)` with `CNF` the disjunction of theirs
//!   and each output its owner's: the signature of a single ECC's SMV module, so, named `ECC`,
//!   it takes a controller's place in the closed loop
//!   ([`crate::smv::composition::compose_controller`]). A test runs it against the recordings
//!   inside NuSMV.
//! - `N.modules.json`: per module its type name, inputs, outputs, states, transitions, guard
//!   literals, and the three minimized figures.
//!
//! # Pick-and-Place
//! On the project's scenarios (`specs/pnp.traces`: 10 scenarios, 566 steps, 10 inputs, 7
//! outputs), K = 3, M = 1..4 give largest modules of 9, 5, 4 and 3 states, A = 8, 14, 15, 20
//! and N' = 9, 10, 11, 12 (`synth bench-modular --traces specs/pnp.traces`; sizes and
//! decompositions are deterministic, times are in `BENCHMARKS.md`). M = 2 puts `c1Extend`,
//! `c1Retract`, `c2Retract` and `vcExtend` in one module (5 states, 7 inputs) and `c2Extend`
//! with `vacuum_on`/`vacuum_off` in the other (5 states, 7 inputs); from M = 3 on the vacuum is
//! a module of its own reading `vcEnd` (and `vac` at M = 4). The largest module falls from 9
//! states to 5, 4 and 3, at the price of more inputs read in total and a few more states.
//!
//! In closed loop, the M = 2 composite with `smv/pnp_surrogate.smv` and `specs/pnp.ltl` is
//! accepted by NuSMV and 6 of the 8 properties hold: modular synthesis learns from the
//! scenarios only. [`run_verified`] closes the loop: `synth infer --modules 2 --traces
//! specs/pnp.traces --ltl specs/pnp.ltl --plant smv/pnp_surrogate.smv` checks composites (the
//! first failing 2 properties) until NuSMV verifies one (largest module 6 states, A = 16,
//! N' = 12). NuSMV prints a counterexample for every violated property in each round, which
//! takes fewer rounds than one counterexample per round.
//!
//! # Limits
//! Guards inside the encoding make the search harder than the tree-exact monolithic model, the
//! more so with more inputs and more irregular recordings (`synth infer --time-limit` bounds a
//! run). On the structured Pick-and-Place recordings every M takes about a second; on a
//! synthetic instance of two *random* machines over 11 inputs (3 + 6 states, inputs flipping
//! at random, 8 recordings of 25 steps) M = 2 takes tens of seconds, most of it proving A and
//! N' minimal, and longer recordings take minutes. The paper's coverage constraint (every
//! transition fired by a recording) is not used: it does not make such instances faster.

use super::{Error, Event, Events};
use crate::sat::modular::synthesize_modular;
use crate::scenario::tree::ScenarioTree;
use crate::scenario::ScenarioSet;

pub(crate) use crate::ecc::modular::Topology;
pub(crate) use crate::sat::modular::{parse_pins, ModularSynthesis};
pub use crate::sat::modular::{ModularOptions as Options, DEFAULT_MAX_OUT_DEGREE};

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

/// A modular controller NuSMV verified in closed loop.
pub(crate) struct VerifiedModular {
    /// The verified composite: M modules and their figures.
    pub(crate) synthesis: ModularSynthesis,
    /// NuSMV's report and the closed-loop model it verified.
    pub(crate) certificate: super::exact::Certificate,
    /// Every round of following the single verified machine ([`super::follow`]).
    pub(crate) rounds: Vec<super::follow::Round>,
    /// The scenarios the composite reproduces: the recordings and those recorded from the
    /// verified machine along counterexamples.
    pub(crate) scenarios: ScenarioSet,
}

/// The modular controller for `set` that NuSMV verifies, given `oracle`, a single machine that
/// reproduces `set` and that NuSMV verified against the same `check`: modular synthesis
/// refined along counterexamples with the oracle's answers ([`super::follow`]). NuSMV stops
/// at `opts.deadline` too.
pub(crate) fn run_verified(
    set: &ScenarioSet,
    oracle: &crate::ecc::Ecc,
    check: &super::Check,
    opts: &Options,
    max_rounds: usize,
    events: Events<'_>,
) -> Result<VerifiedModular, Error> {
    use crate::smv::composition::CONTROLLER_MODULE;
    let mut last = None;
    let check = &check.until(opts.deadline);
    let followed = super::follow::run(set, oracle, check, max_rounds, events, &mut |s, events| {
        let synthesis = run(s, opts, events)?;
        let text =
            crate::export::modular::composite_smv_to_string(&synthesis.modular, CONTROLLER_MODULE)?;
        let size = synthesis.size.clone();
        let made = super::follow::Made {
            largest: size.max_states,
            states: size.total_states,
            sat_seconds: synthesis.stats.sat_seconds,
            smv: text,
        };
        last = Some(synthesis);
        Ok((last.as_ref().expect("just set").modular.clone(), made))
    })?;
    Ok(VerifiedModular {
        synthesis: last.expect("the loop made a composite"),
        certificate: followed.certificate,
        rounds: followed.rounds,
        scenarios: followed.scenarios,
    })
}
