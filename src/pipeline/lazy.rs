//! Lazy synthesis over long recordings: encode a part, replay the whole, add what diverges.
//!
//! In: a [`ScenarioSet`] too long to encode whole, and the synthesis to run on a part of it.
//! Out: the machine that synthesis finds for the part that finally suffices, replayed on every
//! recorded step, with the rounds and the steps encoded in its [`Stats`](crate::sat::Stats).
//!
//! The part is a prefix of every scenario. It starts short; after each synthesis every whole
//! scenario is replayed on the machine (linear, and far cheaper than encoding it), and each
//! scenario that departs from the machine gets a longer prefix, past the step where it departs.
//! The loop ends when the machine reproduces everything.
//!
//! The answer is the one the whole recordings give: every machine that reproduces the whole
//! reproduces each prefix, so the least `C` (then `T`, then `N`) for a part is at most the least
//! for the whole, and a machine of the part's least size that reproduces the whole is therefore
//! least for the whole too.
//!
//! Recordings that contradict themselves are refused before the first round: the scenario
//! tree of the whole (not its encoding, which is what costs) names both places. A single
//! scenario cannot contradict itself, so for one long run even that tree is not built. Found
//! by the rounds instead, a contradiction would first read as a glitch that costs states, and
//! the climb would take minutes.
//!
//! When the whole makes a scenario tree of fewer than [`LAZY_FROM_NODES`] nodes it is encoded at
//! once (one round), as such an encoding is cheap and the loop would only add rounds.

use super::{Error, Event, Events};
use crate::sat::Synthesis;
use crate::scenario::tree::ScenarioTree;
use crate::scenario::{Divergence, Scenario, ScenarioSet};

/// Recordings whose scenario tree has at least this many nodes are synthesized lazily.
pub(crate) const LAZY_FROM_NODES: usize = 4_096;

/// The steps of the first part, shared among the scenarios.
pub(crate) const FIRST_PART_STEPS: usize = 1_024;

/// The shortest first prefix of a scenario (unless the scenario is shorter).
const MIN_PREFIX: usize = 16;

/// The part of `set` made of the first `lens[k]` steps of scenario `k`. Origins are kept, so
/// a contradiction inside the part is reported at its place in the recordings.
pub(crate) fn prefixes(set: &ScenarioSet, lens: &[usize]) -> ScenarioSet {
    ScenarioSet {
        inputs: set.inputs.clone(),
        outputs: set.outputs.clone(),
        initial_outputs: set.initial_outputs.clone(),
        scenarios: set
            .scenarios
            .iter()
            .zip(lens)
            .map(|(s, &n)| Scenario {
                origin: s.origin.clone(),
                steps: s.steps[..n.min(s.steps.len())].to_vec(),
            })
            .collect(),
    }
}

/// The first part's prefix lengths: `first_part` steps shared evenly, at least
/// [`MIN_PREFIX`] each.
fn first_lengths(set: &ScenarioSet, first_part: usize) -> Vec<usize> {
    let share = (first_part / set.scenarios.len().max(1)).max(MIN_PREFIX);
    set.scenarios
        .iter()
        .map(|s| s.steps.len().min(share))
        .collect()
}

/// What a round runs on a part: the part, its scenario tree, and the caller's event sink.
pub(crate) type Round<'f, T> =
    dyn FnMut(&ScenarioSet, &ScenarioTree, Events<'_>) -> Result<T, Error> + 'f;

/// Runs `synthesize` on growing parts of `set` until its machine reproduces all of `set`
/// (see the module documentation), starting from [`FIRST_PART_STEPS`]; once on the whole when
/// its tree has fewer than [`LAZY_FROM_NODES`] nodes (scenarios sharing their beginnings, as
/// fbSAT's sets of hundreds of thousands of steps do, make a small tree). The machine returned
/// is replayed on every step of `set`.
pub(crate) fn synthesize(
    set: &ScenarioSet,
    synthesize: &mut Round<'_, Synthesis>,
    events: Events<'_>,
) -> Result<Synthesis, Error> {
    if let Some(tree) = whole_tree(set)? {
        let mut s = synthesize(set, &tree, events)?;
        s.stats.rounds = 1;
        s.stats.steps_encoded = set.step_count();
        return Ok(s);
    }
    // `whole_tree` has refused contradictory recordings.
    machine_in_parts(set, FIRST_PART_STEPS, synthesize, events)
}

/// The tree of the whole when it is small enough to encode at once (fewer than
/// [`LAZY_FROM_NODES`] nodes), `None` when the recordings are to be taken in parts. Fails on
/// contradictory recordings.
pub(super) fn whole_tree(set: &ScenarioSet) -> Result<Option<ScenarioTree>, Error> {
    // One scenario's tree has a node per active step: its length decides without building it
    // (and one scenario cannot contradict itself).
    if set.scenarios.len() == 1 && set.active_count() >= LAZY_FROM_NODES {
        return Ok(None);
    }
    let tree = ScenarioTree::build(set)?;
    Ok((tree.nodes.len() < LAZY_FROM_NODES).then_some(tree))
}

/// [`synthesize`] in parts whatever the length, the first part holding about `first_part`
/// steps.
pub(crate) fn in_parts(
    set: &ScenarioSet,
    first_part: usize,
    synthesize: &mut Round<'_, Synthesis>,
    events: Events<'_>,
) -> Result<Synthesis, Error> {
    if set.scenarios.len() > 1 {
        ScenarioTree::build(set)?;
    }
    machine_in_parts(set, first_part, synthesize, events)
}

/// The rounds of [`in_parts`], on recordings known to be free of contradictions.
fn machine_in_parts(
    set: &ScenarioSet,
    first_part: usize,
    synthesize: &mut Round<'_, Synthesis>,
    events: Events<'_>,
) -> Result<Synthesis, Error> {
    let (mut s, part) = until_reproduced(
        set,
        first_part,
        synthesize,
        &|s| set.divergences(&s.ecc),
        events,
    )?;
    s.stats.rounds = part.round;
    s.stats.steps_encoded = part.encoded;
    Ok(s)
}

/// The part a run in parts ended with.
pub(super) struct LastPart {
    /// Its round, 1-based.
    pub(crate) round: usize,
    /// Its recorded steps.
    pub(crate) encoded: usize,
}

/// The loop of every run in parts: `run` on the part, `departures` of what it found from the
/// whole recordings (its machines replayed on every step), and while there are any, each
/// scenario a machine departs from gets a longer prefix. Returns the last result and its part.
pub(super) fn until_reproduced<T>(
    set: &ScenarioSet,
    first_part: usize,
    run: &mut Round<'_, T>,
    departures: &dyn Fn(&T) -> Vec<Divergence>,
    events: Events<'_>,
) -> Result<(T, LastPart), Error> {
    let total = set.step_count();
    let mut lens = first_lengths(set, first_part);
    for round in 1.. {
        let part = prefixes(set, &lens);
        let encoded = part.step_count();
        let found = run(&part, &ScenarioTree::build(&part)?, events)?;
        let divergences = departures(&found);
        events(Event::Lazy {
            round,
            encoded,
            total,
            diverging: divergences.len(),
        });
        if divergences.is_empty() {
            return Ok((found, LastPart { round, encoded }));
        }
        for d in divergences {
            grow(set, &mut lens, &d)?;
        }
    }
    unreachable!("the rounds above only end by returning")
}

/// Lengthens the prefix of the scenario `d` departs at, past the departure. A departure
/// inside the prefix is a bug: the machine was made to reproduce the prefix.
fn grow(set: &ScenarioSet, lens: &mut [usize], d: &Divergence) -> Result<(), Error> {
    let len = &mut lens[d.scenario];
    if d.step < *len {
        return Err(Error::Bug(format!(
            "a machine made for the first {} steps of scenario {} departs from it at step {}",
            len,
            d.scenario + 1,
            d.step + 1
        )));
    }
    // Past the departure, and about twice as far as before when it is near the end of the
    // prefix, so the number of rounds grows with the logarithm of the length.
    *len = set.scenarios[d.scenario].steps.len().min(d.step + 1 + *len);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cases::distribution;
    use crate::scenario::ScenarioError;

    fn whole(set: &ScenarioSet, tree: &ScenarioTree, _: Events<'_>) -> Result<Synthesis, Error> {
        let opts = crate::sat::Options::default();
        Ok(crate::sat::Synthesizer::new(set, tree, &opts).minimize(&mut |_| {})?)
    }

    #[test]
    fn parts_give_the_least_size_of_the_whole_recording() {
        let set = distribution::long_run(2_000, 7);
        let all = whole(&set, &ScenarioTree::build(&set).unwrap(), &mut |_| {}).unwrap();
        let mut rounds = Vec::new();
        let lazy = in_parts(&set, 64, &mut whole, &mut |e| {
            if let Event::Lazy { encoded, .. } = e {
                rounds.push(encoded)
            }
        })
        .unwrap();
        assert!(rounds.len() > 1, "a 64-step first part should not suffice");
        assert!(rounds.windows(2).all(|w| w[0] < w[1]), "{rounds:?}");
        assert_eq!(lazy.stats.rounds, rounds.len());
        assert!(lazy.stats.steps_encoded < set.step_count());
        assert_eq!(set.check(&lazy.ecc), Ok(()));
        assert_eq!((lazy.size.c, lazy.size.t), (all.size.c, all.size.t));
        if lazy.guards_exact && all.guards_exact {
            assert_eq!(lazy.size.n, all.size.n);
        }
    }

    #[test]
    fn a_contradiction_far_into_the_recordings_is_found_and_placed() {
        let mut set = distribution::long_run(1_500, 3);
        let mut copy = set.scenarios[0].clone();
        copy.origin.line = 99;
        // The last active step answers otherwise after the same history.
        let k = copy
            .steps
            .iter()
            .rposition(|s| s.outputs.is_some())
            .unwrap();
        let out = copy.steps[k].outputs.as_mut().unwrap();
        out[0] = !out[0];
        set.scenarios.push(copy);
        let mut rounds = 0;
        let e = in_parts(&set, 64, &mut whole, &mut |_| rounds += 1).unwrap_err();
        assert_eq!(rounds, 0, "found before any round");
        match e {
            Error::Scenario(ScenarioError::Contradiction(c)) => {
                assert_eq!(c.first_step, k + 1);
                assert_eq!(c.second.line, 99);
            }
            e => panic!("expected the contradiction, got {e}"),
        }
    }
}
