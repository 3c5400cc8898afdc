//! State labeling (the metaheuristic paper, section IV.E): the `{0,1,x}` algorithm of every state, deduced
//! from the scenarios for a given transition structure.
//!
//! In: a [`Machine`] and the precomputed [`ScenarioData`]. Out: one algorithm per state.
//!
//! The machine runs every scenario from its initial state. At a recorded `CNF` step where the
//! machine fires into state `y`, each output's recorded value before and after the step is
//! counted in `y`'s table `M`: `0 -> 1`, `1 -> 0`, `0 -> 0`, `1 -> 1`. Each output of `y` then
//! gets the arg max of
//! `C = {0: M10 + M00, 1: M01 + M11, x: M00 + M11}`, the number of counted steps each symbol
//! reproduces.
//!
//! The paper's relation is `C = {0: M10, 1: M01, x: M00 + M11}`. It cannot label a state that
//! is entered both from `0` and from `1` and must set `0` (or `1`): `0 -> 0` steps vote for
//! `x` although `0` reproduces them too. On the first Pick-and-Place scenario the paper's rule
//! gives the minimal machine SAT finds `F_ed = 0.75` instead of 1, and the search stalled on
//! exactly such a plateau; the relation above reproduces every step any symbol can.
//!
//! Two adaptations to this project's scenarios, which record passive steps (no `CNF`): only
//! steps where the recording *and* the machine produce `CNF` are counted (a passive step has no
//! new output values to learn from), and a step whose outputs did not change at all counts as
//! "unchanged" for every output (the paper skips it; with `CNF` it is evidence for `x`). Ties go
//! to `x`, then `0`: a state never entered keeps everything.

use super::data::{ScenarioData, PASSIVE};
use super::machine::Machine;
use crate::ecc::Tri;

/// Counts of one output in one state: `[falls (1->0), rises (0->1), stays 0, stays 1]`.
pub(crate) type Counts = [u32; 4];

/// Runs the scenarios; fills `path` with the state entered at every step (`u32::MAX` when the
/// machine does not fire) and `counts` (`states * outputs` tables, state-major).
pub(crate) fn run(m: &Machine, data: &ScenarioData, path: &mut Vec<u32>, counts: &mut Vec<Counts>) {
    let z = data.outputs.len();
    path.clear();
    counts.clear();
    counts.resize(m.states.len() * z, [0; 4]);
    for sc in &data.bounds {
        let mut s = 0usize;
        for st in &data.steps[sc.clone()] {
            match m.fire(s, st.x) {
                Some((_, _, t)) => {
                    s = t.0;
                    path.push(s as u32);
                    if st.expected != PASSIVE {
                        let before = st.before;
                        let after = st.expected;
                        let row = &mut counts[s * z..(s + 1) * z];
                        for (j, c) in row.iter_mut().enumerate() {
                            let b = (before >> j) & 1;
                            let a = (after >> j) & 1;
                            // falls 0, rises 1, stays 0: 2, stays 1: 3
                            let k = if a == b { 2 + a as usize } else { a as usize };
                            c[k] += 1;
                        }
                    }
                }
                None => path.push(u32::MAX),
            }
        }
    }
}

/// The symbol the counts elect (arg max; ties to `x`, then `0`).
pub(crate) fn decide(c: Counts) -> Tri {
    let [falls, rises, same0, same1] = c;
    let (zero, one, same) = (falls + same0, rises + same1, same0 + same1);
    if same >= zero && same >= one {
        Tri::Keep
    } else if falls >= rises {
        Tri::Zero
    } else {
        Tri::One
    }
}

/// The algorithm of every state of `m` on `data`.
pub(crate) fn label(m: &Machine, data: &ScenarioData) -> Vec<Vec<Tri>> {
    let mut path = Vec::new();
    let mut counts = Vec::new();
    run(m, data, &mut path, &mut counts);
    let z = data.outputs.len();
    (0..m.states.len())
        .map(|s| {
            counts[s * z..(s + 1) * z]
                .iter()
                .map(|&c| decide(c))
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ecc::{InputId, StateId};
    use crate::scenario::{Origin, Scenario, ScenarioSet, Step};
    use crate::search::machine::{Group, SearchState};

    fn step(x: bool, out: Option<[bool; 2]>) -> Step {
        Step {
            inputs: vec![x],
            outputs: out.map(|o| o.to_vec()),
        }
    }

    #[test]
    fn hand_made_example() {
        // Two states; input b: in s0, b -> s1; in s1, !b -> s0. Outputs (lamp, beep).
        let mut g0 = Group::empty(vec![InputId(0)]);
        g0.table[1] = Some(StateId(1));
        let mut g1 = Group::empty(vec![InputId(0)]);
        g1.table[0] = Some(StateId(0));
        let m = Machine {
            inputs: 1,
            states: vec![
                SearchState { groups: vec![g0] },
                SearchState { groups: vec![g1] },
            ],
        };
        let sc = |steps| Scenario {
            origin: Origin {
                file: "t".into(),
                line: 1,
                rows: None,
            },
            steps,
        };
        // Entering s1: lamp rises twice; beep rises once and stays 0 once (a tie of 1 and x).
        // Entering s0: lamp falls twice; beep stays 1 once and 0 once (x).
        let set = ScenarioSet {
            inputs: vec!["b".into()],
            outputs: vec!["lamp".into(), "beep".into()],
            initial_outputs: vec![false, false],
            scenarios: vec![
                sc(vec![
                    step(true, Some([true, true])),
                    step(true, None), // no CNF: s1 does not fire on b
                    step(false, Some([false, true])),
                ]),
                sc(vec![
                    step(false, None),
                    step(true, Some([true, false])),
                    step(false, Some([false, false])),
                ]),
            ],
        };
        let data = ScenarioData::new(&set).unwrap();
        let mut path = Vec::new();
        let mut counts = Vec::new();
        run(&m, &data, &mut path, &mut counts);
        assert_eq!(path, vec![1, u32::MAX, 0, u32::MAX, 1, 0]);
        // state-major: s0 lamp, s0 beep, s1 lamp, s1 beep; [falls, rises, stays 0, stays 1]
        assert_eq!(
            counts,
            vec![[2, 0, 0, 0], [0, 0, 1, 1], [0, 2, 0, 0], [0, 1, 1, 0]]
        );
        let algs = label(&m, &data);
        assert_eq!(algs[0], vec![Tri::Zero, Tri::Keep]);
        assert_eq!(algs[1], vec![Tri::One, Tri::Keep]);
    }

    #[test]
    fn arg_max_with_ties_to_keep_then_zero() {
        // [falls, rises, stays 0, stays 1]
        assert_eq!(decide([3, 1, 1, 1]), Tri::Zero);
        assert_eq!(decide([1, 3, 1, 1]), Tri::One);
        assert_eq!(decide([0, 0, 2, 2]), Tri::Keep);
        assert_eq!(decide([2, 2, 0, 0]), Tri::Zero);
        assert_eq!(decide([0, 0, 0, 0]), Tri::Keep);
        // The paper's relation would say `x` here (3 unchanged against 1 fall); `0`
        // reproduces all four steps, `x` three.
        assert_eq!(decide([1, 0, 3, 0]), Tri::Zero);
        assert_eq!(decide([0, 1, 0, 3]), Tri::One);
    }
}
