//! The search's representation of an ECC (the metaheuristic paper, section IV.B): states with transition
//! groups.
//!
//! In: nothing but sizes and a random generator, or an [`Ecc`] whose guards are conjunctions.
//! Out: a [`Machine`] that the operators mutate and the fitness runs, and, with the state
//! algorithms from [`super::labeling`], the project's [`Ecc`] ([`Machine::to_ecc`]) that every
//! exporter, the simulator and the verifier take.
//!
//! A [`Group`] has a set of significant inputs (the paper's significance mask, kept as the sorted
//! list of significant [`InputId`]s) and a table with one optional target per assignment of
//! them. The entry index reads the significant inputs as a binary number, the first
//! significant input being the most significant bit (the paper's `(x0, x1, x2, x3) = 0101 -> 5`).
//! On `REQ` the groups of the current state are tried in order; the first whose entry for the
//! input vector is present fires. In the [`Ecc`] every present entry becomes one transition
//! guarded by the conjunction of all significant literals, in group order then entry order,
//! so the two machines agree step for step.

use crate::ecc::{Algorithm, Ecc, Guard, InputId, State, StateId, Transition, Tri};
use rand::Rng;

/// A transition group of one state.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub(crate) struct Group {
    /// Significant inputs, ascending (the paper's mask `m_t`).
    pub(crate) vars: Vec<InputId>,
    /// `2^vars.len()` entries: the target for that assignment, or `None` (the paper's `-1`).
    pub(crate) table: Vec<Option<StateId>>,
}

/// One state: its transition groups in priority order.
#[derive(Debug, Clone, PartialEq, Eq, Hash, Default)]
pub(crate) struct SearchState {
    /// The groups; on `REQ` the first whose entry for the input vector is present fires.
    pub(crate) groups: Vec<Group>,
}

/// A candidate ECC without algorithms (those come from state labeling).
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
pub struct Machine {
    /// Number of inputs of the interface.
    pub(crate) inputs: usize,
    /// States; index 0 is the initial state.
    pub(crate) states: Vec<SearchState>,
}

/// Names one present table entry: state, group, entry index (all 0-based).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct TransitionRef {
    /// The source state (index in [`Machine::states`]).
    pub(crate) state: StateId,
    /// Index of the group in the state's [`SearchState::groups`].
    pub(crate) group: usize,
    /// Index in the group's [`Group::table`] (the significant inputs read as a number).
    pub(crate) entry: usize,
}

/// Input vectors are bit masks: bit `i` is input `i`. The search supports at most this many.
pub(crate) const MAX_INPUTS: usize = 32;

/// `x` as a bit mask (bit `i` = input `i`).
pub(crate) fn input_bits(x: &[bool]) -> u32 {
    x.iter()
        .enumerate()
        .fold(0, |acc, (i, &b)| acc | (u32::from(b) << i))
}

impl Group {
    /// A group over `vars` with every entry absent.
    pub(crate) fn empty(mut vars: Vec<InputId>) -> Group {
        vars.sort();
        vars.dedup();
        Group {
            table: vec![None; 1 << vars.len()],
            vars,
        }
    }

    /// The table index the input vector `x` (bit mask) selects.
    #[inline]
    pub(crate) fn index(&self, x: u32) -> usize {
        self.vars
            .iter()
            .fold(0, |acc, v| (acc << 1) | ((x >> v.0) & 1) as usize)
    }

    /// The literals of entry `entry`: each significant input with its value in that entry.
    pub(crate) fn literals(&self, entry: usize) -> Vec<(InputId, bool)> {
        let k = self.vars.len();
        self.vars
            .iter()
            .enumerate()
            .map(|(j, &v)| (v, (entry >> (k - 1 - j)) & 1 == 1))
            .collect()
    }

    /// Number of present entries.
    pub(crate) fn present(&self) -> usize {
        self.table.iter().filter(|t| t.is_some()).count()
    }

    /// Whether `v` is significant.
    pub(crate) fn has_var(&self, v: InputId) -> bool {
        self.vars.binary_search(&v).is_ok()
    }
}

impl Machine {
    /// A random machine: `states` states, each with one group over up to `max_vars` random
    /// inputs whose entries are present with probability one half, to random targets.
    pub fn random(rng: &mut impl Rng, inputs: usize, states: usize, max_vars: usize) -> Machine {
        assert!(inputs <= MAX_INPUTS && states >= 1, "checked by the caller");
        let states = (0..states)
            .map(|_| {
                let k = rng.gen_range(0..=max_vars.min(inputs));
                let mut all: Vec<usize> = (0..inputs).collect();
                let mut vars = Vec::with_capacity(k);
                for _ in 0..k {
                    vars.push(InputId(all.swap_remove(rng.gen_range(0..all.len()))));
                }
                let mut g = Group::empty(vars);
                for e in g.table.iter_mut() {
                    if rng.gen_bool(0.5) {
                        *e = Some(StateId(rng.gen_range(0..states)));
                    }
                }
                SearchState { groups: vec![g] }
            })
            .collect();
        Machine { inputs, states }
    }

    /// The entry that fires in state `s` on input vector `x`: `(group, entry, target)`.
    #[inline]
    pub(crate) fn fire(&self, s: usize, x: u32) -> Option<(usize, usize, StateId)> {
        for (gi, g) in self.states[s].groups.iter().enumerate() {
            let e = g.index(x);
            if let Some(t) = g.table[e] {
                return Some((gi, e, t));
            }
        }
        None
    }

    /// Every present entry, in state, group, entry order.
    pub(crate) fn transitions(&self) -> Vec<TransitionRef> {
        let mut out = Vec::new();
        for (s, st) in self.states.iter().enumerate() {
            for (g, grp) in st.groups.iter().enumerate() {
                for (e, t) in grp.table.iter().enumerate() {
                    if t.is_some() {
                        out.push(TransitionRef {
                            state: StateId(s),
                            group: g,
                            entry: e,
                        });
                    }
                }
            }
        }
        out
    }

    /// Number of present entries (transitions of the ECC).
    pub(crate) fn transition_count(&self) -> usize {
        self.states
            .iter()
            .flat_map(|s| &s.groups)
            .map(Group::present)
            .sum()
    }

    /// Target of a present entry.
    pub(crate) fn target(&self, t: TransitionRef) -> Option<StateId> {
        self.states[t.state.0].groups[t.group].table[t.entry]
    }

    /// Sets the target of an entry (present or not).
    pub(crate) fn set_target(&mut self, t: TransitionRef, target: Option<StateId>) {
        self.states[t.state.0].groups[t.group].table[t.entry] = target;
    }

    /// Checks the invariants the operators keep: table sizes, sorted distinct variables in
    /// range, targets in range.
    pub(crate) fn validate(&self) -> Result<(), String> {
        for (s, st) in self.states.iter().enumerate() {
            for (g, grp) in st.groups.iter().enumerate() {
                if grp.table.len() != 1 << grp.vars.len() {
                    return Err(format!("state {s} group {g}: table size"));
                }
                if grp.vars.windows(2).any(|w| w[0] >= w[1]) {
                    return Err(format!("state {s} group {g}: variables not sorted"));
                }
                if grp.vars.iter().any(|v| v.0 >= self.inputs) {
                    return Err(format!("state {s} group {g}: variable out of range"));
                }
                if grp.table.iter().flatten().any(|t| t.0 >= self.states.len()) {
                    return Err(format!("state {s} group {g}: target out of range"));
                }
            }
        }
        Ok(())
    }

    /// The ECC with the given state algorithms (one `{0,1,x}` string per state).
    pub(crate) fn to_ecc(
        &self,
        inputs: &[String],
        outputs: &[String],
        initial_outputs: &[bool],
        algorithms: &[Vec<Tri>],
    ) -> Ecc {
        let states = self
            .states
            .iter()
            .zip(algorithms)
            .enumerate()
            .map(|(i, (st, alg))| State {
                name: format!("s{i}"),
                algorithm: Algorithm::Tri(alg.clone()),
                transitions: st
                    .groups
                    .iter()
                    .flat_map(|g| {
                        g.table.iter().enumerate().filter_map(|(e, t)| {
                            t.map(|target| Transition {
                                target,
                                guard: Guard::cube(&g.literals(e)),
                            })
                        })
                    })
                    .collect(),
            })
            .collect();
        Ecc {
            inputs: inputs.to_vec(),
            outputs: outputs.to_vec(),
            initial_outputs: initial_outputs.to_vec(),
            states,
        }
    }

    /// The machine of an ECC whose guards are conjunctions or disjunctions of conjunctions of
    /// literals: every cube becomes a group of its own with one present entry, in transition
    /// order, so priorities are kept. Algorithms are dropped (labeling recomputes them).
    /// `None` for any other guard or more than [`MAX_INPUTS`] inputs.
    pub(crate) fn from_ecc(ecc: &Ecc) -> Option<Machine> {
        if ecc.inputs.len() > MAX_INPUTS {
            return None;
        }
        let mut states = Vec::with_capacity(ecc.states.len());
        for st in &ecc.states {
            let mut groups = Vec::new();
            for t in &st.transitions {
                for mut cube in t.guard.as_dnf()? {
                    cube.sort();
                    if cube.windows(2).any(|w| w[0].0 == w[1].0) {
                        // x & !x: never fires; x & x: same literal twice.
                        if cube
                            .windows(2)
                            .any(|w| w[0].0 == w[1].0 && w[0].1 != w[1].1)
                        {
                            continue;
                        }
                        cube.dedup();
                    }
                    let mut g = Group::empty(cube.iter().map(|l| l.0).collect());
                    let entry = cube
                        .iter()
                        .fold(0usize, |acc, l| (acc << 1) | usize::from(l.1));
                    g.table[entry] = Some(t.target);
                    groups.push(g);
                }
            }
            states.push(SearchState { groups });
        }
        Some(Machine {
            inputs: ecc.inputs.len(),
            states,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::Run;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn entry_index_reads_the_first_significant_input_as_the_high_bit() {
        let g = Group::empty(vec![InputId(3), InputId(0), InputId(1), InputId(2)]);
        // x0..x3 = 0101 -> entry 5, as in the paper's example.
        let x = input_bits(&[false, true, false, true]);
        assert_eq!(g.index(x), 5);
        assert_eq!(
            g.literals(5),
            vec![
                (InputId(0), false),
                (InputId(1), true),
                (InputId(2), false),
                (InputId(3), true)
            ]
        );
    }

    #[test]
    fn the_ecc_agrees_with_the_machine_on_every_input() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for _ in 0..20 {
            let m = Machine::random(&mut rng, 4, 4, 3);
            m.validate().unwrap();
            let names: Vec<String> = (0..4).map(|i| format!("x{i}")).collect();
            let algs = vec![vec![Tri::Keep]; 4];
            let ecc = m.to_ecc(&names, &["z".into()], &[false], &algs);
            ecc.validate().unwrap();
            for s in 0..4 {
                for x in 0..16u32 {
                    let xs: Vec<bool> = (0..4).map(|i| x >> i & 1 == 1).collect();
                    let mut run = Run::new(&ecc);
                    run.state = StateId(s);
                    let ecc_target = run.step(&xs).map(|f| f.target);
                    assert_eq!(ecc_target, m.fire(s, x).map(|f| f.2));
                }
            }
            assert_eq!(
                Machine::from_ecc(&ecc).map(|b| b.transition_count()),
                Some(m.transition_count())
            );
            let back = Machine::from_ecc(&ecc).unwrap();
            for s in 0..4 {
                for x in 0..16u32 {
                    assert_eq!(back.fire(s, x).map(|f| f.2), m.fire(s, x).map(|f| f.2));
                }
            }
        }
    }
}
