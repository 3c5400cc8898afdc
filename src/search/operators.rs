//! Mutation operators: the four of the metaheuristic paper (section IV.D) and the verification-aware one of
//! the verification-in-the-loop paper (section III.C).
//!
//! In: a [`Machine`], a random generator, and for the weighted operator the input vectors of
//! the parent's counterexamples. Out: the machine changed in place; every operator returns
//! `false` (and leaves the machine as it was) when it has nothing to act on.
//!
//! Every operator keeps the invariants of [`Machine::validate`]; none changes the number of
//! states (the metaheuristic paper searches a fixed number of states).

use super::data::{ScenarioData, PASSIVE};
use super::fitness::Divergence;
use super::machine::{Group, Machine, TransitionRef};
use crate::ecc::{InputId, StateId};
use rand::Rng;

/// The operators, for choosing one and for statistics.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Operator {
    /// A uniformly chosen transition gets another target.
    ChangeTarget,
    /// Per state with a fixed probability: add an absent entry or delete a present one.
    AddDelete,
    /// One significant input of a group becomes insignificant, an insignificant one
    /// significant.
    SwapSignificance,
    /// A group gains a significant input (table doubled) or loses one (table halved).
    ResizeSignificance,
    /// The verification-in-the-loop paper: a transition chosen by counterexample-weighted roulette gets another target.
    WeightedChangeTarget,
    /// Beyond the papers: a step of a counterexample on which the machine stays silent gets an
    /// entry ([`react_on_counterexample`]).
    ReactOnCounterexample,
}

/// A state other than `old`, uniformly (`None` with a single state).
fn other_state(rng: &mut impl Rng, states: usize, old: StateId) -> Option<StateId> {
    if states < 2 {
        return None;
    }
    let t = rng.gen_range(0..states - 1);
    Some(StateId(if t >= old.0 { t + 1 } else { t }))
}

/// The metaheuristic paper, "change transition end state".
pub(crate) fn change_target(rng: &mut impl Rng, m: &mut Machine) -> bool {
    let all = m.transitions();
    if all.is_empty() {
        return false;
    }
    let t = all[rng.gen_range(0..all.len())];
    retarget(rng, m, t)
}

fn retarget(rng: &mut impl Rng, m: &mut Machine, t: TransitionRef) -> bool {
    let old = m.target(t).expect("a present entry");
    match other_state(rng, m.states.len(), old) {
        Some(new) => {
            m.set_target(t, Some(new));
            true
        }
        None => false,
    }
}

/// The metaheuristic paper, "add or delete transitions": each state is touched with probability `p` (at
/// least one state always is). In a uniformly chosen group of the state, either an absent
/// entry gets a uniformly chosen target, or a present entry is deleted; the choice is a fair
/// coin unless only one of them is possible.
pub fn add_or_delete(rng: &mut impl Rng, m: &mut Machine, p: f64) -> bool {
    let n = m.states.len();
    let forced = rng.gen_range(0..n);
    let mut changed = false;
    for s in 0..n {
        if s != forced && !rng.gen_bool(p) {
            continue;
        }
        let groups = m.states[s].groups.len();
        if groups == 0 {
            // A state without groups gets its first one, with no significant input.
            let mut g = Group::empty(vec![]);
            g.table[0] = Some(StateId(rng.gen_range(0..n)));
            m.states[s].groups.push(g);
            changed = true;
            continue;
        }
        let g = &mut m.states[s].groups[rng.gen_range(0..groups)];
        let present: Vec<usize> = (0..g.table.len())
            .filter(|&e| g.table[e].is_some())
            .collect();
        let absent: Vec<usize> = (0..g.table.len())
            .filter(|&e| g.table[e].is_none())
            .collect();
        let add = match (present.is_empty(), absent.is_empty()) {
            (true, true) => continue,
            (false, true) => false,
            (true, false) => true,
            (false, false) => rng.gen_bool(0.5),
        };
        if add {
            let e = absent[rng.gen_range(0..absent.len())];
            g.table[e] = Some(StateId(rng.gen_range(0..n)));
        } else {
            let e = present[rng.gen_range(0..present.len())];
            g.table[e] = None;
        }
        changed = true;
    }
    changed
}

/// All groups as `(state, group)`.
fn groups(m: &Machine) -> impl Iterator<Item = (usize, usize)> + '_ {
    m.states
        .iter()
        .enumerate()
        .flat_map(|(s, st)| (0..st.groups.len()).map(move |g| (s, g)))
}

/// Rebuilds a group's table for new significant inputs: `value(old_vars, old_entry)` says
/// which assignment of the new variables each old entry stands for.
fn reindex(
    g: &Group,
    new_vars: &[InputId],
    map: impl Fn(InputId, usize) -> Option<bool>,
) -> Vec<Option<StateId>> {
    let mut table = vec![None; 1 << new_vars.len()];
    for (e, &t) in g.table.iter().enumerate() {
        let idx = new_vars.iter().fold(0usize, |acc, &v| {
            (acc << 1) | usize::from(map(v, e).unwrap_or(false))
        });
        table[idx] = t;
    }
    table
}

/// The metaheuristic paper, "change significance mask": in a uniformly chosen group with at least one
/// transition, a significant input `i` and an insignificant `j` swap roles; every entry keeps
/// its target, now under `x_j` where it was under `x_i`.
pub(crate) fn swap_significance(rng: &mut impl Rng, m: &mut Machine) -> bool {
    let inputs = m.inputs;
    let candidates: Vec<(usize, usize)> = groups(m)
        .filter(|&(s, g)| {
            let grp = &m.states[s].groups[g];
            grp.present() > 0 && !grp.vars.is_empty() && grp.vars.len() < inputs
        })
        .collect();
    if candidates.is_empty() {
        return false;
    }
    let (s, gi) = candidates[rng.gen_range(0..candidates.len())];
    let g = &m.states[s].groups[gi];
    let i = g.vars[rng.gen_range(0..g.vars.len())];
    let free: Vec<InputId> = (0..inputs)
        .map(InputId)
        .filter(|&v| !g.has_var(v))
        .collect();
    let j = free[rng.gen_range(0..free.len())];
    let mut vars: Vec<InputId> = g.vars.iter().map(|&v| if v == i { j } else { v }).collect();
    vars.sort();
    let old = g.clone();
    let table = reindex(&old, &vars, |v, e| {
        let from = if v == j { i } else { v };
        old.literals(e).iter().find(|l| l.0 == from).map(|l| l.1)
    });
    let g = &mut m.states[s].groups[gi];
    g.vars = vars;
    g.table = table;
    true
}

/// The metaheuristic paper, "change significant variables set": a uniformly chosen group gains an input
/// (each old entry is copied for `x_i = 0` and `x_i = 1`; at most `max_vars` significant) or
/// loses one (of each pair of entries that merge, the `x_i = 0` one is kept when the number of
/// transitions kept so far is even, else the `x_i = 1` one).
pub fn resize_significance(rng: &mut impl Rng, m: &mut Machine, max_vars: usize) -> bool {
    let inputs = m.inputs;
    let all: Vec<(usize, usize)> = groups(m).collect();
    if all.is_empty() {
        return false;
    }
    let (s, gi) = all[rng.gen_range(0..all.len())];
    let g = m.states[s].groups[gi].clone();
    let can_add = g.vars.len() < max_vars.min(inputs);
    let can_delete = !g.vars.is_empty();
    let add = match (can_add, can_delete) {
        (false, false) => return false,
        (true, false) => true,
        (false, true) => false,
        (true, true) => rng.gen_bool(0.5),
    };
    let new = if add {
        let free: Vec<InputId> = (0..inputs)
            .map(InputId)
            .filter(|&v| !g.has_var(v))
            .collect();
        let j = free[rng.gen_range(0..free.len())];
        let mut vars = g.vars.clone();
        vars.push(j);
        vars.sort();
        let mut ng = Group::empty(vars);
        for e in 0..ng.table.len() {
            let lits = ng.literals(e);
            let old_idx = g.vars.iter().fold(0usize, |acc, v| {
                let val = lits
                    .iter()
                    .find(|l| l.0 == *v)
                    .map(|l| l.1)
                    .unwrap_or(false);
                (acc << 1) | usize::from(val)
            });
            ng.table[e] = g.table[old_idx];
        }
        ng
    } else {
        let pos = rng.gen_range(0..g.vars.len());
        let i = g.vars[pos];
        let mut ng = Group::empty(g.vars.iter().copied().filter(|&v| v != i).collect());
        let k = g.vars.len();
        let bit = 1 << (k - 1 - pos);
        let mut kept = 0usize;
        for e in 0..ng.table.len() {
            // Insert a 0 bit at `pos` into the new entry index to get the old `x_i = 0` entry.
            let high = (e >> (k - 1 - pos)) << (k - pos);
            let low = e & (bit - 1);
            let zero = high | low;
            let chosen = if kept.is_multiple_of(2) {
                g.table[zero]
            } else {
                g.table[zero | bit]
            };
            if chosen.is_some() {
                kept += 1;
            }
            ng.table[e] = chosen;
        }
        ng
    };
    m.states[s].groups[gi] = new;
    true
}

/// The entries a run of `m` from the initial state fires on the input vectors `xs`, in order
/// (one per step that fires).
pub(crate) fn visited(m: &Machine, xs: &[u32]) -> Vec<TransitionRef> {
    let mut s = 0usize;
    let mut out = Vec::new();
    for &x in xs {
        if let Some((group, entry, t)) = m.fire(s, x) {
            out.push(TransitionRef {
                state: StateId(s),
                group,
                entry,
            });
            s = t.0;
        }
    }
    out
}

/// The verification-in-the-loop paper's transition weights: 1 for every present entry, plus `lambda` per visit by a
/// replayed counterexample. In [`Machine::transitions`] order.
pub(crate) fn weights(
    m: &Machine,
    counterexamples: &[Vec<u32>],
    lambda: f64,
) -> (Vec<TransitionRef>, Vec<f64>) {
    let all = m.transitions();
    let mut w = vec![1.0; all.len()];
    for cx in counterexamples {
        for t in visited(m, cx) {
            let k = all.binary_search(&t).expect("fired entries are present");
            w[k] += lambda;
        }
    }
    (all, w)
}

/// Roulette wheel: index `k` with probability `w[k] / sum(w)`.
pub(crate) fn roulette(rng: &mut impl Rng, w: &[f64]) -> usize {
    let total: f64 = w.iter().sum();
    let mut r = rng.gen_range(0.0..total);
    for (k, &x) in w.iter().enumerate() {
        if r < x {
            return k;
        }
        r -= x;
    }
    w.len() - 1
}

/// The verification-in-the-loop paper's verification-aware mutation: a transition picked by [`roulette`] over
/// [`weights`] gets another target.
pub(crate) fn weighted_change_target(
    rng: &mut impl Rng,
    m: &mut Machine,
    counterexamples: &[Vec<u32>],
    lambda: f64,
) -> bool {
    let (all, w) = weights(m, counterexamples, lambda);
    if all.is_empty() {
        return false;
    }
    let t = all[roulette(rng, &w)];
    retarget(rng, m, t)
}

/// What the repair of one divergence knows of the parent: the scenarios and its labels.
pub(crate) struct Site<'a> {
    /// The scenarios.
    pub(crate) data: &'a ScenarioData,
    /// The parent's labeled algorithms as `(set to 0, set to 1)` masks per state.
    pub(crate) masks: &'a [(u32, u32)],
    /// Where a failing scenario first goes wrong.
    pub(crate) at: Divergence,
}

/// Beyond the papers, counterexample replay on the scenarios: a change at the first step where
/// a failing scenario goes wrong, of the kind that step needs. The machine fired on a passive
/// step: the entry that fired is deleted, or its group gains a significant input that tells
/// the step apart from the steps the entry serves, and the step's half is deleted. It did not
/// fire on a `CNF` step: an entry for the step's inputs is added, in an existing group or a
/// new last one. It fired with the wrong outputs: the entry gets another target, or its group
/// gains an input and the step's half gets another target. A new target is, with probability
/// one half, a state whose labeled algorithm gives the recorded outputs, else any state
/// (labels follow the structure, so any state may become right).
///
/// The step where a scenario goes wrong is often not where the machine went wrong: an earlier
/// `CNF` step may have entered a state with the right outputs but the wrong future (a second
/// "idle" state, say). So with probability `back`, one of the entries fired at the `CNF` steps
/// before the divergence is sent to another state whose algorithm also gives that step's
/// outputs.
pub(crate) fn repair(
    rng: &mut impl Rng,
    m: &mut Machine,
    site: &Site,
    max_vars: usize,
    back: f64,
) -> bool {
    if rng.gen_bool(back) && redirect_earlier(rng, m, site) {
        return true;
    }
    let step = site.data.steps[site.at.step];
    let s = site.at.state;
    match (step.expected == PASSIVE, m.fire(s, step.x)) {
        (true, Some((g, e, _))) => {
            if rng.gen_bool(0.5) {
                if let Some(e) = split(rng, m, site, (s, g, e), max_vars) {
                    m.states[s].groups[g].table[e] = None;
                    return true;
                }
            }
            m.states[s].groups[g].table[e] = None;
            true
        }
        (true, None) => false,
        (false, None) => {
            let t = fitting_target(rng, m, site);
            add_entry(rng, m, (s, step.x), t, max_vars);
            true
        }
        (false, Some((g, e, old))) => {
            let e = if rng.gen_bool(0.25) {
                split(rng, m, site, (s, g, e), max_vars).unwrap_or(e)
            } else {
                e
            };
            let mut t = fitting_target(rng, m, site);
            if t == old {
                match other_state(rng, m.states.len(), old) {
                    Some(o) => t = o,
                    None => return false,
                }
            }
            m.states[s].groups[g].table[e] = Some(t);
            true
        }
    }
}

/// An entry for input vector `x` in state `s` to `t`: in a random existing group of `s`, or (one
/// time in four, and always when `s` has none) in a new last group over at most two random
/// inputs. `s` must fire nothing on `x`, so the entry is the one that fires.
fn add_entry(
    rng: &mut impl Rng,
    m: &mut Machine,
    (s, x): (usize, u32),
    t: StateId,
    max_vars: usize,
) {
    let groups = m.states[s].groups.len();
    if groups == 0 || rng.gen_bool(0.25) {
        let k = rng.gen_range(0..=max_vars.min(m.inputs).min(2));
        let vars = random_vars(rng, m.inputs, k);
        let mut g = Group::empty(vars);
        let e = g.index(x);
        g.table[e] = Some(t);
        m.states[s].groups.push(g);
    } else {
        let g = &mut m.states[s].groups[rng.gen_range(0..groups)];
        let e = g.index(x);
        g.table[e] = Some(t);
    }
}

/// Beyond the papers, for properties that ask the machine to act: along a counterexample
/// picked at random, a step on which the machine fires nothing gets an entry to another
/// state ([`add_entry`]). A liveness counterexample is often a run in which the controller
/// waits while the plant offers what it should answer; the counterexample-weighted mutation
/// only retargets entries that fire, so it cannot make such a step fire, and adding one
/// entry at random seldom hits the state and inputs the run needs. `false` when the machine
/// fires on every step of the counterexample (or there is none).
pub(crate) fn react_on_counterexample(
    rng: &mut impl Rng,
    m: &mut Machine,
    counterexamples: &[Vec<u32>],
    max_vars: usize,
) -> bool {
    if counterexamples.is_empty() || m.states.len() < 2 {
        return false;
    }
    let cx = &counterexamples[rng.gen_range(0..counterexamples.len())];
    let mut s = 0usize;
    let mut silent = Vec::new();
    for &x in cx {
        match m.fire(s, x) {
            Some((_, _, t)) => s = t.0,
            None => silent.push((s, x)),
        }
    }
    if silent.is_empty() {
        return false;
    }
    let (s, x) = silent[rng.gen_range(0..silent.len())];
    let Some(t) = other_state(rng, m.states.len(), StateId(s)) else {
        return false;
    };
    add_entry(rng, m, (s, x), t, max_vars);
    true
}

/// Sends the entry fired at a uniformly chosen `CNF` step before the divergence to another
/// state whose labeled algorithm gives that step's recorded outputs; `false` when there is
/// no such step or state.
fn redirect_earlier(rng: &mut impl Rng, m: &mut Machine, site: &Site) -> bool {
    let data = site.data;
    let range = data.bounds[site.at.scenario].clone();
    let mut fired = Vec::new();
    let mut s = 0usize;
    for j in range.start..site.at.step {
        let st = data.steps[j];
        if let Some((g, e, t)) = m.fire(s, st.x) {
            if st.expected != PASSIVE {
                fired.push((j, s, g, e, t));
            }
            s = t.0;
        }
    }
    if fired.is_empty() {
        return false;
    }
    let (j, s, g, e, old) = fired[rng.gen_range(0..fired.len())];
    let st = data.steps[j];
    let fits: Vec<usize> = (0..m.states.len().min(site.masks.len()))
        .filter(|&y| {
            let (zero, one) = site.masks[y];
            y != old.0 && (st.before & !zero) | one == st.expected
        })
        .collect();
    if fits.is_empty() {
        return false;
    }
    m.states[s].groups[g].table[e] = Some(StateId(fits[rng.gen_range(0..fits.len())]));
    true
}

/// `m` without the entries no scenario step fires, and without groups left empty: the
/// scenarios behave the same, and input vectors they never record no longer lead anywhere the
/// search put them by chance.
pub(crate) fn prune_unused(m: &Machine, data: &ScenarioData) -> Machine {
    let mut used: Vec<Vec<Vec<bool>>> = (m.states.iter())
        .map(|st| {
            st.groups
                .iter()
                .map(|g| vec![false; g.table.len()])
                .collect()
        })
        .collect();
    for range in &data.bounds {
        let mut s = 0usize;
        for st in &data.steps[range.clone()] {
            if let Some((g, e, t)) = m.fire(s, st.x) {
                used[s][g][e] = true;
                s = t.0;
            }
        }
    }
    let mut out = m.clone();
    for (st, used) in out.states.iter_mut().zip(&used) {
        for (g, used) in st.groups.iter_mut().zip(used) {
            for (t, &u) in g.table.iter_mut().zip(used) {
                if !u {
                    *t = None;
                }
            }
        }
        st.groups.retain(|g| g.present() > 0);
    }
    out
}

/// `k` distinct random inputs of `inputs`.
fn random_vars(rng: &mut impl Rng, inputs: usize, k: usize) -> Vec<InputId> {
    let mut all: Vec<usize> = (0..inputs).collect();
    (0..k.min(inputs))
        .map(|_| InputId(all.swap_remove(rng.gen_range(0..all.len()))))
        .collect()
}

/// A state whose labeled algorithm turns the outputs before the divergence into the recorded
/// ones (with probability one half, when there is one), else a uniformly chosen state.
fn fitting_target(rng: &mut impl Rng, m: &Machine, site: &Site) -> StateId {
    let step = site.data.steps[site.at.step];
    let n = m.states.len();
    if rng.gen_bool(0.5) {
        let fits: Vec<usize> = (0..n.min(site.masks.len()))
            .filter(|&y| {
                let (zero, one) = site.masks[y];
                (step.before & !zero) | one == step.expected
            })
            .collect();
        if !fits.is_empty() {
            return StateId(fits[rng.gen_range(0..fits.len())]);
        }
    }
    StateId(rng.gen_range(0..n))
}

/// Makes the group of entry `(state, group, entry)` significant in one more input, chosen to
/// tell the divergence's inputs apart from the inputs of the `CNF` steps the entry serves
/// (when such an input exists), every old entry copied to both halves. Returns the entry the
/// divergence's inputs now select, or `None` when the group cannot grow.
fn split(
    rng: &mut impl Rng,
    m: &mut Machine,
    site: &Site,
    (s, g, e): (usize, usize, usize),
    max_vars: usize,
) -> Option<usize> {
    let x = site.data.steps[site.at.step].x;
    let grp = &m.states[s].groups[g];
    if grp.vars.len() >= max_vars.min(m.inputs) {
        return None;
    }
    let served = entry_inputs(m, site.data, (s, g, e));
    let free: Vec<InputId> = (0..m.inputs)
        .map(InputId)
        .filter(|&v| !grp.has_var(v))
        .collect();
    let bit = |y: u32, v: InputId| (y >> v.0) & 1;
    let apart: Vec<InputId> = free
        .iter()
        .copied()
        .filter(|&v| !served.is_empty() && served.iter().all(|&y| bit(y, v) != bit(x, v)))
        .collect();
    let pool = if apart.is_empty() { &free } else { &apart };
    let v = pool[rng.gen_range(0..pool.len())];
    let mut vars = grp.vars.clone();
    vars.push(v);
    vars.sort();
    let mut ng = Group::empty(vars);
    for (ne, slot) in ng.table.iter_mut().enumerate() {
        let old = grp.vars.iter().fold(0usize, |acc, w| {
            let pos = ng_pos(&grp.vars, *w, v);
            (acc << 1) | ((ne >> pos) & 1)
        });
        *slot = grp.table[old];
    }
    let idx = ng.index(x);
    m.states[s].groups[g] = ng;
    Some(idx)
}

/// The bit position (from the low end) of input `w` in the entry index of a group over `old`
/// plus `added`.
fn ng_pos(old: &[InputId], w: InputId, added: InputId) -> usize {
    let k = old.len() + 1;
    let rank = old.iter().filter(|&&u| u < w).count() + usize::from(added < w);
    k - 1 - rank
}

/// The input vectors of the `CNF` steps of the scenarios on which the entry fires.
fn entry_inputs(m: &Machine, data: &ScenarioData, (s0, g0, e0): (usize, usize, usize)) -> Vec<u32> {
    let mut out = Vec::new();
    for range in &data.bounds {
        let mut s = 0usize;
        for st in &data.steps[range.clone()] {
            if let Some((g, e, t)) = m.fire(s, st.x) {
                if (s, g, e) == (s0, g0, e0) && st.expected != PASSIVE {
                    out.push(st.x);
                }
                s = t.0;
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::machine::SearchState;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    fn rng() -> ChaCha8Rng {
        ChaCha8Rng::seed_from_u64(11)
    }

    /// The targets of every (state, input vector), for comparing behaviour.
    fn behaviour(m: &Machine) -> Vec<Option<StateId>> {
        (0..m.states.len())
            .flat_map(|s| (0..1u32 << m.inputs).map(move |x| (s, x)))
            .map(|(s, x)| m.fire(s, x).map(|f| f.2))
            .collect()
    }

    fn machines() -> Vec<Machine> {
        let mut r = ChaCha8Rng::seed_from_u64(3);
        (0..30).map(|_| Machine::random(&mut r, 5, 4, 3)).collect()
    }

    /// The pairs of groups that differ between `a` and `b` (same states, same group counts).
    fn changed_groups<'m>(a: &'m Machine, b: &'m Machine) -> Vec<(&'m Group, &'m Group)> {
        a.states
            .iter()
            .zip(&b.states)
            .flat_map(|(a, b)| a.groups.iter().zip(&b.groups))
            .filter(|(a, b)| a != b)
            .collect()
    }

    /// Table entries over all groups.
    fn table_size(m: &Machine) -> usize {
        m.states
            .iter()
            .flat_map(|s| &s.groups)
            .map(|g| g.table.len())
            .sum()
    }

    /// The (state, input) pairs on which `m` fires nothing along `xs` from the initial state.
    fn silent_steps(m: &Machine, xs: &[u32]) -> Vec<(usize, u32)> {
        let mut s = 0;
        let mut silent = Vec::new();
        for &x in xs {
            match m.fire(s, x) {
                Some((_, _, t)) => s = t.0,
                None => silent.push((s, x)),
            }
        }
        silent
    }

    #[test]
    fn reacting_on_a_counterexample_makes_a_silent_step_fire_and_changes_only_silent_steps() {
        let mut r = rng();
        let mut reacted = 0;
        for m in machines() {
            let cx: Vec<u32> = (0..12).map(|_| r.gen_range(0..1u32 << m.inputs)).collect();
            let silent = silent_steps(&m, &cx);
            let mut c = m.clone();
            if !react_on_counterexample(&mut r, &mut c, std::slice::from_ref(&cx), 3) {
                assert!(silent.is_empty());
                assert_eq!(behaviour(&m), behaviour(&c));
                continue;
            }
            reacted += 1;
            c.validate().unwrap();
            // Only steps that were silent changed, all of one state and now into one other
            // state, and a silent step of the run is among them.
            let per_state = 1usize << m.inputs;
            let changed: Vec<(usize, u32)> = (behaviour(&m).iter().zip(&behaviour(&c)))
                .enumerate()
                .filter(|(_, (a, b))| a != b)
                .map(|(k, _)| (k / per_state, (k % per_state) as u32))
                .collect();
            assert!(
                changed.iter().any(|p| silent.contains(p)),
                "{changed:?} {silent:?}"
            );
            let s = changed[0].0;
            let t = c.fire(s, changed[0].1).expect("fires now").2;
            assert_ne!(t.0, s);
            for &(s1, x) in &changed {
                assert_eq!(s1, s);
                assert!(m.fire(s, x).is_none());
                assert_eq!(c.fire(s, x).map(|f| f.2), Some(t));
            }
        }
        assert!(reacted > 0);
        // No counterexample: nothing to react on.
        let mut m = machines().remove(0);
        assert!(!react_on_counterexample(&mut r, &mut m, &[], 3));
    }

    #[test]
    fn change_target_moves_exactly_one_transition_to_another_state() {
        let mut r = rng();
        for m in machines() {
            let mut c = m.clone();
            if !change_target(&mut r, &mut c) {
                assert_eq!(m.transition_count(), 0);
                continue;
            }
            c.validate().unwrap();
            let diff: Vec<_> = m
                .transitions()
                .into_iter()
                .filter(|&t| m.target(t) != c.target(t))
                .collect();
            assert_eq!(diff.len(), 1);
            assert!(c.target(diff[0]).is_some());
            assert_eq!(m.transitions(), c.transitions());
        }
    }

    #[test]
    fn add_or_delete_changes_the_set_of_present_entries_only() {
        let mut r = rng();
        for m in machines() {
            let mut c = m.clone();
            assert!(add_or_delete(&mut r, &mut c, 0.3));
            c.validate().unwrap();
            assert_ne!(m, c);
            // Same significance everywhere; entries present in both keep their targets.
            for (a, b) in m.states.iter().zip(&c.states) {
                for (ga, gb) in a.groups.iter().zip(&b.groups) {
                    assert_eq!(ga.vars, gb.vars);
                    for (ta, tb) in ga.table.iter().zip(&gb.table) {
                        if let (Some(x), Some(y)) = (ta, tb) {
                            assert_eq!(x, y);
                        }
                    }
                }
            }
            assert_ne!(m.transitions(), c.transitions());
        }
    }

    #[test]
    fn swap_significance_exchanges_one_input_and_keeps_the_table() {
        let mut r = rng();
        let mut tried = 0;
        for m in machines() {
            let mut c = m.clone();
            if !swap_significance(&mut r, &mut c) {
                continue;
            }
            tried += 1;
            c.validate().unwrap();
            let changed = changed_groups(&m, &c);
            assert_eq!(changed.len(), 1);
            let (a, b) = changed[0];
            assert_eq!(a.vars.len(), b.vars.len());
            let gone: Vec<_> = a.vars.iter().filter(|v| !b.has_var(**v)).collect();
            let new: Vec<_> = b.vars.iter().filter(|v| !a.has_var(**v)).collect();
            assert_eq!((gone.len(), new.len()), (1, 1));
            let mut ta: Vec<_> = a.table.clone();
            let mut tb: Vec<_> = b.table.clone();
            ta.sort();
            tb.sort();
            assert_eq!(ta, tb, "the same targets, re-indexed");
        }
        assert!(tried > 10);
    }

    #[test]
    fn adding_a_significant_input_keeps_behaviour_and_doubles_the_table() {
        let mut r = rng();
        for m in machines() {
            let mut c = m.clone();
            let before = table_size(&m);
            // Force "add" with room for it: max 5 significant inputs.
            let mut added = false;
            for _ in 0..20 {
                let mut t = m.clone();
                assert!(resize_significance(&mut r, &mut t, 5));
                t.validate().unwrap();
                let after = table_size(&t);
                if after > before {
                    c = t;
                    added = true;
                    break;
                }
            }
            assert!(added);
            let grown = changed_groups(&m, &c);
            assert_eq!(grown.len(), 1);
            assert_eq!(grown[0].1.table.len(), 2 * grown[0].0.table.len());
            assert_eq!(behaviour(&m), behaviour(&c));
        }
    }

    #[test]
    fn deleting_a_significant_input_halves_the_table_and_keeps_the_seed_choice() {
        // One group over x0, x1 with entries 00 -> s0, 01 -> s1, 10 -> s2, 11 -> None.
        let mut g = Group::empty(vec![InputId(0), InputId(1)]);
        g.table = vec![Some(StateId(0)), Some(StateId(1)), Some(StateId(2)), None];
        let m = Machine {
            inputs: 2,
            states: vec![
                SearchState { groups: vec![g] },
                SearchState::default(),
                SearchState::default(),
            ],
        };
        let mut seen = std::collections::HashSet::new();
        let mut r = rng();
        for _ in 0..50 {
            let mut c = m.clone();
            assert!(resize_significance(&mut r, &mut c, 1));
            c.validate().unwrap();
            let g = &c.states[0].groups[0];
            assert_eq!(g.vars.len(), 1);
            assert_eq!(g.table.len(), 2);
            seen.insert((g.vars[0], g.table.clone()));
        }
        // Drop x0: pairs (00,10) and (01,11); first keeps x0=0 -> s0 (1 kept, odd), second
        // keeps x0=1 -> None. Drop x1: pairs (00,01), (10,11): s0, then x1=1 -> None.
        let expected: std::collections::HashSet<_> = [
            (InputId(1), vec![Some(StateId(0)), None]),
            (InputId(0), vec![Some(StateId(0)), None]),
        ]
        .into_iter()
        .collect();
        assert_eq!(seen, expected);
    }

    #[test]
    fn roulette_follows_the_weights() {
        let mut r = rng();
        let w = [1.0, 3.0, 0.5, 5.5];
        let mut hits = [0usize; 4];
        let n = 100_000;
        for _ in 0..n {
            hits[roulette(&mut r, &w)] += 1;
        }
        for k in 0..4 {
            let share = hits[k] as f64 / n as f64;
            assert!((share - w[k] / 10.0).abs() < 0.01, "{k}: {share}");
        }
    }

    #[test]
    fn counterexamples_weigh_the_transitions_they_visit() {
        // s0 --x0--> s1 --!x0--> s0; a counterexample x0, !x0, x0 visits both, the first twice.
        let mut g0 = Group::empty(vec![InputId(0)]);
        g0.table[1] = Some(StateId(1));
        let mut g1 = Group::empty(vec![InputId(0)]);
        g1.table[0] = Some(StateId(0));
        g1.table[1] = Some(StateId(1));
        let m = Machine {
            inputs: 1,
            states: vec![
                SearchState { groups: vec![g0] },
                SearchState { groups: vec![g1] },
            ],
        };
        let (all, w) = weights(&m, &[vec![1, 0, 1]], 2.0);
        assert_eq!(all.len(), 3);
        assert_eq!(w, vec![5.0, 3.0, 1.0]);
        // The weighted operator picks s0's transition about 5/9 of the time.
        let mut r = rng();
        let mut first = 0;
        let n = 20_000;
        for _ in 0..n {
            let mut c = m.clone();
            assert!(weighted_change_target(
                &mut r,
                &mut c,
                &[vec![1, 0, 1]],
                2.0
            ));
            c.validate().unwrap();
            if c.target(all[0]) != m.target(all[0]) {
                first += 1;
            }
        }
        let share = first as f64 / n as f64;
        assert!((share - 5.0 / 9.0).abs() < 0.02, "{share}");
    }

    /// One input `b`, one output `lamp`: `b` sets the lamp (CNF), then `!b` passes without
    /// CNF, then `!b` clears it (CNF).
    fn lamp_data() -> ScenarioData {
        use crate::scenario::{Origin, Scenario, ScenarioSet, Step};
        let step = |b: bool, out: Option<bool>| Step {
            inputs: vec![b],
            outputs: out.map(|o| vec![o]),
        };
        let set = ScenarioSet {
            inputs: vec!["b".into()],
            outputs: vec!["lamp".into()],
            initial_outputs: vec![false],
            scenarios: vec![Scenario {
                origin: Origin {
                    file: "t".into(),
                    line: 1,
                    rows: None,
                },
                steps: vec![
                    step(true, Some(true)),
                    step(false, None),
                    step(false, Some(false)),
                ],
            }],
        };
        ScenarioData::new(&set).unwrap()
    }

    /// Three states; s0 goes to s1 on every input vector.
    fn always_to_s1() -> Machine {
        let mut g = Group::empty(vec![]);
        g.table[0] = Some(StateId(1));
        Machine {
            inputs: 1,
            states: vec![
                SearchState { groups: vec![g] },
                SearchState::default(),
                SearchState::default(),
            ],
        }
    }

    fn site<'a>(data: &'a ScenarioData, masks: &'a [(u32, u32)], step: usize) -> Site<'a> {
        Site {
            data,
            masks,
            at: Divergence {
                scenario: 0,
                step,
                state: 0,
            },
        }
    }

    #[test]
    fn repair_stops_the_machine_firing_on_a_passive_step() {
        let data = lamp_data();
        let masks = [(0, 0); 3];
        let mut r = rng();
        for _ in 0..50 {
            let mut m = always_to_s1();
            assert!(repair(&mut r, &mut m, &site(&data, &masks, 1), 4, 0.0));
            m.validate().unwrap();
            assert_eq!(m.fire(0, 0), None, "still fires on !b: {m:?}");
            // Split or deleted: where it still fires, it goes where it went.
            assert!(m.fire(0, 1).is_none_or(|f| f.2 == StateId(1)));
        }
    }

    #[test]
    fn repair_makes_the_machine_fire_on_a_missed_cnf_step() {
        let data = lamp_data();
        let masks = [(0, 0); 3];
        let mut r = rng();
        for _ in 0..50 {
            let mut m = always_to_s1();
            m.states[0].groups.clear();
            assert!(repair(&mut r, &mut m, &site(&data, &masks, 0), 4, 0.0));
            m.validate().unwrap();
            assert!(m.fire(0, 1).is_some());
        }
    }

    #[test]
    fn repair_sends_a_wrong_output_elsewhere_preferring_a_fitting_state() {
        let data = lamp_data();
        // s1 clears the lamp (wrong at step 0), s2 sets it (right).
        let masks = [(0, 0), (1, 0), (0, 1)];
        let mut r = rng();
        let mut to_s2 = 0;
        for _ in 0..200 {
            let mut m = always_to_s1();
            assert!(repair(&mut r, &mut m, &site(&data, &masks, 0), 4, 0.0));
            m.validate().unwrap();
            let t = m.fire(0, 1).expect("still fires").2;
            assert_ne!(t, StateId(1));
            to_s2 += usize::from(t == StateId(2));
        }
        // Half the time the fitting state, else one of the other two: about 3/4.
        assert!((120..180).contains(&to_s2), "{to_s2}");
    }

    #[test]
    fn repair_can_redirect_an_earlier_step_to_a_state_with_the_same_outputs() {
        let data = lamp_data();
        // The divergence is at step 2; step 0 entered s1, s2 gives the same outputs.
        let masks = [(0, 0), (0, 1), (0, 1)];
        let mut r = rng();
        let mut m = always_to_s1();
        let s = Site {
            data: &data,
            masks: &masks,
            at: Divergence {
                scenario: 0,
                step: 2,
                state: 1,
            },
        };
        assert!(repair(&mut r, &mut m, &s, 4, 1.0));
        assert_eq!(m.fire(0, 1).map(|f| f.2), Some(StateId(2)));
    }
}
